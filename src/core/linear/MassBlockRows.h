#pragma once
/// A unit lower triangular factor stored by rows for the triangular solves, a mass at a time: the three rows of a mass
/// share one pattern outside the mass's own 3x3 block, so they are stored as one list of runs of consecutive columns
/// with three rows of values each, and a solve reads each run's columns and its stretch of the vector once for the
/// three. The same copy serves both solves: the forward one gathers each block's rows (blockDots), the backward one
/// scatters each block's solved values into the rows above it (blockScatter), so a preconditioner application streams
/// the factor twice from one copy.
///
/// Made for the triangular solves with the nested-dissection Cholesky factor, which stream the whole factor on every
/// preconditioner application. The implicit matrix is made of 3x3 blocks, one a pair of joined masses, so in the
/// factor the rows of a mass have the same pattern below its block (a mass's first row is the second's only child in
/// the elimination tree, and the second the third's). A separator's masses are consecutive in the order, so the shared
/// patterns are long runs of consecutive columns: a run stores its first column and its values, and no entry has a
/// column of its own. Solved a row at a time, each row's sum would wait on the rows just solved before it (its last
/// entries are theirs) and pay its own reduction and its own reads of the runs and of the vector; a mass at a time,
/// three independent sums share them, and the dependent arithmetic is the 3x3 block's three entries.
///
/// A sheet held where it touches (sticky contact, a clamp) gives the factor many exact zeros: a held mass's rows and
/// columns of the filtered matrix are the identity's, so its rows and columns of L are zero, and so is the fill that
/// elimination through it would have made (in the vacuum cup at 64x2x64, 35% of the stored values at the first
/// refresh, 82% once the sheet lies on the mould). The solves read the runs with their groups of sixteen columns whose
/// values are all zero left out (view(), gathered at every refill): a group that is left out would only have added
/// zeros to sums that are never -0, so every sum has the bits it has with the group read.
///
/// The values are half precision (IEEE binary16, 11 significant bits, see Half.h), and the solves run in single
/// precision: the factor only preconditions the conjugate gradient, which converges in double precision whatever the
/// preconditioner's rounding (both solves read the same rounded factor L~, and L~ D L~^T is symmetric positive definite
/// for any unit lower triangular L~, so it stays a preconditioner; single-precision arithmetic adds errors of 1e-7 to
/// the half values' 5e-4). Half values halve what the solves stream from memory against single ones.

#include "core/Types.h"
#include "core/linear/Half.h"

#include <Eigen/SparseCore>

#include <algorithm>
#include <cstdint>
#include <vector>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace masse
{
class MassBlockRows
{
public:
    /// The factor as StagedLdlt computes it, in single precision.
    using SparseMatrix = Eigen::SparseMatrix<float>;
    using StorageIndex = SparseMatrix::StorageIndex;

    /// The strictly lower part of `lower` (column-major, each column's rows increasing, three rows a mass): block m
    /// holds rows 3m, 3m+1 and 3m+2 (its rows 0, 1 and 2), their entries in columns below 3m as shared runs (over the
    /// union of the three rows' columns; a row's value is zero where it lacks one of them), and L(3m+1, 3m),
    /// L(3m+2, 3m), L(3m+2, 3m+1) as its in-block entries 0, 1 and 2. Throws std::invalid_argument unless `lower` is
    /// square with a multiple of three rows.
    void assignLowerRows(const SparseMatrix& lower);
    /// The values alone of a factor with the pattern last assigned (one refreshed with its analysed pattern): the runs
    /// stay, and so do the zeros between a run's entries.
    void refillLowerRows(const SparseMatrix& lower);

    Eigen::Index blocks() const { return Eigen::Index(m_blockRuns.size()) - 1; }
    /// Values stored in the shared runs (three a run column, the zeros of joined runs included).
    std::size_t entries() const { return m_values.size() - valuePadding; }
    std::size_t runs() const { return m_runColumn.size(); }
    /// Values the solves read: those of the groups of sixteen run columns that are not all zero.
    std::size_t liveEntries() const { return m_live.values.size() - valuePadding; }

    /// Two columns of a block at most this many apart are in one run, the columns between stored as zeros. A run costs
    /// the solves its loads and a masked vector of its last entries whatever its length. The zeros add nothing to a
    /// sum, but they move the entries after them to other running sums.
    static constexpr StorageIndex joinGap = 32;

    /// The arrays, for the kernels (blockDots below).
    struct View
    {
        const StorageIndex* blockRuns; ///< runs of block b: [blockRuns[b], blockRuns[b + 1])
        const StorageIndex* runColumn; ///< first column of run r
        const StorageIndex* runStart;  ///< run r's values, from there laid out as runValueOffset says
        const StorageIndex* runLength;
        const std::uint16_t* values; ///< binary16 bits, then `valuePadding` zeros (see blockDotsAvx512)
        const float* inBlock;        ///< three a block, its in-block entries (halves read back)
    };
    /// Entries past the last value, so that a kernel may read a full vector of halves from any run's last entries.
    static constexpr std::size_t valuePadding = 16;
    /// The runs the solves read: each laid-out run less its groups of sixteen columns whose values are all zero (a
    /// group of the run from its first column on, or the run's last length mod 16 columns), the groups left on either
    /// side of one left out in runs of their own. A run kept from column 16k of a laid-out run on has its values laid
    /// out as runValueOffset says, as the laid-out run's from there, so each entry goes to the same one of the
    /// kernels' sixteen sums as in the laid-out run.
    View view() const
    {
        return {m_live.blockRuns.data(), m_live.runColumn.data(), m_live.runStart.data(),
                m_live.runLength.data(), m_live.values.data(),    m_inBlock.data()};
    }
    /// Every run as laid out for the pattern, zeros and all.
    View laidOut() const
    {
        return {m_blockRuns.data(), m_runColumn.data(), m_runStart.data(),
                m_runLength.data(), m_values.data(),    m_inBlock.data()};
    }

private:
    /// Where L(row, column) (of the pattern laid out) is kept: an index into m_values, or inBlockPlaces plus one into
    /// m_inBlock. `run` is the shared run that holds it (read only for an entry outside the mass's own block).
    std::uint32_t placeOf(StorageIndex row, StorageIndex column, std::uint32_t run) const;
    /// m_live from the laid-out runs and their values.
    void gatherLiveRuns();
    /// Writes `half`, the factor's stored entry k rounded, to its place (m_place[k]).
    void store(std::size_t k, std::uint16_t half);
#if defined(__x86_64__) && defined(__GNUC__)
    /// The refill of entries [begin, end) eight at a time with F16C's conversion (halvesFromFloatsF16c: the same
    /// halves as halfFromReal's); returns where the eights end.
    std::size_t refillF16c(const float* values, std::size_t begin, std::size_t end);
#endif
    /// Blocks a task of gatherLiveRuns handles.
    static constexpr std::size_t gatherBlocksPerChunk = 512;
    /// Columns of the factor a task of the layout finds the places of.
    static constexpr std::size_t placeColumnsPerChunk = 2048;
    /// Entries of the factor a task of the refill writes.
    static constexpr std::size_t refillEntriesPerChunk = 65536;
    static constexpr std::uint32_t inBlockPlaces = 0x80000000u;
    static constexpr std::uint32_t noPlace = 0xFFFFFFFFu; ///< the factor's diagonal entries (unit, not stored here)

    std::vector<StorageIndex> m_blockRuns;
    std::vector<StorageIndex> m_runColumn;
    std::vector<StorageIndex> m_runStart;
    std::vector<StorageIndex> m_runLength;
    std::vector<std::uint16_t> m_values;
    std::vector<float> m_inBlock;
    /// Per stored entry of the factor laid out, in its storage order: its placeOf, or noPlace.
    std::vector<std::uint32_t> m_place;
    /// The runs the solves read (see view()), with their own copy of the values, so that the solves stream them in
    /// one ascending pass.
    struct LiveRuns
    {
        std::vector<StorageIndex> blockRuns;
        std::vector<StorageIndex> runColumn;
        std::vector<StorageIndex> runStart;
        std::vector<StorageIndex> runLength;
        std::vector<std::uint16_t> values;
        std::vector<StorageIndex> blockValues; ///< per block and one past, where its values start (a gather's counts)
    };
    LiveRuns m_live;
};

/// Where block row `row`'s entry t of a run of `length` entries is among the run's values: the three rows' full groups
/// of sixteen interleaved (row 0's sixteen, row 1's, row 2's), then the three rows' last length mod 16 one after
/// another. A solve reads a run's values in one ascending stream.
inline std::size_t runValueOffset(MassBlockRows::StorageIndex length, int row, MassBlockRows::StorageIndex t)
{
    const MassBlockRows::StorageIndex full = length / 16 * 16;
    if (t < full)
    {
        return std::size_t(3 * (t / 16 * 16) + row * 16 + t % 16);
    }
    return std::size_t(3 * full + row * (length - full) + (t - full));
}

/// For block b, s[l] = sum over its row l's shared entries of value * x[column], in single precision and in a fixed
/// order whoever calls it and on any vector width: per row 16 running sums, entry t of a run going to sum t mod 16
/// (one AVX-512 register, two AVX2 ones), then sum k + sum k+8 for each k < 8, added pairwise (the entries past the
/// last full group of 16 are added one by one; blockDotsAvx2 and blockDotsAvx512 add them under a mask). `toFloat`
/// reads a half exactly (floatFromHalf). The default path's kernel; the vector paths have their own below, with these
/// bits.
template <class ToFloat>
[[gnu::always_inline]] inline void blockDots(const MassBlockRows::View& m, Eigen::Index block, const float* x,
                                             const ToFloat& toFloat, float s[3])
{
    constexpr int lanes = 16;
    float sum[3][lanes] = {};
    for (auto run = m.blockRuns[block]; run < m.blockRuns[block + 1]; ++run)
    {
        const MassBlockRows::StorageIndex length = m.runLength[run];
        const MassBlockRows::StorageIndex full = length / lanes * lanes;
        const float* xs = x + m.runColumn[run];
        const std::uint16_t* values = m.values + m.runStart[run];
        for (MassBlockRows::StorageIndex t = 0; t < full; t += lanes)
        {
            for (int row = 0; row < 3; ++row)
            {
                const std::uint16_t* v = values + 3 * t + row * lanes;
                for (int lane = 0; lane < lanes; ++lane)
                {
                    sum[row][lane] += toFloat(v[lane]) * xs[t + lane];
                }
            }
        }
        for (int row = 0; row < 3; ++row)
        {
            const std::uint16_t* v = values + 3 * full + row * (length - full);
            for (int lane = 0; full + lane < length; ++lane)
            {
                sum[row][lane] += toFloat(v[lane]) * xs[full + lane];
            }
        }
    }
    for (int row = 0; row < 3; ++row)
    {
        float pair[8];
        for (int lane = 0; lane < 8; ++lane)
        {
            pair[lane] = sum[row][lane] + sum[row][lane + 8];
        }
        s[row] = ((pair[0] + pair[1]) + (pair[2] + pair[3])) + ((pair[4] + pair[5]) + (pair[6] + pair[7]));
    }
}
/// For block b, w[column] += L(3b, column) x[0] + L(3b+1, column) x[1] + L(3b+2, column) x[2] over its shared
/// columns, in single precision, added in that order: each entry of w on its own, so the bits do not depend on the
/// vector width.
template <class ToFloat>
[[gnu::always_inline]] inline void blockScatter(const MassBlockRows::View& m, Eigen::Index block, const float x[3],
                                                float* w, const ToFloat& toFloat)
{
    constexpr int lanes = 16;
    for (auto run = m.blockRuns[block]; run < m.blockRuns[block + 1]; ++run)
    {
        const MassBlockRows::StorageIndex length = m.runLength[run];
        const MassBlockRows::StorageIndex full = length / lanes * lanes;
        const std::uint16_t* values = m.values + m.runStart[run];
        float* ws = w + m.runColumn[run];
        // The values as runValueOffset lays them out: the three rows' groups of sixteen, then their last entries.
        for (MassBlockRows::StorageIndex t = 0; t < full; t += lanes)
        {
            const std::uint16_t* group = values + 3 * t;
            for (int lane = 0; lane < lanes; ++lane)
            {
                ws[t + lane] = ((ws[t + lane] + toFloat(group[lane]) * x[0]) + toFloat(group[lanes + lane]) * x[1]) +
                               toFloat(group[2 * lanes + lane]) * x[2];
            }
        }
        const MassBlockRows::StorageIndex rest = length - full;
        const std::uint16_t* tail = values + 3 * full;
        for (MassBlockRows::StorageIndex lane = 0; lane < rest; ++lane)
        {
            ws[full + lane] = ((ws[full + lane] + toFloat(tail[lane]) * x[0]) + toFloat(tail[rest + lane]) * x[1]) +
                              toFloat(tail[2 * rest + lane]) * x[2];
        }
    }
}
#if defined(__x86_64__) && defined(__GNUC__)
/// Eight halves from v as floats (F16C).
[[gnu::always_inline]] inline __attribute__((target("avx2,f16c"))) __m256 halvesAvx2(const std::uint16_t* v)
{
    return _mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(v)));
}

/// The lanes below `count` (0 to 8) of an AVX2 vector, as a mask of all-ones lanes.
[[gnu::always_inline]] inline __attribute__((target("avx2,f16c"))) __m256i lanesBelowAvx2(int count)
{
    return _mm256_cmpgt_epi32(_mm256_set1_epi32(count), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
}

/// blockDots with AVX2, the same bits: a row's sixteen sums in two vectors of eight, each group of sixteen entries
/// added to them in two halves, and a run's last entries (fewer than sixteen) added under a mask, the sums past the
/// run's end kept as they were (a blend, not + 0, which would turn a -0 into +0). The halves are read eight at a time
/// even at a run's end, no further than blockDotsAvx512 reads (MassBlockRows::valuePadding); x is read under the mask.
[[gnu::always_inline]] inline __attribute__((target("avx2,f16c"))) void
blockDotsAvx2(const MassBlockRows::View& m, Eigen::Index block, const float* x, float s[3])
{
    __m256 sum[3][2];
    for (auto& row : sum)
    {
        row[0] = _mm256_setzero_ps();
        row[1] = _mm256_setzero_ps();
    }
    for (auto run = m.blockRuns[block]; run < m.blockRuns[block + 1]; ++run)
    {
        const MassBlockRows::StorageIndex length = m.runLength[run];
        const std::uint16_t* values = m.values + m.runStart[run];
        const float* xs = x + m.runColumn[run];
        MassBlockRows::StorageIndex t = 0;
        for (; t + 16 <= length; t += 16)
        {
            const __m256 xLow = _mm256_loadu_ps(xs + t);
            const __m256 xHigh = _mm256_loadu_ps(xs + t + 8);
            const std::uint16_t* group = values + 3 * t;
            for (int row = 0; row < 3; ++row)
            {
                sum[row][0] = _mm256_add_ps(sum[row][0], _mm256_mul_ps(halvesAvx2(group + 16 * row), xLow));
                sum[row][1] = _mm256_add_ps(sum[row][1], _mm256_mul_ps(halvesAvx2(group + 16 * row + 8), xHigh));
            }
        }
        if (t < length)
        {
            const int rest = int(length - t);
            const std::uint16_t* tail = values + 3 * t;
            for (int half = 0; half < 2 && 8 * half < rest; ++half)
            {
                const __m256i mask = lanesBelowAvx2(std::min(rest - 8 * half, 8));
                const __m256 xv = _mm256_maskload_ps(xs + t + 8 * half, mask);
                for (int row = 0; row < 3; ++row)
                {
                    const __m256 product = _mm256_mul_ps(halvesAvx2(tail + row * rest + 8 * half), xv);
                    sum[row][half] = _mm256_blendv_ps(sum[row][half], _mm256_add_ps(sum[row][half], product),
                                                      _mm256_castsi256_ps(mask));
                }
            }
        }
    }
    for (int row = 0; row < 3; ++row)
    {
        alignas(32) float p[8];
        _mm256_store_ps(p, _mm256_add_ps(sum[row][0], sum[row][1]));
        s[row] = ((p[0] + p[1]) + (p[2] + p[3])) + ((p[4] + p[5]) + (p[6] + p[7]));
    }
}

/// blockScatter with AVX2, the same bits: eight entries of w at a time, a run's last few under a mask (which neither
/// reads nor writes past the run).
[[gnu::always_inline]] inline __attribute__((target("avx2,f16c"))) void
blockScatterAvx2(const MassBlockRows::View& m, Eigen::Index block, const float x[3], float* w)
{
    const __m256 x0 = _mm256_set1_ps(x[0]);
    const __m256 x1 = _mm256_set1_ps(x[1]);
    const __m256 x2 = _mm256_set1_ps(x[2]);
    for (auto run = m.blockRuns[block]; run < m.blockRuns[block + 1]; ++run)
    {
        const MassBlockRows::StorageIndex length = m.runLength[run];
        const std::uint16_t* values = m.values + m.runStart[run];
        float* ws = w + m.runColumn[run];
        MassBlockRows::StorageIndex t = 0;
        for (; t + 16 <= length; t += 16)
        {
            const std::uint16_t* group = values + 3 * t;
            for (int half = 0; half < 2; ++half)
            {
                __m256 sum = _mm256_loadu_ps(ws + t + 8 * half);
                sum = _mm256_add_ps(sum, _mm256_mul_ps(halvesAvx2(group + 8 * half), x0));
                sum = _mm256_add_ps(sum, _mm256_mul_ps(halvesAvx2(group + 16 + 8 * half), x1));
                sum = _mm256_add_ps(sum, _mm256_mul_ps(halvesAvx2(group + 32 + 8 * half), x2));
                _mm256_storeu_ps(ws + t + 8 * half, sum);
            }
        }
        if (t < length)
        {
            const int rest = int(length - t);
            const std::uint16_t* tail = values + 3 * t;
            for (int half = 0; half < 2 && 8 * half < rest; ++half)
            {
                const __m256i mask = lanesBelowAvx2(std::min(rest - 8 * half, 8));
                float* at = ws + t + 8 * half;
                __m256 sum = _mm256_maskload_ps(at, mask);
                sum = _mm256_add_ps(sum, _mm256_mul_ps(halvesAvx2(tail + 8 * half), x0));
                sum = _mm256_add_ps(sum, _mm256_mul_ps(halvesAvx2(tail + rest + 8 * half), x1));
                sum = _mm256_add_ps(sum, _mm256_mul_ps(halvesAvx2(tail + 2 * rest + 8 * half), x2));
                _mm256_maskstore_ps(at, mask, sum);
            }
        }
    }
}

/// Sixteen halves from v as floats, those outside `mask` zero. The zero-masking form: GCC 12's plain _mm512_cvtph_ps
/// merges into an "undefined" vector, which its own -Wmaybe-uninitialized reports.
[[gnu::always_inline]] inline __attribute__((target("avx512f"))) __m512 halvesAvx512(__mmask16 mask,
                                                                                     const std::uint16_t* v)
{
    return _mm512_maskz_cvtph_ps(mask, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(v)));
}

/// Sum k + sum k+8 of the sixteen sums, k < 8. (The zero-masking extracts, for the same reason as above.)
[[gnu::always_inline]] inline __attribute__((target("avx512f"))) __m256 foldedAvx512(__m512 sum)
{
    const auto all = __mmask8(0xFF);
    const __m256 lower = _mm256_castpd_ps(_mm512_maskz_extractf64x4_pd(all, _mm512_castps_pd(sum), 0));
    const __m256 upper = _mm256_castpd_ps(_mm512_maskz_extractf64x4_pd(all, _mm512_castps_pd(sum), 1));
    return _mm256_add_ps(lower, upper);
}

/// blockDots with AVX-512, the same bits: each group of sixteen entries goes into a row's sixteen sums in one
/// vector, and a run's last entries (fewer than sixteen) are added to their sums under a mask instead of one by one, so
/// entry t of a run still goes to sum t mod 16, in order, and the sums past the run's end are left as they were (not
/// even + 0, which would turn a -0 into +0). The halves are read sixteen at a time even at a run's end: the values are
/// padded (MassBlockRows::valuePadding), and those past the run are masked off.
[[gnu::always_inline]] inline __attribute__((target("avx512f"))) void
blockDotsAvx512(const MassBlockRows::View& m, Eigen::Index block, const float* x, float s[3])
{
    __m512 sum0 = _mm512_setzero_ps();
    __m512 sum1 = _mm512_setzero_ps();
    __m512 sum2 = _mm512_setzero_ps();
    const auto all = __mmask16(0xFFFF);
    for (auto run = m.blockRuns[block]; run < m.blockRuns[block + 1]; ++run)
    {
        const MassBlockRows::StorageIndex length = m.runLength[run];
        const std::uint16_t* values = m.values + m.runStart[run];
        const float* xs = x + m.runColumn[run];
        MassBlockRows::StorageIndex t = 0;
        for (; t + 16 <= length; t += 16)
        {
            const __m512 xv = _mm512_loadu_ps(xs + t);
            const std::uint16_t* group = values + 3 * t;
            sum0 = _mm512_add_ps(sum0, _mm512_mul_ps(halvesAvx512(all, group), xv));
            sum1 = _mm512_add_ps(sum1, _mm512_mul_ps(halvesAvx512(all, group + 16), xv));
            sum2 = _mm512_add_ps(sum2, _mm512_mul_ps(halvesAvx512(all, group + 32), xv));
        }
        if (t < length)
        {
            const MassBlockRows::StorageIndex rest = length - t;
            const auto mask = __mmask16((1u << unsigned(rest)) - 1);
            const std::uint16_t* tail = values + 3 * t;
            // The masked load of x reads nothing past the run, so it cannot fault at the end of the array.
            const __m512 xv = _mm512_maskz_loadu_ps(mask, xs + t);
            sum0 = _mm512_mask_add_ps(sum0, mask, sum0, _mm512_mul_ps(halvesAvx512(mask, tail), xv));
            sum1 = _mm512_mask_add_ps(sum1, mask, sum1, _mm512_mul_ps(halvesAvx512(mask, tail + rest), xv));
            sum2 = _mm512_mask_add_ps(sum2, mask, sum2, _mm512_mul_ps(halvesAvx512(mask, tail + 2 * rest), xv));
        }
    }
    alignas(32) float pairs[3][8];
    _mm256_store_ps(pairs[0], foldedAvx512(sum0));
    _mm256_store_ps(pairs[1], foldedAvx512(sum1));
    _mm256_store_ps(pairs[2], foldedAvx512(sum2));
    for (int row = 0; row < 3; ++row)
    {
        const float* p = pairs[row];
        s[row] = ((p[0] + p[1]) + (p[2] + p[3])) + ((p[4] + p[5]) + (p[6] + p[7]));
    }
}

/// blockScatter with AVX-512, the same bits: sixteen entries of w at a time, a run's last few under a mask (which
/// neither reads nor writes past the run).
[[gnu::always_inline]] inline __attribute__((target("avx512f"))) void
blockScatterAvx512(const MassBlockRows::View& m, Eigen::Index block, const float x[3], float* w)
{
    const __m512 x0 = _mm512_set1_ps(x[0]);
    const __m512 x1 = _mm512_set1_ps(x[1]);
    const __m512 x2 = _mm512_set1_ps(x[2]);
    const auto all = __mmask16(0xFFFF);
    for (auto run = m.blockRuns[block]; run < m.blockRuns[block + 1]; ++run)
    {
        const MassBlockRows::StorageIndex length = m.runLength[run];
        const std::uint16_t* values = m.values + m.runStart[run];
        float* ws = w + m.runColumn[run];
        MassBlockRows::StorageIndex t = 0;
        for (; t + 16 <= length; t += 16)
        {
            const std::uint16_t* group = values + 3 * t;
            __m512 sum = _mm512_loadu_ps(ws + t);
            sum = _mm512_add_ps(sum, _mm512_mul_ps(halvesAvx512(all, group), x0));
            sum = _mm512_add_ps(sum, _mm512_mul_ps(halvesAvx512(all, group + 16), x1));
            sum = _mm512_add_ps(sum, _mm512_mul_ps(halvesAvx512(all, group + 32), x2));
            _mm512_storeu_ps(ws + t, sum);
        }
        if (t < length)
        {
            const MassBlockRows::StorageIndex rest = length - t;
            const auto mask = __mmask16((1u << unsigned(rest)) - 1);
            const std::uint16_t* tail = values + 3 * t;
            __m512 sum = _mm512_maskz_loadu_ps(mask, ws + t);
            sum = _mm512_add_ps(sum, _mm512_mul_ps(halvesAvx512(mask, tail), x0));
            sum = _mm512_add_ps(sum, _mm512_mul_ps(halvesAvx512(mask, tail + rest), x1));
            sum = _mm512_add_ps(sum, _mm512_mul_ps(halvesAvx512(mask, tail + 2 * rest), x2));
            _mm512_mask_storeu_ps(ws + t, mask, sum);
        }
    }
}
#endif
} // namespace masse
