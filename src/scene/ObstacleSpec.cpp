#include "scene/ObstacleSpec.h"

#include "bridge/StlFile.h"

#include <cmath>

namespace masse::scene
{
Eigen::Quaternion<Real> rotationFromDegrees(const Vec3& degrees)
{
    const Vec3 radians = degrees * (M_PI / 180.0);
    return Eigen::Quaternion<Real>(Eigen::AngleAxis<Real>(radians.z(), Vec3::UnitZ()) *
                                   Eigen::AngleAxis<Real>(radians.y(), Vec3::UnitY()) *
                                   Eigen::AngleAxis<Real>(radians.x(), Vec3::UnitX()));
}

bridge::ObstacleBody obstacleBody(const ObstacleSpec& spec)
{
    bridge::ObstacleBody body;
    body.name = spec.name;
    body.path.rest = {spec.position, spec.orientation};
    body.path.keys = spec.path;
    bridge::ObstacleShape& shape = body.shape;
    switch (spec.kind)
    {
    case ObstacleKind::Box:
        shape.kind = bridge::ShapeKind::Box;
        shape.halfExtents = spec.halfExtents;
        break;
    case ObstacleKind::Prism:
        shape.kind = bridge::ShapeKind::Prism;
        shape.prismWidth = spec.prismWidth;
        shape.prismHeight = spec.prismHeight;
        shape.prismLength = spec.prismLength;
        shape.prismApex = spec.prismApex;
        break;
    case ObstacleKind::Hull:
        shape.kind = bridge::ShapeKind::Hull;
        shape.hullPoints = spec.hullPoints;
        break;
    case ObstacleKind::Mesh:
        shape.kind = bridge::ShapeKind::Mesh;
        shape.mesh = bridge::loadMeshFile(spec.meshPath, spec.name);
        for (Vec3& v : shape.mesh.vertices)
        {
            v = spec.meshScale * v;
        }
        break;
    }
    return body;
}
} // namespace masse::scene
