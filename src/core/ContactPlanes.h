#pragma once
/// The frame's contact planes, indexed by mass: the detector's list sorted by mass (stably, so each mass's planes keep
/// the order they are applied in) with an offset table, so a kernel over a range of masses finds each one's planes
/// without searching.

#include "Contact.h"

#include <vector>

namespace masse
{
class ContactPlanes
{
public:
    /// The list the detector fills (cleared by clear()); call index() after filling it.
    std::vector<ContactPlane>& list() { return m_planes; }
    void clear() { m_planes.clear(); }
    /// Sorts the planes by mass and builds the offset table for `masses` masses.
    void index(std::size_t masses);

    std::size_t size() const { return m_planes.size(); }
    const ContactPlane& operator[](std::size_t k) const { return m_planes[k]; }
    /// Mass i's planes are [first(i), last(i)).
    std::size_t first(std::size_t i) const { return m_offsets[i]; }
    std::size_t last(std::size_t i) const { return m_offsets[i + 1]; }

private:
    std::vector<ContactPlane> m_planes;
    std::vector<std::size_t> m_offsets;
};
} // namespace masse
