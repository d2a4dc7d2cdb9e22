#pragma once
/// When to refactor a drifting preconditioner: a ski rental. A refresh costs about as much as `cost` iterations with
/// the preconditioner; keeping a drifted one costs the iterations it takes beyond what it took fresh. Refreshing once
/// those extra iterations since the last refresh reach the refresh's cost pays at most about twice what the best
/// schedule would (the ski-rental bound), whatever the drift: a matrix that drifts slowly keeps its factor for many
/// steps, and one that changes fast (contact spreading over the sheet) is not refactored every step for a few
/// iterations saved each time. A solve always gets at least `minimum` iterations before a refresh.

#include <algorithm>

namespace masse
{
class RefreshBudget
{
public:
    RefreshBudget() = default;
    RefreshBudget(int cost, int minimum) : m_cost(std::max(cost, 0)), m_minimum(minimum) {}

    /// Iterations the next solve may take with the current preconditioner before it is refreshed.
    int allowance() const { return std::max(m_minimum, m_freshIterations + m_cost - m_extra); }
    /// A solve with the current preconditioner, not refreshed for it, took `iterations`.
    void used(int iterations) { m_extra += std::max(0, iterations - m_freshIterations); }
    /// The preconditioner was refreshed, and the solve after it took `iterations`.
    void refreshed(int iterations)
    {
        m_freshIterations = iterations;
        m_extra = 0;
    }
    /// Iterations of the first solve after the last refresh.
    int freshIterations() const { return m_freshIterations; }

private:
    int m_cost = 0;
    int m_minimum = 0;
    int m_freshIterations = 0;
    int m_extra = 0; ///< iterations beyond the fresh count, summed over the solves since the last refresh
};
} // namespace masse
