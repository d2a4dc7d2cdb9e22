#include "Screenshot.h"

#include "GlHeaders.h"

#include "scene/output/AtomicFile.h"

#include <stb_image_write.h>

#include <algorithm>
#include <stdexcept>

namespace masse::viewer
{
std::vector<std::uint8_t> readFrame(const Viewport& viewport)
{
    const std::size_t rowBytes = 3 * std::size_t(viewport.width);
    std::vector<std::uint8_t> bottomUp(rowBytes * std::size_t(viewport.height));
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, viewport.width, viewport.height, GL_RGB, GL_UNSIGNED_BYTE, bottomUp.data());
    // GL counts rows from the bottom; images count them from the top.
    std::vector<std::uint8_t> topDown(bottomUp.size());
    for (int row = 0; row < viewport.height; ++row)
    {
        const std::size_t from = rowBytes * std::size_t(viewport.height - 1 - row);
        std::copy_n(bottomUp.begin() + std::ptrdiff_t(from), rowBytes,
                    topDown.begin() + std::ptrdiff_t(rowBytes * std::size_t(row)));
    }
    return topDown;
}

void writePng(const std::string& path, const std::vector<std::uint8_t>& rgb, const Viewport& viewport)
{
    std::string encoded;
    stbi_write_png_compression_level = 9;
    const int ok = stbi_write_png_to_func(
        [](void* context, void* data, int size)
        { static_cast<std::string*>(context)->append(static_cast<const char*>(data), std::size_t(size)); },
        &encoded, viewport.width, viewport.height, 3, rgb.data(), 3 * viewport.width);
    if (!ok)
    {
        throw std::runtime_error("screenshot: cannot encode " + path + " as PNG");
    }
    scene::writeFileAtomically(path, encoded);
}
} // namespace masse::viewer
