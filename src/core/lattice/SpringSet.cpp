#include "core/lattice/SpringSet.h"

#include <cmath>

namespace masse
{
SpringSet::SpringSet() : m_topology(std::make_shared<SpringTopology>()) {}

SpringSet::SpringSet(SpringTopology topology)
    : m_topology(std::make_shared<SpringTopology>(std::move(topology))), m_restLength(m_topology->restLength),
      m_stiffness(m_topology->size(), 0), m_damping(m_topology->size(), 0)
{
}

SpringTopology& SpringSet::ownTopology()
{
    if (m_topology.use_count() > 1)
    {
        m_topology = std::make_shared<SpringTopology>(*m_topology);
    }
    return *m_topology;
}

void SpringSet::add(Index a, Index b, Real rest, SpringClass cls)
{
    SpringTopology& topology = ownTopology();
    topology.ends.push_back({a, b});
    topology.springClass.push_back(cls);
    topology.restLength.push_back(rest);
    topology.rowPlan = nullptr;
    m_restLength.push_back(rest);
    m_stiffness.push_back(0);
    m_damping.push_back(0);
    m_uniform.reset();
}

void SpringSet::setRowPlan(std::shared_ptr<const SpringRowPlan> plan)
{
    ownTopology().rowPlan = std::move(plan);
}

const SpringAdjacency& SpringSet::adjacency(std::size_t massCount) const
{
    if (!m_adjacency || m_adjacency->springCount != size() || m_adjacency->massCount() != massCount)
    {
        m_adjacency = std::make_shared<const SpringAdjacency>(buildSpringAdjacency(ends(), massCount));
    }
    return *m_adjacency;
}

const SpringRowPlan* SpringSet::rowPlan(std::size_t massCount) const
{
    const SpringRowPlan* plan = m_topology->rowPlan.get();
    return plan && plan->springCount == size() && plan->massCount == massCount ? plan : nullptr;
}

std::vector<Real>& SpringSet::mutableStiffness()
{
    m_uniform.reset();
    return m_stiffness;
}

std::vector<Real>& SpringSet::mutableDamping()
{
    m_uniform.reset();
    return m_damping;
}

void SpringSet::summariseUniformClasses()
{
    m_uniform.reset();
    UniformClassCoefficients uniform;
    std::array<bool, springClassCount> seen{};
    for (std::size_t s = 0; s < size(); ++s)
    {
        const std::size_t cls = std::size_t(classes()[s]);
        if (!seen[cls])
        {
            seen[cls] = true;
            uniform.stiffness[cls] = m_stiffness[s];
            uniform.damping[cls] = m_damping[s];
        }
        // Bit for bit: the kernel must give what it would with the per-spring values.
        else if (!(m_stiffness[s] == uniform.stiffness[cls] && m_damping[s] == uniform.damping[cls]) ||
                 std::signbit(m_stiffness[s]) != std::signbit(uniform.stiffness[cls]) ||
                 std::signbit(m_damping[s]) != std::signbit(uniform.damping[cls]))
        {
            return;
        }
    }
    m_uniform = uniform;
}
} // namespace masse
