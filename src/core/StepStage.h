#pragma once
/// The stages of one frame, in the order Simulator::stepFrame runs them: one table, walked by one function
/// (Simulator::runStage). Models join stages as StepHooks (StepHook.h); the obstacle contact, the self-contact and the
/// edge contact are hooks like the others and differ only in the stages they join. docs/step.md draws the table with
/// what each stage reads and writes; a test checks that it names every stage here.

#include "core/Types.h"

#include <cstdint>
#include <initializer_list>
#include <string_view>

namespace masse
{
struct MassSpringSystem;
struct StepContext;

enum class StepStage : std::uint8_t
{
    BeforeFrame,       ///< script actions: grab, release, pin, gravity, heaters, obstacle moves
    PlanFrame,         ///< the substep count (explicit: the stability estimate; implicit: one solve)
    ContactDetection,  ///< the obstacle contact finds each mass's planes and the implicit solve's constraints
    BeginFrame,        ///< heat, springs, pressure, the self- and edge-contact pairs
    Integrate,         ///< forces, then the solve (implicit) or the update (explicit)
    AfterSolve,        ///< implicit only: the layer floor and the self-contact before the obstacle projection
    ContactProjection, ///< projection out of the obstacles, friction, sticking, release
    AfterSubstep,      ///< script paths, layer floor, springs' creep, pressure, self- and edge contact
    ContactReport,     ///< the obstacle contact's sweep and the frame's contact report
    EndFrame,          ///< heat exchange, pressure seal
    Check,             ///< finite check and divergence guard: a bad state stops the run before it is written
};

inline constexpr int stepStageCount = 11;

struct StepStageEntry
{
    StepStage stage;
    std::string_view name; ///< as docs/step.md and a hook's stages() name it
    bool everySubstep;     ///< run once per substep (or per solve), else once a frame
    bool hooksJoin;        ///< whether StepHooks may join it (the others are the Simulator's own)
    /// Whether the divergence guard accounts for the energy its hooks put in or take out (the models' stages; the
    /// Simulator's own stages and the contact projection have checks of their own, in Simulator::runStage).
    bool guardAccountsEnergy;
};

inline constexpr StepStageEntry stepStageTable[stepStageCount] = {
    {StepStage::BeforeFrame, "beforeFrame", false, true, true},
    {StepStage::PlanFrame, "planFrame", false, false, false},
    {StepStage::ContactDetection, "contactDetection", false, true, false},
    {StepStage::BeginFrame, "beginFrame", false, true, true},
    {StepStage::Integrate, "integrate", true, false, false},
    {StepStage::AfterSolve, "afterSolve", true, true, true},
    {StepStage::ContactProjection, "contactProjection", true, true, false},
    {StepStage::AfterSubstep, "afterSubstep", true, true, true},
    {StepStage::ContactReport, "contactReport", false, true, false},
    {StepStage::EndFrame, "endFrame", false, true, true},
    {StepStage::Check, "check", false, false, false},
};

constexpr const StepStageEntry& stageEntry(StepStage stage)
{
    return stepStageTable[int(stage)];
}

/// A set of stages, as a hook declares the ones it joins.
class StageSet
{
public:
    constexpr StageSet() = default;
    constexpr StageSet(std::initializer_list<StepStage> stages)
    {
        for (const StepStage stage : stages)
        {
            m_bits |= bit(stage);
        }
    }
    constexpr bool contains(StepStage stage) const { return (m_bits & bit(stage)) != 0; }
    constexpr StageSet with(StepStage stage) const
    {
        StageSet more = *this;
        more.m_bits |= bit(stage);
        return more;
    }

private:
    static constexpr std::uint32_t bit(StepStage stage) { return std::uint32_t(1) << int(stage); }
    std::uint32_t m_bits = 0;
};

/// What the symplectic pass may skip in a substep: reading external forces that are all +0, storing forces nobody
/// reads after it. The Simulator decides them; the other integrators read neither.
struct SubstepHints
{
    /// False when every external force is +0 (noExternalForces in Forces.h). The Simulator looks once a frame, after
    /// the beginFrame hooks, and again after every substep's hooks when a hook says it writes them then
    /// (StepHook::writesExternalForcesMidFrame; a pressure load does); nothing else in a step writes them.
    bool externalForces = true;
    /// Whether somebody reads particles.force after this substep: true at a frame's last substep (the contact's
    /// reach and the guard read them between frames), and when a hook says it reads them
    /// (StepHook::readsForcesMidFrame: the obstacle contact while it holds a stuck mass, for its release force).
    bool forcesRead = true;
};

/// How the Simulator takes the current frame, for the stages that depend on it. It changes between frames, never
/// within a stage; what the stages hand one another is in StepContext.
struct FramePlan
{
    Real start = 0;              ///< s, the time at the frame's start
    Real dt = 0;                 ///< s, the frame's length
    int substeps = 1;            ///< explicit: from the stability estimate; implicit: 1
    Real substep = 0;            ///< s, dt / substeps
    int substepIndex = 0;        ///< of the substep being taken (every-substep stages)
    bool oneSolveAFrame = false; ///< the integrator takes the frame in one solve (the implicit ones)
    bool constrain = false;      ///< the integrator honours StepContext::constraints (the contact then writes them)
    SubstepHints hints;          ///< for the substep being taken

    /// The time at the end of the substep being taken.
    Real substepEnd() const { return start + Real(substepIndex + 1) * substep; }
};

/// What a hook's stage gets: the sheet, the stages' shared data, the frame's plan, and the time the stage stands at
/// (the frame's start before the substeps, the substep's end in them, the frame's end after them).
struct StageCall
{
    MassSpringSystem& system;
    StepContext& context;
    const FramePlan& plan;
    Real time;
};
} // namespace masse
