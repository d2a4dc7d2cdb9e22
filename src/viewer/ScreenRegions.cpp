#include "ScreenRegions.h"

#include "SceneSnapshot.h"

#include <algorithm>
#include <limits>

namespace masse::viewer
{
std::optional<ScreenBox> screenBox(const OrbitCamera& camera, const Viewport& viewport, const std::vector<Vec3>& points)
{
    const Real infinity = std::numeric_limits<Real>::infinity();
    ScreenBox box{infinity, infinity, -infinity, -infinity};
    for (const Vec3& point : points)
    {
        const std::optional<Vec2> pixel = camera.project(point, viewport);
        if (!pixel)
        {
            return std::nullopt;
        }
        box.left = std::min(box.left, pixel->x());
        box.right = std::max(box.right, pixel->x());
        box.top = std::min(box.top, pixel->y());
        box.bottom = std::max(box.bottom, pixel->y());
    }
    box.left = std::max(box.left, Real(0));
    box.top = std::max(box.top, Real(0));
    box.right = std::min(box.right, Real(viewport.width));
    box.bottom = std::min(box.bottom, Real(viewport.height));
    if (points.empty() || box.left >= box.right || box.top >= box.bottom)
    {
        return std::nullopt;
    }
    return box;
}

std::vector<Vec3> obstacleVertices(const bridge::Obstacle& obstacle)
{
    std::vector<Vec3> world;
    world.reserve(obstacle.geometry.vertices.size());
    for (const Vec3& local : obstacle.geometry.vertices)
    {
        world.push_back(obstacle.pose.position + obstacle.pose.orientation * local);
    }
    return world;
}

namespace
{
nlohmann::json toJson(const std::optional<ScreenBox>& box)
{
    if (!box)
    {
        return nullptr;
    }
    return {box->left, box->top, box->right, box->bottom};
}
} // namespace

nlohmann::json screenRegions(scene::Scene& scene, const OrbitCamera& camera, const Viewport& viewport)
{
    nlohmann::json regions;
    regions["width"] = viewport.width;
    regions["height"] = viewport.height;
    regions["sheet"] = toJson(screenBox(camera, viewport, scene.system().particles.position));
    const bridge::BulletEnvironment& environment = scene.environment();
    const std::vector<std::pair<int, int>>& touched = scene.contact().report().touchedFaces();
    nlohmann::json obstacles = nlohmann::json::array();
    for (int i = 0; i < environment.obstacleCount(); ++i)
    {
        const bridge::Obstacle& obstacle = environment.obstacle(i);
        if (obstacle.partOfRoom)
        {
            continue;
        }
        const bool wasTouched =
            std::any_of(touched.begin(), touched.end(), [i](const auto& f) { return f.first == i; });
        obstacles.push_back({{"name", obstacle.name},
                             {"box", toJson(screenBox(camera, viewport, obstacleVertices(obstacle)))},
                             {"touched", wasTouched}});
    }
    regions["obstacles"] = obstacles;
    return regions;
}
bool wholeInView(const OrbitCamera& camera, const Viewport& viewport, const std::vector<Vec3>& points)
{
    for (const Vec3& point : points)
    {
        const std::optional<Vec2> pixel = camera.project(point, viewport);
        if (!pixel || pixel->x() < 0 || pixel->y() < 0 || pixel->x() > viewport.width || pixel->y() > viewport.height)
        {
            return false;
        }
    }
    return true;
}

nlohmann::json screenRegions(const SceneSnapshot& snapshot, const OrbitCamera& camera, const Viewport& viewport)
{
    nlohmann::json regions;
    regions["width"] = viewport.width;
    regions["height"] = viewport.height;
    regions["sheet"] = toJson(screenBox(camera, viewport, snapshot.positions));
    regions["sheet_whole"] = wholeInView(camera, viewport, snapshot.positions);
    nlohmann::json obstacles = nlohmann::json::array();
    for (const ObstacleShape& obstacle : snapshot.obstacles)
    {
        if (obstacle.partOfRoom)
        {
            continue;
        }
        const bool wasTouched =
            std::find(obstacle.touched.begin(), obstacle.touched.end(), true) != obstacle.touched.end();
        obstacles.push_back({{"name", obstacle.name},
                             {"box", toJson(screenBox(camera, viewport, obstacle.vertices))},
                             {"touched", wasTouched}});
    }
    regions["obstacles"] = obstacles;
    return regions;
}
} // namespace masse::viewer
