// libFuzzer harness: the scene reader, with "extends" (a base scene and the input itself are beside it) and material
// files. Bad input must end in InputError; anything else (a crash, another exception, a leak, a hang) is a finding.

#include "FuzzInput.h"

#include "core/InputError.h"
#include "scene/SceneFile.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    masse::fuzz::provide("data/scenes/slope.json", "base.json");
    masse::fuzz::provide("data/scenes/paper-drop.json", "paper-drop.json");
    masse::fuzz::provide("data/materials/abs.json", "abs.json");
    const std::string path = masse::fuzz::writeInput(data, size, "scene.json");
    try
    {
        masse::scene::loadScene(path);
    }
    catch (const masse::InputError&)
    {
    }
    return 0;
}
