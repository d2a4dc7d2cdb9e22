#include "Panel.h"

#include "ColourBar.h"

#include "core/Format.h"

#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <array>
#include <cstdio>

namespace masse::viewer
{
namespace
{
const ImVec4 errorColour(1.0f, 0.45f, 0.4f, 1.0f);
/// Lines of text the HUD's region holds.
constexpr float hudLines = 11;

/// The forming process on the HUD's time line: pressure, the steered obstacle's height and speed, the heaters on.
std::string processLine(const SceneSnapshot& snapshot)
{
    std::string line;
    if (snapshot.process.forming)
    {
        line += "  p " + formatNumber("%.1f", snapshot.process.pressure / 1000) + " kPa";
    }
    if (const std::optional<std::size_t> k = ProcessControls::steeredObstacle(snapshot))
    {
        const ObstacleShape& plug = snapshot.obstacles[*k];
        line += "  " + plug.name + " y " + formatNumber("%.4f", plug.position.y()) + " m " +
                formatNumber("%+.0f", 1000 * plug.velocity.y()) + " mm/s";
    }
    if (snapshot.heat && !snapshot.heat->heatersOn.empty())
    {
        const auto on = std::count(snapshot.heat->heatersOn.begin(), snapshot.heat->heatersOn.end(), true);
        line += "  heaters " + std::to_string(on) + "/" + std::to_string(snapshot.heat->heatersOn.size());
    }
    return line;
}
const ImVec4 warningColour(1.0f, 0.75f, 0.3f, 1.0f);

constexpr std::array<DrawMode, 3> drawModes{DrawMode::MassesAndSprings, DrawMode::Surface, DrawMode::Scalar};

/// The values of a registry's entries (`value` of an EnumName table, `kind` of the integrators'), in its order: a
/// menu's choices.
template <typename Entry, std::size_t N> auto registryValues(const Entry (&entries)[N])
{
    const auto valueOf = [](const Entry& entry)
    {
        if constexpr (requires { entry.kind; })
        {
            return entry.kind;
        }
        else
        {
            return entry.value;
        }
    };
    std::vector<decltype(valueOf(entries[0]))> values;
    for (const Entry& entry : entries)
    {
        values.push_back(valueOf(entry));
    }
    return values;
}

/// A combo box over an enum, labelled by the enum's own names (the same words the scene files use).
template <typename Enum, typename Values, typename NameOf>
bool enumCombo(const char* label, Enum& value, const Values& values, NameOf nameOf)
{
    bool changed = false;
    if (ImGui::BeginCombo(label, std::string(nameOf(value)).c_str()))
    {
        for (Enum candidate : values)
        {
            if (ImGui::Selectable(std::string(nameOf(candidate)).c_str(), candidate == value))
            {
                changed = candidate != value;
                value = candidate;
            }
        }
        ImGui::EndCombo();
    }
    return changed;
}

// The editor's fields take every keystroke (intermediate values included) into the pending spec: nothing is built
// until Apply, so a value half typed does no harm, and a value typed without Enter is not lost.
bool positiveDouble(const char* label, double& value, const char* format)
{
    double edited = value;
    if (ImGui::InputDouble(label, &edited, 0, 0, format) && edited > 0)
    {
        value = edited;
        return true;
    }
    return false;
}

bool nonNegativeDouble(const char* label, double& value, const char* format)
{
    double edited = value;
    if (ImGui::InputDouble(label, &edited, 0, 0, format) && edited >= 0)
    {
        value = edited;
        return true;
    }
    return false;
}
} // namespace

PanelRequests Panel::draw(const SceneSnapshot& snapshot, SimulationThread& simulation, DrawSettings& draw,
                          bool& pickMode, bool& follow, ProcessControls& process, const FrameStats& stats,
                          const MassScalarRegistry& scalars, const Renderer& renderer, const ScreenRect& column)
{
    PanelRequests requests;
    if (m_generation != snapshot.generation)
    {
        // A new scene: the editor starts from what is running now.
        m_pending = *snapshot.spec;
        m_edited = false;
        m_generation = snapshot.generation;
        if (m_path.empty())
        {
            m_path = snapshot.spec->path;
        }
    }
    // One window filling the side column: fixed, opaque, scrolling when its contents are taller than the window.
    ImGui::SetNextWindowPos(ImVec2(float(column.x), float(column.y)), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(float(column.width), float(column.height)), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(1.0f);
    ImGui::Begin("MaSSE", nullptr,
                 ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                     ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings |
                     ImGuiWindowFlags_NoBringToFrontOnFocus);
    ImGui::PushTextWrapPos(0.0f); // wrap at the column's edge
    // The HUD in a region of fixed height (scrolling if it overflows), so the controls below stay where they are as
    // lines come and go (events, notices) and a click aimed at a field lands on it.
    ImGui::BeginChild("hud", ImVec2(0, ImGui::GetTextLineHeightWithSpacing() * hudLines), false);
    ImGui::PushTextWrapPos(0.0f);
    drawHud(snapshot, stats, draw, renderer);
    ImGui::PopTextWrapPos();
    ImGui::EndChild();
    drawColourBar(snapshot, draw, scalars);
    ImGui::Separator();
    if (visible)
    {
        drawControls(snapshot, simulation, draw, pickMode, follow, process, scalars, requests);
    }
    else
    {
        ImGui::TextDisabled("Tab shows the controls");
    }
    ImGui::PopTextWrapPos();
    ImGui::End();
    return requests;
}

void Panel::drawControls(const SceneSnapshot& snapshot, SimulationThread& simulation, DrawSettings& draw,
                         bool& pickMode, bool& follow, ProcessControls& process, const MassScalarRegistry& scalars,
                         PanelRequests& requests)
{
    ImGui::TextDisabled("Controls (Tab hides them)");
    // Fields narrow enough that their labels fit beside them.
    ImGui::PushItemWidth(ImGui::GetFontSize() * 11);

    if (ImGui::Button(snapshot.paused ? "Run" : "Pause"))
    {
        simulation.post([](ViewerSession& session) { session.setPaused(!session.paused()); });
    }
    ImGui::SameLine();
    if (ImGui::Button("Step"))
    {
        simulation.post(
            [](ViewerSession& session)
            {
                session.setPaused(true);
                session.requestStep();
            });
    }
    ImGui::SameLine();
    if (ImGui::Button("Reset"))
    {
        simulation.post([](ViewerSession& session) { session.reset(); });
    }

    ImGui::Separator();
    ImGui::TextUnformatted("Scene file");
    ImGui::SetNextItemWidth(-60);
    const bool entered = ImGui::InputText("##path", &m_path, ImGuiInputTextFlags_EnterReturnsTrue);
    ImGui::SameLine();
    if (ImGui::Button("Load") || entered)
    {
        // On failure the session keeps the scene it has and holds the file's own message, shown below.
        simulation.post([path = m_path](ViewerSession& session) { session.load(path); });
    }
    if (!snapshot.error.empty())
    {
        ImGui::PushStyleColor(ImGuiCol_Text, errorColour);
        ImGui::TextWrapped("%s", snapshot.error.c_str());
        ImGui::PopStyleColor();
        if (ImGui::SmallButton("Dismiss"))
        {
            simulation.post([](ViewerSession& session) { session.clearError(); });
        }
    }

    ImGui::Separator();
    ImGui::TextUnformatted("View");
    enumCombo("draw", draw.mode, drawModes, drawModeName);
    if (draw.mode == DrawMode::Scalar)
    {
        if (ImGui::BeginCombo("scalar", draw.scalar.c_str()))
        {
            for (const MassScalar& scalar : scalars.all())
            {
                // A scalar this scene lacks is greyed out with the reason beside it, and cannot be chosen.
                const std::string missing = missingScalarReason(snapshot, scalar.name);
                ImGui::BeginDisabled(!missing.empty());
                const std::string label =
                    scalar.name + " (" + unitLabel(scalar) + ")" + (missing.empty() ? "" : ": " + missing);
                if (ImGui::Selectable(label.c_str(), scalar.name == draw.scalar))
                {
                    draw.scalar = scalar.name;
                }
                ImGui::EndDisabled();
                if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
                {
                    ImGui::SetTooltip("%s", scalar.description.c_str());
                }
            }
            ImGui::EndCombo();
        }
    }
    ImGui::Checkbox("pick mode (left drag pulls a mass)", &pickMode);
    ImGui::Checkbox("follow the sheet (f)", &follow);
    ImGui::Checkbox("room", &draw.showRoom);
    if (ImGui::Button("Overview (1)"))
    {
        requests.view = ViewPreset::Overview;
    }
    ImGui::SameLine();
    if (ImGui::Button("From below (2)"))
    {
        requests.view = ViewPreset::FromBelow;
    }
    ImGui::SameLine();
    if (ImGui::Button("Left (3)"))
    {
        requests.view = ViewPreset::ElevatedLeft;
    }

    drawProcessControls(snapshot, simulation, process);
    drawSection(snapshot, simulation);
    drawSceneEditor(snapshot, simulation);

    if (ImGui::CollapsingHeader("Mouse and keys"))
    {
        ImGui::TextUnformatted("left drag: orbit    right drag: pan\n"
                               "wheel or middle drag: zoom\n"
                               "ctrl or shift + left drag: pull a mass\n"
                               "space: run/pause   n: step   r: reset\n"
                               "1 2 3: views   v: reset view\n"
                               "m: draw mode   p: pick mode   tab: panel\n"
                               "f: follow the sheet\n"
                               "j k h, Alt + left drag: the plug\n"
                               "u: vacuum or pressure   w: save the run\n"
                               "q or esc: quit");
    }
    ImGui::PopItemWidth();
}

void Panel::drawProcessControls(const SceneSnapshot& snapshot, SimulationThread& simulation, ProcessControls& process)
{
    const ProcessState& state = snapshot.process;
    const std::optional<std::size_t> steered = ProcessControls::steeredObstacle(snapshot);
    const bool hasTemperatures = std::any_of(snapshot.obstacles.begin(), snapshot.obstacles.end(),
                                             [](const ObstacleShape& o) { return o.hasTemperature && !o.partOfRoom; });
    if ((!state.forming && !steered && !snapshot.heat) ||
        !ImGui::CollapsingHeader("Process (live)", ImGuiTreeNodeFlags_DefaultOpen))
    {
        return;
    }
    // Every change here is a script action at the scene's time (it acts from the next frame) that "save run" writes.
    const CommandSink post = [&simulation](SessionCommand command) { simulation.post(std::move(command)); };
    if (state.forming)
    {
        ImGui::Text("pressure now %.1f kPa", state.pressure / 1000);
        bool on = state.pressure != 0;
        if (ImGui::Checkbox("vacuum / pressure on (u)", &on))
        {
            process.setPressure(on ? process.level : Real(0), post);
        }
        float levelKpa = float(process.level / 1000);
        if (ImGui::SliderFloat("level (kPa)", &levelKpa, -100.0f, 600.0f, "%.1f"))
        {
            process.level = Real(levelKpa) * 1000;
        }
        if (ImGui::IsItemDeactivatedAfterEdit() && on)
        {
            process.setPressure(process.level, post);
        }
        float ramp = float(process.ramp);
        if (ImGui::SliderFloat("ramp (s)", &ramp, 0.0f, 2.0f, "%.2f"))
        {
            process.ramp = Real(ramp);
        }
    }
    if (steered)
    {
        const ObstacleShape& plug = snapshot.obstacles[*steered];
        ImGui::Text("%s at y = %.4f m, moving %.1f mm/s", plug.name.c_str(), plug.position.y(),
                    1000 * plug.velocity.y());
        if (ImGui::Button("down (j)"))
        {
            process.nudge(snapshot, -1, post);
        }
        ImGui::SameLine();
        if (ImGui::Button("up (k)"))
        {
            process.nudge(snapshot, +1, post);
        }
        ImGui::SameLine();
        if (ImGui::Button("hold (h)"))
        {
            process.stop(snapshot, post);
        }
        float speed = float(1000 * process.speed);
        if (ImGui::SliderFloat("speed (mm/s)", &speed, 1.0f, 500.0f, "%.0f"))
        {
            process.speed = Real(speed) / 1000;
        }
        float step = float(1000 * process.step);
        if (ImGui::SliderFloat("step (mm)", &step, 1.0f, 50.0f, "%.0f"))
        {
            process.step = Real(step) / 1000;
        }
    }
    if (snapshot.heat)
    {
        const HeatState& heat = *snapshot.heat;
        float ambient = float(heat.ambientC);
        ImGui::SliderFloat("ambient (C)", &ambient, -20.0f, 250.0f, "%.1f");
        if (ImGui::IsItemDeactivatedAfterEdit())
        {
            process.setAmbient(Real(ambient), post);
        }
        const std::vector<std::string>& heaters = snapshot.spec->heat.heaterNames;
        for (std::size_t i = 0; i < heaters.size() && i < heat.heatersOn.size() && i < state.heaterPower.size(); ++i)
        {
            ImGui::PushID(int(i));
            bool on = heat.heatersOn[i];
            if (ImGui::Checkbox(("heater " + heaters[i]).c_str(), &on))
            {
                process.setHeater(heaters[i], on, state.heaterPower[i], post);
            }
            float watts = float(state.heaterPower[i]);
            ImGui::SliderFloat("power (W)", &watts, 0.0f, 50000.0f, "%.0f");
            if (ImGui::IsItemDeactivatedAfterEdit())
            {
                process.setHeater(heaters[i], heat.heatersOn[i], Real(watts), post);
            }
            ImGui::PopID();
        }
        if (hasTemperatures)
        {
            for (const ObstacleShape& obstacle : snapshot.obstacles)
            {
                if (!obstacle.hasTemperature || obstacle.partOfRoom)
                {
                    continue;
                }
                float celsius = float(obstacle.temperatureC);
                ImGui::SliderFloat((obstacle.name + " (C)").c_str(), &celsius, 0.0f, 250.0f, "%.1f");
                if (ImGui::IsItemDeactivatedAfterEdit())
                {
                    process.setObstacleTemperature(obstacle.name, Real(celsius), post);
                }
            }
        }
        ImGui::Text("sheet %.1f .. %.1f C", heat.lowestC, heat.highestC);
        if (heat.thinnest)
        {
            ImGui::Text("thinnest %.3f mm (%.0f%% of %.3f)", 1000 * *heat.thinnest,
                        100 * *heat.thinnest / heat.initialThickness, 1000 * heat.initialThickness);
        }
    }
    if (process.saveRunPath.empty())
    {
        process.saveRunPath = process.savePath(snapshot);
    }
    ImGui::SetNextItemWidth(-1);
    ImGui::InputText("##saverun", &process.saveRunPath);
    ImGui::BeginDisabled(!state.saveable);
    if (ImGui::Button("Save run (w)"))
    {
        process.saveRun(snapshot, post);
    }
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::Text("%zu action(s) recorded", state.recordedActions);
    if (!state.saveable)
    {
        ImGui::TextDisabled("edited in the panel: only a scene from a file can be saved");
    }
    else if (state.mousePulled)
    {
        ImGui::PushStyleColor(ImGuiCol_Text, warningColour);
        ImGui::TextUnformatted("the mouse pulled the sheet: a saved run will not replay that");
        ImGui::PopStyleColor();
    }
}

void Panel::drawSection(const SceneSnapshot& snapshot, SimulationThread& simulation)
{
    if (!snapshot.thinnest || !ImGui::CollapsingHeader("Section (live)"))
    {
        return;
    }
    const LatticeSpec& sheet = snapshot.spec->sheet.lattice;
    bool changed = ImGui::Checkbox("show the section", &m_sectionOn);
    changed |= ImGui::RadioButton("along x", &m_sectionAxis, 0);
    ImGui::SameLine();
    changed |= ImGui::RadioButton("along z", &m_sectionAxis, 2);
    const int across = m_sectionAxis == 0 ? 2 : 0;
    const float low = float(sheet.minCorner[across]);
    const float high = float(sheet.maxCorner[across]);
    changed |= ImGui::SliderFloat(m_sectionAxis == 0 ? "at z (m)" : "at x (m)", &m_sectionAt, low, high, "%.4f");
    if (changed)
    {
        std::optional<scene::SectionSettings> section;
        if (m_sectionOn)
        {
            scene::SectionSettings settings;
            settings.axis = m_sectionAxis;
            settings.through[across] = Real(m_sectionAt);
            section = settings;
        }
        simulation.post([section](ViewerSession& session) { session.setSection(section); });
    }
    if (!m_sectionOn || snapshot.section.empty())
    {
        return;
    }
    std::vector<float> ratios;
    auto thinnest = snapshot.section.begin();
    for (auto p = snapshot.section.begin(); p != snapshot.section.end(); ++p)
    {
        ratios.push_back(float(p->ratio));
        thinnest = p->ratio < thinnest->ratio ? p : thinnest;
    }
    ImGui::PlotLines("##section", ratios.data(), int(ratios.size()), 0, "h / h0 along the section, 0 to 1.2", 0.0f,
                     1.2f, ImVec2(-1, 90));
    ImGui::Text("thinnest on it %.3f h0 at %.4f m (%zu masses)", thinnest->ratio, thinnest->restCoordinate,
                snapshot.section.size());
}

void Panel::drawSceneEditor(const SceneSnapshot& snapshot, SimulationThread& simulation)
{
    scene::SceneSpec& spec = m_pending;
    bool changed = false;
    if (ImGui::CollapsingHeader("Sheet"))
    {
        static const std::vector<Structure> structures = registryValues(structureTable);
        changed |= enumCombo("structure", spec.sheet.lattice.structure, structures, structureName);
        int size[3] = {spec.sheet.lattice.countX, spec.sheet.lattice.layers, spec.sheet.lattice.countZ};
        if (ImGui::InputInt3("size N x L x N", size))
        {
            spec.sheet.lattice.countX = std::max(1, size[0]);
            spec.sheet.lattice.layers = std::max(1, size[1]);
            spec.sheet.lattice.countZ = std::max(1, size[2]);
            spec.sheet.sizeGiven = "the panel's size";
            changed = true;
        }
        changed |= positiveDouble("mass per mass (kg)", spec.sheet.params.massPerMass, "%.4g");
        changed |= nonNegativeDouble("planar k (N/m)", spec.sheet.params.springClasses[0].stiffness, "%.4g");
        changed |= nonNegativeDouble("inter-layer k (N/m)", spec.sheet.params.springClasses[1].stiffness, "%.4g");
        changed |= nonNegativeDouble("planar damping ratio", spec.sheet.params.springClasses[0].dampingRatio, "%.3g");
        changed |=
            nonNegativeDouble("inter-layer damping ratio", spec.sheet.params.springClasses[1].dampingRatio, "%.3g");
    }
    if (ImGui::CollapsingHeader("Environment and time"))
    {
        double gravity[3] = {spec.environment.gravity.x(), spec.environment.gravity.y(), spec.environment.gravity.z()};
        if (ImGui::InputScalarN("gravity (m/s2)", ImGuiDataType_Double, gravity, 3, nullptr, nullptr, "%.3g"))
        {
            spec.environment.gravity = Vec3(gravity[0], gravity[1], gravity[2]);
            changed = true;
        }
        changed |= nonNegativeDouble("air damping (1/s)", spec.environment.airDampingRate, "%.4g");
        static const std::vector<IntegratorKind> kinds = registryValues(integratorTable);
        changed |= enumCombo("integrator", spec.time.integrator, kinds, integratorName);
        changed |= positiveDouble("dt (s)", spec.time.dt, "%.4g");
    }
    if (ImGui::CollapsingHeader("Contact"))
    {
        static const std::vector<ContactResponse> responses = registryValues(contactResponseTable);
        changed |= enumCombo("response", spec.contact.response, responses, contactResponseName);
        changed |= nonNegativeDouble("friction", spec.contact.friction, "%.3g");
        changed |= positiveDouble("radius (m)", spec.contact.radius, "%.4g");
        if (spec.contact.response == ContactResponse::Sticky)
        {
            changed |= nonNegativeDouble("release force (N)", spec.contact.stickReleaseForce, "%.3g");
        }
    }
    m_edited |= changed;
    ImGui::BeginDisabled(!m_edited);
    if (ImGui::Button("Apply (rebuilds the scene)"))
    {
        // On failure the scene shown stays and the error appears above; the edits are kept for correcting. On
        // success the new generation resets the editor from the scene now running.
        simulation.post([spec](ViewerSession& session) { session.rebuild(spec); });
    }
    ImGui::SameLine();
    if (ImGui::Button("Revert"))
    {
        m_pending = *snapshot.spec;
        m_edited = false;
    }
    ImGui::EndDisabled();
}

void Panel::drawColourBar(const SceneSnapshot& snapshot, const DrawSettings& draw, const MassScalarRegistry& scalars)
{
    const MassScalar* scalar = scalars.find(draw.scalar);
    if (draw.mode != DrawMode::Scalar || scalar == nullptr)
    {
        return;
    }
    const std::string missing = missingScalarReason(snapshot, draw.scalar);
    // The range of the snapshot this frame draws (the renderer maps the same values the same way).
    std::optional<ScalarRange> range;
    if (snapshot.scalarName == draw.scalar && !snapshot.scalar.empty())
    {
        range = snapshot.scalarFixedRange.value_or(rangeOf(snapshot.scalar));
    }
    const ColourBar bar = makeColourBar(*scalar, range, missing);
    ImGui::Separator();
    ImGui::TextUnformatted(bar.title.c_str());
    if (bar.stops.empty())
    {
        ImGui::PushStyleColor(ImGuiCol_Text, missing.empty() ? ImVec4(0.7f, 0.7f, 0.7f, 1.0f) : warningColour);
        ImGui::TextUnformatted(bar.note.c_str());
        ImGui::PopStyleColor();
        return;
    }
    // The map as adjoining gradients between its stops, the full width of the column, the end values under its ends.
    ImDrawList* drawList = ImGui::GetWindowDrawList();
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const float width = ImGui::GetContentRegionAvail().x;
    const float height = ImGui::GetFontSize() * 1.2f;
    const std::size_t segments = bar.stops.size() - 1;
    for (std::size_t k = 0; k < segments; ++k)
    {
        const Rgb& a = bar.stops[k];
        const Rgb& b = bar.stops[k + 1];
        const ImU32 left = ImGui::GetColorU32(ImVec4(a.r, a.g, a.b, 1.0f));
        const ImU32 right = ImGui::GetColorU32(ImVec4(b.r, b.g, b.b, 1.0f));
        const float x0 = origin.x + width * float(k) / float(segments);
        const float x1 = origin.x + width * float(k + 1) / float(segments);
        drawList->AddRectFilledMultiColor(ImVec2(x0, origin.y), ImVec2(x1, origin.y + height), left, right, right,
                                          left);
    }
    ImGui::Dummy(ImVec2(width, height));
    ImGui::TextUnformatted(bar.lowLabel.c_str());
    ImGui::SameLine(
        std::max(0.0f, ImGui::GetWindowContentRegionMax().x - ImGui::CalcTextSize(bar.highLabel.c_str()).x));
    ImGui::TextUnformatted(bar.highLabel.c_str());
}

void Panel::drawHud(const SceneSnapshot& snapshot, const FrameStats& stats, const DrawSettings& draw,
                    const Renderer& renderer)
{
    const scene::SceneSpec& spec = *snapshot.spec;
    ImGui::Text("%s: %s %s %dx%dx%d, %s dt %.3g s", spec.name.c_str(),
                std::string(structureName(spec.sheet.lattice.structure)).c_str(),
                std::string(contactResponseName(spec.contact.response)).c_str(), spec.sheet.lattice.countX,
                spec.sheet.lattice.layers, spec.sheet.lattice.countZ,
                std::string(integratorName(spec.time.integrator)).c_str(), spec.time.dt);
    ImGui::Text("t = %.3f s%s%s", snapshot.time, snapshot.paused ? "  (paused)" : "", processLine(snapshot).c_str());
    ImGui::Text("%zu masses, %zu springs, %zu in contact", snapshot.positions.size(), snapshot.springCount,
                snapshot.touchingCount);
    if (spec.selfCollision)
    {
        ImGui::Text("%zu touching the sheet itself (magenta)", snapshot.selfTouchingCount);
    }
    if (snapshot.ghost)
    {
        // The ghost: Bullet's twin, with the figures that set the two apart.
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.78f, 0.62f, 0.98f, 1.0f));
        ImGui::Text("ghost: Bullet soft body, %zu nodes in contact", snapshot.ghost->touchingCount);
        ImGui::Text("deepest penetration so far: MaSSE %.3g mm, Bullet %.3g mm", 1000 * snapshot.ghost->masseDeepest,
                    1000 * snapshot.ghost->bulletDeepest);
        ImGui::PopStyleColor();
    }
    if (stats.measured)
    {
        ImGui::Text("%.0f frames/s, %.1f steps/s", stats.framesPerSecond, stats.stepsPerSecond);
        if (snapshot.paused)
        {
            ImGui::TextUnformatted("real-time factor: paused");
        }
        else if (stats.fixedSteps > 0)
        {
            ImGui::Text("%d step(s) per frame, not following the clock (capture)", stats.fixedSteps);
        }
        else if (stats.behind)
        {
            ImGui::PushStyleColor(ImGuiCol_Text, warningColour);
            ImGui::Text("real-time factor %.2f: slow motion, this machine cannot keep up", stats.realTimeFactor);
            ImGui::PopStyleColor();
        }
        else
        {
            ImGui::Text("real-time factor %.2f", stats.realTimeFactor);
        }
    }
    if (draw.mode == DrawMode::MassesAndSprings && !renderer.springsShown())
    {
        ImGui::TextUnformatted("springs hidden while under 3 px apart: zoom in to see them");
    }
    if (renderer.massStride() > 1)
    {
        ImGui::Text("sheet drawn through every %d%s row and column (masses under 2.5 px apart)", renderer.massStride(),
                    renderer.massStride() == 2 ? "nd" : "th");
    }
    const std::vector<scene::SceneEvent>& events = snapshot.events;
    const std::size_t shown = std::min<std::size_t>(events.size(), 3);
    for (std::size_t k = events.size() - shown; k < events.size(); ++k)
    {
        ImGui::Text("%8.3f s  %s %s", events[k].simTime, events[k].name.c_str(), events[k].object.c_str());
    }
    if (!snapshot.notice.empty())
    {
        ImGui::PushStyleColor(ImGuiCol_Text, warningColour);
        ImGui::TextUnformatted(snapshot.notice.c_str());
        ImGui::PopStyleColor();
    }
    if (!snapshot.error.empty() && !visible)
    {
        ImGui::PushStyleColor(ImGuiCol_Text, errorColour);
        ImGui::TextUnformatted(snapshot.error.c_str());
        ImGui::PopStyleColor();
    }
}
} // namespace masse::viewer
