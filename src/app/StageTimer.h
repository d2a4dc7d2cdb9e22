#pragma once
/// Wall-clock seconds spent in each of the engine's stages, summed (the core reads no clock: it reports stage
/// boundaries to a StageObserver, and this one times them for `masse bench`).

#include "core/StageObserver.h"

#include <array>
#include <chrono>

namespace masse::app
{
class StageTimer final : public StageObserver
{
public:
    void begin(Stage stage) override { m_start[index(stage)] = std::chrono::steady_clock::now(); }
    void end(Stage stage) override
    {
        m_seconds[index(stage)] +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start[index(stage)]).count();
    }
    double seconds(Stage stage) const { return m_seconds[index(stage)]; }
    double contactSeconds() const
    {
        return seconds(Stage::ContactDetection) + seconds(Stage::ContactProjection) + seconds(Stage::ContactSweep);
    }
    void reset() { m_seconds = {}; }

private:
    static std::size_t index(Stage stage) { return std::size_t(stage); }
    std::array<std::chrono::steady_clock::time_point, stageCount> m_start{};
    std::array<double, stageCount> m_seconds{};
};
} // namespace masse::app
