#pragma once
/// Sheet materials from JSON: the files in data/materials/ or a "material" object inside a scene.
///
/// Keys (SI units; temperatures in celsius, in keys ending in "_c"; see core/Material.h for the model):
///   name (string), source (string, where the numbers come from; optional),
///   density (kg/m^3), specific_heat (J/(kg K)), conductivity (W/(m K)),
///   glass_transition_c, transition_c (optional, defaults to glass_transition_c), upper_c,
///   glassy_modulus (Pa), rubbery_modulus (Pa), transition_width (K, optional, 5),
///   wlf_c1 (optional, 17.44), wlf_c2 (K, optional, 51.6), viscosity_at_transition (Pa s),
///   solid_activation_energy (J/mol, optional, 0: match the WLF slope),
///   kelvin_modulus_ratio (optional, 1), kelvin_viscosity_ratio (optional, 0.05),
///   forming_window: {set_c, lower_c, normal_c, upper_c}.
/// Unknown keys are refused with the nearest known key suggested.

#include "scene/json/JsonObject.h"

#include "core/material/Material.h"

#include <string>

namespace masse::scene
{
/// Reads a material from a JSON object; throws InputError naming the key's path (e.g. "material.conductivity: must
/// be a positive number of W/(m K) (got -0.2)").
Material parseMaterial(const JsonObject& object);

/// Reads a material file; throws InputError naming the file and the key.
Material readMaterialFile(const std::string& path);
} // namespace masse::scene
