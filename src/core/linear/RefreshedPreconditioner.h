#pragma once
/// A preconditioner built from a recent matrix and kept while it serves (the implicit solve rebuilds it only when the
/// conjugate gradient needs more than a few iterations with it), applied through the current step's contact filter.

#include "core/linear/ConjugateGradient.h"

#include <vector>

namespace masse
{
class RefreshedPreconditioner : public Preconditioner
{
public:
    /// Rebuilds from the matrix's current values (same pattern as analysed). Returns false if it cannot (a matrix
    /// that is not positive definite to the factorisation); then ready() is false.
    virtual bool refresh(const SparseMatrix& a) = 0;
    virtual bool ready() const = 0;
    /// The masses filtered this step and their S, the projection onto their free directions (both outlive the
    /// solve); empty for none. apply() gives z = S P^-1 S r + (I - S) r.
    virtual void setFilter(const std::vector<Index>& masses, const std::vector<Mat3>& filters) = 0;
    /// Rebuilds since construction.
    virtual int refreshCount() const = 0;
};
} // namespace masse
