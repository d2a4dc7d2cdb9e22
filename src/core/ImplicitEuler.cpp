/// Linearised backward Euler (Baraff and Witkin, "Large steps in cloth simulation", 1998).
///
/// One Newton step of v' = v + h M^-1 f(x + h v', v') gives the linear system
///     (M - h D - h^2 K) dv = h (f0 + h K v),   v' = v + dv,   x' = x + h v'
/// with K = df/dx and D = df/dv. For a spring with unit direction n, length l and rest length s,
///     -K_aa = k n n^T + k max(0, 1 - s/l) (I - n n^T) + (2 k_r / l^3) n n^T [compressed only],  -D_aa = k_d n n^T,
/// and K_ab = -K_aa. The transverse term is clamped at zero for compressed springs (Choi and Ko 2002) and the
/// repulsion's transverse term is dropped, so the matrix stays symmetric positive definite and conjugate gradient
/// applies. Pinned masses get identity rows and a zero right-hand side, so dv = 0 there.
///
/// Velocity constraints from contact (see VelocityConstraint.h) are honoured with Baraff and Witkin's filter: with
/// S_i the projection onto a mass's free directions and c the prescribed change in the others, dv = S y + c where
///     (S A S + I - S) y = S (b - A c),
/// which keeps the matrix symmetric positive definite.
///
/// The sparsity pattern is built once per topology; each step only rewrites values, through slots recorded per
/// spring (the index of each 3x3 block's columns in Eigen's value array).

#include "Forces.h"
#include "InputError.h"
#include "Integrator.h"
#include "SpringForce.h"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace masse
{
namespace
{
using SparseMatrix = Eigen::SparseMatrix<Real>;
using StorageIndex = SparseMatrix::StorageIndex;
/// For a 3x3 block: the value-array index of its top entry in each of its three columns (the rows below follow).
using BlockSlots = std::array<StorageIndex, 3>;

class ImplicitEuler final : public Integrator
{
public:
    explicit ImplicitEuler(const ImplicitSettings& settings) : m_settings(settings) {}

    IntegratorStats step(MassSpringSystem& system, Real h) override
    {
        Particles& p = system.particles;
        const std::size_t n = p.size();
        if (m_patternSystem != &system || m_patternMasses != n || m_patternSprings != system.springs.size())
        {
            buildPattern(system);
        }
        evaluateForces(system, p.position, p.velocity, p.force);
        assemble(system, h);
        const bool constrained = applyConstraints(system, h);

        m_solver.setTolerance(solverTolerance(system, h));
        m_solver.setMaxIterations(m_settings.maxIterations);
        m_solver.compute(m_matrix);
        // The previous step's solution is a good first guess: the motion changes little between steps.
        if (m_deltaV.size() != m_rhs.size())
        {
            m_deltaV.setZero(m_rhs.size());
        }
        m_deltaV = m_solver.solveWithGuess(m_rhs, m_deltaV);

        if (constrained)
        {
            for (std::size_t k = 0; k < m_constrainedMasses.size(); ++k)
            {
                m_deltaV.segment<3>(Eigen::Index(3 * m_constrainedMasses[k])) += m_prescribed[k];
            }
            writeReactions(system);
        }
        for (std::size_t i = 0; i < n; ++i)
        {
            p.velocity[i] += m_deltaV.segment<3>(Eigen::Index(3 * i));
            p.position[i] += h * p.velocity[i];
        }
        return {int(m_solver.iterations()), m_solver.error()};
    }

    IntegratorKind kind() const override { return IntegratorKind::ImplicitEuler; }
    bool honoursConstraints() const override { return true; }

private:
    /// Eigen's conjugate gradient stops at |r| <= tol |b|. With stiff material springs b is dominated by spring forces
    /// that nearly cancel in the sheet's slow motion (bending, sliding, falling), so a residual of tol |b| leaves an
    /// error in that motion larger than gravity's own impulse: energy appears, b grows with it, and so does the error
    /// allowed (a cold PET sheet over a pyramid reached 149 m/s). The residual is therefore held to tol times the
    /// smaller of |b| and the impulse of the sheet's weight over the step, h |g| sqrt(sum m_i^2).
    Real solverTolerance(const MassSpringSystem& system, Real h) const
    {
        const Real gravity = std::max(system.forces.gravity.norm(), standardGravity);
        Real massSquares = 0;
        for (Real m : system.particles.mass)
        {
            massSquares += m * m;
        }
        const Real weightImpulse = h * gravity * std::sqrt(massSquares);
        const Real rhs = m_rhs.norm();
        if (!(rhs > weightImpulse))
        {
            return m_settings.tolerance;
        }
        // Eigen refuses a tolerance below machine precision.
        return std::max(m_settings.tolerance * weightImpulse / rhs, Real(4) * std::numeric_limits<Real>::epsilon());
    }

    void buildPattern(const MassSpringSystem& system)
    {
        const std::size_t n = system.massCount();
        const SpringSet& springs = system.springs;
        const Eigen::Index size = Eigen::Index(3 * n);
        if (size > Eigen::Index(std::numeric_limits<StorageIndex>::max() / 4))
        {
            throw InputError("integrator: the sheet is too large for the implicit solver's sparse matrix");
        }
        std::vector<Eigen::Triplet<Real, StorageIndex>> triplets;
        triplets.reserve(9 * (n + 2 * springs.size()));
        auto addBlock = [&](std::size_t row, std::size_t column)
        {
            for (int c = 0; c < 3; ++c)
            {
                for (int r = 0; r < 3; ++r)
                {
                    triplets.emplace_back(StorageIndex(3 * row) + r, StorageIndex(3 * column) + c, Real(0));
                }
            }
        };
        for (std::size_t i = 0; i < n; ++i)
        {
            addBlock(i, i);
        }
        for (const SpringEnds& e : springs.ends)
        {
            addBlock(e.a, e.b);
            addBlock(e.b, e.a);
        }
        m_matrix.resize(size, size);
        m_matrix.setFromTriplets(triplets.begin(), triplets.end());
        m_matrix.makeCompressed();

        m_diagonalSlots.resize(n);
        for (std::size_t i = 0; i < n; ++i)
        {
            m_diagonalSlots[i] = findSlots(i, i);
        }
        m_abSlots.resize(springs.size());
        m_baSlots.resize(springs.size());
        for (std::size_t s = 0; s < springs.size(); ++s)
        {
            m_abSlots[s] = findSlots(springs.ends[s].a, springs.ends[s].b);
            m_baSlots[s] = findSlots(springs.ends[s].b, springs.ends[s].a);
        }
        m_rhs.setZero(size);
        m_deltaV.setZero(size);
        m_patternSystem = &system;
        m_patternMasses = n;
        m_patternSprings = springs.size();
    }

    BlockSlots findSlots(std::size_t row, std::size_t column) const
    {
        BlockSlots slots{};
        const StorageIndex* outer = m_matrix.outerIndexPtr();
        const StorageIndex* inner = m_matrix.innerIndexPtr();
        for (int c = 0; c < 3; ++c)
        {
            const std::size_t col = 3 * column + std::size_t(c);
            const StorageIndex* begin = inner + outer[col];
            const StorageIndex* end = inner + outer[col + 1];
            const StorageIndex* found = std::lower_bound(begin, end, StorageIndex(3 * row));
            slots[std::size_t(c)] = StorageIndex(found - inner);
        }
        return slots;
    }

    /// r = A dv - b on the original rows of each constrained mass: the impulse its constraints applied.
    void writeReactions(MassSpringSystem& system) const
    {
        std::vector<Vec3> reaction(m_constrainedMasses.size());
        for (std::size_t k = 0; k < m_constrainedMasses.size(); ++k)
        {
            const Index i = m_constrainedMasses[k];
            Vec3 r = m_rows[k].diagonal * m_deltaV.segment<3>(Eigen::Index(3 * i)) - m_rows[k].rhs;
            for (const auto& [j, block] : m_rows[k].neighbours)
            {
                r += block * m_deltaV.segment<3>(Eigen::Index(3 * j));
            }
            reaction[k] = r;
        }
        for (VelocityConstraint& c : system.constraints)
        {
            c.reaction = c.mass < m_constraintOf.size() && m_constraintOf[c.mass] >= 0
                             ? reaction[std::size_t(m_constraintOf[c.mass])]
                             : Vec3::Zero();
        }
    }

    Mat3 readBlock(const BlockSlots& slots) const
    {
        const Real* values = m_matrix.valuePtr();
        Mat3 block;
        for (int c = 0; c < 3; ++c)
        {
            const Real* column = values + slots[std::size_t(c)];
            block(0, c) = column[0];
            block(1, c) = column[1];
            block(2, c) = column[2];
        }
        return block;
    }

    void writeBlock(const BlockSlots& slots, const Mat3& block)
    {
        Real* values = m_matrix.valuePtr();
        for (int c = 0; c < 3; ++c)
        {
            Real* column = values + slots[std::size_t(c)];
            column[0] = block(0, c);
            column[1] = block(1, c);
            column[2] = block(2, c);
        }
    }

    /// Applies the filter for the system's velocity constraints; returns false when there are none.
    bool applyConstraints(const MassSpringSystem& system, Real h)
    {
        const Particles& p = system.particles;
        m_constrainedMasses.clear();
        m_filters.clear();
        m_prescribed.clear();
        if (system.constraints.empty())
        {
            return false;
        }
        m_constraintOf.assign(p.size(), -1);
        std::vector<std::vector<Vec3>> directions; // orthonormal constrained directions per constrained mass
        for (const VelocityConstraint& c : system.constraints)
        {
            if (c.mass >= p.size() || p.pinned[c.mass])
            {
                continue;
            }
            int& k = m_constraintOf[c.mass];
            if (k < 0)
            {
                k = int(m_constrainedMasses.size());
                m_constrainedMasses.push_back(c.mass);
                directions.emplace_back();
                m_prescribed.push_back(c.velocity); // the target velocity for now; turned into a change below
            }
            std::vector<Vec3>& basis = directions[std::size_t(k)];
            const std::vector<Vec3> candidates = c.directions >= 3
                                                     ? std::vector<Vec3>{Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()}
                                                     : std::vector<Vec3>{c.normal};
            for (Vec3 u : candidates)
            {
                for (const Vec3& b : basis)
                {
                    u -= u.dot(b) * b;
                }
                if (u.norm() > 1e-6 && basis.size() < 3)
                {
                    basis.push_back(u.normalized());
                }
            }
        }
        if (m_constrainedMasses.empty())
        {
            return false;
        }
        // Friction as a tangential damping -c (I - n n^T)(v' - u), added like the air drag before the filter.
        for (const VelocityConstraint& c : system.constraints)
        {
            if (c.tangentialDamping <= 0 || c.mass >= p.size() || p.pinned[c.mass])
            {
                continue;
            }
            const Mat3 tangential = Mat3::Identity() - c.normal * c.normal.transpose();
            addToBlock(m_diagonalSlots[c.mass], (h * c.tangentialDamping) * tangential);
            m_rhs.segment<3>(Eigen::Index(3 * c.mass)) -=
                (h * c.tangentialDamping) * (tangential * (p.velocity[c.mass] - c.velocity));
        }
        for (std::size_t k = 0; k < m_constrainedMasses.size(); ++k)
        {
            Mat3 held = Mat3::Zero(); // I - S: projection onto the constrained directions
            for (const Vec3& b : directions[k])
            {
                held += b * b.transpose();
            }
            m_filters.push_back(Mat3::Identity() - held);
            m_prescribed[k] = held * (m_prescribed[k] - p.velocity[m_constrainedMasses[k]]);
        }
        auto filterOf = [&](Index i) -> const Mat3*
        { return m_constraintOf[i] < 0 ? nullptr : &m_filters[std::size_t(m_constraintOf[i])]; };
        auto changeOf = [&](Index i) { return m_prescribed[std::size_t(m_constraintOf[i])]; };

        // The constrained rows as they are before filtering, to give each constraint its reaction after the solve.
        m_rows.assign(m_constrainedMasses.size(), OriginalRow{});
        for (std::size_t k = 0; k < m_constrainedMasses.size(); ++k)
        {
            const Index i = m_constrainedMasses[k];
            m_rows[k].diagonal = readBlock(m_diagonalSlots[i]);
            m_rows[k].rhs = m_rhs.segment<3>(Eigen::Index(3 * i));
        }
        for (std::size_t s = 0; s < system.springs.size(); ++s)
        {
            const Index a = system.springs.ends[s].a;
            const Index b = system.springs.ends[s].b;
            if (m_constraintOf[a] >= 0)
            {
                m_rows[std::size_t(m_constraintOf[a])].neighbours.emplace_back(b, readBlock(m_abSlots[s]));
            }
            if (m_constraintOf[b] >= 0)
            {
                m_rows[std::size_t(m_constraintOf[b])].neighbours.emplace_back(a, readBlock(m_baSlots[s]));
            }
        }

        // b' = b - A c, before A is filtered.
        for (std::size_t k = 0; k < m_constrainedMasses.size(); ++k)
        {
            const Index i = m_constrainedMasses[k];
            m_rhs.segment<3>(Eigen::Index(3 * i)) -= readBlock(m_diagonalSlots[i]) * m_prescribed[k];
        }
        const SpringSet& springs = system.springs;
        for (std::size_t s = 0; s < springs.size(); ++s)
        {
            const Index a = springs.ends[s].a;
            const Index b = springs.ends[s].b;
            if (m_constraintOf[b] >= 0)
            {
                m_rhs.segment<3>(Eigen::Index(3 * a)) -= readBlock(m_abSlots[s]) * changeOf(b);
            }
            if (m_constraintOf[a] >= 0)
            {
                m_rhs.segment<3>(Eigen::Index(3 * b)) -= readBlock(m_baSlots[s]) * changeOf(a);
            }
        }
        // Filter: rows and columns of constrained masses.
        for (std::size_t s = 0; s < springs.size(); ++s)
        {
            const Mat3* filterA = filterOf(springs.ends[s].a);
            const Mat3* filterB = filterOf(springs.ends[s].b);
            if (!filterA && !filterB)
            {
                continue;
            }
            const Mat3 sa = filterA ? *filterA : Mat3::Identity();
            const Mat3 sb = filterB ? *filterB : Mat3::Identity();
            writeBlock(m_abSlots[s], sa * readBlock(m_abSlots[s]) * sb);
            writeBlock(m_baSlots[s], sb * readBlock(m_baSlots[s]) * sa);
        }
        for (std::size_t k = 0; k < m_constrainedMasses.size(); ++k)
        {
            const Index i = m_constrainedMasses[k];
            const Mat3& filter = m_filters[k];
            writeBlock(m_diagonalSlots[i],
                       filter * readBlock(m_diagonalSlots[i]) * filter + (Mat3::Identity() - filter));
            m_rhs.segment<3>(Eigen::Index(3 * i)) = filter * m_rhs.segment<3>(Eigen::Index(3 * i));
        }
        return true;
    }

    void addToBlock(const BlockSlots& slots, const Mat3& block)
    {
        Real* values = m_matrix.valuePtr();
        for (int c = 0; c < 3; ++c)
        {
            Real* column = values + slots[std::size_t(c)];
            column[0] += block(0, c);
            column[1] += block(1, c);
            column[2] += block(2, c);
        }
    }

    void assemble(const MassSpringSystem& system, Real h)
    {
        const Particles& p = system.particles;
        const SpringSet& springs = system.springs;
        const std::size_t n = p.size();
        const Real h2 = h * h;
        std::fill(m_matrix.valuePtr(), m_matrix.valuePtr() + m_matrix.nonZeros(), Real(0));

        for (std::size_t i = 0; i < n; ++i)
        {
            m_rhs.segment<3>(Eigen::Index(3 * i)) = h * p.force[i];
            if (!p.pinned[i])
            {
                const Real diagonal = p.mass[i] * (Real(1) + h * system.forces.airDamping);
                addToBlock(m_diagonalSlots[i], diagonal * Mat3::Identity());
            }
        }

        const Real repulsion = system.forces.repulsion;
        for (std::size_t s = 0; s < springs.size(); ++s)
        {
            const Index a = springs.ends[s].a;
            const Index b = springs.ends[s].b;
            const Vec3 d = p.position[a] - p.position[b];
            const Real length = d.norm();
            const Real rest = springs.restLength[s];
            if (length <= degenerateLengthFraction * rest)
            {
                continue;
            }
            const Vec3 dir = d / length;
            const Mat3 nn = dir * dir.transpose();
            const Real k = springs.stiffness[s];
            Real axial = k;
            if (repulsion > 0 && length < rest)
            {
                axial += Real(2) * repulsion / (length * length * length);
            }
            const Real transverse = k * std::max(Real(0), Real(1) - rest / length);
            // -K_aa, the stiffness block of this spring.
            const Mat3 stiffnessBlock = axial * nn + transverse * (Mat3::Identity() - nn);
            const Mat3 block = (h * springs.damping[s]) * nn + h2 * stiffnessBlock;
            const Vec3 kv = h2 * (stiffnessBlock * (p.velocity[a] - p.velocity[b]));

            const bool freeA = !p.pinned[a];
            const bool freeB = !p.pinned[b];
            if (freeA)
            {
                addToBlock(m_diagonalSlots[a], block);
                m_rhs.segment<3>(Eigen::Index(3 * a)) -= kv;
            }
            if (freeB)
            {
                addToBlock(m_diagonalSlots[b], block);
                m_rhs.segment<3>(Eigen::Index(3 * b)) += kv;
            }
            if (freeA && freeB)
            {
                addToBlock(m_abSlots[s], -block);
                addToBlock(m_baSlots[s], -block);
            }
        }

        for (const UserSpring& spring : system.userSprings.all())
        {
            const Index i = spring.mass;
            if (p.pinned[i])
            {
                continue;
            }
            const UserSpringForce f = evaluateUserSpring(spring, p.position[i], p.velocity[i]);
            const Real scale = spring.stiffness > 0 ? f.effectiveStiffness / spring.stiffness : Real(1);
            const Real diagonal = h * spring.damping * scale + h2 * f.effectiveStiffness;
            addToBlock(m_diagonalSlots[i], diagonal * Mat3::Identity());
            m_rhs.segment<3>(Eigen::Index(3 * i)) -=
                h2 * f.effectiveStiffness * (p.velocity[i] - spring.targetVelocity);
        }

        for (std::size_t i = 0; i < n; ++i)
        {
            if (p.pinned[i])
            {
                addToBlock(m_diagonalSlots[i], Mat3::Identity());
                m_rhs.segment<3>(Eigen::Index(3 * i)).setZero();
            }
        }
    }

    ImplicitSettings m_settings;
    SparseMatrix m_matrix;
    std::vector<BlockSlots> m_diagonalSlots;
    std::vector<BlockSlots> m_abSlots;
    std::vector<BlockSlots> m_baSlots;
    Eigen::VectorX<Real> m_rhs;
    Eigen::VectorX<Real> m_deltaV;
    Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper> m_solver;
    struct OriginalRow
    {
        Mat3 diagonal;
        Vec3 rhs;
        std::vector<std::pair<Index, Mat3>> neighbours;
    };
    std::vector<OriginalRow> m_rows; // per constrained mass, before filtering
    // Constraint filter of the current step.
    std::vector<int> m_constraintOf; // per mass: index into the arrays below, or -1
    std::vector<Index> m_constrainedMasses;
    std::vector<Mat3> m_filters;    // S_i
    std::vector<Vec3> m_prescribed; // c_i, the velocity change in the constrained directions
    const MassSpringSystem* m_patternSystem = nullptr;
    std::size_t m_patternMasses = 0;
    std::size_t m_patternSprings = 0;
};
} // namespace

std::unique_ptr<Integrator> makeImplicitEuler(const ImplicitSettings& settings)
{
    return std::make_unique<ImplicitEuler>(settings);
}
} // namespace masse
