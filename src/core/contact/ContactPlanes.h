#pragma once
/// The frame's contact planes, indexed by mass: the detector's lists joined and sorted by mass (stably, so each mass's
/// planes keep the order they are applied in), the masses that have planes, and each plane's fields packed for the
/// per-substep projection.
///
/// The projection runs after every substep over the masses near a surface only (a sheet resting on a table has half
/// its masses there, a falling one none), so it walks the list of those masses, not every mass. The planes are kept one
/// array per field, so eight planes' normals load as three vectors and what the projection reads of a plane each time
/// (normal, offset, obstacle, face: 40 bytes) comes without the rest; a run of masses whose planes all lie on still
/// surfaces is marked as such, so the pass reads no velocity there. The detector's lists are joined straight into these
/// arrays: joined first into one list of planes and then copied into the arrays, every plane would be copied twice a
/// frame.

#include "core/contact/Contact.h"

#include <cstdint>
#include <vector>

namespace masse
{
class ContactPlanes
{
public:
    /// What the projection reads of a plane every substep.
    struct Surface
    {
        Vec3 normal;
        Real offset;
        int obstacle;
        int face;
    };
    /// A mass with planes: its index and where its planes start (they end where the next entry's start).
    struct Entry
    {
        Index mass;
        std::uint32_t firstPlane;
    };
    /// Entries per run of the list marked still or not (and per chunk of the projection's parallel pass). Fewer,
    /// longer chunks cost less to hand out: on the 256x2x256 contact bench the pass takes 0.103-0.105 s at 2048 against
    /// 0.108-0.110 s at 1024; 2048 still gives a 64x2x64 sheet's 4,000 entries two chunks (4096 would run them on one
    /// thread, a third slower).
    static constexpr std::size_t runLength = 2048;

    /// The lists the detector fills (replacing the last frame's); call index() after filling them.
    ContactPlaneLists& lists() { return m_lists; }
    /// Joins the lists into the planes' arrays, sorted by mass, and lists the masses that have planes.
    void index();

    std::size_t size() const { return m_mass.size(); }
    /// Plane k, gathered from the arrays.
    ContactPlane operator[](std::size_t k) const
    {
        ContactPlane plane;
        plane.mass = m_mass[k];
        plane.obstacle = m_obstacle[k];
        plane.face = m_face[k];
        plane.normal = Vec3(m_normalX[k], m_normalY[k], m_normalZ[k]);
        plane.offset = m_offset[k];
        plane.velocity = velocity(k);
        return plane;
    }
    Vec3 velocity(std::size_t k) const { return Vec3(m_velocityX[k], m_velocityY[k], m_velocityZ[k]); }
    Surface surface(std::size_t k) const
    {
        return {Vec3(m_normalX[k], m_normalY[k], m_normalZ[k]), m_offset[k], m_obstacle[k], m_face[k]};
    }
    /// The surfaces' fields as arrays, indexed by plane (what surface(k) gathers).
    const Real* normalX() const { return m_normalX.data(); }
    const Real* normalY() const { return m_normalY.data(); }
    const Real* normalZ() const { return m_normalZ.data(); }
    const Real* offsets() const { return m_offset.data(); }
    const int* obstacles() const { return m_obstacle.data(); }
    const int* faces() const { return m_face.data(); }
    /// The list of masses with planes, with a closing entry (whose firstPlane is size()).
    const Entry* entries() const { return m_entries.data(); }

    /// Masses that have planes, in increasing order; entry j's planes are [firstPlane(j), endPlane(j)).
    std::size_t massCount() const { return m_entries.size() - 1; }
    Index mass(std::size_t j) const { return m_entries[j].mass; }
    std::size_t firstPlane(std::size_t j) const { return m_entries[j].firstPlane; }
    std::size_t endPlane(std::size_t j) const { return m_entries[j + 1].firstPlane; }
    /// Whether every plane of the entries [r runLength, (r + 1) runLength) lies on a surface whose velocity is zero,
    /// all bits (+0): there the projection may take the velocity as the constant zero and get the same bits.
    bool stillRun(std::size_t r) const { return m_stillRuns[r] != 0; }

private:
    /// Writes planes [0, count) of `from` to the arrays from `first` on.
    void store(const ContactPlane* from, std::size_t count, std::size_t first);
    /// Counts, per chunk of the arrays, the masses whose planes begin there; returns whether the masses are in order.
    bool countEntries();

    ContactPlaneLists m_lists;
    std::vector<ContactPlane> m_sorted;   ///< index(): the planes of lists out of mass order, joined and sorted
    std::vector<std::size_t> m_listStart; ///< index(): where each list's planes begin in the arrays
    std::vector<Index> m_mass;
    std::vector<Real> m_normalX;
    std::vector<Real> m_normalY;
    std::vector<Real> m_normalZ;
    std::vector<Real> m_offset;
    std::vector<int> m_obstacle;
    std::vector<int> m_face;
    std::vector<Real> m_velocityX;
    std::vector<Real> m_velocityY;
    std::vector<Real> m_velocityZ;
    std::vector<Entry> m_entries{Entry{0, 0}}; ///< with a closing entry, so endPlane needs no test
    std::vector<std::uint8_t> m_stillRuns;
    /// Planes per chunk of index()'s parallel passes.
    static constexpr std::size_t indexChunkSize = 4096;
    std::vector<std::size_t> m_chunkEntries;  ///< index(): entries begun before each chunk
    std::vector<std::uint8_t> m_chunkInOrder; ///< index(): whether each chunk's planes are in mass order
};
} // namespace masse
