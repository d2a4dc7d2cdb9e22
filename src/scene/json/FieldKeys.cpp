#include "scene/json/FieldKeys.h"

#include <cctype>
#include <vector>

namespace masse::scene
{
namespace
{
/// `field` with every index emptied ("heaters[1].power" -> "heaters[].power"), and the indices, in order.
std::string pattern(const std::string& field, std::vector<std::string>& indices)
{
    std::string out;
    for (std::size_t i = 0; i < field.size(); ++i)
    {
        out += field[i];
        if (field[i] != '[')
        {
            continue;
        }
        std::size_t end = i + 1;
        while (end < field.size() && std::isdigit(static_cast<unsigned char>(field[end])))
        {
            ++end;
        }
        indices.push_back(field.substr(i + 1, end - i - 1));
        i = end - 1;
    }
    return out;
}
} // namespace

std::string keyOf(std::span<const FieldKey> keys, const std::string& field)
{
    for (const FieldKey& entry : keys)
    {
        if (entry.field == field) // an entry for one element ("springClasses[1].stiffness")
        {
            return std::string(entry.key);
        }
    }
    std::vector<std::string> indices;
    const std::string wanted = pattern(field, indices);
    for (const FieldKey& entry : keys)
    {
        if (entry.field != wanted)
        {
            continue;
        }
        std::string key;
        std::size_t next = 0;
        for (std::size_t i = 0; i < entry.key.size(); ++i)
        {
            key += entry.key[i];
            if (entry.key[i] == '[' && next < indices.size())
            {
                key += indices[next++];
            }
        }
        return key;
    }
    return "";
}

std::string messageUnder(const std::string& section, std::span<const FieldKey> keys, const InputError& error)
{
    const std::string key = error.field().empty() ? "" : keyOf(keys, error.field());
    if (!key.empty())
    {
        return (section.empty() ? key : section + "." + key) + ": " + error.problem();
    }
    return section.empty() ? std::string(error.what()) : section + ": " + error.what();
}
} // namespace masse::scene
