#pragma once
/// Reductions whose bits do not depend on how the work is split: a vector is cut into chunks of a fixed size, each
/// chunk is summed in index order, and the chunk sums are added in chunk order. The task pool hands the chunks to
/// any number of threads and the result stays the same bit for bit, because the chunking never changes.

#include "core/Types.h"
#include "core/parallel/TaskPool.h"

#include <Eigen/Core>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace masse
{
/// Entries per chunk: large enough that one chunk's loop vectorises and amortises a task, small enough that a
/// 64x2x64 sheet (24,576 unknowns) still splits into a dozen pieces.
inline constexpr std::size_t reductionChunk = 2048;

/// a . b over chunk `chunk`: entries [chunk * reductionChunk, min(size, (chunk + 1) * reductionChunk)).
inline Real chunkDot(const Eigen::VectorX<Real>& a, const Eigen::VectorX<Real>& b, std::size_t chunk)
{
    // Four running sums in a fixed pattern rather than Eigen's dot, whose order follows the SIMD width the build
    // targets: the compiler may not reorder these (no -ffast-math), so every SIMD path gives the same bits.
    const std::size_t begin = chunk * reductionChunk;
    const std::size_t end = std::min(std::size_t(a.size()), begin + reductionChunk);
    const Real* x = a.data();
    const Real* y = b.data();
    Real s0 = 0, s1 = 0, s2 = 0, s3 = 0;
    std::size_t i = begin;
    for (; i + 4 <= end; i += 4)
    {
        s0 += x[i] * y[i];
        s1 += x[i + 1] * y[i + 1];
        s2 += x[i + 2] * y[i + 2];
        s3 += x[i + 3] * y[i + 3];
    }
    for (; i < end; ++i)
    {
        s0 += x[i] * y[i];
    }
    return (s0 + s1) + (s2 + s3);
}

/// The sum over [0, count) of term(begin, end), the terms of chunks of `chunkSize` items computed in parallel and
/// added in chunk order: the same bits at any thread count. `term` sums its own range in index order.
template <class Term> Real chunkedSum(std::size_t count, std::size_t chunkSize, const Term& term)
{
    const std::size_t chunks = chunkCount(count, chunkSize);
    constexpr std::size_t onStack = 1024; // 2M entries at reductionChunk: no allocation below
    Real stackPartial[onStack];
    std::vector<Real> heapPartial(chunks > onStack ? chunks : 0);
    Real* partial = chunks > onStack ? heapPartial.data() : stackPartial;
    parallelFor(count, chunkSize,
                [&](std::size_t begin, std::size_t end) { partial[begin / chunkSize] = term(begin, end); });
    Real sum = 0;
    for (std::size_t c = 0; c < chunks; ++c) // always serial and in order
    {
        sum += partial[c];
    }
    return sum;
}

/// a . b summed chunk by chunk in chunk order (see the file comment).
inline Real chunkedDot(const Eigen::VectorX<Real>& a, const Eigen::VectorX<Real>& b)
{
    return chunkedSum(std::size_t(a.size()), reductionChunk,
                      [&](std::size_t begin, std::size_t) { return chunkDot(a, b, begin / reductionChunk); });
}
} // namespace masse
