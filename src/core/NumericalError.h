#pragma once
/// The one error type for a run that went wrong: the state left double precision's range, a mass outran the speed
/// bound, energy was created, a temperature fell below absolute zero.
///
/// The message says when, where and what to try (for example `the simulation diverged at t = 0.23 s: mass 1056 has
/// a non-finite position or velocity`); the command line turns it into exit code 1, and no output holds the bad state.
/// Bad input is InputError (exit code 2).

#include <stdexcept>
#include <string>

namespace masse
{
class NumericalError : public std::runtime_error
{
public:
    explicit NumericalError(const std::string& message) : std::runtime_error(message) {}
};
} // namespace masse
