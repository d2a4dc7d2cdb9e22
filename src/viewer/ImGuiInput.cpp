#include "ImGuiInput.h"

#include <GL/freeglut.h>
#include <imgui.h>

namespace masse::viewer
{
void mapImGuiKeys()
{
    ImGuiIO& io = ImGui::GetIO();
    io.KeyMap[ImGuiKey_Tab] = '\t';
    io.KeyMap[ImGuiKey_LeftArrow] = specialKeyBase + GLUT_KEY_LEFT;
    io.KeyMap[ImGuiKey_RightArrow] = specialKeyBase + GLUT_KEY_RIGHT;
    io.KeyMap[ImGuiKey_UpArrow] = specialKeyBase + GLUT_KEY_UP;
    io.KeyMap[ImGuiKey_DownArrow] = specialKeyBase + GLUT_KEY_DOWN;
    io.KeyMap[ImGuiKey_PageUp] = specialKeyBase + GLUT_KEY_PAGE_UP;
    io.KeyMap[ImGuiKey_PageDown] = specialKeyBase + GLUT_KEY_PAGE_DOWN;
    io.KeyMap[ImGuiKey_Home] = specialKeyBase + GLUT_KEY_HOME;
    io.KeyMap[ImGuiKey_End] = specialKeyBase + GLUT_KEY_END;
    io.KeyMap[ImGuiKey_Insert] = specialKeyBase + GLUT_KEY_INSERT;
    io.KeyMap[ImGuiKey_Delete] = 127;
    io.KeyMap[ImGuiKey_Backspace] = 8;
    io.KeyMap[ImGuiKey_Space] = ' ';
    io.KeyMap[ImGuiKey_Enter] = 13;
    io.KeyMap[ImGuiKey_Escape] = 27;
    io.KeyMap[ImGuiKey_KeyPadEnter] = 13;
    io.KeyMap[ImGuiKey_A] = 'A';
    io.KeyMap[ImGuiKey_C] = 'C';
    io.KeyMap[ImGuiKey_V] = 'V';
    io.KeyMap[ImGuiKey_X] = 'X';
    io.KeyMap[ImGuiKey_Y] = 'Y';
    io.KeyMap[ImGuiKey_Z] = 'Z';
}

void applyToImGui(const std::vector<InputEvent>& batch)
{
    ImGuiIO& io = ImGui::GetIO();
    for (const InputEvent& event : batch)
    {
        switch (event.kind)
        {
        case InputKind::KeyDown:
        case InputKind::KeyUp:
            if (event.key < 0 || event.key >= keySlotCount)
            {
                break;
            }
            if (event.kind == InputKind::KeyUp && !io.KeysDown[event.key] && event.key < specialKeyBase)
            {
                // GLUT names a released key by the character it gives now: '_' goes down and '-' comes up when
                // Shift was let go first. Whatever character key went down is up again.
                for (int slot = 0; slot < specialKeyBase; ++slot)
                {
                    io.KeysDown[slot] = false;
                }
                break;
            }
            io.KeysDown[event.key] = event.kind == InputKind::KeyDown;
            break;
        case InputKind::Character:
            io.AddInputCharacter(event.character);
            break;
        case InputKind::MouseDown:
        case InputKind::MouseUp:
            io.MousePos = ImVec2(float(event.x), float(event.y));
            if (event.button >= 0 && event.button < 3)
            {
                io.MouseDown[event.button] = event.kind == InputKind::MouseDown;
            }
            break;
        case InputKind::MouseMove:
            io.MousePos = ImVec2(float(event.x), float(event.y));
            break;
        case InputKind::Wheel:
            io.MousePos = ImVec2(float(event.x), float(event.y));
            io.MouseWheel += float(event.wheel);
            break;
        }
        if (event.kind != InputKind::MouseMove && event.kind != InputKind::Wheel)
        {
            io.KeyCtrl = event.modifiers.ctrl;
            io.KeyShift = event.modifiers.shift;
            io.KeyAlt = event.modifiers.alt;
        }
    }
}
} // namespace masse::viewer
