#pragma once
/// Runs a scene to its end under its divergence guard: shared by the tests that check a scene is never stopped.

#include "scene/Scene.h"

#include "core/DivergenceGuard.h"
#include "core/NumericalError.h"

#include <string>

namespace masse::test
{
/// Steps `scene` until it is finished; returns the guard's message, or "" when it ran to the end.
inline std::string guardMessageOfRun(scene::Scene& scene)
{
    try
    {
        while (!scene.finished())
        {
            scene.step();
        }
    }
    catch (const NumericalError& e)
    {
        return e.what();
    }
    return "";
}
} // namespace masse::test
