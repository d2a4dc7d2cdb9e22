#include "scene/shapes/ShapeRegistry.h"

#include "core/InputError.h"

namespace masse::scene
{
// Each entry is defined in its shape's own file, named beside it in the table.
extern const ShapeEntry boxShape;
extern const ShapeEntry prismShape;
extern const ShapeEntry hullShape;
extern const ShapeEntry meshShape;

namespace
{
// The order in which the scene reader's message and the documents list the shapes; the first is the default type.
constexpr const ShapeEntry* shapeTable[] = {
    &boxShape,   // BoxShape.cpp
    &prismShape, // PrismShape.cpp
    &hullShape,  // HullShape.cpp
    &meshShape,  // MeshShape.cpp
};
} // namespace

std::span<const ShapeEntry* const> shapes()
{
    return shapeTable;
}

std::vector<std::string> shapeNames()
{
    std::vector<std::string> names;
    for (const ShapeEntry* shape : shapeTable)
    {
        names.emplace_back(shape->name);
    }
    return names;
}

const ShapeEntry& shapeNamed(std::string_view name)
{
    for (const ShapeEntry* shape : shapeTable)
    {
        if (shape->name == name)
        {
            return *shape;
        }
    }
    throw InputError("unknown obstacle shape '" + std::string(name) + "'");
}
} // namespace masse::scene
