#pragma once
/// The viewer's colours in one place. The paper's (section 8, 9): masses red, green once in contact, and a
/// polyhedron face a mass touches black. Nothing else drawn comes near pure red, green or black, so those three
/// stay readable, and the screenshot test can count them.

#include <algorithm>
#include <array>

namespace masse::viewer
{
struct Rgb
{
    float r = 0;
    float g = 0;
    float b = 0;
};

namespace palette
{
inline constexpr Rgb mass{1, 0, 0};
inline constexpr Rgb massInContact{0, 1, 0};
inline constexpr Rgb massInSelfContact{1, 0.3f, 1}; ///< touching another part of the sheet: magenta
inline constexpr Rgb touchedFace{0, 0, 0};
inline constexpr Rgb pinnedMass{0.25f, 0.45f, 1};
inline constexpr Rgb spring{0.80f, 0.80f, 0.86f};
inline constexpr Rgb pick{1, 0.85f, 0.1f};               ///< the picked mass and the mouse's spring
inline constexpr Rgb scriptedGrab{0.2f, 0.9f, 0.95f};    ///< a scene script's grab
inline constexpr Rgb thinnest{1, 0.15f, 0.6f};           ///< the sheet's thinnest point (material scenes)
inline constexpr Rgb section{1, 0.55f, 0.1f};            ///< the live section's line across the sheet
inline constexpr Rgb missingScalar{0.55f, 0.55f, 0.55f}; ///< a scalar the scene does not have
inline constexpr Rgb heaterOn{1, 0.47f, 0.12f};          ///< a radiant heater switched on: glowing orange
inline constexpr Rgb heaterOff{0.30f, 0.28f, 0.27f};     ///< switched off: dark, but lit well above the touched black
inline constexpr Rgb heaterOutline{0.95f, 0.85f, 0.55f};
inline constexpr Rgb hotAirZone{0.95f, 0.55f, 0.70f}; ///< the outline of a hot-air zone's box
/// Bullet's twin of the sheet (--compare): pale violet links and nodes, its nodes in contact a paler green.
inline constexpr Rgb ghost{0.78f, 0.62f, 0.98f};
inline constexpr Rgb ghostInContact{0.62f, 0.98f, 0.70f};
inline constexpr Rgb background{0.23f, 0.26f, 0.31f};
inline constexpr Rgb floor{0.52f, 0.54f, 0.58f};
inline constexpr Rgb floorGrid{0.44f, 0.46f, 0.50f};
inline constexpr Rgb wall{0.62f, 0.60f, 0.56f};
inline constexpr Rgb edge{0.30f, 0.32f, 0.36f};
/// Obstacles in turn: muted, light and far from the mass colours.
inline constexpr std::array<Rgb, 4> obstacles{Rgb{0.60f, 0.68f, 0.82f}, Rgb{0.85f, 0.74f, 0.52f},
                                              Rgb{0.72f, 0.62f, 0.80f}, Rgb{0.62f, 0.78f, 0.76f}};
} // namespace palette

/// Viridis (perceptually uniform, readable in grey), for surfaces coloured by a scalar; t in [0, 1].
inline Rgb viridis(float t)
{
    static constexpr std::array<Rgb, 9> stops{
        Rgb{0.267f, 0.005f, 0.329f}, Rgb{0.282f, 0.141f, 0.458f}, Rgb{0.254f, 0.265f, 0.530f},
        Rgb{0.207f, 0.372f, 0.553f}, Rgb{0.164f, 0.471f, 0.558f}, Rgb{0.128f, 0.567f, 0.551f},
        Rgb{0.135f, 0.659f, 0.518f}, Rgb{0.478f, 0.821f, 0.318f}, Rgb{0.993f, 0.906f, 0.144f}};
    const float x = std::clamp(t, 0.0f, 1.0f) * float(stops.size() - 1);
    const std::size_t i = std::min(std::size_t(x), stops.size() - 2);
    const float f = x - float(i);
    const Rgb& a = stops[i];
    const Rgb& b = stops[i + 1];
    return {a.r + f * (b.r - a.r), a.g + f * (b.g - a.g), a.b + f * (b.b - a.b)};
}
} // namespace masse::viewer
