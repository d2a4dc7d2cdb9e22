#pragma once
/// How often to draw, so that drawing never starves the simulation. While the scene runs, the simulation comes
/// first: drawing gets the share of the wall clock that the steps leave over (with a margin), and frames come less
/// often when they cost more (a big sheet, software rendering). A simulation that cannot keep up even alone still
/// gets a frame now and then (a minimum share). Paused, frames come as often as the frame-rate cap allows.

#include "core/Types.h"

#include <limits>

namespace masse::viewer
{
/// Shares of wall time. Measured under Xvfb on two shared cores, a 64x2x64 sheet's steps take 85-96% of the
/// clock while the rasteriser runs beside them, so the minimum share and the margin are kept small: a sheet that
/// keeps real time alone keeps it with the viewer open, at a few frames a second if need be.
struct DrawPacing
{
    Real minShare = Real(0.1);        ///< of wall time for drawing, however busy the simulation
    Real maxShare = Real(0.5);        ///< of wall time for drawing, however idle the simulation
    Real margin = Real(0.05);         ///< of wall time left free besides the steps and the frames
    Real minInterval = Real(1) / 120; ///< s between frames at the fastest
};

class DrawPacer
{
public:
    explicit DrawPacer(const DrawPacing& pacing = {}) : m_pacing(pacing) {}

    /// Steps taken: their count, the wall seconds they took, and the scene's dt (their cost per simulated second
    /// is the share of wall time the simulation needs to keep real time).
    void stepped(int steps, Real seconds, Real dt);
    /// A frame started at `start` (s, any steady clock) and took `cost` seconds to draw.
    void drew(Real start, Real cost);

    /// The share of wall time drawing may take now while the simulation runs.
    Real drawShare() const;
    /// Seconds from the start of one frame to the start of the next.
    Real interval(bool simulationRunning) const;
    bool due(Real now, bool simulationRunning) const { return now - m_lastStart >= interval(simulationRunning); }

    Real drawCost() const { return m_drawCost; }
    /// Wall seconds per simulated second the steps take (above 1: slower than real time even without drawing).
    Real simulationLoad() const { return m_load; }

private:
    DrawPacing m_pacing;
    Real m_drawCost = 0; ///< s per frame, averaged
    Real m_load = 0;     ///< averaged
    bool m_drawn = false;
    bool m_stepped = false;
    Real m_lastStart = -std::numeric_limits<Real>::infinity();
};
} // namespace masse::viewer
