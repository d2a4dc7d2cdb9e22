// Checks a viewer screenshot for the paper's colours where they belong (sections 8 and 9): red masses on the sheet,
// green ones where it touches an obstacle, and a black face on the obstacle it touches. The viewer writes, beside
// the PNG, where the sheet and each obstacle are in the picture (--regions).
//
// usage: viewer_screenshot_check SCREENSHOT.png REGIONS.json contact|no-contact|docked
// docked: a frame with the panel shown; the panel's column must not cover the sheet or an obstacle, and all of the
// sheet must be in the scene's view.
// Prints the counts; exits 0 when the picture matches the expectation, 1 when it does not, 2 for bad arguments.

#include <nlohmann/json.hpp>
#include <stb_image.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>

namespace
{
struct Box
{
    int left = 0;
    int top = 0;
    int right = 0;
    int bottom = 0;
};

Box toBox(const nlohmann::json& value, int width, int height)
{
    if (!value.is_array())
    {
        return {};
    }
    Box box{int(value[0].get<double>()), int(value[1].get<double>()), int(value[2].get<double>()) + 1,
            int(value[3].get<double>()) + 1};
    box.right = std::min(box.right, width);
    box.bottom = std::min(box.bottom, height);
    return box;
}

struct Image
{
    int width = 0;
    int height = 0;
    unsigned char* rgb = nullptr;
    const unsigned char* at(int x, int y) const
    {
        return rgb + 3 * (std::size_t(y) * std::size_t(width) + std::size_t(x));
    }
};

// "Near pure": the shading never produces these (lit colours keep an ambient floor; nothing else is saturated).
bool isRed(const unsigned char* p)
{
    return p[0] > 200 && p[1] < 60 && p[2] < 60;
}
bool isGreen(const unsigned char* p)
{
    return p[1] > 200 && p[0] < 60 && p[2] < 60;
}
bool isBlack(const unsigned char* p)
{
    return p[0] < 24 && p[1] < 24 && p[2] < 24;
}

template <typename Test> int count(const Image& image, const Box& box, Test test)
{
    int n = 0;
    for (int y = box.top; y < box.bottom; ++y)
    {
        for (int x = box.left; x < box.right; ++x)
        {
            n += test(image.at(x, y)) ? 1 : 0;
        }
    }
    return n;
}
} // namespace

int main(int argc, char** argv)
{
    const std::string mode = argc == 4 ? argv[3] : "";
    if (mode != "contact" && mode != "no-contact" && mode != "docked")
    {
        std::fprintf(stderr, "usage: %s SCREENSHOT.png REGIONS.json contact|no-contact|docked\n", argv[0]);
        return 2;
    }
    const bool expectContact = mode == "contact";
    Image image;
    int channels = 0;
    image.rgb = stbi_load(argv[1], &image.width, &image.height, &channels, 3);
    if (image.rgb == nullptr)
    {
        std::fprintf(stderr, "%s: cannot read the PNG (%s)\n", argv[1], stbi_failure_reason());
        return 2;
    }
    std::ifstream in(argv[2]);
    const nlohmann::json regions = nlohmann::json::parse(in, nullptr, false);
    if (regions.is_discarded() || !regions.contains("sheet"))
    {
        std::fprintf(stderr, "%s: not a regions file\n", argv[2]);
        return 2;
    }
    bool ok = true;
    auto expect = [&ok](bool condition, const std::string& what)
    {
        std::printf("%s %s\n", condition ? "ok  " : "FAIL", what.c_str());
        ok = ok && condition;
    };
    expect(regions["width"] == image.width && regions["height"] == image.height,
           "the picture is the size the regions describe");

    const Box whole{0, 0, image.width, image.height};
    const Box sheet = toBox(regions["sheet"], image.width, image.height);
    const int red = count(image, sheet, isRed);
    const int green = count(image, sheet, isGreen);
    const int greenAnywhere = count(image, whole, isGreen);
    const int blackAnywhere = count(image, whole, isBlack);
    std::printf("sheet box [%d %d %d %d]: %d red, %d green pixels; whole picture: %d green, %d black\n", sheet.left,
                sheet.top, sheet.right, sheet.bottom, red, green, greenAnywhere, blackAnywhere);
    expect(red >= 50, "red masses on the sheet (>= 50 px)");

    int touchedObstacles = 0;
    int blackOnTouched = 0;
    for (const auto& obstacle : regions["obstacles"])
    {
        const Box box = toBox(obstacle["box"], image.width, image.height);
        const int black = count(image, box, isBlack);
        const bool touched = obstacle["touched"].get<bool>();
        std::printf("obstacle %s%s: %d black pixels in its box\n", obstacle["name"].get<std::string>().c_str(),
                    touched ? " (touched)" : "", black);
        if (touched)
        {
            ++touchedObstacles;
            blackOnTouched += black;
        }
    }
    if (mode == "docked")
    {
        const bool hasPanel = regions.contains("panel") && regions["panel"].is_array();
        expect(hasPanel, "the panel has its own column");
        const Box panel = hasPanel ? toBox(regions["panel"], image.width, image.height) : whole;
        auto overlaps = [](const Box& a, const Box& b)
        { return a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom; };
        std::printf("panel box [%d %d %d %d]\n", panel.left, panel.top, panel.right, panel.bottom);
        expect(!overlaps(sheet, panel), "the panel does not cover the sheet");
        expect(regions.value("sheet_whole", false), "all of the sheet is in the view");
        for (const auto& obstacle : regions["obstacles"])
        {
            if (obstacle["box"].is_array())
            {
                expect(!overlaps(toBox(obstacle["box"], image.width, image.height), panel),
                       "the panel does not cover " + obstacle["name"].get<std::string>());
            }
        }
        // The column is the panel's: no red mass drawn under it.
        expect(count(image, panel, isRed) == 0, "no sheet drawn in the panel's column");
    }
    else if (expectContact)
    {
        expect(touchedObstacles > 0, "an obstacle is touched");
        expect(green >= 30, "green masses in contact on the sheet (>= 30 px)");
        expect(blackOnTouched >= 500, "a black face on the touched obstacle (>= 500 px)");
    }
    else
    {
        expect(touchedObstacles == 0, "no obstacle is touched");
        expect(greenAnywhere == 0, "no green (no mass in contact)");
        expect(blackAnywhere == 0, "no black (no face touched)");
    }
    stbi_image_free(image.rgb);
    return ok ? 0 : 1;
}
