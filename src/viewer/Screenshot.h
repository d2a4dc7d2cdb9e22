#pragma once
/// Saving what the window shows as a PNG, so the viewer can be checked without anyone looking at it.

#include "Camera.h"

#include <cstdint>
#include <string>
#include <vector>

namespace masse::viewer
{
/// RGB pixels of the frame just drawn (the back buffer, before it is swapped), top row first.
std::vector<std::uint8_t> readFrame(const Viewport& viewport);

/// Encodes RGB pixels (top row first) as a PNG and writes it atomically; throws std::runtime_error naming the file.
void writePng(const std::string& path, const std::vector<std::uint8_t>& rgb, const Viewport& viewport);
} // namespace masse::viewer
