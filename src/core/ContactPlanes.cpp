#include "ContactPlanes.h"

#include "TaskPool.h"

#include <algorithm>
#include <cstring>

namespace masse
{
namespace
{
/// Whether every bit of v is zero (+0 in each coordinate; -0 is not).
bool allBitsZero(const Vec3& v)
{
    static constexpr Real zeros[3] = {0, 0, 0};
    return std::memcmp(v.data(), zeros, sizeof(zeros)) == 0;
}
} // namespace

void ContactPlanes::index()
{
    // The Bullet detector gives planes in mass order already; a test detector need not, so sort stably (each mass's
    // planes keep their order, which is the order they are applied in). Whether they are in order, and how many masses
    // begin their planes in each chunk of the list, in one parallel pass.
    const std::size_t count = m_planes.size();
    const std::size_t chunks = chunkCount(count, indexChunkSize);
    m_chunkEntries.assign(chunks + 1, 0);
    m_chunkInOrder.assign(chunks, 1);
    const auto countEntries = [&]
    {
        parallelFor(count, indexChunkSize,
                    [&](std::size_t begin, std::size_t end)
                    {
                        std::size_t starts = 0;
                        bool inOrder = true;
                        for (std::size_t k = begin; k < end; ++k)
                        {
                            const bool first = k == 0 || m_planes[k].mass != m_planes[k - 1].mass;
                            starts += first ? 1 : 0;
                            inOrder = inOrder && (k == 0 || m_planes[k - 1].mass <= m_planes[k].mass);
                        }
                        m_chunkEntries[begin / indexChunkSize + 1] = starts;
                        m_chunkInOrder[begin / indexChunkSize] = inOrder ? 1 : 0;
                    });
    };
    countEntries();
    if (std::find(m_chunkInOrder.begin(), m_chunkInOrder.end(), 0) != m_chunkInOrder.end())
    {
        std::stable_sort(m_planes.begin(), m_planes.end(),
                         [](const ContactPlane& x, const ContactPlane& y) { return x.mass < y.mass; });
        countEntries();
    }
    for (std::size_t chunk = 0; chunk < chunks; ++chunk)
    {
        m_chunkEntries[chunk + 1] += m_chunkEntries[chunk];
    }
    const std::size_t masses = m_chunkEntries[chunks];

    // Each chunk writes its planes' surfaces and the entries of the masses that begin in it.
    m_normalX.resize(count);
    m_normalY.resize(count);
    m_normalZ.resize(count);
    m_offset.resize(count);
    m_obstacle.resize(count);
    m_face.resize(count);
    m_entries.resize(masses + 1);
    parallelFor(count, indexChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    std::size_t entry = m_chunkEntries[begin / indexChunkSize];
                    for (std::size_t k = begin; k < end; ++k)
                    {
                        const ContactPlane& plane = m_planes[k];
                        m_normalX[k] = plane.normal.x();
                        m_normalY[k] = plane.normal.y();
                        m_normalZ[k] = plane.normal.z();
                        m_offset[k] = plane.offset;
                        m_obstacle[k] = plane.obstacle;
                        m_face[k] = plane.face;
                        if (k == 0 || plane.mass != m_planes[k - 1].mass)
                        {
                            m_entries[entry++] = {plane.mass, std::uint32_t(k)};
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
                        still = allBitsZero(m_planes[k].velocity);
                    }
                    m_stillRuns[run] = still ? 1 : 0;
                });
}
} // namespace masse
