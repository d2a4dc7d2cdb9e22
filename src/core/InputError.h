#pragma once
/// The one error type for bad input: a value out of range, an unknown name, a malformed file.
///
/// The message names what is wrong and where (for example `sheet.size: N must be >= 2 (got 1)`); the command line
/// turns it into exit code 2. Anything else thrown is a bug, not a user's mistake.
///
/// The core checks the values of its own structs and does not know where they came from, so it names a bad value by
/// its field in its own terms, a member of the struct it checks (`InputError("stickReleaseForce", "must be >= 0 N (got
/// -1)")`; list elements and nested members as code would reach them, "heaters[1].power"). The layer that read the
/// value knows its name there and says that instead: the scene file's key ("scene.json: contact.release_force: must be
/// >= 0 N (got -1)"), or the flag. On its own, what() reads "<field>: <problem>".

#include <stdexcept>
#include <string>

namespace masse
{
class InputError : public std::runtime_error
{
public:
    /// A message that already says what is wrong and where.
    explicit InputError(const std::string& message) : std::runtime_error(message) {}
    /// A bad value of one field, named in the thrower's terms.
    InputError(const std::string& field, const std::string& problem)
        : std::runtime_error(field + ": " + problem), m_field(field), m_problem(problem)
    {
    }

    /// The bad field, or "" when the message is not about one field.
    const std::string& field() const { return m_field; }
    /// What is wrong with the field (the message without "<field>: "), or the whole message when there is no field.
    std::string problem() const { return m_field.empty() ? std::string(what()) : m_problem; }

private:
    std::string m_field;
    std::string m_problem;
};
} // namespace masse
