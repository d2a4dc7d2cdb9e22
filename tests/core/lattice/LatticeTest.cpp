// Lattice structure tests: the paper's Table 2 counts, derived counts of the other structures, and well-formedness.

#include "core/lattice/Lattice.h"
#include "core/InputError.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <utility>

using namespace masse;

namespace
{
Lattice make(Structure structure, int n, int layers)
{
    LatticeSpec spec;
    spec.structure = structure;
    spec.countX = n;
    spec.countZ = n;
    spec.layers = layers;
    return buildLattice(spec);
}
} // namespace

// Paper Table 2: the TRiMM N x 2 x N sheets of the drop experiment.
TEST(Lattice, TrimmReproducesPaperTable2)
{
    struct Row
    {
        int n;
        std::size_t masses;
        std::size_t springs;
    };
    const Row table2[] = {{3, 13, 33}, {6, 61, 216}, {8, 113, 428}, {9, 145, 561}, {12, 265, 1068}};
    for (const Row& row : table2)
    {
        const Lattice lattice = make(Structure::TRiMM, row.n, 2);
        EXPECT_EQ(lattice.massCount(), row.masses) << row.n << "x2x" << row.n;
        EXPECT_EQ(lattice.springCount(), row.springs) << row.n << "x2x" << row.n;
    }
}

// Counts derived from each layout's description (see SquareLattice.cpp), for N x 2 x N.
TEST(Lattice, SquareFamilyCountsMatchTheirLayouts)
{
    for (int n : {2, 3, 5, 12})
    {
        const std::size_t nn = std::size_t(n);
        const std::size_t m = nn - 1;
        const std::size_t grid = 2 * nn * m;                  // planar edges of the N x N layer
        const std::size_t upperGrid = 2 * m * (m - 1);        // planar edges of the (N-1) x (N-1) layer
        const std::size_t cross = 4 * m * m;                  // four per upper mass
        const std::size_t braces = m * m + (m - 1) * (m - 1); // one per square of each layer
        EXPECT_EQ(make(Structure::Square2D, n, 1).springCount(), grid);
        EXPECT_EQ(make(Structure::Square2D, n, 1).massCount(), nn * nn);
        EXPECT_EQ(make(Structure::SaMM, n, 2).springCount(), grid + upperGrid + cross);
        EXPECT_EQ(make(Structure::SLaMM, n, 2).springCount(), grid + upperGrid + cross + braces);
        EXPECT_EQ(make(Structure::SaMM, n, 2).massCount(), nn * nn + m * m);
    }
}

TEST(Lattice, EverySpringIsWellFormedAndUnique)
{
    for (Structure structure : {Structure::Square2D, Structure::SaMM, Structure::SLaMM, Structure::TRiMM})
    {
        for (int layers : {1, 2, 3, 4})
        {
            if ((structure == Structure::Square2D) != (layers == 1))
            {
                continue;
            }
            const Lattice lattice = make(structure, 7, layers);
            std::set<std::pair<Index, Index>> seen;
            std::vector<int> degree(lattice.massCount(), 0);
            for (std::size_t s = 0; s < lattice.springCount(); ++s)
            {
                const SpringEnds e = lattice.springs.ends()[s];
                ASSERT_LT(e.a, lattice.massCount());
                ASSERT_LT(e.b, lattice.massCount());
                EXPECT_NE(e.a, e.b);
                EXPECT_GT(lattice.springs.restLength()[s], 0.0);
                EXPECT_NEAR(lattice.springs.restLength()[s], (lattice.position[e.a] - lattice.position[e.b]).norm(),
                            1e-15);
                const auto key = std::minmax(e.a, e.b);
                EXPECT_TRUE(seen.insert(key).second)
                    << structureName(structure) << " layers " << layers << ": duplicate spring " << e.a << "-" << e.b;
                ++degree[e.a];
                ++degree[e.b];
            }
            // Nobody is left floating: every mass has at least two springs.
            EXPECT_GE(*std::min_element(degree.begin(), degree.end()), 2) << structureName(structure);
        }
    }
}

TEST(Lattice, MassesFillTheRequestedBox)
{
    for (Structure structure : {Structure::SaMM, Structure::SLaMM, Structure::TRiMM})
    {
        const Lattice lattice = make(structure, 9, 2);
        Vec3 lo = lattice.position[0];
        Vec3 hi = lattice.position[0];
        for (const Vec3& x : lattice.position)
        {
            lo = lo.cwiseMin(x);
            hi = hi.cwiseMax(x);
        }
        const double eps = 1e-12;
        // Bottom layer spans the box in x and z; layers span it in y (Table 1: x, z in [-0.2, 0.8], y in [0.3, 0.4]).
        EXPECT_NEAR(lo.x(), -0.2, eps);
        EXPECT_NEAR(hi.x(), 0.8, eps);
        EXPECT_NEAR(lo.z(), -0.2, eps);
        EXPECT_NEAR(hi.z(), 0.8, eps);
        EXPECT_NEAR(lo.y(), 0.3, eps);
        EXPECT_NEAR(hi.y(), 0.4, eps);
    }
}

// Each upper TRiMM mass sits over the centroid of the triangle it joins, so its three springs share one length.
TEST(Lattice, TrimmUpperMassSitsOverItsTriangleCentroid)
{
    const Lattice lattice = make(Structure::TRiMM, 6, 2);
    std::vector<std::vector<Index>> below(lattice.massCount());
    for (std::size_t s = 0; s < lattice.springCount(); ++s)
    {
        if (lattice.springs.classes()[s] == SpringClass::InterLayer)
        {
            below[lattice.springs.ends()[s].a].push_back(lattice.springs.ends()[s].b);
        }
    }
    for (Index i = lattice.layerStart[1]; i < lattice.layerStart[2]; ++i)
    {
        ASSERT_EQ(below[i].size(), 3u);
        Vec3 centroid = Vec3::Zero();
        for (Index j : below[i])
        {
            centroid += lattice.position[j] / 3.0;
        }
        EXPECT_NEAR(centroid.x(), lattice.position[i].x(), 1e-12);
        EXPECT_NEAR(centroid.z(), lattice.position[i].z(), 1e-12);
    }
}

TEST(Lattice, BadSpecsAreRefusedWithTheValueAndRange)
{
    auto messageOf = [](Structure structure, int n, int layers)
    {
        try
        {
            make(structure, n, layers);
        }
        catch (const InputError& e)
        {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(messageOf(Structure::TRiMM, 1, 2).find("N >= 2"), std::string::npos);
    EXPECT_NE(messageOf(Structure::TRiMM, 1, 2).find("1x2x1"), std::string::npos);
    EXPECT_NE(messageOf(Structure::SaMM, 3, 1).find("2 to"), std::string::npos);
    EXPECT_NE(messageOf(Structure::Square2D, 3, 2).find("exactly 1 layer"), std::string::npos);
    EXPECT_NE(messageOf(Structure::TRiMM, 3, 4).find("N >= 4"), std::string::npos);
    EXPECT_THROW(parseStructure("hexagon"), InputError);
    EXPECT_EQ(parseStructure("TRiMM"), Structure::TRiMM);
    LatticeSpec spec;
    EXPECT_THROW(parseSize("8x2", spec), InputError);
    EXPECT_THROW(parseSize("8x2x8x", spec), InputError);
    EXPECT_THROW(parseSize("ax2x8", spec), InputError);
    parseSize("12x3x7", spec);
    EXPECT_EQ(spec.countX, 12);
    EXPECT_EQ(spec.layers, 3);
    EXPECT_EQ(spec.countZ, 7);
}
