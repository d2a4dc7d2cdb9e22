#pragma once
/// The window's input as a queue of events, handed to the UI a frame's worth at a time. Dear ImGui 1.86 (Debian 12)
/// reads key, button and modifier *states* once per frame and asserts that the modifiers do not change between
/// NewFrame and Render; freeglut reports events whenever the loop polls. Queued here and released in frame-sized
/// batches before NewFrame, no event can land mid-frame, and a press and its release (or Ctrl+A and the letter typed
/// after it) fall in different frames, so none is lost or merged. This is the trickling input queue ImGui 1.87 added
/// (io.AddKeyEvent), built for the ImGui the project has. No GL, no ImGui: the tests drive it directly.

#include <cstdint>
#include <deque>
#include <vector>

namespace masse::viewer
{
/// Modifier keys held when an event happened.
struct Modifiers
{
    bool ctrl = false;
    bool shift = false;
    bool alt = false;
    bool operator==(const Modifiers&) const = default;
};

enum class InputKind
{
    KeyDown,   ///< `key` went down (a slot, see InputEvent::key)
    KeyUp,     ///< `key` went up
    Character, ///< `character` was typed (comes right after its KeyDown)
    MouseDown, ///< `button` (0 left, 1 right, 2 middle) at x, y
    MouseUp,
    MouseMove, ///< the cursor is at x, y
    Wheel,     ///< `wheel` notches (positive: away from the user) at x, y
};

struct InputEvent
{
    InputKind kind = InputKind::MouseMove;
    /// Key slot: a character key by its upper-case code (letters) or its own code (0..255); a special key (arrows,
    /// F-keys, the modifier keys themselves) as 256 + its GLUT code.
    int key = 0;
    unsigned character = 0;
    int button = 0;
    int wheel = 0;
    int x = 0;
    int y = 0;
    Modifiers modifiers; ///< held while the event happened (for a modifier key's own event: after it)
};

/// First slot of the special keys (GLUT's codes are offset by this, as ImGui's GLUT backend maps them).
constexpr int specialKeyBase = 256;
/// Slots the ImGui key-state array has (ImGuiIO::KeysDown).
constexpr int keySlotCount = 512;

/// The key slot of a GLUT character key: letters (and Ctrl+letter, which GLUT reports as 1..26) by their upper case.
int characterKeySlot(unsigned char c);

class InputQueue
{
public:
    void push(const InputEvent& event) { m_events.push_back(event); }
    bool empty() const { return m_events.empty(); }
    std::size_t size() const { return m_events.size(); }

    /// The events for the next frame, taken off the queue. A batch ends before an event that would change a key or
    /// button already changed in it, before a second key press, and before a change of the modifiers once a key
    /// press is in it: within one frame ImGui sees one state per key and one set of modifiers, and these keep every
    /// press, release and modifier distinct. Mouse moves and wheel turns always join the batch.
    std::vector<InputEvent> takeFrame();

private:
    std::deque<InputEvent> m_events;
};
} // namespace masse::viewer
