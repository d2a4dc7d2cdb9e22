#include "scene/EngineEnvironment.h"

#include "core/InputError.h"
#include "core/forces/SimdPath.h"
#include "core/parallel/TaskPool.h"

#include <cstdlib>
#include <string>

namespace masse::scene
{
int threadsFromEnvironment()
{
    const char* text = std::getenv("MASSE_THREADS");
    if (!text)
    {
        return hardwareThreadCount();
    }
    char* end = nullptr;
    const long threads = std::strtol(text, &end, 10);
    if (end == text || *end != '\0' || threads < 1 || threads > maxThreadCount)
    {
        throw InputError("MASSE_THREADS: must be a whole number of threads from 1 to " +
                         std::to_string(maxThreadCount) + " (got \"" + text + "\")");
    }
    return int(threads);
}

StabilityMethod stabilityFromEnvironment()
{
    const char* text = std::getenv("MASSE_STABILITY");
    return text ? parseStabilityMethod(text, "MASSE_STABILITY") : StabilityMethod::Power;
}

EngineSettings engineFromEnvironment(int threads)
{
    EngineSettings engine;
    engine.threads = threads > 0 ? threads : threadsFromEnvironment();
    engine.stability = stabilityFromEnvironment();
    return engine;
}

void applySimdFromEnvironment()
{
    const char* text = std::getenv("MASSE_SIMD");
    if (!text)
    {
        return;
    }
    const SimdPath path = parseSimdPath(text, "MASSE_SIMD");
    if (!simdPathSupported(path))
    {
        throw InputError(std::string("MASSE_SIMD: this processor cannot run the ") + text + " path");
    }
    setSimdPath(path);
}
} // namespace masse::scene
