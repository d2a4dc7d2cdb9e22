#pragma once
/// What a scene will cost in memory, known from its spec before anything is built, so that a sheet that cannot fit
/// is refused at once (exit code 2) instead of allocating for minutes and failing with std::bad_alloc or being
/// killed by the system.

#include "core/lattice/Lattice.h"
#include "scene/SceneSpec.h"

#include <cstddef>

namespace masse::scene
{
/// Masses of the lattice a spec describes, counted without building it: layer l is a (N_x - l) x (N_z - l) grid.
std::size_t massCountOf(const LatticeSpec& spec);
/// Bytes a run of this scene needs at its peak: a model of the peak resident memory of `masse run`, fitted to runs
/// of sheets from 8,000 to 130,000 masses and rounded up (see MemoryBudget.cpp; tests/scene/MemoryBudgetTest.cpp
/// holds it between once and four times what runs take).
double estimatedBytes(const SceneSpec& spec);
/// Bytes this process may still allocate: the smaller of the memory the system says is available and the address
/// space limit, if any.
double availableBytes();
/// Throws InputError for the field "size" (of the sheet), with the estimate and what is available, when the one
/// exceeds the other.
void checkMemory(const SceneSpec& spec);
} // namespace masse::scene
