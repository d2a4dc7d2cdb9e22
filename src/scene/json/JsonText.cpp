#include "scene/json/JsonText.h"

#include "core/InputError.h"

#include <cstddef>

namespace masse::scene
{
namespace
{
/// A forward scanner over JSON text that knows strings and comments, so braces inside them are not structure.
class Scanner
{
public:
    explicit Scanner(const std::string& text) : m_text(text) {}

    std::size_t position() const { return m_at; }
    bool done() const { return m_at >= m_text.size(); }
    char peek() const { return done() ? '\0' : m_text[m_at]; }

    /// Skips whitespace and comments.
    void skipSpace()
    {
        while (!done())
        {
            const char c = m_text[m_at];
            if (c == ' ' || c == '\t' || c == '\n' || c == '\r')
            {
                ++m_at;
            }
            else if (c == '/' && m_at + 1 < m_text.size() && m_text[m_at + 1] == '/')
            {
                const std::size_t end = m_text.find('\n', m_at);
                m_at = end == std::string::npos ? m_text.size() : end + 1;
            }
            else if (c == '/' && m_at + 1 < m_text.size() && m_text[m_at + 1] == '*')
            {
                const std::size_t end = m_text.find("*/", m_at + 2);
                m_at = end == std::string::npos ? m_text.size() : end + 2;
            }
            else
            {
                return;
            }
        }
    }

    /// Reads a string literal starting here and returns its raw contents (escapes left as written).
    std::string readString()
    {
        expect('"');
        const std::size_t start = m_at;
        while (!done() && m_text[m_at] != '"')
        {
            m_at += m_text[m_at] == '\\' ? 2 : 1;
        }
        const std::string contents = m_text.substr(start, m_at - start);
        expect('"');
        return contents;
    }

    /// Skips one value (object, array, string or scalar) starting here.
    void skipValue()
    {
        const char c = peek();
        if (c == '"')
        {
            readString();
            return;
        }
        if (c == '{' || c == '[')
        {
            int depth = 0;
            while (!done())
            {
                skipSpace();
                const char d = peek();
                if (d == '"')
                {
                    readString();
                    continue;
                }
                ++m_at;
                if (d == '{' || d == '[')
                {
                    ++depth;
                }
                else if ((d == '}' || d == ']') && --depth == 0)
                {
                    return;
                }
            }
            fail("an unclosed object or list");
        }
        const std::size_t start = m_at;
        while (!done() && std::string(",}] \t\r\n/").find(m_text[m_at]) == std::string::npos)
        {
            ++m_at;
        }
        if (m_at == start)
        {
            fail("a value");
        }
    }

    void expect(char c)
    {
        if (peek() != c)
        {
            fail(std::string("'") + c + "'");
        }
        ++m_at;
    }

    [[noreturn]] void fail(const std::string& wanted) const
    {
        throw InputError("expected " + wanted + " at character " + std::to_string(m_at) + " of the JSON text");
    }

private:
    const std::string& m_text;
    std::size_t m_at = 0;
};

/// The whitespace that starts the line holding `position`.
std::string indentationAt(const std::string& text, std::size_t position)
{
    const std::size_t lineStart = text.rfind('\n', position == 0 ? 0 : position - 1);
    std::size_t start = lineStart == std::string::npos ? 0 : lineStart + 1;
    std::size_t end = start;
    while (end < text.size() && (text[end] == ' ' || text[end] == '\t'))
    {
        ++end;
    }
    return text.substr(start, end - start);
}

/// `value` pretty-printed with two-space steps, its second and later lines shifted by `indentation`.
std::string indented(const nlohmann::json& value, const std::string& indentation)
{
    const std::string dumped = value.dump(2);
    std::string out;
    for (char c : dumped)
    {
        out += c;
        if (c == '\n')
        {
            out += indentation;
        }
    }
    return out;
}
} // namespace

std::string withTopLevelValue(const std::string& text, const std::string& key, const nlohmann::json& value)
{
    Scanner scan(text);
    scan.skipSpace();
    scan.expect('{');
    std::size_t lastValueEnd = std::string::npos; // just after the last member's value
    std::string memberIndentation = "  ";
    while (true)
    {
        scan.skipSpace();
        if (scan.peek() == '}')
        {
            break;
        }
        if (scan.peek() == ',')
        {
            scan.expect(',');
            continue;
        }
        const std::size_t keyStart = scan.position();
        const std::string name = scan.readString();
        memberIndentation = indentationAt(text, keyStart);
        scan.skipSpace();
        scan.expect(':');
        scan.skipSpace();
        const std::size_t valueStart = scan.position();
        scan.skipValue();
        if (name == key)
        {
            return text.substr(0, valueStart) + indented(value, memberIndentation) + text.substr(scan.position());
        }
        lastValueEnd = scan.position();
    }
    const std::string member = "\"" + key + "\": " + indented(value, memberIndentation);
    if (lastValueEnd == std::string::npos)
    {
        // An empty object: the member goes inside its braces.
        const std::size_t close = scan.position();
        return text.substr(0, close) + "\n" + memberIndentation + member + "\n" + text.substr(close);
    }
    return text.substr(0, lastValueEnd) + ",\n" + memberIndentation + member + text.substr(lastValueEnd);
}
} // namespace masse::scene
