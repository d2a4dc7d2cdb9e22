#include "scene/reports/TopViewMap.h"

#include "scene/output/AtomicFile.h"
#include "scene/output/Plot.h"
#include "scene/reports/ThicknessMapReport.h"

#include "core/Format.h"
#include "core/lattice/LatticeSurface.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace masse::scene
{
TopViewMap topViewMap(const Scene& scene, const std::vector<Real>& perMass, int width)
{
    const std::vector<Vec3>& x = scene.system().particles.position;
    const Lattice& lattice = scene.lattice();
    TopViewMap map;
    map.minX = map.minZ = std::numeric_limits<Real>::infinity();
    map.maxX = map.maxZ = -std::numeric_limits<Real>::infinity();
    for (Index i = lattice.layerStart[0]; i < lattice.layerStart[1]; ++i)
    {
        map.minX = std::min(map.minX, x[i].x());
        map.maxX = std::max(map.maxX, x[i].x());
        map.minZ = std::min(map.minZ, x[i].z());
        map.maxZ = std::max(map.maxZ, x[i].z());
    }
    const Real spanX = std::max(map.maxX - map.minX, Real(1e-9));
    const Real spanZ = std::max(map.maxZ - map.minZ, Real(1e-9));
    map.width = std::max(width, 2);
    map.height = std::max(2, int(std::lround(Real(map.width) * spanZ / spanX)));
    const Real pixelX = spanX / Real(map.width - 1);
    const Real pixelZ = spanZ / Real(map.height - 1);
    map.value.assign(std::size_t(map.width) * std::size_t(map.height), std::numeric_limits<Real>::quiet_NaN());
    std::vector<Real> top(map.value.size(), -std::numeric_limits<Real>::infinity());
    for (const Triangle& t : layerTriangles(lattice, 0))
    {
        const Vec3& a = x[t[0]];
        const Vec3& b = x[t[1]];
        const Vec3& c = x[t[2]];
        const Real det = (b.x() - a.x()) * (c.z() - a.z()) - (c.x() - a.x()) * (b.z() - a.z());
        if (std::abs(det) < 1e-18)
        {
            continue; // seen edge-on from above
        }
        const int x0 = std::max(0, int(std::floor((std::min({a.x(), b.x(), c.x()}) - map.minX) / pixelX)));
        const int x1 = std::min(map.width - 1, int(std::ceil((std::max({a.x(), b.x(), c.x()}) - map.minX) / pixelX)));
        const int z0 = std::max(0, int(std::floor((std::min({a.z(), b.z(), c.z()}) - map.minZ) / pixelZ)));
        const int z1 = std::min(map.height - 1, int(std::ceil((std::max({a.z(), b.z(), c.z()}) - map.minZ) / pixelZ)));
        for (int row = z0; row <= z1; ++row)
        {
            const Real pz = map.minZ + Real(row) * pixelZ;
            for (int column = x0; column <= x1; ++column)
            {
                const Real px = map.minX + Real(column) * pixelX;
                // Barycentric coordinates of the pixel's centre in the projected triangle.
                const Real u = ((px - a.x()) * (c.z() - a.z()) - (c.x() - a.x()) * (pz - a.z())) / det;
                const Real v = ((b.x() - a.x()) * (pz - a.z()) - (px - a.x()) * (b.z() - a.z())) / det;
                const Real w = 1 - u - v;
                const Real slack = -1e-9;
                if (u < slack || v < slack || w < slack)
                {
                    continue;
                }
                const std::size_t pixel = std::size_t(row) * std::size_t(map.width) + std::size_t(column);
                const Real height = w * a.y() + u * b.y() + v * c.y();
                if (height > top[pixel])
                {
                    top[pixel] = height;
                    map.value[pixel] = w * perMass[t[0]] + u * perMass[t[1]] + v * perMass[t[2]];
                }
            }
        }
    }
    return map;
}

std::string mapData(const TopViewMap& map)
{
    std::ostringstream out;
    const Real pixelX = (map.maxX - map.minX) / Real(map.width - 1);
    const Real pixelZ = (map.maxZ - map.minZ) / Real(map.height - 1);
    char line[96];
    for (int row = 0; row < map.height; ++row)
    {
        for (int column = 0; column < map.width; ++column)
        {
            const Real value = map.value[std::size_t(row) * std::size_t(map.width) + std::size_t(column)];
            if (std::isnan(value))
            {
                std::snprintf(line, sizeof(line), "%.6f %.6f NaN\n", map.minX + column * pixelX,
                              map.minZ + row * pixelZ);
            }
            else
            {
                std::snprintf(line, sizeof(line), "%.6f %.6f %.6g\n", map.minX + column * pixelX,
                              map.minZ + row * pixelZ, value);
            }
            out << line;
        }
        out << '\n';
    }
    return out.str();
}

std::string mapPlotScript(const std::string& dataPath, const std::string& title, const std::string& subtitle,
                          const std::string& unitLabel, const std::string& palette,
                          const std::vector<Real>& colourRange)
{
    const std::string range = colourRange.size() == 2 ? "set cbrange [" + formatNumber("%.9g", colourRange[0]) + ":" +
                                                            formatNumber("%.9g", colourRange[1]) + "]\n"
                                                      : std::string();
    // Pixels off the sheet are NaN, which gnuplot's image leaves blank. They must not be declared missing data
    // (`set datafile missing 'NaN'`): image then drops them from their scan lines, the grid no longer lines up, and
    // every row shifts by the pixels dropped before it; the cup's cavity comes out as a sheared ellipse 5 cm off
    // centre (FormingReports.MapsStayOnTheSheetsOwnGrid).
    return "set title \"" + title + "\\n{/*0.8 " + subtitle +
           "}\" enhanced\n"
           "set xlabel 'x (m)'\n"
           "set ylabel 'z (m)'\n"
           "set yrange [*:*] reverse\n" // seen from above (+y) with x to the right, z grows down the page
           "set size ratio -1\n"
           "set cblabel '" +
           unitLabel + "'\n" + range + "set palette " + palette +
           "\n"
           "set tics out\n"
           "unset key\n"
           "plot '" +
           dataPath + "' using 1:2:3 with image\n";
}

void drawTopViewMap(PlotBatch& plots, const Scene& scene, const std::vector<Real>& perMass, const std::string& pngPath,
                    const std::string& title, const std::string& subtitle, const std::string& unitLabel,
                    const std::string& palette, const std::vector<Real>& colourRange)
{
    const int pixels = thicknessMapSettings(scene.spec()).pixels;
    const std::string dataPath = pngPath + ".dat.tmp";
    writeFileAtomically(dataPath, mapData(topViewMap(scene, perMass, pixels / 3)));
    plots.add(mapPlotScript(dataPath, title, subtitle, unitLabel, palette, colourRange), pngPath, pixels,
              pixels * 4 / 5, {dataPath});
}
} // namespace masse::scene
