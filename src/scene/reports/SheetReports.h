#pragma once
/// What a thermoforming user looks at besides the summary: thickness along a section of the formed part, and the
/// sag of a heated sheet against time.

#include "scene/Scene.h"

#include <string>
#include <vector>

namespace masse::scene
{
/// One point of a thickness section: a bottom-layer mass near the section line (chosen by its rest position, so the
/// section follows the material as it deforms).
struct SectionPoint
{
    Index mass;
    Real restCoordinate; ///< m, along the section axis at rest
    Vec3 position;       ///< m, now
    Real thickness;      ///< m, now
    Real ratio;          ///< h / h0
};

/// The section the scene's report asks for (needs a material). Sorted along the axis.
std::vector<SectionPoint> thicknessSection(const Scene& scene);
std::string sectionCsv(const std::vector<SectionPoint>& section);
/// A gnuplot script plotting h/h0 against the rest coordinate, reading the CSV at `csvPath`.
std::string sectionPlotScript(const std::string& csvPath, const std::string& title);

/// Records the sag of one mass (how far it has dropped below where it started) after every step.
class SagRecorder
{
public:
    explicit SagRecorder(const Scene& scene);
    void record(const Scene& scene);
    Index mass() const { return m_mass; }
    const std::vector<std::pair<Real, Real>>& series() const { return m_series; }
    std::string csv() const;
    static std::string plotScript(const std::string& csvPath, const std::string& title);

private:
    Index m_mass = 0;
    Real m_startHeight = 0;
    std::vector<std::pair<Real, Real>> m_series; ///< (s, m)
};
} // namespace masse::scene
