#include "core/forces/SimdPath.h"

#include "core/InputError.h"
#include "core/NamedEnum.h"

#include <atomic>
#include <string>

#if defined(__x86_64__) && defined(__GNUC__)
#include <cpuid.h>
#endif

namespace masse
{
namespace
{
#if defined(__x86_64__) && defined(__GNUC__)
/// F16C (CPUID leaf 1, ECX bit 29), asked of the processor directly: clang's __builtin_cpu_supports has no "f16c".
bool hasF16c()
{
    unsigned eax = 0;
    unsigned ebx = 0;
    unsigned ecx = 0;
    unsigned edx = 0;
    return __get_cpuid(1, &eax, &ebx, &ecx, &edx) != 0 && (ecx & bit_F16C) != 0;
}
#endif
constexpr EnumName<SimdPath> simdNames[] = {
    {SimdPath::Default, "default"},
    {SimdPath::Avx2, "avx2"},
    {SimdPath::Avx512, "avx512"},
};

/// -1 until chosen, else the SimdPath. One for the process, unlike the thread pool: it is a property of the processor
/// the kernels run on, and every path gives the same bits, so two simulators never need different ones.
std::atomic<int> chosenPath{-1};

SimdPath bestSupported()
{
    const std::vector<SimdPath> paths = supportedSimdPaths();
    return paths.back();
}
} // namespace

std::string_view simdPathName(SimdPath path)
{
    return enumName(simdNames, path);
}

SimdPath parseSimdPath(std::string_view name, std::string_view field)
{
    return parseEnum(simdNames, name, field, "SIMD path");
}

bool simdPathSupported(SimdPath path)
{
#if defined(__x86_64__) && defined(__GNUC__)
    switch (path)
    {
    case SimdPath::Default:
        return true;
    case SimdPath::Avx2:
        return __builtin_cpu_supports("avx2") && hasF16c(); // F16C: the Cholesky factor's halves (MassBlockRows)
    case SimdPath::Avx512:
        return __builtin_cpu_supports("avx512f");
    }
    return false;
#else
    return path == SimdPath::Default;
#endif
}

std::vector<SimdPath> supportedSimdPaths()
{
    std::vector<SimdPath> paths;
    for (const EnumName<SimdPath>& entry : simdNames)
    {
        if (simdPathSupported(entry.value))
        {
            paths.push_back(entry.value);
        }
    }
    return paths;
}

SimdPath activeSimdPath()
{
    int path = chosenPath.load(std::memory_order_relaxed);
    if (path < 0)
    {
        path = int(bestSupported());
        chosenPath.store(path, std::memory_order_relaxed);
    }
    return SimdPath(path);
}

void setSimdPath(SimdPath path)
{
    if (!simdPathSupported(path))
    {
        throw InputError("SIMD path " + std::string(simdPathName(path)) + ": this processor cannot run it");
    }
    chosenPath.store(int(path), std::memory_order_relaxed);
}
} // namespace masse
