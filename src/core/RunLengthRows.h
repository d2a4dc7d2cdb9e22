#pragma once
/// A sparse matrix stored by rows as runs of consecutive columns: each run keeps its first column and its values, and
/// no entry has an index of its own.
///
/// Made for the triangular solves with a nested-dissection Cholesky factor, which stream the whole factor on every
/// preconditioner application. A separator's masses are consecutive in the order, so the factor's rows and columns
/// are long runs (at 128x2x128, 25.8 million entries in 172,000 runs by rows, 727,000 by columns). Stored as runs, a
/// solve reads no index per entry and reads x contiguously, in vectors.
///
/// The values are single precision: the factor only preconditions the conjugate gradient, which converges in double
/// precision whatever the preconditioner's rounding (both solves read the same rounded factor, so it stays symmetric
/// positive definite). Half the bytes to stream: one preconditioner application at 128x2x128 took 13 ms with double
/// values, 10 ms with single, at two threads.

#include "Types.h"

#include <Eigen/SparseCore>

#include <vector>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace masse
{
class RunLengthRows
{
public:
    using SparseMatrix = Eigen::SparseMatrix<Real>;
    using StorageIndex = SparseMatrix::StorageIndex;

    /// The strictly lower part of `lower` (column-major, each column's rows increasing) by rows: row i holds L_ij for
    /// j < i, in increasing j.
    void assignLowerRows(const SparseMatrix& lower);
    /// The strictly lower part of `lower` by columns, the last column first: row q holds column n-1-q's entries L_iq'
    /// (q' = n-1-q, i > q'), in increasing i.
    void assignLowerColumnsLastFirst(const SparseMatrix& lower);

    Eigen::Index rows() const { return Eigen::Index(m_rowRuns.size()) - 1; }
    std::size_t entries() const { return m_values.size(); }
    std::size_t runs() const { return m_runColumn.size(); }

    /// The arrays, for the kernels (rowDot below).
    struct View
    {
        const StorageIndex* rowRuns;
        const StorageIndex* runColumn;
        const StorageIndex* runStart;
        const float* values;
    };
    View view() const { return {m_rowRuns.data(), m_runColumn.data(), m_runStart.data(), m_values.data()}; }

private:
    /// Fills the storage from `forEachEntry(visit)`, which calls visit(row, column, value) for every entry, each row's
    /// entries in increasing column (rows may interleave); called twice, to count and to fill.
    template <class ForEachEntry> void assign(Eigen::Index rowCount, const ForEachEntry& forEachEntry);

    std::vector<StorageIndex> m_rowRuns;   ///< runs of row i: [m_rowRuns[i], m_rowRuns[i + 1])
    std::vector<StorageIndex> m_runColumn; ///< first column of run r
    std::vector<StorageIndex> m_runStart;  ///< values of run r: [m_runStart[r], m_runStart[r + 1]); one past the last
    std::vector<float> m_values;
    std::vector<StorageIndex> m_nextValue; ///< scratch of assign(), kept so that a refresh does not allocate it anew
    std::vector<StorageIndex> m_nextRun;
    std::vector<StorageIndex> m_lastColumn;
};

/// sum over row i's entries of value * x[column], in a fixed order whoever calls it and on any vector width: `lanes`
/// running sums (4 or 8), entry t of a run going to sum t mod lanes, added pairwise at the end (the entries past the
/// last full group of lanes are added one by one; rowDotAvx512 adds them under a mask). Inlined into each SIMD path's
/// copy of the caller (see SimdPath.h): only the instruction set differs.
template <int lanes>
[[gnu::always_inline]] inline Real rowDot(const RunLengthRows::View& m, Eigen::Index row, const Real* x)
{
    static_assert(lanes == 4 || lanes == 8);
    Real sum[lanes] = {};
    for (auto run = m.rowRuns[row]; run < m.rowRuns[row + 1]; ++run)
    {
        const float* v = m.values + m.runStart[run];
        const Real* xs = x + m.runColumn[run];
        const RunLengthRows::StorageIndex length = m.runStart[run + 1] - m.runStart[run];
        RunLengthRows::StorageIndex t = 0;
        for (; t + lanes <= length; t += lanes)
        {
            for (int lane = 0; lane < lanes; ++lane)
            {
                sum[lane] += Real(v[t + lane]) * xs[t + lane];
            }
        }
        for (int lane = 0; t + lane < length; ++lane)
        {
            sum[lane] += Real(v[t + lane]) * xs[t + lane];
        }
    }
    if constexpr (lanes == 4)
    {
        return (sum[0] + sum[1]) + (sum[2] + sum[3]);
    }
    else
    {
        return ((sum[0] + sum[1]) + (sum[2] + sum[3])) + ((sum[4] + sum[5]) + (sum[6] + sum[7]));
    }
}
#if defined(__x86_64__) && defined(__GNUC__)
/// rowDot<8> with AVX-512, the same bits: each group of eight entries goes into the eight sums in one vector, and a
/// run's last entries (fewer than eight) are added to their sums under a mask instead of one by one, so entry t of a
/// run still goes to sum t mod 8, in order, and the sums past the run's end are left as they were (not even + 0,
/// which would turn a -0 into +0).
[[gnu::always_inline]] inline __attribute__((target("avx512f"))) Real rowDotAvx512(const RunLengthRows::View& m,
                                                                                   Eigen::Index row, const Real* x)
{
    __m512d sum = _mm512_setzero_pd();
    for (auto run = m.rowRuns[row]; run < m.rowRuns[row + 1]; ++run)
    {
        const float* v = m.values + m.runStart[run];
        const Real* xs = x + m.runColumn[run];
        const RunLengthRows::StorageIndex length = m.runStart[run + 1] - m.runStart[run];
        RunLengthRows::StorageIndex t = 0;
        // The zero-masking forms throughout: GCC 12's plain _mm512_cvtps_pd and _mm512_castps512_ps256 merge into an
        // "undefined" vector, which its own -Wmaybe-uninitialized reports.
        const __mmask8 all = 0xFF;
        for (; t + 8 <= length; t += 8)
        {
            const __m512d values = _mm512_maskz_cvtps_pd(all, _mm256_loadu_ps(v + t));
            sum = _mm512_add_pd(sum, _mm512_mul_pd(values, _mm512_loadu_pd(xs + t)));
        }
        if (t < length)
        {
            const unsigned remaining = unsigned(length - t);
            const __mmask8 mask = __mmask8((1u << remaining) - 1);
            // A masked load reads nothing past the run, so it cannot fault at the end of the arrays.
            const __m512 tail = _mm512_maskz_loadu_ps(__mmask16((1u << remaining) - 1), v + t);
            const __m256 low = _mm256_castpd_ps(_mm512_maskz_extractf64x4_pd(__mmask8(0xF), _mm512_castps_pd(tail), 0));
            const __m512d values = _mm512_maskz_cvtps_pd(mask, low);
            const __m512d product = _mm512_mul_pd(values, _mm512_maskz_loadu_pd(mask, xs + t));
            sum = _mm512_mask_add_pd(sum, mask, sum, product);
        }
    }
    alignas(64) Real lanes[8];
    _mm512_store_pd(lanes, sum);
    return ((lanes[0] + lanes[1]) + (lanes[2] + lanes[3])) + ((lanes[4] + lanes[5]) + (lanes[6] + lanes[7]));
}
#endif
} // namespace masse
