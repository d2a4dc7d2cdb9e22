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
        const SpringEnds& e = springs.ends()[s];
        const Real rest = springs.restLength()[s];
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
    // Heat scenes: without a heat model the sheet is at its start temperature, without a material it has no
    // thickness to show (0).
    registry.add({"temperature", "C", "Temperature of each mass (scenes with a \"heat\" section)",
                  [](const scene::Scene& scene, std::vector<float>& values)
                  {
                      values.assign(scene.system().massCount(),
                                    float(scene.spec().heat.settings.initialTemperature - 273.15));
                      if (const ThermalModel* thermal = scene.thermal())
                      {
                          std::transform(thermal->temperature().begin(), thermal->temperature().end(), values.begin(),
                                         [](Real kelvin) { return float(kelvin - 273.15); });
                      }
                  }});
    registry.add({"thickness", "mm", "Local sheet thickness h = h0 A0 / A (scenes with a \"material\")",
                  [](const scene::Scene& scene, std::vector<float>& values)
                  {
                      values.assign(scene.system().massCount(), 0.0f);
                      if (const SheetThickness* thickness = scene.thickness())
                      {
                          std::transform(thickness->thickness().begin(), thickness->thickness().end(), values.begin(),
                                         [](Real h) { return float(1000 * h); });
                      }
                  },
                  [](const scene::Scene& scene) -> std::optional<ScalarRange>
                  {
                      const SheetThickness* thickness = scene.thickness();
                      return thickness ? std::optional<ScalarRange>(
                                             ScalarRange{0.0f, float(1000 * thickness->initialThickness())})
                                       : std::nullopt;
                  }});
    registry.add({"thickness_ratio", "", "Local thickness over the sheet's starting thickness, h / h0 (\"material\")",
                  [](const scene::Scene& scene, std::vector<float>& values)
                  {
                      values.assign(scene.system().massCount(), 0.0f);
                      if (const SheetThickness* thickness = scene.thickness())
                      {
                          const Real initial = thickness->initialThickness();
                          std::transform(thickness->thickness().begin(), thickness->thickness().end(), values.begin(),
                                         [initial](Real h) { return float(h / initial); });
                      }
                  },
                  [](const scene::Scene&) -> std::optional<ScalarRange> {
                      return ScalarRange{0.0f, 1.0f};
                  }});
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
