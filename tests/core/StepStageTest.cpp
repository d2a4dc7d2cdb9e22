// The frame's stage table (core/StepStage.h): hooks run at the stages they join, in the table's order, with the time
// each stage stands at; docs/step.md names every stage.

#include "support/TestSystems.h"

#include "core/Simulator.h"
#include "core/StepStage.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

using namespace masse;

namespace
{
/// Every stage a hook may join.
StageSet everyHookStage()
{
    StageSet all;
    for (const StepStageEntry& entry : stepStageTable)
    {
        if (entry.hooksJoin)
        {
            all = all.with(entry.stage);
        }
    }
    return all;
}

/// Records the stages it is called at and the time each stands at.
class StageRecorder final : public StepHook
{
public:
    explicit StageRecorder(StageSet joined) : m_joined(joined) {}
    StageSet stages() const override { return m_joined; }
    void run(StepStage stage, const StageCall& call) override { calls.emplace_back(stage, call.time); }

    std::vector<std::pair<StepStage, Real>> calls;

private:
    StageSet m_joined;
};

std::vector<StepStage> stagesOf(const StageRecorder& recorder)
{
    std::vector<StepStage> stages;
    for (const auto& [stage, time] : recorder.calls)
    {
        stages.push_back(stage);
    }
    return stages;
}
} // namespace

TEST(StepStage, TheTableListsEveryStageOnceInItsOrder)
{
    std::set<std::string_view> names;
    for (int k = 0; k < stepStageCount; ++k)
    {
        EXPECT_EQ(int(stepStageTable[k].stage), k) << stepStageTable[k].name;
        EXPECT_TRUE(names.insert(stepStageTable[k].name).second) << stepStageTable[k].name;
    }
    // The every-substep stages are one run, so that a frame is: stages before, the substeps, stages after.
    int runs = 0;
    for (int k = 0; k < stepStageCount; ++k)
    {
        runs += stepStageTable[k].everySubstep && (k == 0 || !stepStageTable[k - 1].everySubstep) ? 1 : 0;
    }
    EXPECT_EQ(runs, 1);
}

TEST(StepStage, StepPageNamesEveryStage)
{
    std::ifstream in(std::filesystem::path(MASSE_SOURCE_DIR) / "docs/step.md");
    std::ostringstream page;
    page << in.rdbuf();
    ASSERT_FALSE(page.str().empty());
    for (const StepStageEntry& entry : stepStageTable)
    {
        std::string quoted = "`";
        quoted.append(entry.name).append("`");
        EXPECT_NE(page.str().find(quoted), std::string::npos)
            << "docs/step.md does not name the stage `" << entry.name << "`";
    }
}

// An explicit frame of several substeps: a hook joining every stage is called before the substeps, at the
// every-substep stages once per substep (but afterSolve: there is no solve), and after them; one joining only
// endFrame only there; within a stage, hooks in the order added.
TEST(StepStage, HooksRunAtTheStagesTheyJoinInTheTablesOrder)
{
    SimulatorSettings settings;
    settings.integrator = IntegratorKind::SymplecticEuler;
    Simulator simulator(test::paperSheet(8), settings);
    StageRecorder every(everyHookStage());
    StageRecorder last({StepStage::EndFrame});
    simulator.addHook(&every);
    simulator.addHook(&last);
    constexpr Real dt = 0.01;
    const int substeps = simulator.substepsFor(dt);
    ASSERT_GE(substeps, 2);
    simulator.step(dt);

    std::vector<StepStage> expected = {StepStage::BeforeFrame, StepStage::ContactDetection, StepStage::BeginFrame};
    for (int i = 0; i < substeps; ++i)
    {
        expected.push_back(StepStage::ContactProjection);
        expected.push_back(StepStage::AfterSubstep);
    }
    expected.push_back(StepStage::ContactReport);
    expected.push_back(StepStage::EndFrame);
    EXPECT_EQ(stagesOf(every), expected);
    EXPECT_EQ(stagesOf(last), std::vector<StepStage>{StepStage::EndFrame});

    // The time each stage stands at: the frame's start, each substep's end, the frame's end.
    const Real h = dt / Real(substeps);
    EXPECT_EQ(every.calls.front().second, 0);
    EXPECT_EQ(every.calls[3].second, h);
    EXPECT_EQ(every.calls[3 + 2 * (substeps - 1)].second, Real(substeps) * h);
    EXPECT_EQ(every.calls.back().second, dt);
    EXPECT_EQ(last.calls.back().second, dt);
}

// An implicit frame is one solve, followed by afterSolve before the obstacle projection.
TEST(StepStage, AnImplicitFrameRunsAfterSolveBeforeTheProjection)
{
    SimulatorSettings settings;
    settings.integrator = IntegratorKind::ImplicitEuler;
    Simulator simulator(test::paperSheet(8), settings);
    StageRecorder every(everyHookStage());
    simulator.addHook(&every);
    simulator.step(0.01);
    const std::vector<StepStage> expected = {
        StepStage::BeforeFrame,       StepStage::ContactDetection, StepStage::BeginFrame,    StepStage::AfterSolve,
        StepStage::ContactProjection, StepStage::AfterSubstep,     StepStage::ContactReport, StepStage::EndFrame};
    EXPECT_EQ(stagesOf(every), expected);
}

// The Simulator's own stages take no hooks: a hook naming them is not called there.
TEST(StepStage, TheSimulatorsOwnStagesTakeNoHooks)
{
    SimulatorSettings settings;
    settings.integrator = IntegratorKind::ImplicitEuler;
    Simulator simulator(test::paperSheet(8), settings);
    StageRecorder own({StepStage::PlanFrame, StepStage::Integrate, StepStage::Check});
    simulator.addHook(&own);
    simulator.step(0.01);
    EXPECT_TRUE(own.calls.empty());
}
