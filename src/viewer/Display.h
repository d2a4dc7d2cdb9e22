#pragma once
/// Whether the viewer can open a window. freeglut ends the process when it cannot open a display, so the check
/// comes first, with a message that says how to run without one.
///
/// The check's connection stays open until the window is up: an X server whose last client disconnects resets
/// itself (Xvfb does, by default), and a connection attempted during the reset is refused, so closing the check's
/// connection just before freeglut opens its own would make the viewer fail now and then.

#include <memory>
#include <string>

namespace masse::viewer
{
class DisplayConnection
{
public:
    /// Tries to connect to $DISPLAY.
    DisplayConnection();
    ~DisplayConnection();
    DisplayConnection(const DisplayConnection&) = delete;
    DisplayConnection& operator=(const DisplayConnection&) = delete;

    bool connected() const { return m_display != nullptr; }
    /// Why there is no connection ("" when connected).
    const std::string& problem() const { return m_problem; }
    /// Throws InputError when not connected, naming the headless commands and xvfb-run.
    void require() const;

private:
    void* m_display = nullptr;
    std::string m_problem;
};
} // namespace masse::viewer
