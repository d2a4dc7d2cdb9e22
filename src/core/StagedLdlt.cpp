#include "StagedLdlt.h"

#include "TaskPool.h"

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
}

void StagedLdlt::assignUpper(const SparseMatrix& permuted)
{
    // Eigen's expression, with its identity permutation: the same entries in the same order as Eigen's factorisation
    // reads (see analyse).
    const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, StorageIndex> identity;
    m_upper.resize(permuted.rows(), permuted.cols());
    m_upper.selfadjointView<Eigen::Upper>() = permuted.selfadjointView<Eigen::Lower>().twistedBy(identity);
}

bool StagedLdlt::factorize(const SparseMatrix& permuted)
{
    assignUpper(permuted);
    m_generation = ++factorisations;
    std::atomic<bool> ok{true};
    for (const std::vector<OrderRange>& ranges : m_stages)
    {
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

bool StagedLdlt::factorRows(StorageIndex begin, StorageIndex end)
{
    // Eigen's factorize_preordered<true> over rows [begin, end), with this thread's scratch.
    thread_local RowWorkspace work;
    const std::size_t n = std::size_t(m_upper.rows());
    work.fit(n);
    Real* y = work.y.data();
    StorageIndex* pattern = work.pattern.data();
    long long* mark = work.mark.data();
    const StorageIndex* start = m_lower.outerIndexPtr();
    StorageIndex* rows = m_lower.innerIndexPtr();
    Real* values = m_lower.valuePtr();
    const long long base = m_generation * (long long)(n);
    for (StorageIndex k = begin; k < end; ++k)
    {
        // The pattern of row k of L, in topological order: every row the etree reaches from A's column k above k.
        const long long visit = base + k;
        y[k] = 0;
        StorageIndex top = StorageIndex(n);
        mark[k] = visit;
        m_columnCount[std::size_t(k)] = 0;
        for (SparseMatrix::InnerIterator it(m_upper, k); it; ++it)
        {
            StorageIndex i = StorageIndex(it.index());
            if (i <= k)
            {
                y[i] += it.value();
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
        // Row k's values: a sparse triangular solve with the rows above.
        Real d = y[k];
        y[k] = 0;
        for (; top < StorageIndex(n); ++top)
        {
            const StorageIndex i = pattern[top];
            const Real yi = y[i];
            y[i] = 0;
            const Real lki = yi / m_diagonal[i];
            const StorageIndex last = start[i] + m_columnCount[std::size_t(i)];
            StorageIndex p = start[i];
            for (; p < last; ++p)
            {
                y[rows[p]] -= values[p] * yi;
            }
            d -= lki * yi;
            rows[p] = k;
            values[p] = lki;
            ++m_columnCount[std::size_t(i)];
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
} // namespace masse
