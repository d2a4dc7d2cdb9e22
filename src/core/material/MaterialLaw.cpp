#include "core/material/MaterialLaw.h"

#include "core/InputError.h"

namespace masse
{
// Each entry is defined in its law's own file, named beside it in the table.
extern const MaterialLawEntry wlfLawEntry;

namespace
{
// The first is the law of a material file that names none; messages list the laws in this order.
constexpr const MaterialLawEntry* lawTable[] = {
    &wlfLawEntry, // WlfLaw.cpp
};
} // namespace

std::span<const MaterialLawEntry* const> materialLaws()
{
    return lawTable;
}

const MaterialLawEntry& materialLawNamed(std::string_view name)
{
    std::string names;
    for (const MaterialLawEntry* law : lawTable)
    {
        if (law->name == name)
        {
            return *law;
        }
        names += (names.empty() ? "" : ", ") + std::string(law->name);
    }
    throw InputError("law", "unknown material law '" + std::string(name) + "' (expected " + names + ")");
}
} // namespace masse
