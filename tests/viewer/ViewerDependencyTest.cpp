// Drawing stays in src/viewer: the scene and the Bullet bridge include no GL, GLUT or ImGui (the core has its own
// stricter test), and the viewer's model files (camera, picking, session...) include none either, so the tests
// and a future second front end can use them without a window.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

namespace
{
void expectNoGraphicsIncludes(const std::filesystem::path& file)
{
    const std::regex graphics(R"(^\s*#\s*include\s*[<"](GL/|GLFW|imgui|.*GlHeaders|X11/|stb_))");
    std::ifstream in(file);
    std::string line;
    while (std::getline(in, line))
    {
        EXPECT_FALSE(std::regex_search(line, graphics)) << file << ": " << line;
    }
}
} // namespace

TEST(ViewerDependency, SceneAndBridgeKnowNothingOfGraphics)
{
    int files = 0;
    for (const char* folder : {"src/scene", "src/bridge"})
    {
        const std::filesystem::path layer = std::filesystem::path(MASSE_SOURCE_DIR) / folder;
        for (const auto& entry : std::filesystem::recursive_directory_iterator(layer))
        {
            if (!entry.is_regular_file())
            {
                continue;
            }
            expectNoGraphicsIncludes(entry.path());
            ++files;
        }
    }
    EXPECT_GT(files, 20);
}

TEST(ViewerDependency, ViewerModelFilesKnowNothingOfGraphics)
{
    const std::filesystem::path viewer = std::filesystem::path(MASSE_SOURCE_DIR) / "src" / "viewer";
    for (const char* stem :
         {"Camera", "Picking", "PickSpring", "StepScheduler", "RateMeter", "FramePacing", "MassScalars",
          "ScreenRegions", "ViewerSession", "SceneSnapshot", "SceneGeometry", "Controls", "ScreenLayout", "ColourBar"})
    {
        for (const char* extension : {".h", ".cpp"})
        {
            const std::filesystem::path file = viewer / (std::string(stem) + extension);
            ASSERT_TRUE(std::filesystem::exists(file)) << file;
            expectNoGraphicsIncludes(file);
        }
    }
}
