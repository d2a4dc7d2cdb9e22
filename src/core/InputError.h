#pragma once
/// The one error type for bad input: a value out of range, an unknown name, a malformed file.
///
/// The message names what is wrong and where (for example `size: N must be >= 2 (got 1)`); the command line turns
/// it into exit code 2. Anything else thrown is a bug, not a user's mistake.

#include <stdexcept>
#include <string>

namespace masse
{
class InputError : public std::runtime_error
{
public:
    explicit InputError(const std::string& message) : std::runtime_error(message) {}
};
} // namespace masse
