// libFuzzer harness: the material reader. Bad input must end in InputError; anything else is a finding.

#include "FuzzInput.h"

#include "core/InputError.h"
#include "scene/MaterialFile.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const std::string path = masse::fuzz::writeInput(data, size, "material.json");
    try
    {
        masse::scene::readMaterialFile(path);
    }
    catch (const masse::InputError&)
    {
    }
    return 0;
}
