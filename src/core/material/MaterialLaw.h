#pragma once
/// How a material's stiffness and viscosity follow temperature, and the registry of such laws: one entry a law,
/// listed in one table (MaterialLaw.cpp), as the integrators are in core/integrate/Integrator.h. A material file
/// names its law (`law`, the first entry's when it does not) and the scene's reader reads that law's keys through its
/// entry. A law is its own file in this folder (its parameters, how it reads them, E(T), eta(T) and their checks),
/// its line in the table and its row in data/scenes/README.md's material-file table (docs/development.md).

#include "core/Types.h"

#include <memory>
#include <span>
#include <string>
#include <string_view>

namespace masse
{
struct Material;

/// A law with its parameters. The temperatures every law shares (the transition, the top of the model's range) are
/// the material's own and are passed in.
class MaterialLaw
{
public:
    virtual ~MaterialLaw() = default;
    /// Young's modulus E(T) in Pa.
    virtual Real modulusAt(const Material& material, Real temperature) const = 0;
    /// Shear viscosity eta(T) in Pa s.
    virtual Real viscosityAt(const Material& material, Real temperature) const = 0;
    /// Throws InputError naming the first bad parameter by its field (as the entry's `keys` list it).
    virtual void validate(const Material& material) const = 0;
};

/// A law's keys in a material file, as the scene's reader hands them over: the core does not know the file's format,
/// and a missing or malformed value gets the reader's own message naming the key.
class LawKeys
{
public:
    virtual ~LawKeys() = default;
    /// A number the file must give.
    virtual Real number(const std::string& key) const = 0;
    /// A number, or `fallback` when the file leaves the key out.
    virtual Real number(const std::string& key, Real fallback) const = 0;
};

/// A parameter's field, as a law's validate names it, and its key in a material file.
struct LawParameterKey
{
    std::string_view field;
    std::string_view key;
};

struct MaterialLawEntry
{
    std::string_view name; ///< `law` in material files
    /// Reads the law's parameters, key by key in the order a missing one is reported.
    std::shared_ptr<const MaterialLaw> (*read)(const LawKeys& keys) = nullptr;
    /// Its parameters' fields and keys, so that the reader names the key of a value validate refuses.
    std::span<const LawParameterKey> keys = {};
};

/// Every registered law, in the table's order; the first is the law of a material file that names none.
std::span<const MaterialLawEntry* const> materialLaws();
/// The registered law of `name`; throws InputError naming the registered ones for any other.
const MaterialLawEntry& materialLawNamed(std::string_view name);
} // namespace masse
