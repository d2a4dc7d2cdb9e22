#pragma once
/// A sparse matrix stored by rows as runs of consecutive columns: each run keeps its first column and its values, and
/// no entry has an index of its own.
///
/// Made for the triangular solves with a nested-dissection Cholesky factor, which stream the whole factor on every
/// preconditioner application. A separator's masses are consecutive in the order, so the factor's rows and columns
/// are long runs (at 128x2x128, 25.8 million entries in 172,000 runs by rows, 727,000 by columns). Stored as runs, a
/// solve reads no index per entry and reads x contiguously, in vectors.
///
/// The values are half precision (IEEE binary16, 11 significant bits), and the solves run in single precision: the
/// factor only preconditions the conjugate gradient, which converges in double precision whatever the
/// preconditioner's rounding (both solves read the same rounded factor L~, and L~ D L~^T is symmetric positive definite
/// for any unit lower triangular L~, so it stays a preconditioner; single-precision arithmetic adds errors of 1e-7 to
/// the half values' 5e-4). The solves stream the whole factor on every application: at 128x2x128 an application takes
/// 13 ms with double values, 10 ms with single, 4.1-4.6 ms with half values in single arithmetic (masse_benchmarks'
/// choleskyApply, two threads); half values in double arithmetic would be bound by the conversions to double instead of
/// memory. Drape forming needs 1% more iterations than with single values (4.03 against 3.99 a step over its first 20 s
/// at 128x2x128), a fresh factor two instead of one. The rounding to half is done in software (halfFromReal), the same
/// bits whatever the processor; reading a half back is exact on every SIMD path.

#include "core/Types.h"

#include <Eigen/SparseCore>

#include <cstdint>
#include <cstring>
#include <vector>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace masse
{
/// `value` rounded to the nearest binary16 (ties to even), as its bits; magnitudes past the largest finite half
/// (65504) are clamped to it rather than made infinite, and those below the smallest subnormal (2^-24) flush to zero
/// as the rounding gives. Direct from double, so there is no double rounding through float.
inline std::uint16_t halfFromReal(double value)
{
    std::uint64_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    const std::uint64_t sign = bits & 0x8000000000000000ull;
    const std::uint64_t magnitude = bits ^ sign;
    const auto signBit = std::uint16_t(sign >> 48);
    constexpr std::uint64_t clampFrom = 0x40EFFE0000000000ull;      // 65520: rounds to infinity from here up (and NaN)
    constexpr std::uint64_t smallestNormal = 0x3F10000000000000ull; // 2^-14
    if (magnitude >= clampFrom)
    {
        return std::uint16_t(signBit | 0x7BFF);
    }
    if (magnitude < smallestNormal)
    {
        // Adding 2^28, whose last bit is worth 2^-24 (a half subnormal's step), rounds to a subnormal's steps.
        double magnitudeValue;
        std::memcpy(&magnitudeValue, &magnitude, sizeof magnitudeValue);
        const double shifted = magnitudeValue + 268435456.0;
        std::uint64_t shiftedBits;
        std::memcpy(&shiftedBits, &shifted, sizeof shiftedBits);
        return std::uint16_t(signBit | std::uint16_t(shiftedBits - 0x41B0000000000000ull));
    }
    // Rebias the exponent (1023 to 15) and round the 52-bit mantissa to 10 bits, ties to even; a carry out of the
    // mantissa moves into the exponent, as it should.
    const std::uint64_t oddLast = (magnitude >> 42) & 1;
    const std::uint64_t rounded = magnitude - (std::uint64_t(1023 - 15) << 52) + ((1ull << 41) - 1) + oddLast;
    return std::uint16_t(signBit | std::uint16_t(rounded >> 42));
}

/// The binary16 `bits` as a float (exact; never infinite or NaN here).
inline float floatFromHalf(std::uint16_t bits)
{
    const std::uint32_t sign = std::uint32_t(bits & 0x8000) << 16;
    const std::uint32_t exponent = (bits >> 10) & 0x1F;
    const std::uint32_t mantissa = bits & 0x3FF;
    if (exponent == 0)
    {
        const float magnitude = float(mantissa) * 5.9604644775390625e-8f; // 2^-24, exact
        return sign ? -magnitude : magnitude;
    }
    const std::uint32_t floatBits = sign | ((exponent + 112) << 23) | (mantissa << 13);
    float value;
    std::memcpy(&value, &floatBits, sizeof value);
    return value;
}

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
    /// The values alone of a matrix with the pattern last assigned (a factor refreshed with its analysed pattern): the
    /// runs stay, and so do the zeros between a run's entries. Half the work of an assign, which counts the runs first.
    void refillLowerRows(const SparseMatrix& lower);
    void refillLowerColumnsLastFirst(const SparseMatrix& lower);

    Eigen::Index rows() const { return Eigen::Index(m_rowRuns.size()) - 1; }
    /// Values stored, the zeros of joined runs included.
    std::size_t entries() const { return m_values.size() - valuePadding; }
    std::size_t runs() const { return m_runColumn.size(); }

    /// Two entries of a row at most this many columns apart are in one run, the columns between stored as zeros (1:
    /// only neighbours). A run costs the solves its loads and a masked vector of its last entries whatever its length,
    /// and by columns the factor's runs are short (35 entries on average at 128x2x128, 727,000 of them; 150 by rows),
    /// so with only neighbours joined the backward solve takes longer than the forward one over the same entries. An
    /// application at 128x2x128 (masse_benchmarks' choleskyApply, alternated): 4.7-4.8 ms with only neighbours joined,
    /// 4.1-4.2 at 16, 3.9-4.1 at 32; one thread 7.7-8.2 ms against 6.1-7.4 at 32 and 64. Drape forming at 128x2x128
    /// over the whole 60 s: 172.3 s against 186.7 s, one run each, the same iterations and refactorisations. The zeros
    /// add nothing to a sum, but they move the entries after them to other running sums, so the last bits differ from
    /// storing runs apart.
    static constexpr StorageIndex joinGap = 32;

    /// The arrays, for the kernels (rowDot below).
    struct View
    {
        const StorageIndex* rowRuns;
        const StorageIndex* runColumn;
        const StorageIndex* runStart;
        const std::uint16_t* values; ///< binary16 bits, then `valuePadding` zeros (see rowDotAvx512)
    };
    /// Entries past the last value, so that a kernel may read a full vector of halves from any run's last entries.
    static constexpr std::size_t valuePadding = 16;
    View view() const { return {m_rowRuns.data(), m_runColumn.data(), m_runStart.data(), m_values.data()}; }

private:
    /// Fills the storage from `forEachEntry(visit)`, which calls visit(row, column, value) for every entry, each row's
    /// entries in increasing column (rows may interleave); called twice, to count and to fill.
    template <class ForEachEntry> void assign(Eigen::Index rowCount, const ForEachEntry& forEachEntry);
    /// Writes the values of `forEachEntry`'s entries (as for assign) into the runs laid out for them.
    template <class ForEachEntry> void refill(const ForEachEntry& forEachEntry);

    std::vector<StorageIndex> m_rowRuns;   ///< runs of row i: [m_rowRuns[i], m_rowRuns[i + 1])
    std::vector<StorageIndex> m_runColumn; ///< first column of run r
    std::vector<StorageIndex> m_runStart;  ///< values of run r: [m_runStart[r], m_runStart[r + 1]); one past the last
    std::vector<std::uint16_t> m_values;
    std::vector<StorageIndex> m_nextValue; ///< scratch of assign(), kept so that a refresh does not allocate it anew
    std::vector<StorageIndex> m_nextRun;
    std::vector<StorageIndex> m_lastColumn;
};

/// sum over row i's entries of value * x[column], in single precision and in a fixed order whoever calls it and on any
/// vector width: 16 running sums, entry t of a run going to sum t mod 16 (one AVX-512 register), then sum l + sum l+8
/// for each l < 8, added pairwise (the entries past the last full group of 16 are added one by one; rowDotAvx512 adds
/// them under a mask). `toFloat` reads a half exactly (floatFromHalf, or F16C's instruction). Inlined into each SIMD
/// path's copy of the caller (see SimdPath.h): only the instruction set differs.
template <class ToFloat>
[[gnu::always_inline]] inline float rowDot(const RunLengthRows::View& m, Eigen::Index row, const float* x,
                                           const ToFloat& toFloat)
{
    constexpr int lanes = 16;
    float sum[lanes] = {};
    for (auto run = m.rowRuns[row]; run < m.rowRuns[row + 1]; ++run)
    {
        const std::uint16_t* v = m.values + m.runStart[run];
        const float* xs = x + m.runColumn[run];
        const RunLengthRows::StorageIndex length = m.runStart[run + 1] - m.runStart[run];
        RunLengthRows::StorageIndex t = 0;
        for (; t + lanes <= length; t += lanes)
        {
            for (int lane = 0; lane < lanes; ++lane)
            {
                sum[lane] += toFloat(v[t + lane]) * xs[t + lane];
            }
        }
        for (int lane = 0; t + lane < length; ++lane)
        {
            sum[lane] += toFloat(v[t + lane]) * xs[t + lane];
        }
    }
    float pair[8];
    for (int lane = 0; lane < 8; ++lane)
    {
        pair[lane] = sum[lane] + sum[lane + 8];
    }
    return ((pair[0] + pair[1]) + (pair[2] + pair[3])) + ((pair[4] + pair[5]) + (pair[6] + pair[7]));
}
#if defined(__x86_64__) && defined(__GNUC__)
/// rowDot with AVX-512, the same bits: each group of sixteen entries goes into the sixteen sums in one vector, and a
/// run's last entries (fewer than sixteen) are added to their sums under a mask instead of one by one, so entry t of a
/// run still goes to sum t mod 16, in order, and the sums past the run's end are left as they were (not even + 0,
/// which would turn a -0 into +0). The halves are read sixteen at a time even at a run's end: the values are padded
/// (RunLengthRows::valuePadding), and those past the run are masked off.
[[gnu::always_inline]] inline __attribute__((target("avx512f"))) float rowDotAvx512(const RunLengthRows::View& m,
                                                                                    Eigen::Index row, const float* x)
{
    __m512 sum = _mm512_setzero_ps();
    // The zero-masking forms: GCC 12's plain _mm512_cvtph_ps merges into an "undefined" vector, which its own
    // -Wmaybe-uninitialized reports.
    const auto all = __mmask16(0xFFFF);
    for (auto run = m.rowRuns[row]; run < m.rowRuns[row + 1]; ++run)
    {
        const std::uint16_t* v = m.values + m.runStart[run];
        const float* xs = x + m.runColumn[run];
        const RunLengthRows::StorageIndex length = m.runStart[run + 1] - m.runStart[run];
        RunLengthRows::StorageIndex t = 0;
        for (; t + 16 <= length; t += 16)
        {
            const __m512 values =
                _mm512_maskz_cvtph_ps(all, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(v + t)));
            sum = _mm512_add_ps(sum, _mm512_mul_ps(values, _mm512_loadu_ps(xs + t)));
        }
        if (t < length)
        {
            const auto mask = __mmask16((1u << unsigned(length - t)) - 1);
            const __m512 values =
                _mm512_maskz_cvtph_ps(mask, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(v + t)));
            // The masked load of x reads nothing past the run, so it cannot fault at the end of the array.
            const __m512 product = _mm512_mul_ps(values, _mm512_maskz_loadu_ps(mask, xs + t));
            sum = _mm512_mask_add_ps(sum, mask, sum, product);
        }
    }
    alignas(64) float lanes[16];
    _mm512_store_ps(lanes, sum);
    float pair[8];
    for (int lane = 0; lane < 8; ++lane)
    {
        pair[lane] = lanes[lane] + lanes[lane + 8];
    }
    return ((pair[0] + pair[1]) + (pair[2] + pair[3])) + ((pair[4] + pair[5]) + (pair[6] + pair[7]));
}
#endif
} // namespace masse
