#pragma once
/// A fill-reducing elimination order for the implicit solve's Cholesky factor: geometric nested dissection.
///
/// A sheet is a thin lattice, nearly planar at rest, so cutting it at the median of its longest extent splits it in
/// two with a thin line of masses between (the separator: the masses of one half with a spring into the other).
/// Ordering each half recursively and the separator last keeps the factor's fill to O(n log n) on a 2D lattice,
/// about half of what Eigen's approximate minimum degree gives on these sheets, and the factor's two triangular solves
/// are most of a step's cost. Only rest positions and springs are used, so the order is fixed per topology.

#include "SpringSet.h"
#include "Types.h"

#include <vector>

namespace masse
{
/// Masses in elimination order (a permutation of 0..positions.size()-1).
std::vector<Index> nestedDissectionOrder(const std::vector<Vec3>& positions, const SpringSet& springs);
} // namespace masse
