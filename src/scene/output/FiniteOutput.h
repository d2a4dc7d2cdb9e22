#pragma once
/// The guard between a run and its files: nothing non-finite is ever written. A state whose positions and velocities
/// are finite can still have quantities derived from them that are not (a speed or kinetic energy of 1e200 m/s
/// squared overflows); these checks find them and stop the run with a NumericalError (exit code 1) instead.

#include "core/NumericalError.h"
#include "scene/Scene.h"

#include <nlohmann/json.hpp>

namespace masse::scene
{
/// Throws NumericalError naming the mass and the quantity if any mass's position, speed or kinetic energy, or the
/// sheet's total kinetic energy, is not a finite number.
void requireFiniteState(const Scene& scene);
/// Throws NumericalError naming the key ("final.kinetic_energy") of the first number in `document` that is NaN or
/// infinite (nlohmann would write it as null).
void requireFiniteJson(const nlohmann::json& document, const std::string& what);
} // namespace masse::scene
