// The progress line of `masse run`: the time left while it runs, and an end that says how the run ended.

#include "scene/output/Progress.h"

#include <gtest/gtest.h>

#include <sstream>

using masse::scene::Progress;

// The bar shows the time left (ETA), and its end says how the run ended: a run that stops at rest at, say, 32% of its
// duration ends with a full bar saying so, since a bar left at 32% reads as an abort.
TEST(Progress, ShowsTheTimeLeftAndEndsSayingHowTheRunEnded)
{
    std::ostringstream out;
    Progress progress(out, false, 10.0);
    // 2 s simulated in 30 s of wall time: the 8 s left take 120 s at that pace.
    const std::string running = progress.line(2.0, 30.0, "contact floor at 1.50 s");
    EXPECT_NE(running.find(" 20.0%"), std::string::npos) << running;
    EXPECT_NE(running.find("ETA 2 min 00 s  last: contact floor at 1.50 s"), std::string::npos) << running;

    progress.finish(3.2, 12.0, true);
    EXPECT_NE(out.str().find("[########################] stopped at rest at t = 3.20 s of 10.00 s"), std::string::npos)
        << out.str();
    EXPECT_NE(out.str().find("done in 12 s"), std::string::npos) << out.str();
    EXPECT_EQ(out.str().find("32.0%"), std::string::npos) << out.str();

    std::ostringstream whole;
    Progress(whole, false, 10.0).finish(10.0, 3700.0, false);
    EXPECT_NE(whole.str().find("100.0%  t =   10.00 / 10.00 s"), std::string::npos) << whole.str();
    EXPECT_NE(whole.str().find("done in 1 h 01 min"), std::string::npos) << whole.str();
    EXPECT_EQ(whole.str().find("ETA"), std::string::npos) << whole.str();
}
