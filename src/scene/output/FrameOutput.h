#pragma once
/// The frames of a run, written as ParaView and VTK expect them: OUT/frames/frame_STEP.vtp (and .obj) every k steps
/// and always the final state; each obstacle (the polyhedra and the room's floor) as OUT/frames/obstacle_I_NAME.vtp,
/// written once when it stands still and as obstacle_I_NAME_STEP.vtp at every frame when it moves; and
/// OUT/frames.pvd, the collection that lists them all with each frame's simulated time.

#include "scene/Scene.h"
#include "scene/output/PvdCollection.h"

#include "core/lattice/LatticeSurface.h"

#include <string>
#include <vector>

namespace masse::scene
{
class FrameOutput
{
public:
    /// Creates OUT/frames, writes the still obstacles and the scene's present state.
    FrameOutput(Scene& scene, const std::string& outDir);
    /// Writes the scene's present state as a frame.
    void write(Scene& scene);
    /// Writes the present state unless it was the last frame written (the final state is always a frame), then the
    /// collection.
    void finish(Scene& scene);

private:
    struct ObstaclePart
    {
        int index; ///< in the environment, as in contact_obstacle
        std::string name;
        std::string file; ///< relative to OUT; for a moving obstacle, the stem before _STEP.vtp
        bool moving;
    };

    std::string m_outDir;
    bool m_vtp = false;
    std::vector<Triangle> m_surface;
    std::vector<std::string> m_obstacleNames;
    std::vector<ObstaclePart> m_obstacles;
    PvdCollection m_collection;
    std::uint64_t m_lastStep = 0;
    bool m_anyWritten = false;
};
} // namespace masse::scene
