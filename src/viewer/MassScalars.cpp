#include "MassScalars.h"

#include <algorithm>

namespace masse::viewer
{
void MassScalarRegistry::add(MassScalar scalar)
{
    for (MassScalar& existing : m_scalars)
    {
        if (existing.name == scalar.name)
        {
            existing = std::move(scalar);
            return;
        }
    }
    m_scalars.push_back(std::move(scalar));
}

const MassScalar* MassScalarRegistry::find(std::string_view name) const
{
    for (const MassScalar& scalar : m_scalars)
    {
        if (scalar.name == name)
        {
            return &scalar;
        }
    }
    return nullptr;
}

std::string MassScalarRegistry::names() const
{
    std::string out;
    for (const MassScalar& scalar : m_scalars)
    {
        out += (out.empty() ? "" : ", ") + scalar.name;
    }
    return out;
}

void meanSpringStrain(const MassSpringSystem& system, std::vector<float>& values)
{
    const std::vector<Vec3>& x = system.particles.position;
    const SpringSet& springs = system.springs;
    values.assign(x.size(), 0.0f);
    std::vector<int> count(x.size(), 0);
    for (std::size_t s = 0; s < springs.size(); ++s)
    {
        const SpringEnds& e = springs.ends[s];
        const Real rest = springs.restLength[s];
        const float strain = float(((x[e.a] - x[e.b]).norm() - rest) / rest);
        values[e.a] += strain;
        values[e.b] += strain;
        ++count[e.a];
        ++count[e.b];
    }
    for (std::size_t i = 0; i < values.size(); ++i)
    {
        if (count[i] > 0)
        {
            values[i] /= float(count[i]);
        }
    }
}

MassScalarRegistry standardMassScalars()
{
    MassScalarRegistry registry;
    registry.add({"speed", "m/s", "How fast each mass moves",
                  [](const scene::Scene& scene, std::vector<float>& values)
                  {
                      const std::vector<Vec3>& v = scene.system().particles.velocity;
                      values.resize(v.size());
                      std::transform(v.begin(), v.end(), values.begin(), [](const Vec3& u) { return float(u.norm()); });
                  }});
    registry.add({"strain", "", "Mean relative stretch of the springs at each mass (negative: compressed)",
                  [](const scene::Scene& scene, std::vector<float>& values)
                  { meanSpringStrain(scene.system(), values); }});
    return registry;
}

ScalarRange rangeOf(const std::vector<float>& values)
{
    if (values.empty())
    {
        return {};
    }
    const auto [low, high] = std::minmax_element(values.begin(), values.end());
    ScalarRange range{*low, *high};
    if (!(range.high - range.low > 1e-12f))
    {
        range.low -= 0.5f;
        range.high += 0.5f;
    }
    return range;
}
} // namespace masse::viewer
