#include "Integrator.h"

#include "InputError.h"

#include <string>

namespace masse
{
namespace
{
struct IntegratorName
{
    IntegratorKind kind;
    std::string_view name;
};
constexpr IntegratorName integratorNames[] = {
    {IntegratorKind::ExplicitEuler, "euler"},
    {IntegratorKind::SymplecticEuler, "symplectic"},
    {IntegratorKind::VelocityVerlet, "verlet"},
    {IntegratorKind::ImplicitEuler, "implicit"},
};
} // namespace

IntegratorKind parseIntegrator(std::string_view name)
{
    for (const IntegratorName& entry : integratorNames)
    {
        if (entry.name == name)
        {
            return entry.kind;
        }
    }
    throw InputError("integrator: unknown integrator '" + std::string(name) +
                     "' (expected one of euler, symplectic, verlet, implicit)");
}

std::string_view integratorName(IntegratorKind kind)
{
    for (const IntegratorName& entry : integratorNames)
    {
        if (entry.kind == kind)
        {
            return entry.name;
        }
    }
    return "unknown";
}

bool isExplicit(IntegratorKind kind)
{
    return kind != IntegratorKind::ImplicitEuler;
}

std::unique_ptr<Integrator> makeIntegrator(IntegratorKind kind, const ImplicitSettings& implicit)
{
    switch (kind)
    {
    case IntegratorKind::ExplicitEuler:
        return makeExplicitEuler();
    case IntegratorKind::SymplecticEuler:
        return makeSymplecticEuler();
    case IntegratorKind::VelocityVerlet:
        return makeVelocityVerlet();
    case IntegratorKind::ImplicitEuler:
        return makeImplicitEuler(implicit);
    }
    return nullptr;
}
} // namespace masse
