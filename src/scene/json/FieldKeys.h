#pragma once
/// The scene file's names for the fields of the core's structs.
///
/// The core names a bad value by its field in its own terms (InputError::field(): "airHeatTransfer",
/// "heaters[1].power"); it does not know that the value came from a scene file. The scene layer read the value from a
/// key, so it says the key instead: "heat.air_heat_transfer: must be >= 0 W/(m^2 K) (got -1)". Each place that hands
/// a section's values to a core check keeps a table of the fields that check may name.

#include "core/InputError.h"

#include <span>
#include <string>
#include <string_view>

namespace masse::scene
{
/// One field of a core struct and the key the scene file gives it within its section. List indices are written "[]"
/// in both and carried over in order: {"hotAirZones[].maxCorner", "hot_air_zones[].max"}; an entry may also name one
/// element: {"springClasses[1].stiffness", "stiffness.inter_layer"}.
struct FieldKey
{
    std::string_view field;
    std::string_view key;
};

// The tables: for each core struct a section of the scene file (or a material file) fills, the keys of the fields its
// checks may name. A field missing from its table still reaches the user, in the core's terms under the section.

/// LatticeSpec, from "sheet".
inline constexpr FieldKey latticeKeys[] = {
    {"structure", "structure"}, {"size", "size"}, {"minCorner", "min"}, {"maxCorner", "max"}};
/// SheetParams, from "sheet".
inline constexpr FieldKey sheetKeys[] = {{"massPerMass", "mass"},
                                         {"springClasses[0].stiffness", "stiffness.planar"},
                                         {"springClasses[1].stiffness", "stiffness.inter_layer"},
                                         {"springClasses[0].dampingRatio", "damping.planar"},
                                         {"springClasses[1].dampingRatio", "damping.inter_layer"}};
/// ContactSettings, from "contact".
inline constexpr FieldKey contactKeys[] = {{"response", "response"},
                                           {"radius", "radius"},
                                           {"friction", "friction"},
                                           {"stickReleaseForce", "release_force"},
                                           {"slipRegularization", "slip_regularization"}};
/// SelfContactSettings, from "contact".
inline constexpr FieldKey selfContactKeys[] = {{"radius", "radius"}, {"friction", "self_friction"}};
/// The step the simulator is asked for, from "integrator".
inline constexpr FieldKey integratorKeys[] = {{"integrator", "type"}, {"dt", "dt"}};
/// Material, from a material file or "material.properties"; its law's parameters are in the law's entry
/// (MaterialLawEntry::keys).
inline constexpr FieldKey materialKeys[] = {{"density", "density"},
                                            {"specificHeat", "specific_heat"},
                                            {"conductivity", "conductivity"},
                                            {"glassTransition", "glass_transition_c"},
                                            {"transitionTemperature", "transition_c"},
                                            {"upperTemperature", "upper_c"},
                                            {"kelvinModulusRatio", "kelvin_modulus_ratio"},
                                            {"kelvinViscosityRatio", "kelvin_viscosity_ratio"},
                                            {"forming.set", "forming_window.set_c"},
                                            {"forming.lower", "forming_window.lower_c"},
                                            {"forming.normal", "forming_window.normal_c"},
                                            {"forming.upper", "forming_window.upper_c"}};
/// The material sheet and its springs (makeMaterialSheet, SpringModelSettings), from "material".
inline constexpr FieldKey materialSheetKeys[] = {{"thickness", "thickness"},
                                                 {"dampingRatio", "damping_ratio"},
                                                 {"model", "spring_model"},
                                                 {"strainHardening", "strain_hardening"}};
/// ThermalSettings, from "heat".
inline constexpr FieldKey thermalKeys[] = {{"initialTemperature", "initial_temperature_c"},
                                           {"airTemperature", "air_temperature_c"},
                                           {"airHeatTransfer", "air_heat_transfer"},
                                           {"absorptivity", "absorptivity"},
                                           {"contactHeatTransfer", "contact_heat_transfer"},
                                           {"solverTolerance", "solver_tolerance"},
                                           {"maxIterations", "max_iterations"},
                                           {"heaters[].power", "heaters[].power"},
                                           {"heaters[].width", "heaters[].width"},
                                           {"heaters[].length", "heaters[].length"},
                                           {"heaters[].centre", "heaters[].centre"},
                                           {"heaters[].normal", "heaters[].normal"},
                                           {"heaters[].widthAxis", "heaters[].width_axis"},
                                           {"hotAirZones[].minCorner", "hot_air_zones[].min"},
                                           {"hotAirZones[].maxCorner", "hot_air_zones[].max"},
                                           {"hotAirZones[].temperature", "hot_air_zones[].temperature_c"},
                                           {"hotAirZones[].heatTransfer", "hot_air_zones[].heat_transfer"}};
/// bridge::SoftBodyTwinSettings, from "bullet".
inline constexpr FieldKey bulletKeys[] = {{"kLST", "kLST"},
                                          {"kDP", "kDP"},
                                          {"kDF", "kDF"},
                                          {"kCHR", "kCHR"},
                                          {"kKHR", "kKHR"},
                                          {"margin", "margin"},
                                          {"piterations", "piterations"},
                                          {"substeps", "substeps"},
                                          {"sdfCellSize", "sdf_cell_size"}};
/// PressureSchedule, from "forming".
inline constexpr FieldKey pressureKeys[] = {{"keys[].time", "pressure[].time"},
                                            {"keys[].pressure", "pressure[].pressure"}};

/// The key of `field` by the table, with its indices, or "" when the table has no entry for it.
std::string keyOf(std::span<const FieldKey> keys, const std::string& field);

/// The message of a core InputError raised while checking the values of `section` ("heat", "" for a file's top
/// level): "<section>.<key>: <problem>" when the error names a field of the table, else "<section>: <message>".
std::string messageUnder(const std::string& section, std::span<const FieldKey> keys, const InputError& error);

/// Runs `check`; a core InputError is re-thrown under the scene's names (messageUnder).
template <typename Check> void checkUnder(const std::string& section, std::span<const FieldKey> keys, Check&& check)
{
    try
    {
        check();
    }
    catch (const InputError& e)
    {
        throw InputError(messageUnder(section, keys, e));
    }
}
} // namespace masse::scene
