#include "scene/json/JsonPath.h"

#include "core/InputError.h"
#include "core/NearestName.h"

#include <cctype>

namespace masse::scene
{
namespace
{
std::string prefixText(const JsonPath& path, std::size_t count)
{
    JsonPath prefix;
    prefix.steps.assign(path.steps.begin(), path.steps.begin() + std::ptrdiff_t(count));
    return prefix.text();
}

std::string kindOf(const nlohmann::json& value)
{
    if (value.is_object())
    {
        return "an object";
    }
    if (value.is_array())
    {
        return "a list";
    }
    return "a " + std::string(value.type_name()) + " (" + value.dump() + ")";
}
} // namespace

std::string JsonPath::text() const
{
    std::string out;
    for (const JsonPathStep& step : steps)
    {
        // Appended piece by piece: "[" + std::to_string(...) trips GCC 12's false -Wrestrict warning.
        if (step.isIndex)
        {
            out += '[';
            out += std::to_string(step.index);
            out += ']';
        }
        else
        {
            if (!out.empty())
            {
                out += '.';
            }
            out += step.key;
        }
    }
    return out;
}

JsonPath parseJsonPath(const std::string& text)
{
    JsonPath path;
    std::size_t i = 0;
    auto fail = [&](const std::string& what) { throw InputError(text + ": " + what); };
    if (text.empty())
    {
        fail("empty key");
    }
    while (i < text.size())
    {
        if (text[i] == '[')
        {
            const std::size_t close = text.find(']', i);
            if (close == std::string::npos || close == i + 1)
            {
                fail("expected an index in brackets, such as [0]");
            }
            const std::string digits = text.substr(i + 1, close - i - 1);
            for (char c : digits)
            {
                if (!std::isdigit(static_cast<unsigned char>(c)))
                {
                    fail("index '" + digits + "' is not a whole number >= 0");
                }
            }
            if (path.steps.empty() || digits.size() > 9)
            {
                fail(path.steps.empty() ? "a path starts with a key, not an index" : "index too large");
            }
            path.steps.push_back({"", std::stoul(digits), true});
            i = close + 1;
            if (i < text.size() && text[i] != '.' && text[i] != '[')
            {
                fail("expected '.' or '[' after ']'");
            }
            if (i < text.size() && text[i] == '.')
            {
                ++i;
                if (i == text.size())
                {
                    fail("ends with '.'");
                }
            }
            continue;
        }
        const std::size_t end = text.find_first_of(".[]", i);
        const std::string key = text.substr(i, end == std::string::npos ? std::string::npos : end - i);
        if (key.empty())
        {
            fail("empty key between dots");
        }
        path.steps.push_back({key, 0, false});
        i = end == std::string::npos ? text.size() : end;
        if (i < text.size() && text[i] == ']')
        {
            fail("']' without '['");
        }
        if (i < text.size() && text[i] == '.')
        {
            ++i;
            if (i == text.size())
            {
                fail("ends with '.'");
            }
        }
    }
    return path;
}

const nlohmann::json* findAt(const nlohmann::json& document, const JsonPath& path)
{
    const nlohmann::json* at = &document;
    for (const JsonPathStep& step : path.steps)
    {
        if (step.isIndex)
        {
            if (!at->is_array() || step.index >= at->size())
            {
                return nullptr;
            }
            at = &(*at)[step.index];
        }
        else
        {
            if (!at->is_object())
            {
                return nullptr;
            }
            const auto it = at->find(step.key);
            if (it == at->end())
            {
                return nullptr;
            }
            at = &*it;
        }
    }
    return at;
}

void assignAt(nlohmann::json& document, const JsonPath& path, nlohmann::json value)
{
    nlohmann::json* at = &document;
    for (std::size_t i = 0; i < path.steps.size(); ++i)
    {
        const JsonPathStep& step = path.steps[i];
        const std::string here = prefixText(path, i);
        if (step.isIndex)
        {
            if (!at->is_array())
            {
                throw InputError(path.text() + ": " + here + " is " + kindOf(*at) + ", not a list");
            }
            if (step.index >= at->size())
            {
                throw InputError(path.text() + ": " + here + " has " + std::to_string(at->size()) +
                                 " element(s), so no [" + std::to_string(step.index) + "]");
            }
            at = &(*at)[step.index];
        }
        else
        {
            if (at->is_null())
            {
                *at = nlohmann::json::object(); // a section the scene leaves to its defaults
            }
            if (!at->is_object())
            {
                throw InputError(path.text() + ": " + (here.empty() ? std::string("the document") : here) + " is " +
                                 kindOf(*at) + ", not an object with keys");
            }
            if (!at->contains(step.key) && i + 1 < path.steps.size() && path.steps[i + 1].isIndex)
            {
                // A list that is not there cannot be indexed: most often a misspelt name ("heater" for "heaters").
                std::vector<std::string> keys;
                for (auto it = at->begin(); it != at->end(); ++it)
                {
                    keys.push_back(it.key());
                }
                throw InputError(path.text() + ": " + (here.empty() ? std::string("the document") : here) +
                                 " has no list '" + step.key + "'" + didYouMean(step.key, keys));
            }
            at = &(*at)[step.key];
        }
    }
    *at = std::move(value);
}
} // namespace masse::scene
