#include "core/contact/ContactPlanes.h"

#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <bit>
#include <cstdint>

namespace masse
{
namespace
{
/// Whether every bit of x is zero (+0; -0 is not).
bool plusZero(Real x)
{
    return std::bit_cast<std::uint64_t>(x) == 0;
}
} // namespace

void ContactPlanes::store(const ContactPlane* from, std::size_t count, std::size_t first)
{
    for (std::size_t n = 0; n < count; ++n)
    {
        const ContactPlane& plane = from[n];
        const std::size_t k = first + n;
        m_mass[k] = plane.mass;
        m_normalX[k] = plane.normal.x();
        m_normalY[k] = plane.normal.y();
        m_normalZ[k] = plane.normal.z();
        m_offset[k] = plane.offset;
        m_obstacle[k] = plane.obstacle;
        m_face[k] = plane.face;
        m_velocityX[k] = plane.velocity.x();
        m_velocityY[k] = plane.velocity.y();
        m_velocityZ[k] = plane.velocity.z();
    }
}

bool ContactPlanes::countEntries()
{
    const std::size_t count = m_mass.size();
    const std::size_t chunks = chunkCount(count, indexChunkSize);
    m_chunkEntries.assign(chunks + 1, 0);
    m_chunkInOrder.assign(chunks, 1);
    parallelFor(count, indexChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    std::size_t starts = 0;
                    bool inOrder = true;
                    for (std::size_t k = begin; k < end; ++k)
                    {
                        starts += k == 0 || m_mass[k] != m_mass[k - 1] ? 1 : 0;
                        inOrder = inOrder && (k == 0 || m_mass[k - 1] <= m_mass[k]);
                    }
                    m_chunkEntries[begin / indexChunkSize + 1] = starts;
                    m_chunkInOrder[begin / indexChunkSize] = inOrder ? 1 : 0;
                });
    return std::find(m_chunkInOrder.begin(), m_chunkInOrder.end(), 0) == m_chunkInOrder.end();
}

void ContactPlanes::index()
{
    // Each list's planes go to the arrays where the lists before it end, all lists at once.
    const std::size_t lists = m_lists.size();
    m_listStart.assign(lists + 1, 0);
    for (std::size_t list = 0; list < lists; ++list)
    {
        m_listStart[list + 1] = m_listStart[list] + m_lists[list].size();
    }
    const std::size_t count = m_listStart[lists];
    m_mass.resize(count);
    m_normalX.resize(count);
    m_normalY.resize(count);
    m_normalZ.resize(count);
    m_offset.resize(count);
    m_obstacle.resize(count);
    m_face.resize(count);
    m_velocityX.resize(count);
    m_velocityY.resize(count);
    m_velocityZ.resize(count);
    parallelFor(lists, 1,
                [&](std::size_t list, std::size_t)
                { store(m_lists[list].data(), m_lists[list].size(), m_listStart[list]); });

    // The Bullet detector lists planes in mass order; a test detector need not, so those are joined and sorted stably
    // (each mass's planes keep their order, which is the order they are applied in) and stored again.
    if (!countEntries())
    {
        m_sorted.clear();
        for (std::size_t list = 0; list < lists; ++list)
        {
            m_sorted.insert(m_sorted.end(), m_lists[list].begin(), m_lists[list].end());
        }
        std::stable_sort(m_sorted.begin(), m_sorted.end(),
                         [](const ContactPlane& x, const ContactPlane& y) { return x.mass < y.mass; });
        store(m_sorted.data(), count, 0);
        countEntries();
    }
    const std::size_t chunks = m_chunkInOrder.size();
    for (std::size_t chunk = 0; chunk < chunks; ++chunk)
    {
        m_chunkEntries[chunk + 1] += m_chunkEntries[chunk];
    }
    const std::size_t masses = m_chunkEntries[chunks];

    // Each chunk writes the entries of the masses that begin in it.
    m_entries.resize(masses + 1);
    parallelFor(count, indexChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    std::size_t entry = m_chunkEntries[begin / indexChunkSize];
                    for (std::size_t k = begin; k < end; ++k)
                    {
                        if (k == 0 || m_mass[k] != m_mass[k - 1])
                        {
                            m_entries[entry++] = {m_mass[k], std::uint32_t(k)};
                        }
                    }
                });
    m_entries[masses] = {0, std::uint32_t(count)}; // the closing entry

    // Runs of entries whose planes all lie on still surfaces.
    const std::size_t runs = chunkCount(masses, runLength);
    m_stillRuns.resize(runs);
    parallelFor(runs, 1,
                [&](std::size_t run, std::size_t)
                {
                    const std::size_t firstPlane = m_entries[run * runLength].firstPlane;
                    const std::size_t endPlane = m_entries[std::min(masses, (run + 1) * runLength)].firstPlane;
                    bool still = true;
                    for (std::size_t k = firstPlane; k < endPlane && still; ++k)
                    {
                        still = plusZero(m_velocityX[k]) && plusZero(m_velocityY[k]) && plusZero(m_velocityZ[k]);
                    }
                    m_stillRuns[run] = still ? 1 : 0;
                });
}
} // namespace masse
