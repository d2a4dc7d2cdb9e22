#pragma once
/// Hands one frame's batch of input events (InputQueue::takeFrame) to Dear ImGui's io. Called before NewFrame only,
/// so the key and modifier states ImGui reads stay fixed from NewFrame to Render.

#include "InputEvents.h"

#include <vector>

namespace masse::viewer
{
/// Sets ImGui's key map to the key slots of InputEvents.h (letters upper case, special keys at 256 + GLUT code).
void mapImGuiKeys();
void applyToImGui(const std::vector<InputEvent>& batch);
} // namespace masse::viewer
