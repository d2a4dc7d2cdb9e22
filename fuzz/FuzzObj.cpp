// libFuzzer harness: the OBJ mesh reader (our checks, then tinyobjloader). Bad input must end in InputError; anything
// else is a finding.

#include "FuzzInput.h"

#include "bridge/MeshFile.h"
#include "core/InputError.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const std::string path = masse::fuzz::writeInput(data, size, "mesh.obj");
    try
    {
        masse::bridge::loadObj(path, "fuzz");
    }
    catch (const masse::InputError&)
    {
    }
    return 0;
}
