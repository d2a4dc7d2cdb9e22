#pragma once
/// The registry of obstacle shapes: one entry a shape, listed in one table (ShapeRegistry.cpp), as the reports are in
/// scene/reports/ReportRegistry.cpp. The scene reader takes `obstacles[].type` from its names and reads each shape's
/// keys through it; the obstacle's solid, the guard's bound on how fast a turning obstacle's surface moves and the
/// check that a mould is closed all ask the entry. A shape is its own file in this folder (its parameters, reader,
/// solid, reach and face numbering), its line in the table and its row in data/scenes/README.md's `obstacles[]`
/// table (docs/development.md).

#include "scene/json/JsonObject.h"

#include "bridge/ObstacleShape.h"

#include "core/Types.h"

#include <any>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace masse::scene
{
struct ShapeEntry
{
    std::string_view name; ///< `obstacles[].type` in scene files
    /// Whether its surface is closed by construction; an open one (a mesh) is checked edge by edge before it serves
    /// as a forming mould, whose cavity the sheet must seal.
    bool closed = true;
    /// Reads the shape's own keys of an obstacle's object with JsonObject's accessors (so a bad value gets the
    /// reader's message naming `obstacles[i].key`) into its parameters; a file it names is taken relative to
    /// `baseDirectory`.
    std::any (*read)(const JsonObject& obstacle, const std::string& baseDirectory) = nullptr;
    /// The solid in the obstacle's frame for its parameters, in the faces' numbering the shape documents; `obstacle`
    /// names the obstacle in messages (a mesh file that will not load).
    bridge::ObstacleShape (*solid)(const std::any& parameters, const std::string& obstacle) = nullptr;
    /// m, how far a point of the solid can be from its origin: turning about it moves the surface this fast per
    /// radian a second. The divergence guard's speed bound takes it; it may be generous, never short.
    Real (*reach)(const std::any& parameters) = nullptr;
    /// The file the solid is read from, for messages ("" for a shape made from its keys alone).
    std::string (*file)(const std::any& parameters) = nullptr;
};

/// An obstacle's shape as a scene gives it: its registered entry and the parameters its reader made.
struct ShapeSpec
{
    const ShapeEntry* entry = nullptr;
    std::any parameters;

    bridge::ObstacleShape solid(const std::string& obstacle) const { return entry->solid(parameters, obstacle); }
    Real reach() const { return entry->reach(parameters); }
    std::string file() const { return entry->file ? entry->file(parameters) : std::string(); }
};

/// Every registered shape, in the table's order: the order in which messages and documents list them.
std::span<const ShapeEntry* const> shapes();
/// Their names, for the scene reader's choice and its message (which suggests the nearest).
std::vector<std::string> shapeNames();
/// The registered shape of `name`; the name must be one of shapeNames().
const ShapeEntry& shapeNamed(std::string_view name);
} // namespace masse::scene
