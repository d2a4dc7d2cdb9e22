#pragma once
/// Names of enum values for files and flags ("trimm", "implicit", "sticky"...): one table per enum, parsed and
/// printed the same way everywhere, with the same message for a name that is not in the table.

#include "core/InputError.h"

#include <algorithm>
#include <cctype>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

namespace masse
{
template <typename Enum> struct EnumName
{
    Enum value;
    std::string_view name;
};

/// The value of the entry named `name` (any case) in a table whose entries have a `name` (a registry such as the
/// integrators'), `valueOf` giving an entry's value; throws InputError for `field` (the setting the name is for, in
/// the caller's terms): "<field>: unknown <what> '<name>' (expected one of a, b, c)".
template <typename Entries, typename ValueOf>
auto parseNamed(const Entries& entries, std::string_view name, std::string_view field, std::string_view what,
                ValueOf valueOf)
{
    std::string lower(name);
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    std::string list;
    for (const auto& entry : entries)
    {
        if (entry.name == lower)
        {
            return valueOf(entry);
        }
        list += (list.empty() ? "" : ", ") + std::string(entry.name);
    }
    throw InputError(std::string(field),
                     "unknown " + std::string(what) + " '" + std::string(name) + "' (expected one of " + list + ")");
}

/// The value named `name` (any case) in an enum's name table (parseNamed).
template <typename Enum, std::size_t N>
Enum parseEnum(const EnumName<Enum> (&names)[N], std::string_view name, std::string_view field, std::string_view what)
{
    return parseNamed(names, name, field, what, [](const EnumName<Enum>& entry) { return entry.value; });
}

/// The names of a table whose entries have a `name`, in its order: a scene reader's choices.
template <typename Entries> std::vector<std::string> namesOf(const Entries& entries)
{
    std::vector<std::string> names;
    for (const auto& entry : entries)
    {
        names.emplace_back(entry.name);
    }
    return names;
}

/// "a, b, c or d": the names of a table whose entries have a `name`, for help strings.
template <typename Entries> std::string nameList(const Entries& entries)
{
    std::string list;
    const std::size_t count = std::size(entries);
    std::size_t k = 0;
    for (const auto& entry : entries)
    {
        list += (k == 0 ? "" : k + 1 == count ? " or " : ", ") + std::string(entry.name);
        ++k;
    }
    return list;
}

template <typename Enum, std::size_t N> std::string_view enumName(const EnumName<Enum> (&names)[N], Enum value)
{
    for (const EnumName<Enum>& entry : names)
    {
        if (entry.value == value)
        {
            return entry.name;
        }
    }
    return "unknown";
}
} // namespace masse
