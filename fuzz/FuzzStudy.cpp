// libFuzzer harness: the study reader (masse sweep), which also reads the base scene and checks every case's scene.
// A base scene, slope.json, is beside the input. Bad input must end in InputError; anything else is a finding.

#include "FuzzInput.h"

#include "core/InputError.h"
#include "scene/study/Study.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    masse::fuzz::provide("data/scenes/slope.json", "slope.json");
    const std::string path = masse::fuzz::writeInput(data, size, "study.json");
    try
    {
        masse::scene::loadStudy(path);
    }
    catch (const masse::InputError&)
    {
    }
    return 0;
}
