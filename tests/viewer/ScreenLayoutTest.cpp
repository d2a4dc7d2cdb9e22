// The window's layout without a window: the side column beside the scene's view, the camera framing the sheet in the
// view's own rectangle, and the colour bar's labels and units for every scalar the viewer can paint.

#include "viewer/ScreenLayout.h"
#include "viewer/ColourBar.h"
#include "viewer/Controls.h"
#include "viewer/SceneSnapshot.h"
#include "viewer/ScreenRegions.h"

#include "scene/SceneFile.h"

#include <gtest/gtest.h>

namespace masse::viewer
{
namespace
{
scene::SceneSpec shippedScene(const std::string& name)
{
    return scene::loadScene(std::string(MASSE_SOURCE_DIR) + "/data/scenes/" + name);
}
} // namespace

TEST(ScreenLayout, TheColumnSitsBesideTheSceneAndTheyFillTheWindow)
{
    for (const auto& [width, height] : {std::pair{1024, 720}, std::pair{800, 600}, std::pair{500, 400}})
    {
        const ScreenLayout layout = screenLayout(width, height, true);
        EXPECT_FALSE(layout.scene.overlaps(layout.column)) << width;
        EXPECT_EQ(layout.scene.x, 0) << "mouse positions are the scene's own";
        EXPECT_EQ(layout.scene.y, 0);
        EXPECT_EQ(layout.scene.width + layout.column.width, width);
        EXPECT_EQ(layout.scene.height, height);
        EXPECT_EQ(layout.column.height, height);
        EXPECT_EQ(layout.column.right(), width);
        EXPECT_LE(layout.column.width, columnWidth);
        EXPECT_GE(layout.scene.width, width / 2) << "the view keeps at least half the window";
    }
    const ScreenLayout clean = screenLayout(800, 600, false);
    EXPECT_EQ(clean.scene.width, 800) << "no UI: the scene has the whole window";
    EXPECT_EQ(clean.column.width, 0);
}

// What a user sees at start in a 1024x720 window: each shipped scene's sheet, its obstacles and heaters framed whole
// in the view beside the column, so the panel covers none of it.
TEST(ScreenLayout, TheStartingViewShowsTheWholeSheetBesideThePanel)
{
    for (const char* name : {"paper-drop.json", "drape-forming.json", "own-forming.json", "vacuum-forming-cup.json"})
    {
        ViewerSession session(shippedScene(name));
        SceneSnapshot snapshot;
        captureSnapshot(session, standardMassScalars(), "", nullptr, snapshot);
        const ScreenLayout layout = screenLayout(1024, 720, true);
        Controls controls(ViewPreset::Overview, DrawSettings{});
        controls.viewport = layout.sceneViewport();
        controls.setView(ViewPreset::Overview, snapshot);
        EXPECT_TRUE(wholeInView(controls.camera, controls.viewport, snapshot.positions)) << name;
        const std::optional<ScreenBox> sheet = screenBox(controls.camera, controls.viewport, snapshot.positions);
        ASSERT_TRUE(sheet) << name;
        EXPECT_LT(sheet->right, layout.column.x) << name << ": the sheet ends left of the column";
        const scene::HeatSpec& heat = snapshot.spec->heat;
        if (heat.enabled)
        {
            for (const RadiantHeater& heater : heat.settings.heaters)
            {
                const std::array<Vec3, 4> corners = heaterCorners(heater);
                EXPECT_TRUE(wholeInView(controls.camera, controls.viewport, {corners.begin(), corners.end()}))
                    << name << ": the heater is framed too";
            }
        }
    }
}

TEST(ColourBar, EveryScalarHasAUnitAndItsBarLabelsBothEnds)
{
    const MassScalarRegistry scalars = standardMassScalars();
    ASSERT_GE(scalars.all().size(), 5u);
    for (const MassScalar& scalar : scalars.all())
    {
        const ColourBar bar = makeColourBar(scalar, ScalarRange{1.5f, 4.25f}, "");
        const std::string unit = unitLabel(scalar);
        EXPECT_FALSE(unit.empty()) << scalar.name;
        EXPECT_NE(bar.title.find(scalar.name), std::string::npos);
        EXPECT_NE(bar.title.find("(" + unit + ")"), std::string::npos) << bar.title;
        EXPECT_EQ(bar.lowLabel.rfind("1.5", 0), 0u) << bar.lowLabel;
        EXPECT_EQ(bar.highLabel.rfind("4.25", 0), 0u) << bar.highLabel;
        if (!scalar.unit.empty())
        {
            EXPECT_NE(bar.highLabel.find(scalar.unit), std::string::npos) << bar.highLabel;
        }
        ASSERT_GE(bar.stops.size(), 2u);
        // The bar runs over the same map the sheet is painted with.
        EXPECT_EQ(bar.stops.front().r, viridis(0).r);
        EXPECT_EQ(bar.stops.back().g, viridis(1).g);
        EXPECT_TRUE(bar.note.empty());
    }
    EXPECT_EQ(unitLabel(*scalars.find("speed")), "m/s");
    EXPECT_EQ(unitLabel(*scalars.find("temperature")), "C");
    EXPECT_EQ(unitLabel(*scalars.find("thickness")), "mm");
    EXPECT_EQ(unitLabel(*scalars.find("thickness_ratio")), "ratio");
    EXPECT_EQ(unitLabel(*scalars.find("strain")), "ratio");
}

TEST(ColourBar, AScalarTheSceneLacksHasNoBarButItsReason)
{
    const MassScalarRegistry scalars = standardMassScalars();
    const ColourBar bar = makeColourBar(*scalars.find("temperature"), ScalarRange{}, "this scene has no heat");
    EXPECT_TRUE(bar.stops.empty());
    EXPECT_NE(bar.note.find("no heat"), std::string::npos);
    EXPECT_NE(bar.note.find("grey"), std::string::npos);
    EXPECT_TRUE(makeColourBar(*scalars.find("speed"), std::nullopt, "").stops.empty()) << "no values drawn yet";
}
} // namespace masse::viewer
