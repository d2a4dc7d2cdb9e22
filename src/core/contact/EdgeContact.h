#pragma once
/// The sheet's surface against the obstacles' sharp edges and corners: a spring between two masses cannot cut across a
/// ridge, and an apex cannot pass between masses. The masses themselves meet the obstacles as spheres (ContactSolver);
/// this adds what spheres miss: a sheet edge against an obstacle edge (the closest points inside both segments,
/// ClosestPointsOfSegments.h) and a sheet triangle against an obstacle corner (ClosestPointOnTriangle.h). A pair whose
/// closest point is a sheet mass is left to the mass's own contact.
///
/// At each frame's start the detector (EdgeContactDetector.h; Bullet in the bridge) lists the pairs that may meet
/// within the frame while every surface mass stays within its reach (how far its speed and acceleration can carry it,
/// as the obstacle contact reckons, plus a quarter radius); a substep that finds a mass beyond its reach lists them
/// again (unless the sheet was clear of every feature by more than a radius: that check is a pass over the masses,
/// and a tenth of a large sheet's step). After every substep each listed pair is measured, and one closer than the
/// contact radius gets the response: the sheet side pushed out to the radius and its approaching velocity relative to
/// the obstacle removed (inelastic), with the obstacle's friction (Coulomb, capped so it never reverses the slip;
/// sticky stops the slip; frictionless none), all shared among the sheet feature's masses by their weights and inverse
/// masses. The obstacle is not moved by it (it is static or follows its path), so each impulse only takes kinetic
/// energy away, as seen from the obstacle. The normal points away from the obstacle: a sheet point found behind both
/// faces of an edge (or every face of a corner), inside the obstacle, is pushed back out through the edge, not further
/// in.
///
/// Runs as a StepHook after the obstacle contact of every substep, or of every solve under the implicit integrators.
/// One solve moves the sheet a whole frame at once and can carry a sheet edge clean over a ridge: a sheet point
/// behind the feature's faces further than a radius still counts if it was outside them at the frame's start and has
/// moved at least that far since (measure). Detection runs over ranges of pairs on every thread; the responses are
/// applied in one pass in pair order, so the result is the same bit for bit at any thread count.

#include "core/StageObserver.h"
#include "core/StepHook.h"
#include "core/contact/Contact.h"
#include "core/contact/EdgeContactDetector.h"
#include "core/lattice/Lattice.h"
#include "core/lattice/LatticeSurface.h"
#include "core/parallel/PerChunk.h"

#include <cstdint>
#include <vector>

namespace masse
{
/// What the edge contact did.
struct EdgeContactReport
{
    std::size_t edgePairs = 0;         ///< sheet edge / obstacle edge pairs in the last list
    std::size_t cornerPairs = 0;       ///< sheet triangle / obstacle corner pairs in the last list
    std::uint64_t lists = 0;           ///< lists made so far (one per frame, more when a mass outruns its reach)
    std::size_t lastSubstep = 0;       ///< pairs closer than the radius at the last substep
    std::size_t lastFrame = 0;         ///< pair touches summed over the last frame's substeps
    std::uint64_t total = 0;           ///< pair touches summed over every substep so far
    Real firstTime = -1;               ///< s, the first touch (negative: none yet)
    int firstObstacle = -1;            ///< the obstacle of the first touch
    Vec3 firstPosition = Vec3::Zero(); ///< m, the sheet's point of the first touch
};

class EdgeContact final : public StepHook
{
public:
    /// `settings` gives the radius and each obstacle's response and friction.
    EdgeContact(const Lattice& lattice, EdgeContactDetector& detector, const ContactSettings& settings);

    StageSet stages() const override { return {StepStage::BeginFrame, StepStage::AfterSubstep}; }
    void beginFrame(MassSpringSystem& system, StepContext& context, Real time, Real dt) override;
    void afterSubstep(MassSpringSystem& system, StepContext& context, Real h, Real time) override;

    const EdgeContactReport& report() const { return m_report; }
    /// Per mass, how many touches its edges and triangles took part in over the last frame.
    const std::vector<std::uint32_t>& touchesPerMass() const { return m_massTouches; }
    const SheetSurface& surface() const { return m_surface; }
    /// Told when the listing and each substep's solve begin and end (nullptr: nobody).
    void setStageObserver(StageObserver* observer) { m_observer = observer; }

private:
    /// A listed pair measured now: the sheet's point as weights of up to three masses, and how to push it.
    struct Contact
    {
        Index masses[3] = {0, 0, 0};
        Real weights[3] = {0, 0, 0};
        int count = 0;
        Vec3 normal = Vec3::UnitY(); ///< unit, from the obstacle toward the sheet's point
        Real depth = 0;              ///< m, how far the sheet's point must move along the normal to be a radius away
        Vec3 point = Vec3::Zero();   ///< the sheet's point
        Vec3 obstacleVelocity = Vec3::Zero();
        int obstacle = -1;
    };
    /// Pair k of the list (the edge pairs, then the corner pairs) closer than the radius now, or false.
    bool measure(const std::vector<Vec3>& x, std::size_t k, Real elapsed, Contact& out) const;
    void respond(Particles& p, const Contact& contact, Real h) const;
    void computeReach(const Particles& p, const Vec3& gravity, Real dt);
    void listPairs(const std::vector<Vec3>& x, Real time, Real dt);
    /// Whether some surface mass has moved farther than its reach since the pairs were listed.
    bool outgrewPairs(const std::vector<Vec3>& x);

    EdgeContactDetector& m_detector;
    ContactSettings m_settings;
    SheetSurface m_surface;
    EdgeContactCandidates m_candidates;
    std::vector<Real> m_reach;                      ///< per mass, m (surface masses only)
    std::vector<Vec3> m_listedAt;                   ///< per mass, where it was when the pairs were listed
    std::vector<Vec3> m_frameStart;                 ///< per mass of the surface, where it was at the frame's start
    std::vector<std::uint32_t> m_massTouches;       ///< per mass, touches over the last frame
    std::vector<std::uint8_t> m_chunkOutgrew;       ///< per range of surface masses
    PerChunk<std::vector<std::uint32_t>> m_touches; ///< per range of pairs, the touching ones
    Real m_listTime = 0;
    Real m_frameStartTime = 0;
    Real m_frameEnd = 0;
    EdgeContactReport m_report;
    StageObserver* m_observer = nullptr;
};
} // namespace masse
