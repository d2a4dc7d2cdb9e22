#pragma once
/// What a sheet will cost in memory, known from its size before anything is built, so that a sheet that cannot fit
/// is refused at once (exit code 2) instead of allocating for minutes and failing with std::bad_alloc.

#include "core/integrate/Integrator.h"
#include "core/lattice/Lattice.h"

#include <cstddef>

namespace masse::scene
{
/// Masses of the lattice a spec describes, counted without building it: layer l is a (N_x - l) x (N_z - l) grid.
std::size_t massCountOf(const LatticeSpec& spec);
/// Bytes a running scene of this sheet needs at its peak, from per-mass costs measured on runs of large sheets
/// (see MemoryBudget.cpp), rounded up.
double estimatedBytes(const LatticeSpec& spec, IntegratorKind integrator);
/// Bytes this process may still allocate: the smaller of the memory the system says is available and the address
/// space limit, if any.
double availableBytes();
/// Throws InputError for the LatticeSpec's field "size", with the estimate and what is available, when the one
/// exceeds the other.
void checkMemory(const LatticeSpec& spec, IntegratorKind integrator);
} // namespace masse::scene
