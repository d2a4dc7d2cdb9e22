#pragma once
/// Keeps sheet masses out of obstacles and applies the contact response (sticky, Coulomb friction, frictionless).
///
/// Once per frame, the detector finds every obstacle a mass could reach within the frame and gives its supporting
/// plane (speculative contacts, as Box2D and Jolt use). After every integrator substep each mass is projected out of
/// its planes and its approach velocity removed: a few dot products per contact, so contact stays cheap however many
/// substeps an explicit integrator takes. At the end of the frame, any mass that moved farther than its reach is
/// checked by a swept test, so nothing tunnels through a thin obstacle.
///
/// Friction acts at the impulse level: the tangential velocity a contact may remove in one substep is mu times the
/// normal velocity it removed, which reproduces Coulomb's law (a block on a slope of angle a slides with acceleration
/// g (sin a - mu cos a), and stays when mu > tan a).

#include "core/MassSpringSystem.h"
#include "core/StageObserver.h"
#include "core/StepContext.h"
#include "core/StepHook.h"
#include "core/contact/Contact.h"
#include "core/contact/ContactConstraints.h"
#include "core/contact/ContactPlanes.h"
#include "core/contact/ContactReport.h"
#include "core/contact/StartOverlap.h"
#include "core/contact/StuckContacts.h"
#include "core/parallel/PerChunk.h"

#include <utility>
#include <vector>

namespace masse
{
/// A StepHook of the frame's three contact stages (StepStage.h), in order: detection and the implicit integrator's
/// constraints (contactDetection: detect), the projection after every substep (contactProjection: project,
/// ContactProjection.h), the sweep and the report (contactReport: sweepAndReport). After each it publishes the report's
/// per-mass obstacles in StepContext::touchingObstacle. Each
/// concept has its own file: the frame's planes indexed by mass (ContactPlanes.h), the masses held by sticky contact
/// (StuckContacts.h), the constraint builder (ContactConstraints.h) and what the frame did (ContactReport.h).
class ContactSolver final : public StepHook
{
public:
    ContactSolver(ContactDetector& detector, const ContactSettings& settings);

    StageSet stages() const override
    {
        return {StepStage::ContactDetection, StepStage::ContactProjection, StepStage::ContactReport};
    }
    void run(StepStage stage, const StageCall& call) override;
    /// Whether the next projection reads the substep's forces (particles.force): while a mass is stuck, whose pull
    /// off its surface decides its release.
    bool readsForcesMidFrame() const override { return m_stuck.any; }

    void setSettings(const ContactSettings& settings);
    const ContactSettings& settings() const { return m_settings; }

    /// The three stages (run calls them). With `constrain`, the integrator honours velocity
    /// constraints, and stuck and resting masses are handed to it as such in context.constraints (see
    /// VelocityConstraint.h), whose reactions project reads; sweepAndReport clears them.
    void detect(MassSpringSystem& system, StepContext& context, Real time, Real dt, bool constrain);
    void project(MassSpringSystem& system, const StepContext& context, Real h);
    void sweepAndReport(MassSpringSystem& system, StepContext& context, Real time);

    /// What the last frame and the run so far did (touches, forces, faces, first contacts).
    const ContactReport& report() const { return m_report; }
    /// Masses held by sticky contact.
    const std::vector<std::uint8_t>& stuck() const { return m_stuck.stuck; }
    std::size_t planeCount() const { return m_planes.size(); }

    /// Deepest penetration of any mass's sphere into an obstacle now (m, 0 if none), measured afresh by the detector.
    Real maxPenetration(const MassSpringSystem& system);
    /// Releases every stuck mass (for a reset or a change of response).
    void releaseAll() { m_stuck.releaseAll(); }
    /// Releases one mass, if it is stuck: the layer floor (LayerGap.h) lifted it off the obstacle it had reached
    /// through the sheet's own lower layer. Touches only that mass's state.
    void release(Index mass)
    {
        if (mass < m_stuck.stuck.size())
        {
            m_stuck.stuck[mass] = 0;
        }
    }
    /// Puts mass i at x back onto a surface this frame found near it, as it is now, if its centre is behind it, and
    /// takes out of v its speed into that surface; touches only that mass. For a correction made after the projection
    /// (the layer floor's, LayerGap.h), which nothing else would keep out of the mould before the next frame: that
    /// frame would find the centre behind the surface and take it for a touch from the other side.
    void keepInFront(Index i, Vec3& x, Vec3& v) const;
    /// Told when each contact stage begins and ends (nullptr: nobody); a profiler outside the core reads its clock.
    void setStageObserver(StageObserver* observer) { m_observer = observer; }

private:
    /// Simulated time now: the frame's start plus the substeps taken in it.
    Real now() const { return m_frameTime + m_elapsed; }
    /// Sweeps mass i's path over the frame, which went beyond its reach: stopped before the first surface it crossed.
    void sweep(Particles& p, std::size_t i);

    ContactDetector& m_detector;
    ContactSettings m_settings;
    ContactPlanes m_planes;
    StuckContacts m_stuck;
    StartOverlap m_startOverlap;
    ContactConstraints m_constraints;
    ContactReport m_report;
    std::vector<Vec3> m_frameStart;                 ///< each mass's position at the frame's start (for the sweep)
    std::vector<Real> m_reach;                      ///< m, how far each mass may get this frame
    PerChunk<std::vector<int>> m_chunkFirstTouches; ///< per mass chunk, the obstacles first touched this substep
    std::vector<std::uint8_t> m_chunkMadeStuck;     ///< per mass chunk, whether a mass stuck this substep
    PerChunk<std::vector<Index>> m_chunkOutran;     ///< per mass chunk, the masses that went beyond their reach
    Real m_frameTime = 0;
    Real m_frameDt = 0;
    Real m_elapsed = 0;
    StageObserver* m_observer = nullptr;
};
} // namespace masse
