#include "core/integrate/ImplicitSolve.h"

#include "core/InputError.h"
#include "core/forces/Forces.h"
#include "core/forces/SpringForce.h"
#include "core/lattice/SpringAdjacency.h"
#include "core/linear/NestedDissection.h"
#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace masse
{
namespace
{
/// Springs per chunk of the assembly's spring pass: about a megabyte of terms.
constexpr std::size_t springChunkSize = 8192;
/// Constrained masses, and springs with a constrained end, per chunk of the filter's passes (applyConstraints): each
/// item reads and writes a few blocks scattered over the matrix, some hundred nanoseconds, so a thousand is worth
/// waking a thread for, and the few thousand a 64x2x64 sheet has on the mould make several chunks.
constexpr std::size_t constrainedChunkSize = 1024;
/// The smallest allowance of an old factor's try that the conjugate gradient's foresight watches (see runSolver).
constexpr int foresightFrom = 64;
} // namespace

IntegratorStats ImplicitSolve::solve(MassSpringSystem& system, std::vector<VelocityConstraint>& constraints, Real a,
                                     const std::vector<Vec3>& offset, const std::vector<Vec3>& momentum,
                                     HeldPlacement held)
{
    const std::size_t n = system.particles.size();
    if (m_patternSystem != &system || m_patternMasses != n || m_patternSprings != system.springs.size())
    {
        const StageScope analysis(m_observer, Stage::SolverAnalysis);
        buildPattern(system);
    }
    for (VelocityConstraint& c : constraints)
    {
        c.engaged = false;
        c.released = false;
    }
    IntegratorStats stats;
    const Real driving = drivingImpulse(system, a); // the same for every round: masses and loads do not change
    for (int round = 1;; ++round)
    {
        const std::vector<Vec3>& roundOffset = heldOffset(system.particles, constraints, a, offset, held);
        bool constrained = false;
        {
            const StageScope assembly(m_observer, Stage::SolverAssembly);
            assemble(system, a, roundOffset, momentum);
            constrained = applyConstraints(system, constraints, a);
            markIdentityMasses(system.particles);
        }
        const Real rhs = m_rhs.norm();
        const Real scale = residualScale(rhs, driving);
        m_tolerance = rhs > 0
                          ? std::max(m_settings.tolerance * scale / rhs, Real(4) * std::numeric_limits<Real>::epsilon())
                          : m_settings.tolerance;
        IntegratorStats roundStats = runSolver();
        if (scale > 0) // reported over the scale the tolerance applies to (the conjugate gradient's is over |b|)
        {
            roundStats.solverResidual *= rhs / scale;
        }
        stats.add(roundStats);
        if (constrained)
        {
            for (std::size_t k = 0; k < m_constrainedMasses.size(); ++k)
            {
                m_deltaV.segment<3>(Eigen::Index(3 * m_constrainedMasses[k])) += m_prescribed[k];
            }
            writeReactions(system, constraints);
        }
        if (round == maxSpeculativeRounds)
        {
            return stats;
        }
        const bool capped = m_coulombCap && constrained && capFriction(system, constraints, a);
        const bool arrivals = m_speculative && updateSpeculative(system, constraints, a, roundOffset);
        const bool lifted = m_releaseLifting && constrained && releaseLifting(constraints);
        if (!capped && !arrivals && !lifted)
        {
            return stats;
        }
    }
}

const std::vector<Vec3>& ImplicitSolve::heldOffset(const Particles& p,
                                                   const std::vector<VelocityConstraint>& constraints, Real a,
                                                   const std::vector<Vec3>& offset, HeldPlacement held)
{
    if (held.step <= 0 || offset.empty() || constraints.empty())
    {
        return offset;
    }
    m_heldOffset.resize(offset.size());
    std::copy(offset.begin(), offset.end(), m_heldOffset.begin());
    const bool fromStart = held.fromStart && !held.fromStart->empty();
    for (const VelocityConstraint& c : constraints)
    {
        if (!c.honoured() || c.mass >= p.size() || p.pinned[c.mass])
        {
            continue;
        }
        const Vec3 start = fromStart ? (*held.fromStart)[c.mass] : Vec3(Vec3::Zero());
        const Vec3 wanted = start + (held.step - a) * c.velocity;
        Vec3& d = m_heldOffset[c.mass];
        if (c.directions >= 3)
        {
            d = wanted;
        }
        else
        {
            d += c.normal * c.normal.dot(wanted - d);
        }
    }
    return m_heldOffset;
}

bool ImplicitSolve::updateSpeculative(const MassSpringSystem& system, std::vector<VelocityConstraint>& constraints,
                                      Real a, const std::vector<Vec3>& offset)
{
    const Particles& p = system.particles;
    bool changed = false;
    for (VelocityConstraint& c : constraints)
    {
        if (!c.speculative || c.released || c.mass >= p.size() || p.pinned[c.mass])
        {
            continue;
        }
        if (c.engaged)
        {
            // Stopped short of the surface by the masses it is joined to (the upper layer of a sheet whose lower
            // layer lands): the surface would have to pull it there.
            if (c.reaction.dot(c.normal) < 0)
            {
                c.engaged = false;
                c.released = true;
                c.reaction.setZero();
                changed = true;
            }
            continue;
        }
        Vec3 move = a * (p.velocity[c.mass] + deltaV(c.mass));
        if (!offset.empty())
        {
            move += offset[c.mass];
        }
        if (c.gap + c.normal.dot(move) < 0)
        {
            c.engaged = true;
            changed = true;
        }
    }
    return changed;
}

bool ImplicitSolve::releaseLifting(std::vector<VelocityConstraint>& constraints)
{
    bool changed = false;
    for (VelocityConstraint& c : constraints)
    {
        if (c.speculative || c.directions != 1 || !c.honoured() || c.reaction.dot(c.normal) >= 0)
        {
            continue;
        }
        c.released = true;
        c.reaction.setZero();
        changed = true;
    }
    return changed;
}

bool ImplicitSolve::capFriction(const MassSpringSystem& system, std::vector<VelocityConstraint>& constraints, Real a)
{
    const Particles& p = system.particles;
    bool changed = false;
    for (VelocityConstraint& c : constraints)
    {
        if (c.directions != 1 || !c.honoured() || c.tangentialDamping <= 0 || c.friction <= 0 || c.mass >= p.size() ||
            p.pinned[c.mass])
        {
            continue;
        }
        const Vec3 relative = p.velocity[c.mass] + deltaV(c.mass) - c.velocity;
        const Real slip = (relative - relative.dot(c.normal) * c.normal).norm();
        const Real limit = c.friction * std::max(Real(0), c.reaction.dot(c.normal));
        if (a * c.tangentialDamping * slip > limit * (Real(1) + Real(1e-6)))
        {
            c.tangentialDamping = limit / (a * slip);
            changed = true;
        }
    }
    return changed;
}

Real ImplicitSolve::largestDeltaV() const
{
    Real largest = 0;
    for (Eigen::Index i = 0; i + 2 < m_deltaV.size(); i += 3)
    {
        largest = std::max(largest, m_deltaV.segment<3>(i).norm());
    }
    return largest;
}

Real ImplicitSolve::drivingImpulse(const MassSpringSystem& system, Real a)
{
    const Real gravity = std::max(system.forces.gravity.norm(), standardGravity);
    Real massSquares = 0;
    for (Real m : system.particles.mass)
    {
        massSquares += m * m;
    }
    Real loadSquares = 0;
    for (const Vec3& f : system.particles.externalForce)
    {
        loadSquares += f.squaredNorm();
    }
    return std::max(a * gravity * std::sqrt(massSquares), a * std::sqrt(loadSquares));
}

Real ImplicitSolve::residualScale(Real rhs, Real drivingImpulse)
{
    // The conjugate gradient stops at |r| <= tol |b|. Its residual is held instead to tol times a scale set by the
    // impulse D of the loads that drive the sheet over the step: its weight, a |g| sqrt(sum m_i^2), or the loads
    // applied to it (a forming pressure, forces set by a program), a sqrt(sum |f_i|^2), whichever is larger.
    // - Where |b| is larger than D (stiff material springs whose forces nearly cancel in the sheet's slow motion), a
    //   residual of tol |b| leaves an error in that motion larger than gravity's own impulse: energy appears, b grows
    //   with it, and so does the error allowed (a cold PET sheet over a pyramid reaches 149 m/s). The scale is D. A
    //   vacuum of 80 kPa on a 2 mm sheet is some 4000 times its weight, and held to the load the cup's thinnest wall
    //   is the one held to its weight gives, to seven digits.
    // - Where |b| is smaller the sheet is near its equilibrium, and the scale is |b|, down to a hundredth of D. The
    //   floor keeps such a sheet from being balanced far below its weight at every step: the drape-forming sheet under
    //   its heater has |b| at 4e-8 of D, and with the floor its thinnest wall at 128x2x128 is the same to nine digits.
    //   Above the floor the scale stays |b|: near equilibrium a residual of tol D is large enough to decide a buckling
    //   (the heated band of ThermoplasticSheet.HeaterSoftensTheSideItWarms bulges up with it, not down).
    return std::max(std::min(rhs, drivingImpulse), equilibriumFloor * drivingImpulse);
}

IntegratorStats ImplicitSolve::runSolver()
{
    const int cap = m_settings.maxIterations;
    SolveResult result;
    int refactorisations = 0;
    // The stages a profiler sees (StageObserver.h): the preconditioner's refreshes and following, and the iterations.
    const auto refresh = [&](auto& preconditioner)
    {
        const StageScope stage(m_observer, Stage::SolverPreconditioner);
        return preconditioner.refresh(m_matrix.matrix());
    };
    const auto iterate = [&](const Preconditioner& preconditioner, int maxIterations, bool foresee = false)
    {
        const StageScope stage(m_observer, Stage::SolverIterations);
        return m_cg.solve(m_matrix.matrix(), m_rhs, m_deltaV, preconditioner, m_tolerance, maxIterations, foresee);
    };
    if (m_settings.preconditioner == PreconditionerKind::Jacobi)
    {
        refresh(m_jacobi);
        result = iterate(m_jacobi, cap);
    }
    else
    {
        // Build the preconditioner only when the old one has drifted: first try it for a few iterations, and rebuild
        // it from the current matrix (then finish) only if that was not enough.
        const bool multigrid = m_settings.preconditioner == PreconditionerKind::Multigrid;
        RefreshedPreconditioner& recent = multigrid ? static_cast<RefreshedPreconditioner&>(m_multigrid) : m_cholesky;
        recent.setFilter(m_constrainedMasses, m_filters);
        bool fresh = false;
        if (!recent.ready())
        {
            ++refactorisations;
            fresh = refresh(recent);
        }
        if (!fresh && !multigrid)
        {
            const StageScope stage(m_observer, Stage::SolverPreconditioner);
            m_cholesky.followDiagonal(m_matrix.matrix()); // see CholeskyPreconditioner.h
        }
        // A factor fresh from the matrix solves in one or two iterations, and is kept while the iterations it takes
        // beyond that, summed since it was made, cost less than a refactorisation (RefreshBudget). A multigrid cycle
        // takes several even when fresh (ten on a cold material sheet at its tight tolerance): it is rebuilt when a
        // solve needs more than its allowance beyond what it took fresh. The try with an old factor stops as soon as
        // its rate foretells that it will not finish within the allowance (ConjugateGradient's `foresee`): in the
        // plug-assist cup's stroke, where the friction under the plug changes the matrix every frame, a factor one
        // frame old would take its whole allowance of some 75 iterations before each refresh, a fresh one 2 or 3.
        const int allowance =
            multigrid ? std::max(m_settings.multigridRefreshAfterIterations,
                                 m_refreshBudget.freshIterations() + m_settings.multigridRefreshAfterIterations / 2)
                      : std::min(m_refreshBudget.allowance(), cap / 2); // room left to finish after a refresh
        const int firstTry = fresh ? cap : std::min(cap, allowance);
        if (recent.ready())
        {
            result = iterate(recent, firstTry, !fresh && !multigrid && firstTry >= foresightFrom);
            if (fresh)
            {
                m_refreshBudget.refreshed(result.iterations);
            }
            else
            {
                m_refreshBudget.used(result.iterations);
            }
        }
        const bool drifted = !result.converged && result.iterations < cap && !fresh;
        if (drifted)
        {
            ++refactorisations;
        }
        if (drifted && refresh(recent))
        {
            const int used = result.iterations;
            result = iterate(recent, cap - used);
            m_refreshBudget.refreshed(result.iterations);
            result.iterations += used;
        }
        if (!recent.ready()) // not positive definite to the factorisation: fall back to the diagonal
        {
            const int used = result.iterations;
            refresh(m_jacobi);
            result = iterate(m_jacobi, cap - used);
            result.iterations += used;
        }
    }
    IntegratorStats stats;
    stats.solverIterations = result.iterations;
    stats.solverResidual = result.residual;
    stats.hitIterationCap = !result.converged;
    stats.refactorisations = refactorisations;
    return stats;
}

void ImplicitSolve::buildPattern(const MassSpringSystem& system)
{
    const std::size_t n = system.massCount();
    const SpringSet& springs = system.springs;
    if (n > SlotMatrix<3>::maxMasses())
    {
        throw InputError("the sheet's " + std::to_string(n) +
                         " masses are too many for the implicit solver's sparse matrix (at most " +
                         std::to_string(SlotMatrix<3>::maxMasses()) + "); use an explicit integrator");
    }
    m_matrix.build(n, springs.ends());
    // A spring's two off-diagonal blocks are shared with any other spring joining the same two masses; the block
    // above the diagonal names the pair. Per spring, how it writes them: the first of the springs joining two masses
    // writes them, the later ones add to them, so the first's blocks hold them all (None: a spring from a mass to
    // itself). The gathers read it through m_columnEntries.
    std::vector<OffDiagonal> offDiagonal(springs.size(), OffDiagonal::None);
    m_sharedBlocks = false;
    std::vector<bool> pairSeen(std::size_t(m_matrix.matrix().nonZeros()), false);
    for (std::size_t s = 0; s < springs.size(); ++s)
    {
        const SpringEnds& e = springs.ends()[s];
        if (e.a == e.b)
        {
            m_sharedBlocks = true; // its two blocks are one, its mass's own
            continue;
        }
        const std::size_t upper = std::size_t(e.a < e.b ? m_matrix.ab(s)[0] : m_matrix.ba(s)[0]);
        offDiagonal[s] = pairSeen[upper] ? OffDiagonal::Later : OffDiagonal::First;
        m_sharedBlocks = m_sharedBlocks || pairSeen[upper];
        pairSeen[upper] = true;
    }
    const SpringAdjacency& adjacency = springs.adjacency(n);
    const auto* outer = m_matrix.matrix().outerIndexPtr();
    m_columnEntries.resize(adjacency.entries.size());
    for (std::size_t i = 0; i < n; ++i)
    {
        for (std::size_t e = adjacency.offsets[i]; e < adjacency.offsets[i + 1]; ++e)
        {
            const std::size_t s = std::size_t(adjacency.entries[e].spring);
            const bool first = Index(i) == springs.ends()[s].a;
            const SlotMatrix<3>::Slots& column = first ? m_matrix.ba(s) : m_matrix.ab(s);
            const auto offset = column[0] - outer[3 * i];
            if (column[1] - outer[3 * i + 1] != offset || column[2] - outer[3 * i + 2] != offset)
            {
                throw std::logic_error("ImplicitSolve: a block column whose three columns differ in pattern");
            }
            m_columnEntries[e] = {offset, offDiagonal[s], first};
        }
    }
    // Each mass's three columns hold the same blocks: the conjugate gradient's product may take them as threes.
    m_cg.setMassRows(rowsComeInThrees(m_matrix.matrix()));
    m_identityMasses.assign(n, 0);
    m_cg.setIdentityMasses(&m_identityMasses);
    const Eigen::Index size = m_matrix.matrix().rows();
    m_rhs.setZero(size);
    m_deltaV.setZero(size);
    // No mass or spring is constrained in the new pattern: the lists the next round resets from are emptied with it
    // (a pattern for fewer masses or springs would otherwise be reset at indices it no longer has).
    m_constraintOf.assign(n, -1);
    m_constrainedMasses.clear();
    m_constrainedSpringOf.assign(springs.size(), -1);
    m_constrainedSprings.clear();
    if (m_settings.preconditioner == PreconditionerKind::Cholesky)
    {
        m_cholesky.analyse(m_matrix.matrix(),
                           nestedDissection(system.particles.position, springs, CholeskyPreconditioner::parallelDepth));
        m_refreshBudget = RefreshBudget(int(std::lround(m_cholesky.refreshCost())), m_settings.refreshAfterIterations);
    }
    else if (m_settings.preconditioner == PreconditionerKind::Multigrid)
    {
        m_multigrid.analyse(m_matrix.matrix(), springs, n);
    }
    m_patternSystem = &system;
    m_patternMasses = n;
    m_patternSprings = springs.size();
}

void ImplicitSolve::markIdentityMasses(const Particles& p)
{
    // A pinned mass's rows are assembled as the identity's, and a mass held in every direction (S = 0) has the
    // identity's rows in S A S + I - S, the filter's zeros times its blocks.
    for (std::size_t i = 0; i < m_identityMasses.size(); ++i)
    {
        m_identityMasses[i] = p.pinned[i] ? 1 : 0;
    }
    for (std::size_t k = 0; k < m_constrainedMasses.size(); ++k)
    {
        if (m_heldEverywhere[k])
        {
            m_identityMasses[std::size_t(m_constrainedMasses[k])] = 1;
        }
    }
}

/// r = A dv - b on the original rows of each constrained mass: the impulse its constraints applied.
void ImplicitSolve::writeReactions(const MassSpringSystem& system, std::vector<VelocityConstraint>& constraints)
{
    // Each constrained mass gathers its row of A dv - b, on the pool: its own block's term first, then its springs' in
    // increasing spring order (the adjacency's), the order of a scatter spring by spring.
    const SpringAdjacency& adjacency = system.springs.adjacency(system.particles.size());
    m_reaction.resize(m_constrainedMasses.size());
    parallelFor(m_constrainedMasses.size(), constrainedChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t k = begin; k < end; ++k)
                    {
                        const Index i = m_constrainedMasses[k];
                        Vec3 reaction = m_rowDiagonal[k] * deltaV(i) - m_rowRhs[k];
                        for (std::size_t e = adjacency.offsets[i]; e < adjacency.offsets[i + 1]; ++e)
                        {
                            if (m_columnEntries[e].kind != OffDiagonal::First)
                            {
                                continue; // a pair's block once, at its first spring (it holds the others' too)
                            }
                            const std::size_t j = std::size_t(m_constrainedSpringOf[adjacency.entries[e].spring]);
                            const bool first = m_columnEntries[e].first;
                            reaction +=
                                m_constrainedBlocks[first ? 2 * j : 2 * j + 1] * deltaV(adjacency.entries[e].other);
                        }
                        m_reaction[k] = reaction;
                    }
                });
    for (VelocityConstraint& c : constraints)
    {
        c.reaction = c.honoured() && c.mass < m_constraintOf.size() && m_constraintOf[c.mass] >= 0
                         ? m_reaction[std::size_t(m_constraintOf[c.mass])]
                         : Vec3::Zero();
    }
    splitSharedReactions(constraints);
}

void ImplicitSolve::splitSharedReactions(std::vector<VelocityConstraint>& constraints)
{
    // A mass under two constraints, each along its own normal (an obstacle's and the self-contact's), has one
    // reaction R in the span of the two: each takes its part r_i n_i of R = r_1 n_1 + r_2 n_2, so that the obstacle
    // reads its own press and the self-contact its own push. The first of a mass's constraints is remembered in
    // m_firstConstraint.
    if (!m_sharedMass)
    {
        return;
    }
    m_firstConstraint.assign(m_constrainedMasses.size(), -1);
    for (std::size_t j = 0; j < constraints.size(); ++j)
    {
        const VelocityConstraint& c = constraints[j];
        if (!c.honoured() || c.mass >= m_constraintOf.size() || m_constraintOf[c.mass] < 0)
        {
            continue;
        }
        const std::size_t k = std::size_t(m_constraintOf[c.mass]);
        if (m_bases[k].constraints < 2)
        {
            continue;
        }
        if (m_firstConstraint[k] < 0)
        {
            m_firstConstraint[k] = int(j);
            continue;
        }
        VelocityConstraint& first = constraints[std::size_t(m_firstConstraint[k])];
        VelocityConstraint& second = constraints[j];
        if (first.directions != 1 || second.directions != 1)
        {
            // A mass held in every direction: the reaction is the hold's (the self-contact adds none to such a mass).
            (first.directions != 1 ? second : first).reaction = Vec3::Zero();
            continue;
        }
        const Vec3& n1 = first.normal;
        const Vec3& n2 = second.normal;
        const Vec3 r = m_reaction[k];
        const Real c12 = n1.dot(n2);
        const Real determinant = 1 - c12 * c12;
        if (!(determinant > 1e-6))
        {
            second.reaction = Vec3::Zero(); // parallel: the first holds the direction alone
            continue;
        }
        const Real a1 = n1.dot(r);
        const Real a2 = n2.dot(r);
        first.reaction = ((a1 - c12 * a2) / determinant) * n1;
        second.reaction = ((a2 - c12 * a1) / determinant) * n2;
    }
}

/// Applies the filter for the velocity constraints; returns false when there are none.
bool ImplicitSolve::applyConstraints(const MassSpringSystem& system, const std::vector<VelocityConstraint>& constraints,
                                     Real a)
{
    const Particles& p = system.particles;
    for (Index i : m_constrainedMasses) // reset only what the last step set
    {
        m_constraintOf[i] = -1;
    }
    for (const ConstrainedSpring& spring : m_constrainedSprings)
    {
        m_constrainedSpringOf[spring.spring] = -1;
    }
    m_constrainedMasses.clear();
    m_filters.clear();
    m_prescribed.clear();
    m_bases.clear();
    m_constrainedSprings.clear();
    m_sharedMass = false;
    if (constraints.empty())
    {
        return false;
    }
    for (const VelocityConstraint& c : constraints)
    {
        if (c.mass >= p.size() || p.pinned[c.mass] || !c.honoured())
        {
            continue;
        }
        int& k = m_constraintOf[c.mass];
        if (k < 0)
        {
            k = int(m_constrainedMasses.size());
            m_constrainedMasses.push_back(c.mass);
            m_bases.emplace_back();
            m_prescribed.push_back(c.velocity); // the target velocity for now; turned into a change below
        }
        Basis& basis = m_bases[std::size_t(k)];
        ++basis.constraints;
        m_sharedMass = m_sharedMass || basis.constraints > 1;
        const int candidates = c.directions >= 3 ? 3 : 1;
        for (int j = 0; j < candidates; ++j)
        {
            const Vec3 wanted = c.directions >= 3 ? Vec3(Vec3::Unit(j)) : c.normal;
            Vec3 u = wanted;
            for (int b = 0; b < basis.count; ++b)
            {
                u -= u.dot(basis.direction[std::size_t(b)]) * basis.direction[std::size_t(b)];
            }
            const Real length = u.norm();
            if (length > 1e-6 && basis.count < 3)
            {
                // The speed along the new direction that gives `wanted` its constraint's speed, the directions
                // before it keeping theirs: wanted . d_new = |u|.
                Real speed = c.velocity.dot(wanted);
                for (int b = 0; b < basis.count; ++b)
                {
                    speed -= basis.speed[std::size_t(b)] * basis.direction[std::size_t(b)].dot(wanted);
                }
                basis.speed[std::size_t(basis.count)] = speed / length;
                basis.direction[std::size_t(basis.count++)] = u / length;
            }
        }
    }
    if (m_constrainedMasses.empty())
    {
        return false;
    }
    // Friction as a tangential damping -c (I - n n^T)(v' - u), added like the air drag before the filter.
    for (const VelocityConstraint& c : constraints)
    {
        if (c.tangentialDamping <= 0 || c.mass >= p.size() || p.pinned[c.mass] || !c.honoured())
        {
            continue;
        }
        const Mat3 tangential = Mat3::Identity() - c.normal * c.normal.transpose();
        m_matrix.add(m_matrix.diagonal(c.mass), (a * c.tangentialDamping) * tangential);
        m_rhs.segment<3>(Eigen::Index(3 * c.mass)) -=
            (a * c.tangentialDamping) * (tangential * (p.velocity[c.mass] - c.velocity));
    }
    // Each constrained mass's filter, velocity change and rows before the filter, on the pool: each writes its own.
    const std::size_t constrainedCount = m_constrainedMasses.size();
    m_filters.resize(constrainedCount);
    m_heldEverywhere.resize(constrainedCount);
    m_rowDiagonal.resize(constrainedCount);
    m_rowRhs.resize(constrainedCount);
    parallelFor(constrainedCount, constrainedChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t k = begin; k < end; ++k)
                    {
                        const Basis& basis = m_bases[k];
                        Mat3 held = Mat3::Zero(); // I - S: projection onto the constrained directions
                        for (int b = 0; b < basis.count; ++b)
                        {
                            held += basis.direction[std::size_t(b)] * basis.direction[std::size_t(b)].transpose();
                        }
                        m_filters[k] = Mat3::Identity() - held;
                        m_heldEverywhere[k] = (m_filters[k].array() == 0).all() ? 1 : 0;
                        const Index i = m_constrainedMasses[k];
                        const Vec3& v = p.velocity[i];
                        if (basis.constraints == 1)
                        {
                            // The projection of its one constraint's velocity change: the sum below, in the fewest
                            // roundings.
                            m_prescribed[k] = held * (m_prescribed[k] - v);
                        }
                        else
                        {
                            // Several constraints (an obstacle's and the self-contact's): each direction takes its
                            // own constraint's speed.
                            Vec3 change = Vec3::Zero();
                            for (int b = 0; b < basis.count; ++b)
                            {
                                const Vec3& d = basis.direction[std::size_t(b)];
                                change += (basis.speed[std::size_t(b)] - d.dot(v)) * d;
                            }
                            m_prescribed[k] = change;
                        }
                        m_rowDiagonal[k] = m_matrix.read(m_matrix.diagonal(i));
                        m_rowRhs[k] = m_rhs.segment<3>(Eigen::Index(3 * i));
                    }
                });

    // The springs with a constrained end, and their blocks before the filter, read once on the pool into one array
    // that the right-hand side's terms and the reactions read in sequence (a contact-rich frame constrains half the
    // masses, and the matrix's blocks, read spring by spring, are scattered over its columns).
    const SpringSet& springs = system.springs;
    for (std::size_t s = 0; s < springs.size(); ++s)
    {
        const SpringEnds e = springs.ends()[s];
        if (m_constraintOf[e.a] >= 0 || m_constraintOf[e.b] >= 0)
        {
            m_constrainedSpringOf[s] = int(m_constrainedSprings.size());
            m_constrainedSprings.push_back({std::uint32_t(s), e.a, e.b});
        }
    }
    // Filter: rows and columns of constrained masses, S_a B S_b. A mass held in every direction has a zero filter,
    // and its springs' blocks are zero.
    const auto filterSpring = [&](const ConstrainedSpring& spring, const Mat3& blockAB, const Mat3& blockBA)
    {
        const int ka = m_constraintOf[spring.a];
        const int kb = m_constraintOf[spring.b];
        const SlotMatrix<3>::Slots& ab = m_matrix.ab(spring.spring);
        const SlotMatrix<3>::Slots& ba = m_matrix.ba(spring.spring);
        if ((ka >= 0 && m_heldEverywhere[std::size_t(ka)]) || (kb >= 0 && m_heldEverywhere[std::size_t(kb)]))
        {
            m_matrix.write(ab, Mat3::Zero());
            m_matrix.write(ba, Mat3::Zero());
            return;
        }
        const Mat3 sa = ka >= 0 ? m_filters[std::size_t(ka)] : Mat3(Mat3::Identity());
        const Mat3 sb = kb >= 0 ? m_filters[std::size_t(kb)] : Mat3(Mat3::Identity());
        m_matrix.write(ab, sa * blockAB * sb);
        m_matrix.write(ba, sb * blockBA * sa);
    };
    // Each spring writes its own two blocks, on the pool, as it reads them; springs sharing their blocks are filtered
    // below.
    m_constrainedBlocks.resize(2 * m_constrainedSprings.size());
    parallelFor(m_constrainedSprings.size(), constrainedChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t j = begin; j < end; ++j)
                    {
                        const ConstrainedSpring& spring = m_constrainedSprings[j];
                        m_constrainedBlocks[2 * j] = m_matrix.read(m_matrix.ab(spring.spring));
                        m_constrainedBlocks[2 * j + 1] = m_matrix.read(m_matrix.ba(spring.spring));
                        if (!m_sharedBlocks)
                        {
                            filterSpring(spring, m_constrainedBlocks[2 * j], m_constrainedBlocks[2 * j + 1]);
                        }
                    }
                });

    // b' = b - A c with A before the filter: each mass gathers its row's terms, on the pool, its own block's first
    // (the diagonal blocks are filtered below) and then its springs' in increasing spring order (the adjacency's),
    // the order of a scatter spring by spring.
    const SpringAdjacency& adjacency = springs.adjacency(p.size());
    parallelFor(p.size(), massChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t i = begin; i < end; ++i)
                    {
                        const int own = m_constraintOf[i];
                        Vec3 rhs = m_rhs.segment<3>(Eigen::Index(3 * i));
                        bool changed = false;
                        if (own >= 0)
                        {
                            rhs -= m_matrix.read(m_matrix.diagonal(Index(i))) * m_prescribed[std::size_t(own)];
                            changed = true;
                        }
                        for (std::size_t e = adjacency.offsets[i]; e < adjacency.offsets[i + 1]; ++e)
                        {
                            const int other = m_constraintOf[adjacency.entries[e].other];
                            if (other < 0 || m_columnEntries[e].kind != OffDiagonal::First)
                            {
                                continue; // a pair's block once, at its first spring (it holds the others' too)
                            }
                            const std::size_t j = std::size_t(m_constrainedSpringOf[adjacency.entries[e].spring]);
                            const bool first = m_columnEntries[e].first;
                            rhs -= m_constrainedBlocks[first ? 2 * j : 2 * j + 1] * m_prescribed[std::size_t(other)];
                            changed = true;
                        }
                        if (changed)
                        {
                            m_rhs.segment<3>(Eigen::Index(3 * i)) = rhs;
                        }
                    }
                });
    // Springs sharing their blocks, one after the other, each filtering the block the one before left; after the
    // gather, which reads the diagonal blocks as they were (a spring from a mass to itself has its mass's diagonal
    // block).
    if (m_sharedBlocks)
    {
        for (const ConstrainedSpring& spring : m_constrainedSprings)
        {
            filterSpring(spring, m_matrix.read(m_matrix.ab(spring.spring)), m_matrix.read(m_matrix.ba(spring.spring)));
        }
    }
    parallelFor(constrainedCount, constrainedChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t k = begin; k < end; ++k)
                    {
                        const Index i = m_constrainedMasses[k];
                        const Mat3& filter = m_filters[k];
                        const SlotMatrix<3>::Slots& diagonal = m_matrix.diagonal(i);
                        m_matrix.write(diagonal,
                                       filter * m_matrix.read(diagonal) * filter + (Mat3::Identity() - filter));
                        m_rhs.segment<3>(Eigen::Index(3 * i)) = filter * m_rhs.segment<3>(Eigen::Index(3 * i));
                    }
                });
    return true;
}

void ImplicitSolve::assemble(const MassSpringSystem& system, Real a, const std::vector<Vec3>& offset,
                             const std::vector<Vec3>& momentum)
{
    const Particles& p = system.particles;
    const SpringSet& springs = system.springs;
    const std::size_t n = p.size();
    const Real a2 = a * a;
    const bool hasOffset = !offset.empty();
    const SpringAdjacency& adjacency = springs.adjacency(n); // built here, on one thread, if the springs changed

    // Each spring's block and right-hand side term, once, over spring ranges.
    m_springTerms.resize(springs.size());
    m_springEngaged.resize(springs.size());
    const SimdPath path = activeSimdPath();
    SpringTermInputs inputs;
    inputs.a = a;
    inputs.offset = &offset;
    parallelFor(springs.size(), springChunkSize,
                [&](std::size_t begin, std::size_t end) {
                    computeSpringTerms(path, system, inputs, begin, end, m_springTerms.data(), m_springEngaged.data());
                });

    const auto* outer = m_matrix.matrix().outerIndexPtr();
    // Each mass gathers its row over mass ranges: its springs in increasing index, the order the serial scatter added
    // them in, so the sums have the same bits at any thread count. Each mass is the only writer of its own block column
    // (Eigen's storage is column-major), the diagonal block and one block per spring.
    parallelFor(n, massChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t i = begin; i < end; ++i)
                    {
                        const bool freeI = !p.pinned[i];
                        Mat3 diagonal = Mat3::Zero();
                        Vec3 rhs = a * p.force[i];
                        if (!momentum.empty())
                        {
                            rhs += p.mass[i] * momentum[i];
                        }
                        if (freeI)
                        {
                            diagonal += (p.mass[i] * (Real(1) + a * system.forces.airDamping)) * Mat3::Identity();
                        }
                        // Mass i writes its own block column, so its writes stay in one place in memory.
                        const SlotMatrix<3>::Slots columnTop = {outer[3 * i], outer[3 * i + 1], outer[3 * i + 2]};
                        for (std::size_t e = adjacency.offsets[i]; e < adjacency.offsets[i + 1]; ++e)
                        {
                            const std::size_t s = std::size_t(adjacency.entries[e].spring);
                            const Index other = adjacency.entries[e].other;
                            const ColumnEntry& entry = m_columnEntries[e];
                            const bool engaged = m_springEngaged[s] != 0;
                            const bool couples = engaged && freeI && !p.pinned[other];
                            const SpringTerm& term = m_springTerms[s];
                            const Mat3 block = engaged ? term.block() : Mat3(Mat3::Zero());
                            const SlotMatrix<3>::Slots column = {
                                columnTop[0] + entry.offset, columnTop[1] + entry.offset, columnTop[2] + entry.offset};
                            // 0 - B has the bits of 0 + (-B), the serial scatter's sum, signed zeros included.
                            if (entry.kind == OffDiagonal::First)
                            {
                                m_matrix.write(column, couples ? Mat3(Mat3::Zero() - block) : Mat3(Mat3::Zero()));
                            }
                            else if (entry.kind == OffDiagonal::Later && couples)
                            {
                                m_matrix.add(column, -block);
                            }
                            if (!engaged || !freeI)
                            {
                                continue;
                            }
                            diagonal += block;
                            if (entry.first)
                            {
                                rhs -= term.kv;
                            }
                            else
                            {
                                rhs += term.kv;
                            }
                        }
                        if (!freeI) // an identity row and a zero right-hand side: dv = 0
                        {
                            diagonal += Mat3::Identity();
                            rhs.setZero();
                        }
                        m_matrix.write(m_matrix.diagonal(i), diagonal);
                        m_rhs.segment<3>(Eigen::Index(3 * i)) = rhs;
                    }
                });

    for (const UserSpring& spring : system.userSprings.all())
    {
        const Index i = spring.mass;
        if (p.pinned[i])
        {
            continue;
        }
        const UserSpringForce f = evaluateUserSpring(spring, p.position[i], p.velocity[i]);
        const Real scale = spring.stiffness > 0 ? f.effectiveStiffness / spring.stiffness : Real(1);
        const Real diagonal = a * spring.damping * scale + a2 * f.effectiveStiffness;
        m_matrix.add(m_matrix.diagonal(i), diagonal * Mat3::Identity());
        Vec3 move = a * (p.velocity[i] - spring.targetVelocity);
        if (hasOffset)
        {
            move += offset[i];
        }
        m_rhs.segment<3>(Eigen::Index(3 * i)) -= a * f.effectiveStiffness * move;
    }
}
} // namespace masse
