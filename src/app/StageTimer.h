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
    void beginStep(StepStage stage) override { m_stepStart[std::size_t(stage)] = std::chrono::steady_clock::now(); }
    void endStep(StepStage stage) override
    {
        m_stepSeconds[std::size_t(stage)] +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - m_stepStart[std::size_t(stage)]).count();
    }
    double seconds(Stage stage) const { return m_seconds[index(stage)]; }
    double seconds(StepStage stage) const { return m_stepSeconds[std::size_t(stage)]; }
    double contactSeconds() const
    {
        return seconds(Stage::ContactDetection) + seconds(Stage::ContactProjection) + seconds(Stage::ContactSweep);
    }
    void reset()
    {
        m_seconds = {};
        m_stepSeconds = {};
    }

private:
    static std::size_t index(Stage stage) { return std::size_t(stage); }
    std::array<std::chrono::steady_clock::time_point, stageCount> m_start{};
    std::array<double, stageCount> m_seconds{};
    std::array<std::chrono::steady_clock::time_point, stepStageCount> m_stepStart{};
    std::array<double, stepStageCount> m_stepSeconds{};
};
} // namespace masse::app
