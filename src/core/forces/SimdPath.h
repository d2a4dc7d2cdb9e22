#pragma once
/// Which instruction set the hot kernels run with: the baseline x86-64 code (SSE2), AVX2 or AVX-512, chosen at run
/// time. Every path gives the same bits: the kernels use only element-wise IEEE + - * / and sqrt, in the same order on
/// each lane, and -ffp-contract=off keeps multiply-adds unfused. A wider path only does more springs per instruction.

#include <string_view>
#include <vector>

namespace masse
{
enum class SimdPath
{
    Default, ///< the build's baseline (x86-64: SSE2), runs everywhere
    Avx2,
    Avx512, ///< AVX-512F
};

std::string_view simdPathName(SimdPath path);
/// Parses "default", "avx2" or "avx512"; throws InputError for `field` naming the allowed names.
SimdPath parseSimdPath(std::string_view name, std::string_view field = "simd");
/// Whether this processor can run the path.
bool simdPathSupported(SimdPath path);
/// The paths this processor can run, widest last.
std::vector<SimdPath> supportedSimdPaths();
/// The path in use: set by setSimdPath, else the widest this processor supports.
SimdPath activeSimdPath();
/// Forces a path (for tests and benchmarks); throws InputError if this processor cannot run it.
void setSimdPath(SimdPath path);
} // namespace masse
