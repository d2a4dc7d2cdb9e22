#include "InputEvents.h"

#include <set>

namespace masse::viewer
{
int characterKeySlot(unsigned char c)
{
    if (c >= 1 && c <= 26 && c != '\t' && c != '\r' && c != '\b')
    {
        return 'A' + c - 1;
    }
    if (c >= 'a' && c <= 'z')
    {
        return c - 'a' + 'A';
    }
    return c;
}

std::vector<InputEvent> InputQueue::takeFrame()
{
    std::vector<InputEvent> batch;
    std::set<int> changed; // key slots, and buttons as -1 - button
    bool keyPressed = false;
    Modifiers pressModifiers;
    while (!m_events.empty())
    {
        const InputEvent& event = m_events.front();
        const bool carriesModifiers = event.kind != InputKind::MouseMove && event.kind != InputKind::Wheel;
        if (keyPressed && carriesModifiers && !(event.modifiers == pressModifiers))
        {
            break;
        }
        switch (event.kind)
        {
        case InputKind::KeyDown:
        case InputKind::KeyUp:
            if (changed.count(event.key) || (event.kind == InputKind::KeyDown && keyPressed))
            {
                return batch;
            }
            changed.insert(event.key);
            if (event.kind == InputKind::KeyDown)
            {
                keyPressed = true;
                pressModifiers = event.modifiers;
            }
            break;
        case InputKind::MouseDown:
        case InputKind::MouseUp:
            if (changed.count(-1 - event.button))
            {
                return batch;
            }
            changed.insert(-1 - event.button);
            break;
        case InputKind::Character:
        case InputKind::MouseMove:
        case InputKind::Wheel:
            break;
        }
        batch.push_back(event);
        m_events.pop_front();
    }
    return batch;
}
} // namespace masse::viewer
