#include "Display.h"

#include "core/InputError.h"

#include <X11/Xlib.h>

#include <cstdlib>

namespace masse::viewer
{
DisplayConnection::DisplayConnection()
{
    const char* name = std::getenv("DISPLAY");
    if (name == nullptr || *name == '\0')
    {
        m_problem = "DISPLAY is not set";
        return;
    }
    m_display = XOpenDisplay(name);
    if (m_display == nullptr)
    {
        m_problem = std::string("cannot open display '") + name + "'";
    }
}

DisplayConnection::~DisplayConnection()
{
    if (m_display != nullptr)
    {
        XCloseDisplay(static_cast<Display*>(m_display));
    }
}

void DisplayConnection::require() const
{
    if (connected())
    {
        return;
    }
    throw InputError("view: no display (" + m_problem +
                     "). The viewer opens a window; without a screen, run it under a virtual one: "
                     "xvfb-run -a masse view [SCENE] ..., or run headless: masse run SCENE, masse demo --headless");
}
} // namespace masse::viewer
