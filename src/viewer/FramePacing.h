#pragma once
/// When the window draws a frame. The simulation runs on its own thread and shares the cores with the rasteriser (under
/// Xvfb, Mesa's software rasteriser takes some 20 ms for a 64x2x64 frame), so a frame that would show the same
/// picture as the last one is not worth drawing while the scene runs.

#include "core/Types.h"

namespace masse::viewer
{
struct FrameMoment
{
    bool mustDraw = false;   ///< the first or last frame, a capture's frame, or input waiting
    bool paused = false;     ///< the scene is paused (the simulation leaves the cores to the window)
    bool newPicture = false; ///< a snapshot the last frame did not show
    Real sinceLastFrame = 0; ///< s since the last frame started
};

/// While the scene runs: a new picture at most every `runningInterval` (0.8 of 1/30 s: snapshots come at the scene's
/// steps, some 33 a second for a forming scene keeping real time at dt = 0.03 s, and not evenly, as a step that
/// refactors takes longer; the margin lets a snapshot that comes a little early be drawn rather than wait for the
/// next); the same picture only every `idleInterval`, which keeps the panel's own timers (a text cursor's blink) alive.
/// Paused: up to 60 frames a second.
struct FramePacing
{
    Real runningInterval = Real(0.8) / 30;
    Real idleInterval = Real(0.25);
    Real pausedInterval = Real(1) / 60;
};

bool frameDue(const FrameMoment& moment, const FramePacing& pacing = {});
} // namespace masse::viewer
