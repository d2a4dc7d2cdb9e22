// The viewer's input queue: a frame's batch never holds two changes of one key or button, nor a key press under
// other modifiers than the events that follow it, so Dear ImGui (which reads states once a frame) sees every press,
// release and Ctrl+letter distinctly.

#include "viewer/InputEvents.h"

#include <gtest/gtest.h>

namespace masse::viewer
{
namespace
{
InputEvent key(InputKind kind, int slot, Modifiers modifiers = {})
{
    InputEvent event;
    event.kind = kind;
    event.key = slot;
    event.modifiers = modifiers;
    return event;
}

InputEvent character(unsigned c, Modifiers modifiers = {})
{
    InputEvent event;
    event.kind = InputKind::Character;
    event.character = c;
    event.modifiers = modifiers;
    return event;
}

/// Frames needed to drain the queue, and the batches.
std::vector<std::vector<InputEvent>> drain(InputQueue& queue)
{
    std::vector<std::vector<InputEvent>> frames;
    while (!queue.empty())
    {
        frames.push_back(queue.takeFrame());
        if (frames.back().empty())
        {
            ADD_FAILURE() << "a frame took nothing from a non-empty queue";
            break;
        }
    }
    return frames;
}
} // namespace

TEST(InputQueue, PressAndReleaseOfOneKeyFallInDifferentFrames)
{
    InputQueue queue;
    queue.push(key(InputKind::KeyDown, 'A'));
    queue.push(character('a'));
    queue.push(key(InputKind::KeyUp, 'A'));
    const auto frames = drain(queue);
    ASSERT_EQ(frames.size(), 2u);
    EXPECT_EQ(frames[0].size(), 2u); // the press and its character together
    EXPECT_EQ(frames[1][0].kind, InputKind::KeyUp);
}

TEST(InputQueue, CtrlAAndTheLetterTypedAfterItNeverShareAFrame)
{
    const Modifiers ctrl{true, false, false};
    const Modifiers shift{false, true, false};
    InputQueue queue;
    queue.push(key(InputKind::KeyDown, specialKeyBase + 114, ctrl)); // Ctrl itself
    queue.push(key(InputKind::KeyDown, 'A', ctrl));
    queue.push(key(InputKind::KeyUp, 'A', ctrl));
    queue.push(key(InputKind::KeyUp, specialKeyBase + 114, {}));
    queue.push(key(InputKind::KeyDown, specialKeyBase + 112, shift));
    queue.push(key(InputKind::KeyDown, 'X', shift));
    queue.push(character('X', shift));
    const auto frames = drain(queue);
    for (const auto& frame : frames)
    {
        // Within a frame every event after a key press carries the press's modifiers: ImGui's one KeyCtrl/KeyShift
        // per frame is then right for the press.
        bool pressed = false;
        Modifiers atPress;
        for (const InputEvent& event : frame)
        {
            if (pressed)
            {
                EXPECT_EQ(event.modifiers, atPress);
            }
            if (event.kind == InputKind::KeyDown)
            {
                pressed = true;
                atPress = event.modifiers;
            }
        }
    }
    // Ctrl+A's frame holds no character, and 'X' arrives with Shift alone.
    for (const auto& frame : frames)
    {
        for (const InputEvent& event : frame)
        {
            if (event.kind == InputKind::Character)
            {
                EXPECT_FALSE(event.modifiers.ctrl);
            }
        }
    }
    EXPECT_GE(frames.size(), 4u);
}

TEST(InputQueue, AtMostOneKeyPressAFrameAndMouseMovesJoinFreely)
{
    InputQueue queue;
    for (char c : {'A', 'B', 'C'})
    {
        queue.push(key(InputKind::KeyDown, c));
        InputEvent move;
        move.kind = InputKind::MouseMove;
        move.x = c;
        queue.push(move);
    }
    const auto frames = drain(queue);
    ASSERT_EQ(frames.size(), 3u);
    for (const auto& frame : frames)
    {
        EXPECT_EQ(frame.size(), 2u);
    }
}

TEST(InputQueue, AClickTakesTwoFrames)
{
    InputQueue queue;
    InputEvent down;
    down.kind = InputKind::MouseDown;
    InputEvent up = down;
    up.kind = InputKind::MouseUp;
    queue.push(down);
    queue.push(up);
    EXPECT_EQ(drain(queue).size(), 2u);
}

TEST(InputQueue, CtrlLetterCodesMapToTheLetterSlot)
{
    EXPECT_EQ(characterKeySlot(1), 'A'); // GLUT reports Ctrl+A as 1
    EXPECT_EQ(characterKeySlot('a'), 'A');
    EXPECT_EQ(characterKeySlot('A'), 'A');
    EXPECT_EQ(characterKeySlot('\t'), '\t'); // Tab, not Ctrl+I
    EXPECT_EQ(characterKeySlot('_'), '_');
}
} // namespace masse::viewer
