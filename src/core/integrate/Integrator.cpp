#include "core/integrate/Integrator.h"

#include "core/NamedEnum.h"

#include <stdexcept>
#include <string>

namespace masse
{
namespace
{
const IntegratorEntry& entryOf(IntegratorKind kind)
{
    for (const IntegratorEntry& entry : integratorTable)
    {
        if (entry.kind == kind)
        {
            return entry;
        }
    }
    throw std::logic_error("an integrator without an entry in integratorTable");
}

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

std::span<const IntegratorEntry> integrators()
{
    return integratorTable;
}

std::string integratorNameList()
{
    return nameList(integratorTable);
}

IntegratorKind parseIntegrator(std::string_view name)
{
    return parseNamed(integratorTable, name, "integrator", "integrator",
                      [](const IntegratorEntry& entry) { return entry.kind; });
}

std::string_view integratorName(IntegratorKind kind)
{
    return entryOf(kind).name;
}

bool isExplicit(IntegratorKind kind)
{
    return entryOf(kind).explicitStep;
}

int solvesKept(IntegratorKind kind)
{
    return entryOf(kind).solvesKept;
}

std::unique_ptr<Integrator> makeIntegrator(IntegratorKind kind, const ImplicitSettings& implicit)
{
    return entryOf(kind).make(implicit);
}
} // namespace masse
