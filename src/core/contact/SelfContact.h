#pragma once
/// The sheet against itself: the vertices of its surface (the triangles of its bottom and top layers) are kept at
/// least the contact radius from the surface's triangles, so a fold cannot pass through the sheet.
///
/// At each frame's start a broadphase (SelfContactBroadphase.h; Bullet's btDbvt in the bridge) lists the (vertex,
/// triangle) pairs within the radius plus a skin: how far each mass may move this frame relative to the surface's
/// mean motion (from its velocity and its last frame's change of velocity). A pair's distance does not change when
/// the whole sheet moves, so a falling sheet needs no more pairs than a resting one. The list is complete while every
/// mass stays within its skin of where it was listed, relative to the mean displacement; a substep that finds one
/// beyond lists the pairs again (rare: the skin is twice the expected motion). After every substep each listed pair
/// is measured (the closest point of the triangle, ClosestPointOnTriangle.h) and a pair closer than the radius gets
/// the response; so does a pair whose vertex passed through the triangle during the substep (a swept test: the
/// vertex crossed the triangle's plane inside the triangle, all four masses moving in straight lines), which a fold
/// fast enough to jump the sheet's thickness in one substep would otherwise leave crossed, and which is pushed back to
/// the side it came from. The response: positions pushed apart to the radius and the approaching normal relative
/// velocity removed (inelastic), with Coulomb friction between sheet and sheet, both shared among the four masses by
/// their barycentric weights and inverse masses so the sheet's momentum is kept. The impulse never exceeds the one that
/// stops the relative motion, so the response takes kinetic energy away and never adds any.
///
/// Pairs are never formed between a vertex and a triangle that contains it or one of whose masses is joined to it by
/// a spring (the springs hold those apart), nor between a vertex and a triangle within twice the radius of it at rest:
/// with a radius above the lattice's spacing (a fine sheet) or its layers' distance (a thin one), the flat sheet
/// would otherwise touch itself everywhere.
///
/// Runs as a StepHook, after the obstacle contact of every substep. With the integrators that take a frame in one
/// solve (`implicit`, `bdf2`, `trbdf2`: FramePlan::oneSolveAFrame), four things change. The pairs are listed by
/// boxes over each mass's motion in the step (swept, SelfContactBroadphase::findSweptPairs), not spheres about it: at
/// the frame's start from where each mass is to where its velocity would carry it, keeping only the pairs the
/// arrivals below may take (findSweptArrivingPairs), after the solve over the motion it made. At the frame's start each
/// surface vertex whose pair the step would carry within the radius at its present velocity, or which rests within a
/// quarter radius of touching (unless the solve had to pull it back last frame: it was leaving), gets a velocity
/// constraint along the pair's normal, so the solve stops it together with the springs behind it (the inelastic outcome
/// of its most urgent pair: the pair's common normal speed, plus its share of closing the gap to the radius). The
/// responses are repeated until none moves a mass (at most 128 passes), and they run both before the obstacle contact
/// (afterImplicitSolve) and after it. Before a frame the pairs are listed and weighed once (solvesFor), and a frame in
/// which some pair would close by more than six lattice spacings in one solve is taken as several, each with its own
/// list and constraints: the 128x2x128 fold's halves, meeting at 2 m/s, otherwise crumple through each other within one
/// step at dt 0.03 and the run diverges. Known limit: the 64x2x64 fold over the rod ends frames up to 7 mm inside the
/// rod.
///
/// Detection runs over ranges of pairs on every thread, each range listing its touches; the responses are
/// applied in one pass in pair order, so the result is the same bit for bit at any thread count. Buffers are sized when
/// the pairs are listed, so a substep that keeps its list allocates nothing.

#include "core/StageObserver.h"
#include "core/StepHook.h"
#include "core/contact/SelfContactBroadphase.h"
#include "core/lattice/Lattice.h"
#include "core/lattice/LatticeSurface.h"
#include "core/parallel/PerChunk.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace masse
{
struct SelfContactSettings
{
    Real radius = 0.01;  ///< m, the sheet's half thickness for contact: the scene's contact radius
    Real friction = 0.3; ///< Coulomb coefficient mu between sheet and sheet
};

/// Throws InputError naming the field (radius, friction) when a value is out of range.
void validate(const SelfContactSettings& settings);

/// What the self-contact did.
struct SelfContactReport
{
    std::size_t pairs = 0;             ///< candidate pairs in the last list
    std::uint64_t queries = 0;         ///< broadphase queries so far (one per frame, more when a mass outruns its skin)
    std::size_t lastSubstep = 0;       ///< pairs closer than the radius at the last substep
    std::size_t lastFrame = 0;         ///< pair touches summed over the last frame's substeps
    std::uint64_t total = 0;           ///< pair touches summed over every substep so far
    Real firstTime = -1;               ///< s, the first touch (negative: none yet)
    Index firstVertex = 0;             ///< the mass of the first touch
    Vec3 firstPosition = Vec3::Zero(); ///< m, where that mass was when it first touched
};

class SelfContact final : public StepHook
{
public:
    /// Which of each mass's exclusions (the triangles it is never tested against: those holding it or a spring
    /// neighbour of it, and those within twice the radius of it at rest) the constructor lists.
    enum class Exclusions
    {
        /// All: a run's self-contact, whose broadphase is asked every frame.
        Listed,
        /// Those of the springs; the ones near at rest are tested pair by pair in pairsWithin, and listed only if a
        /// frame is run. For a self-contact asked once (the webbing report): listing them asks a broadphase over the
        /// whole flat sheet, the test looks at the pairs found (the report at 128x2x128: 0.58 s listing, 0.35 s
        /// testing).
        SpringsOnly
    };

    SelfContact(const Lattice& lattice, SelfContactBroadphase& broadphase, const SelfContactSettings& settings,
                Exclusions exclusions = Exclusions::Listed);

    /// With one solve a frame: lists and weighs the frame's pairs (kept for beginFrame) and asks for the frame to be
    /// split when some pair would close by more than six lattice spacings in one solve.
    int solvesFor(MassSpringSystem& system, Real dt) override;
    StageSet stages() const override { return {StepStage::BeginFrame, StepStage::AfterSolve, StepStage::AfterSubstep}; }
    /// Takes the frame's plan (one solve a frame or substeps) before handing the stage to the functions below.
    void run(StepStage stage, const StageCall& call) override
    {
        listRestExclusions(); // once, for a self-contact made with SpringsOnly that runs frames after all
        m_oneSolveAFrame = call.plan.oneSolveAFrame;
        StepHook::run(stage, call);
    }
    void beginFrame(MassSpringSystem& system, StepContext& context, Real time, Real dt) override;
    void afterSubstep(MassSpringSystem& system, StepContext& context, Real h, Real time) override;
    void afterImplicitSolve(MassSpringSystem& system, StepContext& context, Real h, Real time) override;

    const SelfContactReport& report() const { return m_report; }
    const SelfContactSettings& settings() const { return m_settings; }
    const std::vector<Triangle>& triangles() const { return m_triangles; }
    /// Replaces `out` by the (vertex, triangle) pairs of the surface at positions x that are closer than `distance` and
    /// that the contact would test (not adjacent, not near at rest), in the broadphase's order. It asks the broadphase
    /// afresh, so a run's own SelfContact would list its frame's pairs again afterwards: ask one kept for this.
    void pairsWithin(const std::vector<Vec3>& x, Real distance, std::vector<SelfContactPair>& out);
    /// Sets flags[i] to 1 for every mass of a pair (its vertex and its triangle's three masses) that touched at the
    /// last substep, leaving the others as they are; `flags` holds one entry per mass. For the viewer's colour.
    void markTouchingMasses(std::vector<std::uint8_t>& flags) const;
    /// Told when the broadphase and each substep's solve begin and end (nullptr: nobody).
    void setStageObserver(StageObserver* observer) { m_observer = observer; }

private:
    /// A pair closer than the radius, found by the substep's detection.
    struct Touch
    {
        std::uint32_t pair; ///< into m_pairs
        Vec3 weights;       ///< barycentric weights of the triangle's closest point
        /// 0: the vertex is within the radius now, pushed out along the line from the closest point. +1 or -1: it
        /// passed through the triangle during the substep, from the side its face normal (b - a) x (c - a) points to
        /// (+1) or the other (-1), and goes back to that side.
        Real side = 0;
    };
    /// Lists, once, the triangles each vertex is never tested against for its springs: those holding it or a spring
    /// neighbour of it.
    void listSpringExclusions(const SpringAdjacency& springsAt);
    /// Adds, once, to each vertex's exclusions the triangles within twice the radius of it at rest (nearAtRest).
    void listRestExclusions();
    /// Whether triangle k is within twice the radius of vertex v at rest: with a radius above the lattice's spacing (a
    /// fine sheet) or its layers' distance (a thin one), the flat sheet itself would be in contact with itself
    /// everywhere.
    bool nearAtRest(Index v, Index k) const;
    /// With one solve a frame: lists the pairs that may meet during a step of dt (swept boxes).
    void listSweptPairs(const Particles& p, Real dt);
    /// Whether solvesFor listed the pairs for this state and step (nothing has moved a mass since).
    bool preparedFor(const Particles& p, Real dt) const;
    /// For an integrator that takes the frame in one solve: weighs every listed pair (weighArrival) and returns how
    /// far the fastest closing pair that the step of length dt would carry within the radius closes in it.
    Real weighArrivals(const Particles& p, Real dt);
    /// Makes the pair its vertex's most urgent (m_arrival) if the step of length test.dt would carry the vertex deeper
    /// within the radius through it than through the most urgent so far, or if it rests within a quarter radius of
    /// that; returns how far the pair closes in the step if it comes within the radius, else 0.
    Real weighArrival(const Particles& p, const ArrivalTest& test, const SelfContactPair& pair);
    /// Which pairs the arrivals of a step of length dt may take, at the masses' present velocities.
    ArrivalTest arrivalTest(const Particles& p, Real dt) const;
    /// Gives each surface vertex with an arrival a normal velocity constraint, unless the obstacle contact holds it
    /// (its constraint is already in `constraints`) or it is pinned.
    void constrainArrivals(const Particles& p, std::vector<VelocityConstraint>& constraints);
    /// Asks the broadphase for the pairs within reach of the masses' skins now.
    void listPairs(const std::vector<Vec3>& x);
    /// After a list: where the masses were (x), and the detection's buffers sized for it.
    void pairsListed(const std::vector<Vec3>& x);
    /// Whether some mass has moved farther than its skin, relative to the surface's mean displacement, since the
    /// pairs were listed (the list may then miss a pair).
    bool outgrewPairs(const std::vector<Vec3>& x) const;
    /// Each triangle's box at positions x, into m_triangleLow and m_triangleHigh, and with `withMotion` the box of its
    /// masses' moves since m_substepStart, into m_triangleMotionLow and m_triangleMotionHigh.
    void measureTriangleBoxes(const std::vector<Vec3>& x, bool withMotion);
    struct Passed
    {
        std::size_t touches = 0; ///< pairs found closer than the radius (or passed through)
        std::size_t moved = 0;   ///< of those, the ones whose response moved the masses
    };
    /// Measures the listed pairs at the current positions (the triangles' boxes measured for them) and responds to
    /// those that touch, in pair order; with `measured`, only the pairs of those masses. Every mass of a touching pair
    /// goes into m_moved, and into m_pushed if its response moved the pair beyond the settling bound, else into
    /// m_waiting.
    Passed detectAndRespond(Particles& p, Real h, Real time, const std::vector<Index>* measured);
    /// detectAndRespond again and again until no response moves a mass (at most selfResponsePasses); returns the
    /// first pass's touches. The first pass measures every pair (with `firstOnlyMoved`, only those of the masses
    /// m_moved holds); a pass after a response moved a pair measures the pairs of the masses it moved (m_pushed);
    /// one after a pass that moved nothing measures the pairs of every mass changed since its pairs were last
    /// measured (m_waiting), and when that one moves nothing either the passes end. A pair none of whose masses
    /// changed since it was last measured would be found as it was, not touching.
    std::size_t respondUntilSettled(Particles& p, Real h, Real time, bool firstOnlyMoved);
    /// Lists, once, the surface triangles each of the n masses belongs to (m_trianglesOfStart, m_trianglesOf).
    void listTrianglesOfMasses(std::size_t n);
    /// Lists, for the present pairs, each mass's own (a run of the list) and each triangle's (m_pairsOfTriangle).
    void indexPairs();
    /// Marks in m_pairMarks every pair of one of the masses, as its vertex or one of its triangle's masses.
    void markPairsOf(const std::vector<Index>& masses);
    /// Triangle k's box at positions x, and with `withMotion` the box of its masses' moves (measureTriangleBoxes).
    void measureTriangle(const std::vector<Vec3>& x, std::size_t k, bool withMotion);
    /// Measures pair k at positions x and appends it to `out` if it touches.
    void detectPair(const std::vector<Vec3>& x, std::size_t k, std::vector<Touch>& out) const;
    /// The swept test of pair k over the substep from m_substepStart to x: whether the vertex crossed the triangle's
    /// plane inside the triangle, as all four masses moved in straight lines.
    bool crossed(const std::vector<Vec3>& x, std::size_t k, Touch& touch) const;
    struct Responded
    {
        /// It pushed the pair apart, or stopped its approach, by more than the settling bound (a thousandth of the
        /// radius): not when an earlier pass has already put the pair a radius apart and parting, nor when all four
        /// are pinned. The passes go on while a response does.
        bool moved = false;
        /// It changed a mass's position by more than the settling bound (the push or the friction's slide).
        bool displaced = false;
    };
    Responded respond(Particles& p, const Touch& touch, Real h) const;

    SelfContactBroadphase& m_broadphase;
    SelfContactSettings m_settings;
    std::vector<Triangle> m_triangles;
    std::vector<Index> m_vertices;    ///< the surface's masses, increasing
    SelfContactExclusions m_excluded; ///< per mass, the triangles it is never tested against
    bool m_restExcluded = false;      ///< m_excluded holds the exclusions near at rest too (listRestExclusions)
    std::vector<Real> m_skin;         ///< per mass, m: how far it may move before the pairs are listed again
    std::vector<Vec3> m_listedAt;     ///< per mass, where it was when the pairs were listed
    std::vector<Vec3> m_restPosition; ///< the lattice's
    Real m_spacing = 0;               ///< m, the lattice's smaller spacing (its columns' or its rows')
    std::vector<Vec3> m_triangleLow;  ///< per triangle, its box at this substep
    std::vector<Vec3> m_triangleHigh;
    std::vector<Vec3> m_lastVelocity;      ///< per mass, its velocity at the last frame's start
    std::vector<Vec3> m_substepStart;      ///< per mass, its position when the current substep began
    std::vector<Vec3> m_sweptEnd;          ///< per surface mass, where one solve a frame would carry it unhindered
    std::vector<Vec3> m_triangleMotionLow; ///< per triangle, the box of its masses' moves this substep
    std::vector<Vec3> m_triangleMotionHigh;
    std::vector<SelfContactPair> m_pairs; ///< this frame's pairs
    /// What solvesFor listed the pairs for, so beginFrame keeps them if nothing has moved since.
    bool m_prepared = false;
    Real m_preparedDt = 0;
    std::vector<Vec3> m_preparedPosition;
    std::vector<Vec3> m_preparedVelocity;
    std::vector<Real> m_rangeClosing; ///< per range of pairs, the fastest closing (solvesFor)
    /// Per mass, the pair that constrains it this frame (constrainArrivals).
    struct Arrival
    {
        bool held = false;             ///< by the obstacle contact's constraint
        Vec3 heldAlong = Vec3::Zero(); ///< that constraint's normal, if it holds one direction
        Real endGap = 0;               ///< m, below 0: how far within the radius the step would carry it
        Vec3 normal = Vec3::Zero();
        Real speed = 0; ///< m/s, the normal speed it is given
    };
    std::vector<Arrival> m_arrival;
    /// This frame's constraints: (mass, index into StepContext::constraints), in the order added.
    std::vector<std::pair<Index, std::size_t>> m_constraints;
    /// Per mass, whether its constraint of the last frame pulled it towards the triangle (it was leaving): a resting
    /// pair of such a mass is not held this frame, only one that would come within the radius.
    std::vector<std::uint8_t> m_leaving;
    PerChunk<std::vector<Touch>> m_touches; ///< per range of pairs, sized at the frame's start
    /// Some of the masses: a flag per mass and the flagged ones in the order added (a mass whose flag was lowered
    /// by hand may stay listed, and may be listed twice once added again: clear() takes care of both).
    struct MassSet
    {
        std::vector<std::uint8_t> has;
        std::vector<Index> masses;

        void add(Index i)
        {
            if (!has[i])
            {
                has[i] = 1;
                masses.push_back(i);
            }
        }
        void clear()
        {
            for (const Index i : masses)
            {
                has[i] = 0;
            }
            masses.clear();
        }
        /// Appends the flagged masses to `out`, each once, and empties the set.
        void moveInto(std::vector<Index>& out)
        {
            for (const Index i : masses)
            {
                if (has[i])
                {
                    has[i] = 0;
                    out.push_back(i);
                }
            }
            masses.clear();
        }
    };
    /// A response of the last pass was given a pair of it (it may have changed); once the passes end, also every mass
    /// still in m_waiting.
    MassSet m_moved;
    MassSet m_pushed;  ///< a response of the last pass moved a pair of it beyond the settling bound
    MassSet m_waiting; ///< a response changed it by less than that, and its pairs have not been measured since
    std::vector<Index> m_measuring; ///< the masses whose pairs the next pass measures
    /// Per mass, its own pairs are m_pairs[start[i], start[i + 1]); per triangle, its pairs are listed in
    /// m_pairsOfTriangle[start[t], start[t + 1]), increasing. Built for a list when a pass first needs them.
    std::vector<std::size_t> m_pairsOfVertexStart;
    std::vector<std::size_t> m_pairsOfTriangleStart;
    std::vector<std::uint32_t> m_pairsOfTriangle;
    std::vector<std::size_t> m_pairsFilled; ///< indexPairs' scratch
    bool m_pairsIndexed = false;
    std::vector<std::uint64_t> m_pairMarks;      ///< one bit per pair: to be measured in this pass (all clear between)
    std::vector<std::size_t> m_trianglesOfStart; ///< mass i's triangles are m_trianglesOf[start[i], start[i + 1])
    std::vector<Index> m_trianglesOf;
    /// afterImplicitSolve's passes have measured every pair since its masses last moved, but for m_moved's.
    bool m_settledAfterSolve = false;
    SelfContactReport m_report;
    StageObserver* m_observer = nullptr;
    /// Whether the integrator takes the frame in one solve (FramePlan::oneSolveAFrame), as the last stage was told.
    bool m_oneSolveAFrame = false;
};
} // namespace masse
