#include "core/integrate/Integrator.h"

#include "core/NamedEnum.h"

#include <string>

namespace masse
{
namespace
{
constexpr EnumName<IntegratorKind> integratorNames[] = {
    {IntegratorKind::ExplicitEuler, "euler"},
    {IntegratorKind::SymplecticEuler, "symplectic"},
    {IntegratorKind::VelocityVerlet, "verlet"},
    {IntegratorKind::ImplicitEuler, "implicit"},
    {IntegratorKind::Bdf2, "bdf2"},
    {IntegratorKind::TrBdf2, "trbdf2"},
};
constexpr EnumName<PreconditionerKind> preconditionerNames[] = {
    {PreconditionerKind::Multigrid, "multigrid"},
    {PreconditionerKind::Cholesky, "cholesky"},
    {PreconditionerKind::Jacobi, "jacobi"},
};
} // namespace

std::string_view preconditionerName(PreconditionerKind kind)
{
    return enumName(preconditionerNames, kind);
}

PreconditionerKind parsePreconditioner(std::string_view name)
{
    return parseEnum(preconditionerNames, name, "preconditioner", "preconditioner");
}

IntegratorKind parseIntegrator(std::string_view name)
{
    return parseEnum(integratorNames, name, "integrator", "integrator");
}

std::string_view integratorName(IntegratorKind kind)
{
    return enumName(integratorNames, kind);
}

bool isExplicit(IntegratorKind kind)
{
    return kind != IntegratorKind::ImplicitEuler && kind != IntegratorKind::Bdf2 && kind != IntegratorKind::TrBdf2;
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
    case IntegratorKind::Bdf2:
        return makeBdf2(implicit);
    case IntegratorKind::TrBdf2:
        return makeTrBdf2(implicit);
    }
    return nullptr;
}
} // namespace masse
