#pragma once
/// A 64-bit fingerprint of every mass's position and velocity bits (FNV-1a), for determinism tests and golden
/// results: two runs agree bit for bit exactly when their hashes do (up to hash collisions).

#include "core/lattice/Particles.h"

namespace masse
{
std::uint64_t stateHash(const Particles& particles);
} // namespace masse
