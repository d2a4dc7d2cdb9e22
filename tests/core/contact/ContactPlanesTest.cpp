// The frame's contact planes indexed by mass (ContactPlanes::index, run in parallel chunks): what the projection walks.

#include "support/TestSystems.h"
#include "support/TestThreads.h"

#include "core/contact/ContactPlanes.h"
#include "core/parallel/TaskPool.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

using namespace masse;
using masse::test::BoundPool;

namespace
{
/// 30,000 masses' planes (several of index()'s chunks and of the projection's runs): masses 0, 3, 6... with one to
/// three planes each, a moving surface under masses 20,000 to 20,099 only, listed in mass order or shuffled.
std::vector<ContactPlane> someMassesPlanes(bool shuffled)
{
    std::vector<ContactPlane> planes;
    for (Index mass = 0; mass < 30000; mass += 3)
    {
        for (Index copy = 0; copy <= mass % 7 % 3; ++copy)
        {
            ContactPlane plane;
            plane.mass = mass;
            plane.obstacle = int(copy);
            plane.face = int(mass % 5);
            plane.normal = Vec3(Real(copy), 1, Real(mass));
            plane.offset = Real(mass) + Real(copy) / 8;
            plane.velocity = mass >= 20000 && mass < 20100 ? Vec3(0, 0.1, 0) : Vec3::Zero();
            planes.push_back(plane);
        }
    }
    if (shuffled)
    {
        std::mt19937 random(7);
        std::shuffle(planes.begin(), planes.end(), random);
    }
    return planes;
}
} // namespace

// Joined from lists of several sizes, the masses come out in increasing order, each once, with its planes in the order
// the detector listed them (a stable sort when they came shuffled), each plane as listed, and a run marked still
// exactly when none of its planes moves; the same at every thread count. A second call with fewer planes (the lists
// are kept from frame to frame) leaves nothing of the first.
TEST(ContactPlanes, IndexesThePlanesByMassKeepingEachMassesOrder)
{
    for (const bool shuffled : {false, true})
    {
        for (const int threads : {1, 2, 3})
        {
            const BoundPool pool(threads);
            const std::vector<ContactPlane> listed = someMassesPlanes(shuffled);
            std::vector<ContactPlane> expected = listed;
            std::stable_sort(expected.begin(), expected.end(),
                             [](const ContactPlane& a, const ContactPlane& b) { return a.mass < b.mass; });
            // In lists of several sizes, one of them empty, as the detector's chunks may give them.
            ContactPlanes planes;
            const std::size_t n = listed.size();
            const std::size_t ends[] = {0, n / 4, n / 4, n / 4 + 1, n / 2 + 7, n - 1, n};
            planes.lists().resize(std::size(ends) - 1);
            for (std::size_t list = 0; list + 1 < std::size(ends); ++list)
            {
                planes.lists()[list].assign(listed.begin() + std::ptrdiff_t(ends[list]),
                                            listed.begin() + std::ptrdiff_t(ends[list + 1]));
            }
            planes.index();
            ASSERT_EQ(planes.size(), expected.size());
            ASSERT_EQ(planes.massCount(), 10000u);
            for (std::size_t j = 0; j < planes.massCount(); ++j)
            {
                const Index mass = Index(3 * j);
                ASSERT_EQ(planes.mass(j), mass) << j;
                ASSERT_EQ(planes.endPlane(j) - planes.firstPlane(j), std::size_t(1 + mass % 7 % 3)) << j;
                for (std::size_t k = planes.firstPlane(j); k < planes.endPlane(j); ++k)
                {
                    // The mass's planes in the order listed (in mass order, the copies 0, 1, 2 as made).
                    ASSERT_EQ(planes[k].obstacle, expected[k].obstacle) << k;
                    ASSERT_EQ(planes[k].mass, mass) << k;
                    ASSERT_EQ(planes.velocity(k), expected[k].velocity) << k;
                    if (!shuffled)
                    {
                        ASSERT_EQ(planes[k].obstacle, int(k - planes.firstPlane(j))) << k;
                    }
                    const ContactPlanes::Surface surface = planes.surface(k);
                    ASSERT_EQ(surface.normal, expected[k].normal);
                    ASSERT_EQ(surface.offset, expected[k].offset);
                    ASSERT_EQ(surface.obstacle, expected[k].obstacle);
                    ASSERT_EQ(surface.face, expected[k].face);
                    ASSERT_EQ(planes.normalX()[k], expected[k].normal.x());
                    ASSERT_EQ(planes.faces()[k], expected[k].face);
                }
            }
            ASSERT_EQ(planes.entries()[planes.massCount()].firstPlane, planes.size()); // the closing entry
            for (std::size_t run = 0; run * ContactPlanes::runLength < planes.massCount(); ++run)
            {
                const std::size_t first = run * ContactPlanes::runLength;
                const std::size_t end = std::min(planes.massCount(), first + ContactPlanes::runLength);
                const bool moving = planes.mass(first) < 20100 && planes.mass(end - 1) >= 20000;
                EXPECT_EQ(planes.stillRun(run), !moving) << "run " << run << " at " << threads << " threads";
            }

            planes.lists().resize(1);
            planes.lists()[0].resize(2);
            planes.lists()[0][0].mass = 5;
            planes.lists()[0][1].mass = 9;
            planes.index();
            ASSERT_EQ(planes.massCount(), 2u);
            EXPECT_EQ(planes.mass(1), 9u);
            EXPECT_EQ(planes.endPlane(1), 2u);
        }
    }
}
