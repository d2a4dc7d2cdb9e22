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

        m_solver.setTolerance(m_settings.tolerance);
        m_solver.setMaxIterations(m_settings.maxIterations);
        m_solver.compute(m_matrix);
        // The previous step's solution is a good first guess: the motion changes little between steps.
        if (m_deltaV.size() != m_rhs.size())
        {
            m_deltaV.setZero(m_rhs.size());
        }
        m_deltaV = m_solver.solveWithGuess(m_rhs, m_deltaV);

        for (std::size_t i = 0; i < n; ++i)
        {
            p.velocity[i] += m_deltaV.segment<3>(Eigen::Index(3 * i));
            p.position[i] += h * p.velocity[i];
        }
        return {int(m_solver.iterations()), m_solver.error()};
    }

    IntegratorKind kind() const override { return IntegratorKind::ImplicitEuler; }

private:
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
