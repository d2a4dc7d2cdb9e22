#pragma once
/// The divergence guard's bounds for a scene (see core/DivergenceGuard.h): how fast anything in it can sensibly
/// move, from its gravity, air, room and script.

#include "scene/SceneSpec.h"

#include "core/DivergenceGuard.h"

namespace masse::scene
{
/// Margin between the fastest speed the scene's causes can give a mass and the speed the guard stops at.
inline constexpr Real guardSpeedMargin = 100;

/// m/s, the fastest any kinematic obstacle's surface moves along its path or its scripted moves.
Real fastestObstacleSpeed(const SceneSpec& spec);

/// m/s, the fastest speed gravity (with the air's drag and the room's height), the scripted motions (obstacles, grab
/// targets and the pull of grabs) and a forming pressure can give a mass of `lightestMass` kg.
Real fastestScriptedSpeed(const SceneSpec& spec, Real lightestMass);

/// The guard's settings for a scene whose lightest mass is `lightestMass` kg.
GuardSettings guardSettings(const SceneSpec& spec, Real lightestMass);
} // namespace masse::scene
