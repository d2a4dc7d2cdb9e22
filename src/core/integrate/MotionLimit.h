#pragma once
/// Splits an implicit frame into as many solves as keep each mass's motion in one solve within a set length, the
/// rule particle methods call the CFL condition (dt <= C dx / |v|max). One implicit solve of a long frame carries a
/// fast mass straight across several cells: past the reach of the obstacle contact, which projects where the solve
/// ended, and of the layer floor, which measures each upper mass against the cell the solve left beneath it. A finer
/// lattice has smaller cells for the same motion, so a step that a coarse sheet takes safely carries a fine one across
/// many cells: the vacuum cup with dt 0.01 s runs at 32x2x32, where its sheet moves 3 to 6 spacings in a solve early
/// on, and diverges at 64x2x64 and 96x2x96. A limit in spacings gives every lattice the same step in cells.
///
/// The motion of mass i over a frame of dt is predicted from its velocity at the frame's start and that velocity's
/// change over the frame before, (|v_i| + |v_i - v_i,before|) dt, so a sheet that a load is accelerating is split
/// before it is fast; the first frame, with no change to go by, is taken in the most solves. The largest over the
/// masses decides, so the count does not depend on the order of the masses or on the threads.
///
/// The first frame's count is a guess, so it is corrected as the frame goes (solvesForRest): after each solve the rest
/// of the frame is split by the speeds and the accelerations that solve showed, each next solve at most twice as long
/// as the frame so far: a load rising over the frame (the vacuum cup's) does more in each solve than the one before
/// showed, which the doubling bounds. The 64x2x64 vacuum cup's first frame takes 5 solves this way.

#include "core/StepHook.h"

#include <vector>

namespace masse
{
class MotionLimit final : public StepHook
{
public:
    /// maxMotion: m a mass may move in one solve (> 0); maxSolves: the most solves a frame is split into (>= 1).
    MotionLimit(Real maxMotion, int maxSolves);

    /// Joins no stage: it only answers solvesFor before a frame.
    StageSet stages() const override { return {}; }
    int solvesFor(MassSpringSystem& system, Real dt) override;
    int solvesForRest(MassSpringSystem& system, Real taken, Real rest) override;

    /// m, the largest predicted motion of the frame last asked about, before it was split (infinite for the first).
    Real predictedMotion() const { return m_predictedMotion; }

private:
    Real m_maxMotion;
    int m_maxSolves;
    std::vector<Vec3> m_velocityBefore; ///< at the start of the frame last asked about (empty before the first)
    std::vector<Real> m_chunkLargest;   ///< each chunk's largest of a measure (largestOverMasses), kept between calls
    // The first frame's correction (solvesForRest):
    bool m_guessing = false;             ///< the frame being taken is the first, its split a guess
    std::vector<Vec3> m_velocityBySolve; ///< at the start of the solve just taken
    Real m_frameSoFar = 0;               ///< s of the first frame taken so far
    int m_solvesSoFar = 0;               ///< solves of the first frame taken so far
    Real m_predictedMotion = 0;
};
} // namespace masse
