#pragma once
/// Turning a PinSpec (indices, corners, edges) into mass indices of a lattice.

#include "scene/SceneSpec.h"

namespace masse::scene
{
/// The masses a PinSpec names, sorted, each once.
std::vector<Index> resolvePins(const PinSpec& pins, const Lattice& lattice);
} // namespace masse::scene
