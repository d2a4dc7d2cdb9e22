#include "StagedLdlt.h"

#include "PermutedValues.h"
#include "TaskPool.h"

#include <algorithm>
#include <atomic>

namespace masse
{
using StorageIndex = StagedLdlt::StorageIndex;

namespace
{
/// Numbers every factorisation in the process, so that a thread's visit marks (see RowWorkspace) left by one
/// factorisation, of this factor or another of the same size, never match another's.
std::atomic<long long> factorisations{0};

/// One thread's scratch for the rows it factors: kept from call to call (no allocation per refresh).
struct RowWorkspace
{
    std::vector<Real> y;               ///< the row being solved for, scattered; all zero between rows
    std::vector<StorageIndex> pattern; ///< the row's pattern, as a stack in topological order
    std::vector<long long> mark;       ///< generation * n + row of the row that last visited each row

    void fit(std::size_t n)
    {
        if (y.size() != n)
        {
            y.assign(n, 0);
            pattern.assign(n, 0);
            mark.assign(n, -1);
        }
    }
};
} // namespace

void StagedLdlt::analyse(const SparseMatrix& permuted, const std::vector<std::vector<OrderRange>>& stages)
{
    m_stages = stages;
    m_upperSources.clear(); // a new pattern
    const StorageIndex n = StorageIndex(permuted.rows());
    // Eigen's factorisation reads the upper triangle it makes from the full matrix; the same expression here gives
    // the same entries in the same order, which fixes the order of each row's updates and so the bits.
    assignUpper(permuted);
    // The elimination tree and L's column counts (Eigen's analyzePattern_preordered).
    m_parent.assign(std::size_t(n), -1);
    m_columnCount.assign(std::size_t(n), 0);
    std::vector<StorageIndex> tags(std::size_t(n), 0);
    for (StorageIndex k = 0; k < n; ++k)
    {
        tags[std::size_t(k)] = k;
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
            }
        }
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
    analyseTopStage();
}

void StagedLdlt::analyseTopStage()
{
    const StorageIndex n = StorageIndex(m_upper.rows());
    m_top = TopStage{};
    if (m_stages.empty() || m_stages.back().size() != 1 || StorageIndex(m_stages.back()[0].end) != n ||
        m_stages.back()[0].begin == 0)
    {
        return; // not a single top separator at the end of the order: row by row
    }
    const StorageIndex begin = StorageIndex(m_stages.back()[0].begin);
    m_top.begin = begin;
    m_top.end = n;
    const StorageIndex* start = m_lower.outerIndexPtr();
    std::vector<long long> mark(std::size_t(n), -1);
    std::vector<StorageIndex> pattern(static_cast<std::size_t>(n));
    std::vector<StorageIndex> inTop(std::size_t(begin), 0); // per column below: entries in the separator's rows
    m_top.belowStart.push_back(0);
    m_top.ownStart.push_back(0);
    for (StorageIndex k = begin; k < n; ++k)
    {
        for (StorageIndex t = rowPattern(k, k, mark.data(), pattern.data()); t < n; ++t)
        {
            const StorageIndex column = pattern[std::size_t(t)];
            if (column < begin)
            {
                m_top.belowColumn.push_back(column);
                ++inTop[std::size_t(column)];
            }
            else
            {
                m_top.ownColumn.push_back(column);
            }
        }
        m_top.belowStart.push_back(m_top.belowColumn.size());
        m_top.ownStart.push_back(m_top.ownColumn.size());
    }
    // A column's entries are in increasing row, and the separator's rows come last: each of its entries goes after
    // the column's entries from below, in the order of the separator's rows.
    m_top.belowCount.resize(std::size_t(begin));
    for (StorageIndex c = 0; c < begin; ++c)
    {
        m_top.belowCount[std::size_t(c)] = start[c + 1] - start[c] - inTop[std::size_t(c)];
    }
    std::vector<StorageIndex> placed(std::size_t(begin), 0);
    m_top.belowPosition.resize(m_top.belowColumn.size());
    for (std::size_t e = 0; e < m_top.belowColumn.size(); ++e)
    {
        const std::size_t c = std::size_t(m_top.belowColumn[e]);
        m_top.belowPosition[e] = start[c] + m_top.belowCount[c] + placed[c]++;
    }
    const std::size_t rows = std::size_t(n - begin);
    m_top.belowY.resize(m_top.belowColumn.size());
    m_top.partialPivot.resize(rows);
    m_top.schur.resize(rows * (rows - 1) / 2);
    m_top.row.resize(rows);
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
    // Eigen's expression, with its identity permutation: the same entries in the same order as Eigen's factorisation
    // reads (see analyse). Found once; each factorisation gathers the values.
    if (m_upperSources.empty())
    {
        const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, StorageIndex> identity;
        m_upperSources = findPermutedSources(
            permuted,
            [&](const SparseMatrix& m)
            {
                SparseMatrix upper(m.rows(), m.cols());
                upper.selfadjointView<Eigen::Upper>() = m.selfadjointView<Eigen::Lower>().twistedBy(identity);
                return upper;
            },
            m_upper);
    }
    gatherPermutedValues(permuted, m_upperSources, m_upper);
}

bool StagedLdlt::factorize(const SparseMatrix& permuted)
{
    assignUpper(permuted);
    m_generation = ++factorisations;
    std::atomic<bool> ok{true};
    for (const std::vector<OrderRange>& ranges : m_stages)
    {
        if (m_top.begin < m_top.end && &ranges == &m_stages.back())
        {
            return factorTopStage();
        }
        sharedPool().run(ranges.size(),
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
    return true;
}

Real StagedLdlt::appendToColumn(StorageIndex i, StorageIndex k, Real* y, StorageIndex offset)
{
    const StorageIndex* start = m_lower.outerIndexPtr();
    StorageIndex* rows = m_lower.innerIndexPtr();
    Real* values = m_lower.valuePtr();
    const Real yi = y[i - offset];
    y[i - offset] = 0;
    const Real lki = yi / m_diagonal[i];
    const StorageIndex last = start[i] + m_columnCount[std::size_t(i)];
    StorageIndex p = start[i];
    for (; p < last; ++p)
    {
        y[rows[p] - offset] -= values[p] * yi;
    }
    rows[p] = k;
    values[p] = lki;
    ++m_columnCount[std::size_t(i)];
    return lki * yi;
}

bool StagedLdlt::factorRows(StorageIndex begin, StorageIndex end)
{
    // Eigen's factorize_preordered<true> over rows [begin, end), with this thread's scratch.
    thread_local RowWorkspace work;
    const std::size_t n = std::size_t(m_upper.rows());
    work.fit(n);
    Real* y = work.y.data();
    StorageIndex* pattern = work.pattern.data();
    long long* mark = work.mark.data();
    const long long base = m_generation * (long long)(n);
    for (StorageIndex k = begin; k < end; ++k)
    {
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
        Real d = y[k];
        y[k] = 0;
        for (; top < StorageIndex(n); ++top)
        {
            d -= appendToColumn(pattern[top], k, y, 0);
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
bool StagedLdlt::factorTopStage()
{
    const StorageIndex begin = m_top.begin;
    const StorageIndex n = m_top.end;
    const StorageIndex* start = m_lower.outerIndexPtr();
    StorageIndex* rows = m_lower.innerIndexPtr();
    Real* values = m_lower.valuePtr();
    const std::size_t count = std::size_t(n - begin);
    // Row r's column of the Schur complement holds its r entries above it, packed after those of the rows before.
    auto schurOffset = [](std::size_t r) { return r == 0 ? std::size_t(0) : r * (r - 1) / 2; };

    // 1. Each row's entries in the columns below the separator: a sparse triangular solve with those columns alone,
    // Eigen's arithmetic restricted to them (their entries so far are all in rows below the separator).
    sharedPool().run(count,
                     [&](std::size_t r)
                     {
                         thread_local RowWorkspace work;
                         work.fit(std::size_t(n));
                         Real* y = work.y.data();
                         const StorageIndex k = begin + StorageIndex(r);
                         Real d = 0;
                         for (SparseMatrix::InnerIterator it(m_upper, k); it; ++it)
                         {
                             const StorageIndex i = StorageIndex(it.index());
                             if (i < begin)
                             {
                                 y[i] += it.value();
                             }
                             else if (i == k)
                             {
                                 d += it.value();
                             }
                         }
                         for (std::size_t e = m_top.belowStart[r]; e < m_top.belowStart[r + 1]; ++e)
                         {
                             const StorageIndex c = m_top.belowColumn[e];
                             const Real yc = y[c];
                             y[c] = 0;
                             const Real lkc = yc / m_diagonal[c];
                             const StorageIndex last = start[c] + m_top.belowCount[std::size_t(c)];
                             for (StorageIndex p = start[c]; p < last; ++p)
                             {
                                 y[rows[p]] -= values[p] * yc;
                             }
                             d -= lkc * yc;
                             rows[m_top.belowPosition[e]] = k;
                             values[m_top.belowPosition[e]] = lkc;
                             m_top.belowY[e] = yc;
                         }
                         m_top.partialPivot[r] = d;
                     });

    // 2. Each row's column of the Schur complement: A's entries above it in the separator, less what the columns
    // below give them (their entries in the separator's rows above this one, written in step 1).
    sharedPool().run(count,
                     [&](std::size_t r)
                     {
                         const StorageIndex k = begin + StorageIndex(r);
                         Real* z = m_top.schur.data() + schurOffset(r);
                         std::fill(z, z + r, Real(0));
                         for (SparseMatrix::InnerIterator it(m_upper, k); it; ++it)
                         {
                             const StorageIndex i = StorageIndex(it.index());
                             if (i >= begin && i < k)
                             {
                                 z[i - begin] += it.value();
                             }
                         }
                         for (std::size_t e = m_top.belowStart[r]; e < m_top.belowStart[r + 1]; ++e)
                         {
                             const StorageIndex c = m_top.belowColumn[e];
                             const Real yc = m_top.belowY[e];
                             for (StorageIndex p = start[c] + m_top.belowCount[std::size_t(c)];
                                  p < start[c + 1] && rows[p] < k; ++p)
                             {
                                 z[rows[p] - begin] -= values[p] * yc;
                             }
                         }
                     });

    // 3. The separator's own block, row by row as Eigen does, from the Schur complement.
    Real* y = m_top.row.data();
    for (std::size_t r = 0; r < count; ++r)
    {
        const StorageIndex k = begin + StorageIndex(r);
        const Real* z = m_top.schur.data() + schurOffset(r);
        std::copy(z, z + r, y);
        Real d = m_top.partialPivot[r];
        m_columnCount[std::size_t(k)] = 0;
        for (std::size_t e = m_top.ownStart[r]; e < m_top.ownStart[r + 1]; ++e)
        {
            d -= appendToColumn(m_top.ownColumn[e], k, y, begin);
        }
        m_diagonal[k] = d;
        if (d == 0)
        {
            return false;
        }
    }
    return true;
}
} // namespace masse
