#include "core/linear/RefreshBudget.h"

#include <gtest/gtest.h>

namespace masse
{
// The ski rental: after a refresh whose solve took 2 iterations, with a refresh worth 100 iterations and at least 10
// allowed a step, steps of 30 iterations (28 beyond fresh) are allowed 102, 74, 46 and 18, and the next one the
// minimum, 10: it does not converge in it, and the caller refreshes. So the extra iterations paid before that refresh
// (28 x 4 + 10) stay within the refresh's cost plus one step's allowance. A refresh starts the count again.
TEST(RefreshBudget, KeepsTheFactorUntilItsExtraIterationsHaveCostARefresh)
{
    RefreshBudget budget(100, 10);
    budget.refreshed(2);
    EXPECT_EQ(budget.freshIterations(), 2);
    int extraPaid = 0;
    int steps = 0;
    for (const int expected : {102, 74, 46, 18, 10})
    {
        ASSERT_EQ(budget.allowance(), expected) << "after " << steps << " steps";
        const int taken = std::min(30, budget.allowance()); // a solve needing 30 stops at its allowance
        extraPaid += taken - 2;
        budget.used(taken);
        ++steps;
    }
    EXPECT_LE(extraPaid, 100 + 10);
    EXPECT_EQ(budget.allowance(), 10); // spent: only the minimum is left
    budget.refreshed(3);
    EXPECT_EQ(budget.allowance(), 103);
    budget.used(2); // fewer than fresh: nothing spent
    EXPECT_EQ(budget.allowance(), 103);
}

// With no budget (a refresh worth nothing) the rule is the old fixed one: refresh after the minimum.
TEST(RefreshBudget, WithoutACostItIsTheFixedAllowance)
{
    RefreshBudget budget(0, 10);
    budget.refreshed(2);
    EXPECT_EQ(budget.allowance(), 10);
    budget.used(9);
    EXPECT_EQ(budget.allowance(), 10);
}
} // namespace masse
