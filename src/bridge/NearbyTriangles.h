#pragma once
/// The triangles of a mesh obstacle near one mass, kept from one frame to the next (frame coherence).
///
/// A mass's query walks the mesh's tree for the triangles whose boxes meet its search box and computes the nearest
/// point of each that is not turned away; on a mould most masses lie still or move a fraction of their search distance
/// a frame. So the walk gathers the triangles within a sphere a little larger than the search's about the mass (in the
/// mesh's own frame), and while the mass stays inside that sphere's margin, its next queries test those triangles
/// alone: every triangle within the search sphere of the new centre lies within the kept sphere of the old one (the
/// distance from the old centre is at most the new search radius plus the distance moved), so the triangles found, and
/// hence the planes, are the same as the walk's, whatever the order they come in (the planes are chosen by distance,
/// ties by triangle).
///
/// On the vacuum cup and the pressure tray at 64x2x64, over their whole runs, some 94% of the queries test kept
/// triangles, and contact detection takes half the time it takes walking the tree for every query (masse bench).

#include "core/Types.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace masse::bridge
{
struct NearbyTriangles
{
    /// Triangles kept at most; a mass with more near it walks the tree every frame (a mould's finely faceted rim
    /// within a small sheet's search sphere, or a fast mass's wide search). While the vacuum cup's sheet is drawn down
    /// (its first 20 frames at 64x2x64), 30% of its queries walk the tree; with room for 48, 36% would, and detection
    /// would take some 30% longer. The list's unused room is never read.
    static constexpr int capacity = 96;
    /// The kept sphere's radius is the search radius plus this many contact radii. A larger margin lets a moving
    /// mass keep its triangles for longer, but every query then tests more of them: on the cup and the tray, margins
    /// of 0.25 to 0.5 contact radii take the least time, 2 radii a third more, twice the search radius half as much
    /// again.
    static constexpr Real margin = 0.5;

    Vec3 centre = Vec3::Zero(); ///< mesh frame, where the triangles were gathered
    Real radius = -1;           ///< m, of the sphere about `centre` they were gathered in; negative: nothing kept
    std::int32_t count = 0;
    /// Each triangle with a distance no more than its distance from `centre` (m), in increasing distance: a triangle
    /// farther than the search radius plus the distance moved cannot be near, nor can any after it. Side by side, so
    /// that a query reads the few it needs from one or two cache lines.
    struct Entry
    {
        float distance;
        std::int32_t triangle;
    };
    std::array<Entry, capacity> entry{};

    /// Lists a triangle at distance `gap` from `centre` (count -1 once more than the capacity were listed); sort()
    /// puts the list in order once it is complete.
    void add(std::int32_t triangleIndex, Real gap)
    {
        if (count < 0)
        {
            return;
        }
        if (count == capacity)
        {
            count = -1;
            radius = -1;
            return;
        }
        float lower = float(gap);
        if (Real(lower) > gap)
        {
            lower = std::nextafter(lower, -std::numeric_limits<float>::infinity());
        }
        entry[std::size_t(count)] = {lower, triangleIndex};
        ++count;
    }

    /// Puts the listed triangles in distance order, ties by triangle, so the list does not depend on the walk's
    /// order. Once, after the walk: inserting each in place would move some n^2/4 entries, a walk near a finely
    /// faceted rim lists dozens.
    void sort()
    {
        if (count > 1)
        {
            std::sort(entry.begin(), entry.begin() + count,
                      [](const Entry& a, const Entry& b)
                      { return a.distance < b.distance || (a.distance == b.distance && a.triangle < b.triangle); });
        }
    }

    /// Whether the kept triangles hold every triangle within `searchRadius` of `localCentre`. The margin covers the
    /// rounding of the distances the triangles were kept by (some 1e-16 relative).
    bool covers(const Vec3& localCentre, Real searchRadius) const
    {
        return radius >= 0 && (localCentre - centre).norm() + searchRadius <= radius * (1 - Real(1e-9)) - Real(1e-12);
    }
};
} // namespace masse::bridge
