#pragma once
/// The engine settings a program takes from its environment when its user names none. The engine itself reads no
/// environment variable: the `masse` command (src/app) and the Python module call these and pass the settings in.
///   MASSE_THREADS    kernel threads of each scene, 1 to 1024 (default: every core)
///   MASSE_STABILITY  the explicit integrators' stable-step estimate, power or gershgorin (default: power)
///   MASSE_SIMD       the kernels' instruction set, default, avx2 or avx512 (default: the widest the processor runs)

#include "scene/SceneSpec.h"

namespace masse::scene
{
/// $MASSE_THREADS if set, else the core count; throws InputError naming the variable for a value that is not a whole
/// number from 1 to 1024.
int threadsFromEnvironment();
/// $MASSE_STABILITY if set, else the power estimate; throws InputError naming the variable for an unknown name.
StabilityMethod stabilityFromEnvironment();
/// Threads from `threads` when it is positive, else from the environment, and the stability estimate from the
/// environment.
EngineSettings engineFromEnvironment(int threads = 0);
/// Forces the SIMD path $MASSE_SIMD names, if it is set; throws InputError naming the variable for an unknown path or
/// one this processor cannot run.
void applySimdFromEnvironment();
} // namespace masse::scene
