#pragma once
/// Webbing, the defect forming engineers look for first: places where the sheet lies on itself. A surface mass within
/// a distance of a surface triangle of another part of the sheet (SelfContact's pairs: not its own triangles, not those
/// of its spring neighbours, not those near it in the flat sheet) lies on the sheet; such masses, the masses of the
/// triangles they lie on, and their spring neighbours that lie on the sheet too make one place. Found from the
/// positions alone, so it tells where a forming run's sheet folded onto itself whether or not the run kept the folds
/// apart (contact.self_collision) or let them pass through each other.

#include "core/contact/SelfContact.h"
#include "core/lattice/Lattice.h"

#include <vector>

namespace masse
{
struct WebbingPlace
{
    std::vector<Index> masses;  ///< increasing
    Vec3 centre = Vec3::Zero(); ///< m, the masses' mean position now
    Vec3 low = Vec3::Zero();    ///< m, their box now
    Vec3 high = Vec3::Zero();
    Vec3 restLow = Vec3::Zero();  ///< m, their box in the flat sheet (the lattice's rest positions): which part
    Vec3 restHigh = Vec3::Zero(); ///< of the sheet folded
};

/// The places where the sheet at positions x lies on itself, `distance` apart or closer; the largest first (ties: the
/// one with the lowest mass first). `surface` is a SelfContact of the same lattice kept for this (its broadphase is
/// asked afresh).
std::vector<WebbingPlace> findWebbing(SelfContact& surface, const Lattice& lattice, const std::vector<Vec3>& x,
                                      Real distance);
} // namespace masse
