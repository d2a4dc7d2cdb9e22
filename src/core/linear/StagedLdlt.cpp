#include "core/linear/StagedLdlt.h"

#include "core/forces/SimdPath.h"
#include "core/linear/FlushSubnormals.h"
#include "core/linear/PermutedValues.h"
#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <atomic>
#include <cmath>

namespace masse
{
using StorageIndex = StagedLdlt::StorageIndex;
using Value = StagedLdlt::Value;

namespace
{
/// Numbers every factorisation in the process, so that a thread's visit marks (see RowWorkspace) left by one
/// factorisation, of this factor or another of the same size, never match another's.
std::atomic<long long> factorisations{0};

/// One thread's scratch for the rows it factors: kept from call to call (no allocation per refresh).
struct RowWorkspace
{
    std::vector<Value> y;              ///< the row being solved for, scattered; all zero between rows
    std::vector<StorageIndex> pattern; ///< the row's pattern, as a stack in topological order
    std::vector<long long> mark;       ///< generation * n + row of the row that last visited each row
    std::vector<Value> massY;          ///< a mass's three rows, scattered, four values a row; all zero between masses

    void fit(std::size_t n)
    {
        if (y.size() != n)
        {
            y.assign(n, 0);
            pattern.assign(n, 0);
            mark.assign(n, -1);
            massY.assign(4 * n, 0);
        }
    }
};
/// A mass's three rows' values of one column, and a fourth lane kept at zero: GCC's vector extension (one SSE
/// register); each lane's arithmetic is the scalar operation. Aligned as one value, since its vectors start at any
/// row's values; declared with typedef, as clang ignores `aligned` on an alias declaration.
typedef Value MassLanes __attribute__((vector_size(4 * sizeof(Value)), aligned(sizeof(Value))));
/// One block of separator rows' entries (StagedLdlt::Blocks' arrays from the block's first entry): `count` columns
/// below the separator, each with where its entries below the separator and in the separator's rows end, and the
/// block's y (`lanes` to a column).
struct BlockColumns
{
    std::size_t count;
    const StorageIndex* column;
    const StorageIndex* belowEnd;
    const StorageIndex* separatorEnd;
    const unsigned char* together; ///< StagedLdlt::Blocks::together
    Value* y;
};

constexpr std::size_t lanes = StagedLdlt::lanes;

/// runChunks with subnormals flushed in every chunk, whichever thread runs it (FlushSubnormals.h).
template <class Body> void runFlushedChunks(std::size_t chunkCount, const Body& body)
{
    runChunks(chunkCount,
              [&](std::size_t chunk)
              {
                  const FlushSubnormals flush;
                  body(chunk);
              });
}

/// A block's lanes as one value: GCC's vector extension, one AVX-512 register on that path and split into the
/// path's registers on the others; each lane's arithmetic is the scalar operation. Aligned as one value (a typedef,
/// as MassLanes): a dense column's vectors start at any of its entries.
typedef Value LaneValues __attribute__((vector_size(lanes * sizeof(Value)), aligned(sizeof(Value))));

/// Whether every lane of `values` is zero (+0 or -0).
[[gnu::always_inline]] inline bool allLanesZero(const LaneValues& values)
{
    bool zero = true;
    for (std::size_t lane = 0; lane < lanes; ++lane)
    {
        zero = zero && values[lane] == 0;
    }
    return zero;
}

// One copy of the blocks' kernels per SIMD path: only the instruction set differs (each lane's arithmetic is the
// scalar code's, in the same order, so the bits do not).
#define MASSE_BLOCK_KERNELS(suffix, targetAttribute)                                                                   \
    /* Step 1 for a block: each column below in increasing order takes its y from the block's scratch `y` (lanes       \
       values per row, cleared as it goes), keeps it, and updates the y of its entries below the separator and the     \
       block's pivots d. A run of columns with the same rows below it (block.together) updates each of those rows' y   \
       in one read and write, each column's subtraction in turn. */                                                    \
    targetAttribute void eliminateBelow##suffix(const BlockColumns& block, const StorageIndex* start,                  \
                                                const StorageIndex* rows, const Value* values, const Value* diagonal,  \
                                                Value* y, Value* d)                                                    \
    {                                                                                                                  \
        LaneValues pivots = *reinterpret_cast<const LaneValues*>(d);                                                   \
        for (std::size_t j = 0; j < block.count; ++j)                                                                  \
        {                                                                                                              \
            const StorageIndex c = block.column[j];                                                                    \
            const std::size_t width = block.together[j];                                                               \
            if (width > 1)                                                                                             \
            {                                                                                                          \
                /* The run's own triangle first: column c + r's first entries are rows c + r + 1 onwards. */           \
                alignas(64) LaneValues yv[StagedLdlt::mostTogether]; /* clang loads them as aligned vectors */         \
                const Value* columnValues[StagedLdlt::mostTogether];                                                   \
                std::size_t live = 0;                                                                                  \
                for (std::size_t r = 0; r < width; ++r)                                                                \
                {                                                                                                      \
                    const StorageIndex cr = c + StorageIndex(r);                                                       \
                    LaneValues* yc = reinterpret_cast<LaneValues*>(y + std::size_t(cr) * lanes);                       \
                    yv[r] = *yc;                                                                                       \
                    *reinterpret_cast<LaneValues*>(block.y + (j + r) * lanes) = yv[r];                                 \
                    *yc = LaneValues{};                                                                                \
                    const StorageIndex first = start[cr];                                                              \
                    columnValues[r] = values + first + (width - 1 - r);                                                \
                    if (allLanesZero(yv[r]))                                                                           \
                    {                                                                                                  \
                        columnValues[r] = nullptr;                                                                     \
                        continue;                                                                                      \
                    }                                                                                                  \
                    ++live;                                                                                            \
                    pivots -= (yv[r] / diagonal[cr]) * yv[r];                                                          \
                    for (std::size_t q = r + 1; q < width; ++q)                                                        \
                    {                                                                                                  \
                        *reinterpret_cast<LaneValues*>(y + std::size_t(c + StorageIndex(q)) * lanes) -=                \
                            values[first + (q - r - 1)] * yv[r];                                                       \
                    }                                                                                                  \
                }                                                                                                      \
                const StorageIndex* rowsBelow = rows + start[c] + StorageIndex(width - 1);                             \
                const std::size_t count = std::size_t(block.belowEnd[j] - (start[c] + StorageIndex(width - 1)));       \
                if (live == width)                                                                                     \
                {                                                                                                      \
                    for (std::size_t i = 0; i < count; ++i)                                                            \
                    {                                                                                                  \
                        LaneValues* target = reinterpret_cast<LaneValues*>(y + std::size_t(rowsBelow[i]) * lanes);     \
                        LaneValues t = *target;                                                                        \
                        for (std::size_t r = 0; r < width; ++r)                                                        \
                        {                                                                                              \
                            t -= columnValues[r][i] * yv[r];                                                           \
                        }                                                                                              \
                        *target = t;                                                                                   \
                    }                                                                                                  \
                }                                                                                                      \
                else                                                                                                   \
                {                                                                                                      \
                    for (std::size_t r = 0; r < width; ++r)                                                            \
                    {                                                                                                  \
                        for (std::size_t i = 0; columnValues[r] && i < count; ++i)                                     \
                        {                                                                                              \
                            LaneValues* target = reinterpret_cast<LaneValues*>(y + std::size_t(rowsBelow[i]) * lanes); \
                            *target -= columnValues[r][i] * yv[r];                                                     \
                        }                                                                                              \
                    }                                                                                                  \
                }                                                                                                      \
                j += width - 1;                                                                                        \
                continue;                                                                                              \
            }                                                                                                          \
            LaneValues* yc = reinterpret_cast<LaneValues*>(y + std::size_t(c) * lanes);                                \
            const LaneValues yv = *yc;                                                                                 \
            *reinterpret_cast<LaneValues*>(block.y + j * lanes) = yv;                                                  \
            *yc = LaneValues{};                                                                                        \
            if (allLanesZero(yv)) /* a column no row of the block reaches: its updates would subtract zeros */         \
            {                                                                                                          \
                continue;                                                                                              \
            }                                                                                                          \
            pivots -= (yv / diagonal[c]) * yv;                                                                         \
            for (StorageIndex p = start[c]; p < block.belowEnd[j]; ++p)                                                \
            {                                                                                                          \
                LaneValues* target = reinterpret_cast<LaneValues*>(y + std::size_t(rows[p]) * lanes);                  \
                *target -= values[p] * yv;                                                                             \
            }                                                                                                          \
        }                                                                                                              \
        *reinterpret_cast<LaneValues*>(d) = pivots;                                                                    \
    }                                                                                                                  \
    /* Step 2 for a block: each column below subtracts its entries in the separator's rows before `lastRow` times      \
       the block's y from `z` (lanes values per separator row from `begin`); a run of columns with the same rows       \
       (block.together) in one read and write of each row's z, as step 1. */                                           \
    targetAttribute void schurBlock##suffix(const BlockColumns& block, const StorageIndex* rows, const Value* values,  \
                                            StorageIndex begin, StorageIndex lastRow, Value* z)                        \
    {                                                                                                                  \
        for (std::size_t j = 0; j < block.count; ++j)                                                                  \
        {                                                                                                              \
            const std::size_t width = block.together[j];                                                               \
            if (width > 1)                                                                                             \
            {                                                                                                          \
                alignas(64) LaneValues yc[StagedLdlt::mostTogether];                                                   \
                const Value* columnValues[StagedLdlt::mostTogether];                                                   \
                std::size_t live = 0;                                                                                  \
                for (std::size_t r = 0; r < width; ++r)                                                                \
                {                                                                                                      \
                    yc[r] = *reinterpret_cast<const LaneValues*>(block.y + (j + r) * lanes);                           \
                    const bool zero = allLanesZero(yc[r]);                                                             \
                    columnValues[r] = zero ? nullptr : values + block.belowEnd[j + r];                                 \
                    live += zero ? 0 : 1;                                                                              \
                }                                                                                                      \
                const StorageIndex* rowsIn = rows + block.belowEnd[j];                                                 \
                std::size_t count = std::size_t(block.separatorEnd[j] - block.belowEnd[j]);                            \
                count = std::size_t(std::lower_bound(rowsIn, rowsIn + count, lastRow) - rowsIn);                       \
                if (live == width)                                                                                     \
                {                                                                                                      \
                    for (std::size_t i = 0; i < count; ++i)                                                            \
                    {                                                                                                  \
                        LaneValues* target =                                                                           \
                            reinterpret_cast<LaneValues*>(z + std::size_t(rowsIn[i] - begin) * lanes);                 \
                        LaneValues t = *target;                                                                        \
                        for (std::size_t r = 0; r < width; ++r)                                                        \
                        {                                                                                              \
                            t -= columnValues[r][i] * yc[r];                                                           \
                        }                                                                                              \
                        *target = t;                                                                                   \
                    }                                                                                                  \
                }                                                                                                      \
                else                                                                                                   \
                {                                                                                                      \
                    for (std::size_t r = 0; r < width; ++r)                                                            \
                    {                                                                                                  \
                        for (std::size_t i = 0; columnValues[r] && i < count; ++i)                                     \
                        {                                                                                              \
                            LaneValues* target =                                                                       \
                                reinterpret_cast<LaneValues*>(z + std::size_t(rowsIn[i] - begin) * lanes);             \
                            *target -= columnValues[r][i] * yc[r];                                                     \
                        }                                                                                              \
                    }                                                                                                  \
                }                                                                                                      \
                j += width - 1;                                                                                        \
                continue;                                                                                              \
            }                                                                                                          \
            const LaneValues yc = *reinterpret_cast<const LaneValues*>(block.y + j * lanes);                           \
            if (allLanesZero(yc))                                                                                      \
            {                                                                                                          \
                continue;                                                                                              \
            }                                                                                                          \
            for (StorageIndex p = block.belowEnd[j]; p < block.separatorEnd[j] && rows[p] < lastRow; ++p)              \
            {                                                                                                          \
                LaneValues* target = reinterpret_cast<LaneValues*>(z + std::size_t(rows[p] - begin) * lanes);          \
                *target -= values[p] * yc;                                                                             \
            }                                                                                                          \
        }                                                                                                              \
    }

MASSE_BLOCK_KERNELS(Default, )
#if defined(__x86_64__) && defined(__GNUC__)
MASSE_BLOCK_KERNELS(Avx2, __attribute__((target("avx2"))))
MASSE_BLOCK_KERNELS(Avx512, __attribute__((target("avx512f"))))
#endif
#undef MASSE_BLOCK_KERNELS

/// A mass's columns below its block (StagedLdlt::factorMass): the columns in topological order, L's arrays, and the
/// mass's scattered y.
struct MassColumns
{
    const StorageIndex* column;
    std::size_t count;
    const StorageIndex* start;
    StorageIndex* columnCount;
    StorageIndex* rows;
    Value* values;
    const Value* diagonal;
    Value* massY;
    StorageIndex firstRow;
    /// Per mass: whether its three columns have the same rows below its block (StagedLdlt::m_columnsShareRows),
    /// all zero where columns are not taken together.
    const unsigned char* shareRows;
};

// One copy of the mass kernel per SIMD path, as the blocks' kernels (each lane's arithmetic is the scalar code's, in
// the same order, so the bits do not differ); four lanes fill one SSE register, so the AVX-512 path takes the AVX2
// copy.
#define MASSE_MASS_KERNEL(suffix, targetAttribute)                                                                     \
    /* Each column below the mass: its y for the three rows gives their entries and updates the y of its entries so    \
       far (rows below the mass), and, as Eigen's later rows of the mass would see them, the entries just made in the  \
       earlier rows (`inBlock`: row 1's y in column 0, row 2's in columns 0 and 1); `pivots` less each column's part.  \
       An earlier mass's three columns that come together and have the same rows (mass.shareRows) update each row's    \
       y in one read and write, each column's subtraction in turn. */                                                  \
    targetAttribute void massColumns##suffix(const MassColumns& mass, Value* pivotsOut, Value* inBlock)                \
    {                                                                                                                  \
        MassLanes pivots = *reinterpret_cast<const MassLanes*>(pivotsOut);                                             \
        for (std::size_t j = 0; j < mass.count; ++j)                                                                   \
        {                                                                                                              \
            const StorageIndex c = mass.column[j];                                                                     \
            const bool triple = c % 3 == 0 && j + 2 < mass.count && mass.column[j + 1] == c + 1 &&                     \
                                mass.column[j + 2] == c + 2 && mass.shareRows[c / 3];                                  \
            const std::size_t taken = triple ? 3 : 1;                                                                  \
            alignas(32) MassLanes yv[3];                                                                               \
            bool live[3];                                                                                              \
            StorageIndex last[3];                                                                                      \
            for (std::size_t r = 0; r < taken; ++r)                                                                    \
            {                                                                                                          \
                const StorageIndex cr = c + StorageIndex(r);                                                           \
                MassLanes* yc = reinterpret_cast<MassLanes*>(mass.massY + 4 * std::size_t(cr));                        \
                yv[r] = *yc;                                                                                           \
                *yc = MassLanes{};                                                                                     \
                const MassLanes l = yv[r] / mass.diagonal[cr];                                                         \
                last[r] = mass.start[cr] + mass.columnCount[cr];                                                       \
                for (int q = 0; q < 3; ++q)                                                                            \
                {                                                                                                      \
                    mass.rows[last[r] + q] = mass.firstRow + q;                                                        \
                    mass.values[last[r] + q] = l[q];                                                                   \
                }                                                                                                      \
                mass.columnCount[cr] += 3;                                                                             \
                live[r] = !(yv[r][0] == 0 && yv[r][1] == 0 && yv[r][2] == 0); /* else its updates subtract zeros */    \
                if (!live[r])                                                                                          \
                {                                                                                                      \
                    continue;                                                                                          \
                }                                                                                                      \
                /* Taken alone, all its entries so far; taken together, its entries in the mass's own block (rows      \
                   after it among the three), the rows below after all three. */                                       \
                const StorageIndex end = triple ? mass.start[cr] + StorageIndex(2 - r) : last[r];                      \
                for (StorageIndex p = mass.start[cr]; p < end; ++p)                                                    \
                {                                                                                                      \
                    MassLanes* target = reinterpret_cast<MassLanes*>(mass.massY + 4 * std::size_t(mass.rows[p]));      \
                    *target -= mass.values[p] * yv[r];                                                                 \
                }                                                                                                      \
                inBlock[0] -= l[0] * yv[r][1];                                                                         \
                inBlock[1] -= l[0] * yv[r][2];                                                                         \
                inBlock[2] -= l[1] * yv[r][2];                                                                         \
                pivots -= l * yv[r];                                                                                   \
            }                                                                                                          \
            if (!triple)                                                                                               \
            {                                                                                                          \
                continue;                                                                                              \
            }                                                                                                          \
            const StorageIndex* rowsBelow = mass.rows + mass.start[c] + 2;                                             \
            const Value* v0 = mass.values + mass.start[c] + 2;                                                         \
            const Value* v1 = mass.values + mass.start[c + 1] + 1;                                                     \
            const Value* v2 = mass.values + mass.start[c + 2];                                                         \
            const std::size_t count = std::size_t(last[0] - (mass.start[c] + 2));                                      \
            if (live[0] && live[1] && live[2])                                                                         \
            {                                                                                                          \
                for (std::size_t i = 0; i < count; ++i)                                                                \
                {                                                                                                      \
                    MassLanes* target = reinterpret_cast<MassLanes*>(mass.massY + 4 * std::size_t(rowsBelow[i]));      \
                    MassLanes t = *target;                                                                             \
                    t -= v0[i] * yv[0];                                                                                \
                    t -= v1[i] * yv[1];                                                                                \
                    t -= v2[i] * yv[2];                                                                                \
                    *target = t;                                                                                       \
                }                                                                                                      \
            }                                                                                                          \
            else                                                                                                       \
            {                                                                                                          \
                const Value* v[3] = {v0, v1, v2};                                                                      \
                for (std::size_t r = 0; r < 3; ++r)                                                                    \
                {                                                                                                      \
                    for (std::size_t i = 0; live[r] && i < count; ++i)                                                 \
                    {                                                                                                  \
                        MassLanes* target = reinterpret_cast<MassLanes*>(mass.massY + 4 * std::size_t(rowsBelow[i]));  \
                        *target -= v[r][i] * yv[r];                                                                    \
                    }                                                                                                  \
                }                                                                                                      \
            }                                                                                                          \
            j += 2;                                                                                                    \
        }                                                                                                              \
        *reinterpret_cast<MassLanes*>(pivotsOut) = pivots;                                                             \
    }

MASSE_MASS_KERNEL(Default, )
#if defined(__x86_64__) && defined(__GNUC__)
MASSE_MASS_KERNEL(Avx2, __attribute__((target("avx2"))))
#endif
#undef MASSE_MASS_KERNEL

void massColumnsOn(SimdPath path, const MassColumns& mass, Value* pivots, Value* inBlock)
{
    switch (path)
    {
#if defined(__x86_64__) && defined(__GNUC__)
    case SimdPath::Avx512:
    case SimdPath::Avx2:
        return massColumnsAvx2(mass, pivots, inBlock);
#endif
    default:
        return massColumnsDefault(mass, pivots, inBlock);
    }
}

// One copy of the dense factorisation per SIMD path, as the blocks' kernels: each entry's arithmetic is the scalar
// code's, in the same order, so the bits do not differ.
#define MASSE_DENSE_KERNEL(suffix, targetAttribute)                                                                    \
    /* LDL^T of the symmetric `count` x `count` matrix whose lower triangle `m` holds (column-major), in place, right- \
       looking: column k's entries below its pivot d_k become L's, and each later column j takes l_ik t_j from its     \
       entries i >= j (t: column k before the division, d_k l_jk). False if a pivot is zero. */                        \
    targetAttribute bool denseLdlt##suffix(Value* m, std::size_t count, Value* t, Value* d)                            \
    {                                                                                                                  \
        for (std::size_t k = 0; k < count; ++k)                                                                        \
        {                                                                                                              \
            Value* columnK = m + k * count;                                                                            \
            const Value dk = columnK[k];                                                                               \
            d[k] = dk;                                                                                                 \
            if (dk == 0)                                                                                               \
            {                                                                                                          \
                return false;                                                                                          \
            }                                                                                                          \
            for (std::size_t i = k + 1; i < count; ++i)                                                                \
            {                                                                                                          \
                t[i] = columnK[i];                                                                                     \
                columnK[i] = t[i] / dk;                                                                                \
            }                                                                                                          \
            for (std::size_t j = k + 1; j < count; ++j)                                                                \
            {                                                                                                          \
                const Value tj = t[j];                                                                                 \
                if (tj == 0) /* a zero of the pattern: the update would subtract zeros */                              \
                {                                                                                                      \
                    continue;                                                                                          \
                }                                                                                                      \
                Value* columnJ = m + j * count;                                                                        \
                std::size_t i = j;                                                                                     \
                for (; i + lanes <= count; i += lanes)                                                                 \
                {                                                                                                      \
                    LaneValues* target = reinterpret_cast<LaneValues*>(columnJ + i);                                   \
                    *target -= *reinterpret_cast<const LaneValues*>(columnK + i) * tj;                                 \
                }                                                                                                      \
                for (; i < count; ++i)                                                                                 \
                {                                                                                                      \
                    columnJ[i] -= columnK[i] * tj;                                                                     \
                }                                                                                                      \
            }                                                                                                          \
        }                                                                                                              \
        return true;                                                                                                   \
    }

MASSE_DENSE_KERNEL(Default, )
#if defined(__x86_64__) && defined(__GNUC__)
MASSE_DENSE_KERNEL(Avx2, __attribute__((target("avx2"))))
MASSE_DENSE_KERNEL(Avx512, __attribute__((target("avx512f"))))
#endif
#undef MASSE_DENSE_KERNEL

bool denseLdltOn(SimdPath path, Value* m, std::size_t count, Value* t, Value* d)
{
    switch (path)
    {
#if defined(__x86_64__) && defined(__GNUC__)
    case SimdPath::Avx512:
        return denseLdltAvx512(m, count, t, d);
    case SimdPath::Avx2:
        return denseLdltAvx2(m, count, t, d);
#endif
    default:
        return denseLdltDefault(m, count, t, d);
    }
}

void eliminateBelowOn(SimdPath path, const BlockColumns& block, const StorageIndex* start, const StorageIndex* rows,
                      const Value* values, const Value* diagonal, Value* y, Value* d)
{
    switch (path)
    {
#if defined(__x86_64__) && defined(__GNUC__)
    case SimdPath::Avx512:
        return eliminateBelowAvx512(block, start, rows, values, diagonal, y, d);
    case SimdPath::Avx2:
        return eliminateBelowAvx2(block, start, rows, values, diagonal, y, d);
#endif
    default:
        return eliminateBelowDefault(block, start, rows, values, diagonal, y, d);
    }
}

void schurBlockOn(SimdPath path, const BlockColumns& block, const StorageIndex* rows, const Value* values,
                  StorageIndex begin, StorageIndex lastRow, Value* z)
{
    switch (path)
    {
#if defined(__x86_64__) && defined(__GNUC__)
    case SimdPath::Avx512:
        return schurBlockAvx512(block, rows, values, begin, lastRow, z);
    case SimdPath::Avx2:
        return schurBlockAvx2(block, rows, values, begin, lastRow, z);
#endif
    default:
        return schurBlockDefault(block, rows, values, begin, lastRow, z);
    }
}
} // namespace

void StagedLdlt::analyse(const SparseMatrix& permuted, const std::vector<std::vector<OrderRange>>& stages)
{
    m_stages = stages;
    m_upperSources.clear(); // a new pattern
    const StorageIndex n = StorageIndex(permuted.rows());
    // Eigen's factorisation reads the upper triangle it makes from the full matrix; the same expression here gives
    // the same entries in the same order, which fixes the order of each row's updates and so the bits.
    assignUpper(permuted);
    // The elimination tree and L's column counts (Eigen's analyzePattern_preordered), and of each column's entries
    // those in the separators' rows (the stages after the first).
    m_parent.assign(std::size_t(n), -1);
    m_columnCount.assign(std::size_t(n), 0);
    std::vector<std::uint8_t> separatorRow(std::size_t(n), 0);
    for (std::size_t stage = 1; stage < m_stages.size(); ++stage)
    {
        for (const OrderRange& range : m_stages[stage])
        {
            std::fill(separatorRow.begin() + std::ptrdiff_t(range.begin),
                      separatorRow.begin() + std::ptrdiff_t(range.end), std::uint8_t(1));
        }
    }
    std::vector<StorageIndex> separatorEntries(std::size_t(n), 0);
    std::vector<StorageIndex> tags(std::size_t(n), 0);
    for (StorageIndex k = 0; k < n; ++k)
    {
        tags[std::size_t(k)] = k;
        const bool inSeparator = separatorRow[std::size_t(k)] != 0;
        for (SparseMatrix::InnerIterator it(m_upper, k); it; ++it)
        {
            StorageIndex i = StorageIndex(it.index());
            for (; i < k && tags[std::size_t(i)] != k; i = m_parent[std::size_t(i)])
            {
                if (m_parent[std::size_t(i)] == -1)
                {
                    m_parent[std::size_t(i)] = k;
                }
                ++m_columnCount[std::size_t(i)];
                tags[std::size_t(i)] = k;
                if (inSeparator)
                {
                    ++separatorEntries[std::size_t(i)];
                }
                else if (separatorEntries[std::size_t(i)] > 0)
                {
                    // analyseSeparators places the separators' entries after the others in each column.
                    throw std::logic_error("StagedLdlt: a row of the first stage below a separator's in the factor");
                }
            }
        }
    }
    m_updates = 0;
    for (const StorageIndex count : m_columnCount)
    {
        m_updates += 0.5 * double(count) * double(count - 1);
    }
    m_lower.resize(n, n);
    StorageIndex* start = m_lower.outerIndexPtr();
    start[0] = 0;
    for (StorageIndex k = 0; k < n; ++k)
    {
        start[k + 1] = start[k] + m_columnCount[std::size_t(k)];
    }
    m_lower.resizeNonZeros(start[n]);
    m_diagonal.resize(n);
    m_columnsShareRows.assign(std::size_t(n / 3), 0);
    for (std::size_t m = 0; m < m_columnsShareRows.size(); ++m)
    {
        m_columnsShareRows[m] = sharesRowsWithNext(3 * m) && sharesRowsWithNext(3 * m + 1);
    }
    analyseSeparators(separatorEntries);
    analyseMasses();
}

void StagedLdlt::analyseSeparators(const std::vector<StorageIndex>& separatorEntries)
{
    const StorageIndex n = StorageIndex(m_upper.rows());
    const StorageIndex* start = m_lower.outerIndexPtr();
    m_separators.clear();
    m_blocks = Blocks{};
    m_blocks.start.push_back(0);
    m_stageSeparators.assign(1, 0);
    std::vector<std::ptrdiff_t> separatorOf(std::size_t(n), -1);
    for (std::size_t stage = 0; stage < m_stages.size(); ++stage)
    {
        for (const OrderRange& range : m_stages[stage])
        {
            if (stage > 0 && range.end > range.begin)
            {
                for (std::size_t k = range.begin; k < range.end; ++k)
                {
                    separatorOf[k] = std::ptrdiff_t(m_separators.size());
                }
                Separator& separator = m_separators.emplace_back();
                separator.begin = StorageIndex(range.begin);
                separator.end = StorageIndex(range.end);
            }
        }
        m_stageSeparators.push_back(m_separators.size());
    }
    m_stageBlocks.assign(m_stages.size(), {});
    if (m_separators.empty())
    {
        return;
    }
    // The separators' rows' patterns in elimination order, to find where each of their entries goes in L: a column's
    // entries come in increasing row, those of the first stage's rows before the separators' (a column's rows are its
    // ancestors in the elimination tree: its own leaf's rows, numbered before the separators above it, and those
    // separators'), so a separator's entry in column c is at the column's start plus its entries in the first stage's
    // rows plus those in the separators' rows before. A separator's rows are consecutive, and each is blocked once its
    // last row is reached.
    std::vector<StorageIndex> filled(static_cast<std::size_t>(n));
    for (std::size_t c = 0; c < std::size_t(n); ++c)
    {
        filled[c] = m_columnCount[c] - separatorEntries[c];
    }
    std::vector<long long> mark(std::size_t(n), -1);
    std::vector<StorageIndex> pattern(static_cast<std::size_t>(n));
    std::vector<StorageIndex> firstInSeparator(std::size_t(n), -1); // per column: its first entry in the separator
    std::vector<StorageIndex> lastInSeparator(std::size_t(n), -1);
    std::vector<std::size_t> belowStart{0};  // per row of the separator and one past: its entries in columns below
    std::vector<StorageIndex> belowColumn;   // those columns
    std::vector<StorageIndex> belowPosition; // and where each entry goes
    std::vector<std::size_t> ownStart{0};    // per row of the separator and one past: its entries in its own columns
    std::vector<StorageIndex> ownColumn;     // those columns
    std::vector<StorageIndex> slot(std::size_t(n), -1); // per column: its entry in the block being built
    for (StorageIndex k = 0; k < n; ++k)
    {
        const std::ptrdiff_t which = separatorOf[std::size_t(k)];
        if (which < 0)
        {
            continue;
        }
        Separator* separator = &m_separators[std::size_t(which)];
        if (k == separator->begin)
        {
            ownStart.assign(1, 0);
            ownColumn.clear();
            belowStart.assign(1, 0);
            belowColumn.clear();
            belowPosition.clear();
        }
        for (StorageIndex t = rowPattern(k, k, mark.data(), pattern.data()); t < n; ++t)
        {
            const StorageIndex column = pattern[std::size_t(t)];
            const StorageIndex position = start[column] + filled[std::size_t(column)]++;
            if (column < separator->begin)
            {
                belowColumn.push_back(column);
                belowPosition.push_back(position);
                if (firstInSeparator[std::size_t(column)] < 0)
                {
                    firstInSeparator[std::size_t(column)] = position;
                }
                lastInSeparator[std::size_t(column)] = position;
            }
            else
            {
                ownColumn.push_back(column);
            }
        }
        belowStart.push_back(belowColumn.size());
        ownStart.push_back(ownColumn.size());
        if (k + 1 < separator->end)
        {
            continue;
        }
        // The separator's blocks: each block's columns below in increasing order (the elimination tree's parents
        // come after their children, so that is a topological order for every row), with the rows that have each.
        const std::size_t rows = std::size_t(separator->end - separator->begin);
        separator->firstBlock = m_blocks.separator.size();
        for (std::size_t first = 0; first < rows; first += lanes)
        {
            const std::size_t blockBegin = m_blocks.column.size();
            const std::size_t last = std::min(rows, first + lanes);
            std::vector<StorageIndex> columns;
            for (std::size_t e = belowStart[first]; e < belowStart[last]; ++e)
            {
                if (slot[std::size_t(belowColumn[e])] < 0)
                {
                    slot[std::size_t(belowColumn[e])] = 0;
                    columns.push_back(belowColumn[e]);
                }
            }
            std::sort(columns.begin(), columns.end());
            for (std::size_t j = 0; j < columns.size(); ++j)
            {
                const StorageIndex c = columns[j];
                slot[std::size_t(c)] = StorageIndex(j);
                m_blocks.column.push_back(c);
                m_blocks.belowEnd.push_back(firstInSeparator[std::size_t(c)]);
                m_blocks.separatorEnd.push_back(lastInSeparator[std::size_t(c)] + 1);
            }
            m_blocks.rows.resize(m_blocks.column.size(), 0);
            m_blocks.position.resize(m_blocks.column.size() * lanes, -1);
            for (std::size_t r = first; r < last; ++r)
            {
                for (std::size_t e = belowStart[r]; e < belowStart[r + 1]; ++e)
                {
                    const std::size_t entry = blockBegin + std::size_t(slot[std::size_t(belowColumn[e])]);
                    m_blocks.rows[entry] |= 1u << (r - first);
                    m_blocks.position[entry * lanes + (r - first)] = belowPosition[e];
                }
            }
            for (StorageIndex c : columns)
            {
                slot[std::size_t(c)] = -1;
            }
            m_blocks.separator.push_back(std::size_t(which));
            m_blocks.firstRow.push_back(separator->begin + StorageIndex(first));
            m_blocks.start.push_back(m_blocks.column.size());
        }
        for (std::size_t e = 0; e < belowColumn.size(); ++e)
        {
            firstInSeparator[std::size_t(belowColumn[e])] = -1;
        }
        separator->endBlock = m_blocks.separator.size();
        separator->partialPivot.resize(rows);
        separator->schur.resize(rows * (rows - 1) / 2);
        // The own block's pattern by columns, for step 3's output: each row's own columns, transposed (walking the
        // rows in order gives each column's rows in increasing order).
        separator->ownColumnStart.assign(rows + 1, 0);
        for (const StorageIndex column : ownColumn)
        {
            ++separator->ownColumnStart[std::size_t(column - separator->begin) + 1];
        }
        for (std::size_t j = 0; j < rows; ++j)
        {
            separator->ownColumnStart[j + 1] += separator->ownColumnStart[j];
        }
        separator->ownColumnRows.resize(ownColumn.size());
        std::vector<std::size_t> nextEntry(separator->ownColumnStart.begin(), separator->ownColumnStart.end() - 1);
        for (std::size_t r = 0; r < rows; ++r)
        {
            for (std::size_t e = ownStart[r]; e < ownStart[r + 1]; ++e)
            {
                const std::size_t j = std::size_t(ownColumn[e] - separator->begin);
                separator->ownColumnRows[nextEntry[j]++] = separator->begin + StorageIndex(r);
            }
        }
    }
    m_blocks.together.assign(m_blocks.column.size(), 0);
    for (std::size_t b = 0; b + 1 < m_blocks.start.size(); ++b)
    {
        for (std::size_t e = m_blocks.start[b]; e < m_blocks.start[b + 1];)
        {
            const std::size_t width = runFrom(e, m_blocks.start[b + 1]);
            m_blocks.together[e] = (unsigned char)(width);
            e += width;
        }
    }
    m_blocks.y.resize(m_blocks.column.size() * lanes);
    for (std::size_t stage = 0; stage < m_stages.size(); ++stage)
    {
        for (std::size_t k = m_stageSeparators[stage]; k < m_stageSeparators[stage + 1]; ++k)
        {
            for (std::size_t b = m_separators[k].firstBlock; b < m_separators[k].endBlock; ++b)
            {
                m_stageBlocks[stage].push_back(b);
            }
        }
    }
}

StorageIndex StagedLdlt::rowPattern(StorageIndex k, long long visit, long long* mark, StorageIndex* pattern) const
{
    // Eigen's walk: from each entry i <= k of A's column k up the elimination tree until a row already reached; each
    // path is stacked above the ones before it, so the rows come out children first.
    StorageIndex top = StorageIndex(m_upper.rows());
    mark[k] = visit;
    for (SparseMatrix::InnerIterator it(m_upper, k); it; ++it)
    {
        StorageIndex i = StorageIndex(it.index());
        if (i <= k)
        {
            StorageIndex length = 0;
            for (; mark[i] != visit; i = m_parent[std::size_t(i)])
            {
                pattern[length++] = i;
                mark[i] = visit;
            }
            while (length > 0)
            {
                pattern[--top] = pattern[--length];
            }
        }
    }
    return top;
}

void StagedLdlt::assignUpper(const SparseMatrix& permuted)
{
    // The upper triangle Eigen's factorisation makes from the full matrix: the same entries in the same order (see
    // analyse). Found once; each factorisation gathers the values.
    if (m_upperSources.empty())
    {
        m_upperSources = upperFromLower(permuted, m_upper);
    }
    gatherPermutedValues(permuted, m_upperSources, m_upper);
}

bool StagedLdlt::sharesRowsWithNext(std::size_t j) const
{
    // Column j's rows below its parent are among the parent's (the elimination tree's rule): where the parent is j + 1
    // and j has one row more, j's rows below j + 1 are j + 1's.
    return m_parent[j] == StorageIndex(j + 1) && m_columnCount[j] == m_columnCount[j + 1] + 1;
}

std::size_t StagedLdlt::runFrom(std::size_t e, std::size_t blockEnd) const
{
    // A run of columns each sharing its rows with the next holds its own triangle in full and has the same rows below
    // it, in every stretch the steps read: the stretches end at rows (the separator's first and last), and the rows
    // are sorted.
    const std::vector<StorageIndex>& column = m_blocks.column;
    std::size_t width = 1;
    while (width < mostTogether && e + width < blockEnd && column[e + width] == column[e] + StorageIndex(width) &&
           sharesRowsWithNext(std::size_t(column[e + width - 1])))
    {
        ++width;
    }
    return width;
}

bool StagedLdlt::factorize(const SparseMatrix& permuted)
{
    const FlushSubnormals flush; // for the work on this thread outside the chunks: the single-precision copy of A
    assignUpper(permuted);
    if (!m_takeTogether)
    {
        m_notTogether.assign(std::max(m_blocks.together.size(), m_columnsShareRows.size()), 0);
    }
    m_generation = ++factorisations;
    std::atomic<bool> ok{true};
    for (std::size_t stage = 0; stage < m_stages.size(); ++stage)
    {
        if (stage > 0)
        {
            if (!factorSeparators(stage))
            {
                return false;
            }
            continue;
        }
        const std::vector<OrderRange>& ranges = m_stages[stage];
        runFlushedChunks(ranges.size(),
                         [&](std::size_t r)
                         {
                             if (!factorRows(StorageIndex(ranges[r].begin), StorageIndex(ranges[r].end)))
                             {
                                 ok = false;
                             }
                         });
        if (!ok)
        {
            return false;
        }
    }
    // A matrix whose elimination leaves single precision's range (no implicit matrix of a sheet comes near it) has an
    // infinite or NaN pivot, and every row after it is lost with it.
    return std::all_of(m_diagonal.begin(), m_diagonal.end(), [](Value d) { return std::isfinite(d); });
}

Value StagedLdlt::appendToColumn(StorageIndex i, StorageIndex k, Value* y)
{
    const StorageIndex* start = m_lower.outerIndexPtr();
    StorageIndex* rows = m_lower.innerIndexPtr();
    Value* values = m_lower.valuePtr();
    const Value yi = y[i];
    y[i] = 0;
    const Value lki = yi / m_diagonal[i];
    const StorageIndex last = start[i] + m_columnCount[std::size_t(i)];
    StorageIndex p = start[i];
    for (; p < last; ++p)
    {
        y[rows[p]] -= values[p] * yi;
    }
    rows[p] = k;
    values[p] = lki;
    ++m_columnCount[std::size_t(i)];
    return lki * yi;
}

bool StagedLdlt::factorRows(StorageIndex begin, StorageIndex end)
{
    // Eigen's factorize_preordered<true> over rows [begin, end), with this thread's scratch, a mass at a time where
    // the mass's rows allow it.
    thread_local RowWorkspace work;
    const std::size_t n = std::size_t(m_upper.rows());
    work.fit(n);
    Value* y = work.y.data();
    StorageIndex* pattern = work.pattern.data();
    long long* mark = work.mark.data();
    const long long base = m_generation * (long long)(n);
    for (StorageIndex k = begin; k < end; ++k)
    {
        if (k % 3 == 0 && m_massTogether[std::size_t(k / 3)])
        {
            if (!factorMass(k, work.massY.data(), base + k, mark, pattern))
            {
                return false;
            }
            k += 2;
            continue;
        }
        // The pattern of row k of L, in topological order: every row the etree reaches from A's column k above k.
        y[k] = 0;
        m_columnCount[std::size_t(k)] = 0;
        StorageIndex top = rowPattern(k, base + k, mark, pattern);
        for (SparseMatrix::InnerIterator it(m_upper, k); it; ++it)
        {
            if (StorageIndex(it.index()) <= k)
            {
                y[it.index()] += it.value();
            }
        }
        // Row k's values: a sparse triangular solve with the rows above.
        Value d = y[k];
        y[k] = 0;
        for (; top < StorageIndex(n); ++top)
        {
            d -= appendToColumn(pattern[top], k, y);
        }
        m_diagonal[k] = d;
        if (d == 0)
        {
            work.y.assign(n, 0); // a row left half solved: clear it for the next factorisation
            return false;
        }
    }
    return true;
}
bool StagedLdlt::factorMass(StorageIndex k0, Value* massY, long long visit, long long* mark, StorageIndex* pattern)
{
    const StorageIndex* start = m_lower.outerIndexPtr();
    StorageIndex* rows = m_lower.innerIndexPtr();
    Value* values = m_lower.valuePtr();
    const StorageIndex n = StorageIndex(m_upper.rows());
    // The mass's columns below its block, in topological order: row k0's pattern, which the other two rows share.
    const StorageIndex top = rowPattern(k0, visit, mark, pattern);
    alignas(32) Value pivots[4] = {};
    Value inBlock[3] = {}; // row k0 + 1's y in column k0, row k0 + 2's in columns k0 and k0 + 1
    for (int r = 0; r < 3; ++r)
    {
        const StorageIndex k = k0 + r;
        m_columnCount[std::size_t(k)] = 0;
        for (SparseMatrix::InnerIterator it(m_upper, k); it; ++it)
        {
            const StorageIndex i = StorageIndex(it.index());
            if (i < k0)
            {
                massY[4 * std::size_t(i) + std::size_t(r)] += it.value();
            }
            else if (i == k)
            {
                pivots[r] += it.value();
            }
            else if (i < k)
            {
                inBlock[r == 1 ? 0 : i == k0 ? 1 : 2] += it.value();
            }
        }
    }
    MassColumns columns{pattern + top,
                        std::size_t(n - top),
                        start,
                        m_columnCount.data(),
                        rows,
                        values,
                        m_diagonal.data(),
                        massY,
                        k0,
                        m_takeTogether ? m_columnsShareRows.data() : m_notTogether.data()};
    massColumnsOn(activeSimdPath(), columns, pivots, inBlock);
    // The mass's block, as Eigen's rows k0 + 1 and k0 + 2 finish with columns k0 and k0 + 1.
    const StorageIndex k1 = k0 + 1;
    const StorageIndex k2 = k0 + 2;
    Value& y10 = inBlock[0];
    Value& y20 = inBlock[1];
    Value& y21 = inBlock[2];
    const Value d0 = pivots[0];
    m_diagonal[k0] = d0;
    if (d0 == 0)
    {
        return false;
    }
    const Value l10 = y10 / d0;
    rows[start[k0]] = k1;
    values[start[k0]] = l10;
    const Value d1 = pivots[1] - l10 * y10;
    m_diagonal[k1] = d1;
    if (d1 == 0)
    {
        return false;
    }
    const Value l20 = y20 / d0;
    y21 -= l10 * y20;
    rows[start[k0] + 1] = k2;
    values[start[k0] + 1] = l20;
    const Value l21 = y21 / d1;
    rows[start[k1]] = k2;
    values[start[k1]] = l21;
    const Value d2 = (pivots[2] - l20 * y20) - l21 * y21;
    m_diagonal[k2] = d2;
    m_columnCount[std::size_t(k0)] = 2;
    m_columnCount[std::size_t(k1)] = 1;
    return d2 != 0;
}

void StagedLdlt::analyseMasses()
{
    // A mass qualifies when rows k0 + 1 and k0 + 2 have exactly row k0's columns below the block plus the block's
    // columns before them (then row k0's topological order serves all three).
    const StorageIndex n = StorageIndex(m_upper.rows());
    m_massTogether.assign(std::size_t(n / 3), 0);
    if (m_stages.empty())
    {
        return;
    }
    std::vector<long long> mark(std::size_t(n), -1);
    std::vector<StorageIndex> member(std::size_t(n), -1); // k0 for the columns of row k0's pattern
    std::vector<StorageIndex> pattern(static_cast<std::size_t>(n));
    long long visit = 0;
    for (const OrderRange& range : m_stages[0])
    {
        for (std::size_t first = (range.begin + 2) / 3 * 3; first + 3 <= range.end; first += 3)
        {
            const StorageIndex k0 = StorageIndex(first);
            const StorageIndex top0 = rowPattern(k0, visit++, mark.data(), pattern.data());
            for (StorageIndex t = top0; t < n; ++t)
            {
                member[std::size_t(pattern[std::size_t(t)])] = k0;
            }
            bool shared = true;
            for (StorageIndex r = 1; r < 3 && shared; ++r)
            {
                const StorageIndex top = rowPattern(k0 + r, visit++, mark.data(), pattern.data());
                shared = n - top == (n - top0) + r;
                for (StorageIndex t = top; t < n && shared; ++t)
                {
                    const StorageIndex c = pattern[std::size_t(t)];
                    shared = member[std::size_t(c)] == k0 || (c >= k0 && c < k0 + r);
                }
            }
            m_massTogether[first / 3] = shared ? 1 : 0;
        }
    }
}

bool StagedLdlt::factorSeparators(std::size_t stage)
{
    const std::size_t firstSeparator = m_stageSeparators[stage];
    const std::size_t endSeparator = m_stageSeparators[stage + 1];
    if (firstSeparator == endSeparator)
    {
        return true;
    }
    const std::vector<std::size_t>& blocks = m_stageBlocks[stage];
    const StorageIndex* start = m_lower.outerIndexPtr();
    StorageIndex* rows = m_lower.innerIndexPtr();
    Value* values = m_lower.valuePtr();
    const std::size_t n = std::size_t(m_upper.rows());
    const SimdPath path = activeSimdPath();
    // Row r's column of the Schur complement holds its r entries above it, packed after those of the rows before.
    auto schurOffset = [](std::size_t r) { return r == 0 ? std::size_t(0) : r * (r - 1) / 2; };
    auto blockColumns = [&](std::size_t b)
    {
        const std::size_t first = m_blocks.start[b];
        return BlockColumns{m_blocks.start[b + 1] - first,
                            m_blocks.column.data() + first,
                            m_blocks.belowEnd.data() + first,
                            m_blocks.separatorEnd.data() + first,
                            (m_takeTogether ? m_blocks.together.data() : m_notTogether.data()) + first,
                            m_blocks.y.data() + first * lanes};
    };

    // 1. Each row's entries in the columns below the separator: a sparse triangular solve with those columns alone
    // (their entries so far are all in rows below the separator), for a block of rows at once: each column's entries
    // are read once for the block rather than once a row (row by row, these reads would be most of a refactorisation).
    // The block's columns come in increasing order; where a row has no entry its y is zero, and its lane's arithmetic
    // changes nothing.
    runFlushedChunks(blocks.size(),
                     [&](std::size_t task)
                     {
                         const std::size_t b = blocks[task];
                         Separator& separator = m_separators[m_blocks.separator[b]];
                         const StorageIndex firstRow = m_blocks.firstRow[b];
                         const std::size_t count = std::min(lanes, std::size_t(separator.end - firstRow));
                         thread_local std::vector<Value> scratch; // lanes values per row, all zero between blocks
                         if (scratch.size() != n * lanes)
                         {
                             scratch.assign(n * lanes, 0);
                         }
                         Value* y = scratch.data();
                         alignas(64) Value d[lanes] = {};
                         for (std::size_t lane = 0; lane < count; ++lane)
                         {
                             const StorageIndex k = firstRow + StorageIndex(lane);
                             for (SparseMatrix::InnerIterator it(m_upper, k); it; ++it)
                             {
                                 const StorageIndex i = StorageIndex(it.index());
                                 if (i < separator.begin)
                                 {
                                     y[std::size_t(i) * lanes + lane] += it.value();
                                 }
                                 else if (i == k)
                                 {
                                     d[lane] += it.value();
                                 }
                             }
                         }
                         const BlockColumns block = blockColumns(b);
                         eliminateBelowOn(path, block, start, rows, values, m_diagonal.data(), y, d);
                         const std::size_t firstEntry = m_blocks.start[b];
                         for (std::size_t j = 0; j < block.count; ++j)
                         {
                             const StorageIndex* position = m_blocks.position.data() + (firstEntry + j) * lanes;
                             const Value* yc = block.y + j * lanes;
                             for (unsigned set = m_blocks.rows[firstEntry + j]; set != 0; set &= set - 1)
                             {
                                 const int lane = __builtin_ctz(set);
                                 rows[position[lane]] = firstRow + StorageIndex(lane);
                                 values[position[lane]] = yc[lane] / m_diagonal[block.column[j]];
                             }
                         }
                         for (std::size_t lane = 0; lane < count; ++lane)
                         {
                             separator.partialPivot[std::size_t(firstRow - separator.begin) + lane] = d[lane];
                         }
                     });

    // 2. Each row's column of the Schur complement: A's entries above it in the separator, less what the columns
    // below give them (their entries in the separator's rows above this one, written in step 1), a block of rows at
    // once as in step 1.
    runFlushedChunks(blocks.size(),
                     [&](std::size_t task)
                     {
                         const std::size_t b = blocks[task];
                         Separator& separator = m_separators[m_blocks.separator[b]];
                         const StorageIndex firstRow = m_blocks.firstRow[b];
                         const std::size_t count = std::min(lanes, std::size_t(separator.end - firstRow));
                         const std::size_t first = std::size_t(firstRow - separator.begin);
                         thread_local std::vector<Value> scratch; // lanes values per separator row
                         const std::size_t needed = (first + count) * lanes;
                         if (scratch.size() < needed)
                         {
                             scratch.resize(needed, 0);
                         }
                         Value* z = scratch.data();
                         for (std::size_t lane = 0; lane < count; ++lane)
                         {
                             const StorageIndex k = firstRow + StorageIndex(lane);
                             for (SparseMatrix::InnerIterator it(m_upper, k); it; ++it)
                             {
                                 const StorageIndex i = StorageIndex(it.index());
                                 if (i >= separator.begin && i < k)
                                 {
                                     z[std::size_t(i - separator.begin) * lanes + lane] += it.value();
                                 }
                             }
                         }
                         const StorageIndex lastRow = firstRow + StorageIndex(count) - 1;
                         schurBlockOn(path, blockColumns(b), rows, values, separator.begin, lastRow, z);
                         // Each row takes the rows above it in its lane; the block's rows before its last were
                         // written for the lanes below them, and all are cleared for the next block.
                         for (std::size_t lane = 0; lane < count; ++lane)
                         {
                             const std::size_t r = first + lane;
                             Value* packed = separator.schur.data() + schurOffset(r);
                             for (std::size_t j = 0; j < r; ++j)
                             {
                                 packed[j] = z[j * lanes + lane];
                             }
                         }
                         std::fill(z, z + (first + count - 1) * lanes, Value(0));
                     });

    // 3. Each separator's own block: its Schur complement, dense, factored column by column, then its pattern's
    // entries written to L.
    std::atomic<bool> ok{true};
    runFlushedChunks(endSeparator - firstSeparator,
                     [&](std::size_t task)
                     {
                         Separator& separator = m_separators[firstSeparator + task];
                         const std::size_t count = std::size_t(separator.end - separator.begin);
                         thread_local std::vector<Value> dense; // column-major, the lower triangle used
                         thread_local std::vector<Value> scratch;
                         if (dense.size() < count * count)
                         {
                             dense.resize(count * count);
                         }
                         if (scratch.size() < 2 * count)
                         {
                             scratch.resize(2 * count);
                         }
                         Value* m = dense.data();
                         for (std::size_t r = 0; r < count; ++r)
                         {
                             const Value* z = separator.schur.data() + schurOffset(r);
                             for (std::size_t j = 0; j < r; ++j)
                             {
                                 m[r + j * count] = z[j];
                             }
                             m[r + r * count] = separator.partialPivot[r];
                         }
                         Value* d = scratch.data();
                         if (!denseLdltOn(path, m, count, scratch.data() + count, d))
                         {
                             ok = false;
                             return;
                         }
                         for (std::size_t j = 0; j < count; ++j)
                         {
                             const StorageIndex column = separator.begin + StorageIndex(j);
                             m_diagonal[column] = d[j];
                             StorageIndex p = start[column];
                             for (std::size_t e = separator.ownColumnStart[j]; e < separator.ownColumnStart[j + 1];
                                  ++e, ++p)
                             {
                                 const StorageIndex row = separator.ownColumnRows[e];
                                 rows[p] = row;
                                 values[p] = m[std::size_t(row - separator.begin) + j * count];
                             }
                             m_columnCount[std::size_t(column)] = p - start[column];
                         }
                     });
    return ok;
}
} // namespace masse
