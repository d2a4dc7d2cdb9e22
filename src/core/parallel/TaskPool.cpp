#include "core/parallel/TaskPool.h"

#include "core/InputError.h"

#include <string>
#include <system_error>
#include <utility>

namespace masse
{
namespace
{
/// True on a pool's worker threads, and on any thread while it runs a chunk: a nested loop then runs inline.
thread_local bool insideChunk = false;

/// The pool a PoolScope bound to this thread, if any.
thread_local TaskPool* poolOfThisThread = nullptr;

/// Polls of a word before sleeping on it. A step's loops come microseconds apart (four or five per substep), while a
/// futex sleep and wake-up on a virtual machine costs tens of microseconds and a system call on both sides: a worker
/// that polls this long (about 20-60 us) after a job catches the next one awake. Bounded, so an idle pool sleeps and
/// steals no core from a shared machine.
constexpr int pollsBeforeSleep = 4000;

inline void cpuRelax()
{
#if defined(__x86_64__) && defined(__GNUC__)
    __builtin_ia32_pause(); // the core includes only Eigen and the standard library
#endif
}

/// Polls `word` until it differs from `seen` (true) or the polls run out (false).
template <class T> bool pollWhileEqual(const std::atomic<T>& word, T seen)
{
    for (int poll = 0; poll < pollsBeforeSleep; ++poll)
    {
        if (word.load(std::memory_order_acquire) != seen)
        {
            return true;
        }
        cpuRelax();
    }
    return false;
}

} // namespace

TaskPool::TaskPool(int threads)
{
    requireThreadCount(threads);
    m_workers.reserve(std::size_t(std::max(threads - 1, 0))); // only starting a thread can fail below
    try
    {
        for (int i = 1; i < threads; ++i)
        {
            m_workers.emplace_back([this] { workerLoop(); });
        }
    }
    catch (const std::system_error& e)
    {
        // The workers already started are stopped and joined here: destroyed still running (the constructor does not
        // finish, so the destructor does not run), they would end the program in std::terminate.
        const std::size_t started = m_workers.size() + 1;
        stopWorkers();
        throw InputError("threads", "the system cannot start " + std::to_string(threads) + " threads (it stopped at " +
                                        std::to_string(started) + ": " + e.what() +
                                        "; a memory or process limit?): ask for fewer");
    }
}

TaskPool::~TaskPool()
{
    stopWorkers();
}

void TaskPool::stopWorkers()
{
    m_stop.store(true, std::memory_order_release);
    m_jobNumber.fetch_add(1, std::memory_order_release);
    m_jobNumber.notify_all();
    for (std::thread& worker : m_workers)
    {
        worker.join();
    }
}

void TaskPool::workerLoop()
{
    insideChunk = true;
    std::uint32_t seen = 0;
    for (;;)
    {
        if (!pollWhileEqual(m_jobNumber, seen))
        {
            m_jobNumber.wait(seen, std::memory_order_acquire);
        }
        seen = m_jobNumber.load(std::memory_order_acquire);
        if (m_stop.load(std::memory_order_acquire))
        {
            return;
        }
        workOn(seen);
    }
}

void TaskPool::workOn(std::uint32_t job)
{
    std::uint64_t claim = m_claim.load(std::memory_order_acquire);
    for (;;)
    {
        if (std::uint32_t(claim >> 32) != job)
        {
            return; // a late wake-up: that job is over
        }
        const std::size_t chunk = std::size_t(claim & 0xffffffffu);
        if (chunk >= m_chunkCount.load(std::memory_order_seq_cst))
        {
            return;
        }
        if (!m_claim.compare_exchange_weak(claim, claim + 1, std::memory_order_seq_cst, std::memory_order_acquire))
        {
            continue;
        }
        // The claimed chunk keeps the job open (the caller waits for it), so its fields stay valid while it runs.
        const std::size_t count = m_chunkCount.load(std::memory_order_relaxed);
        try
        {
            m_call.load(std::memory_order_relaxed)(m_context.load(std::memory_order_relaxed), chunk);
        }
        catch (...)
        {
            const std::lock_guard lock(m_errorMutex);
            if (!m_error)
            {
                m_error = std::current_exception();
            }
        }
        if (m_done.fetch_add(1, std::memory_order_acq_rel) + 1 == count)
        {
            m_done.notify_one();
        }
        claim = m_claim.load(std::memory_order_acquire);
    }
}

void TaskPool::runErased(std::size_t chunkCount, const void* context, ChunkFunction call)
{
    std::unique_lock lock(m_runMutex, std::try_to_lock);
    if (insideChunk || m_workers.empty() || !lock.owns_lock() || chunkCount <= 1 || chunkCount >= 0xffffffffu)
    {
        const bool wasInside = insideChunk;
        insideChunk = true;
        try
        {
            for (std::size_t chunk = 0; chunk < chunkCount; ++chunk)
            {
                call(context, chunk);
            }
        }
        catch (...)
        {
            insideChunk = wasInside;
            throw;
        }
        insideChunk = wasInside;
        return;
    }
    const std::uint32_t job = m_jobNumber.load(std::memory_order_relaxed) + 1;
    // Close the last job before its fields change: a worker still leaving it may hold an old claim value and, reading
    // the new (larger) chunk count, would otherwise win its compare-exchange and run and count a chunk that belongs
    // to no job (m_done then overshot and the caller waited for ever). Sequentially consistent, so a worker that sees
    // the new count also sees the claim closed.
    m_claim.store((std::uint64_t(job) << 32) | 0xffffffffu, std::memory_order_seq_cst);
    m_chunkCount.store(chunkCount, std::memory_order_seq_cst);
    m_context.store(context, std::memory_order_relaxed);
    m_call.store(call, std::memory_order_relaxed);
    m_done.store(0, std::memory_order_relaxed);
    m_error = nullptr;
    m_claim.store(std::uint64_t(job) << 32, std::memory_order_release); // opens the job
    m_jobNumber.store(job, std::memory_order_release);
    m_jobNumber.notify_all();
    insideChunk = true;
    workOn(job);
    insideChunk = false;
    // Wait only for chunks that were claimed and are still running; unclaimed ones do not exist any more.
    for (std::size_t done = m_done.load(std::memory_order_acquire); done != chunkCount;
         done = m_done.load(std::memory_order_acquire))
    {
        if (!pollWhileEqual(m_done, done))
        {
            m_done.wait(done, std::memory_order_acquire);
        }
    }
    if (m_error)
    {
        std::rethrow_exception(std::exchange(m_error, nullptr));
    }
}

void requireThreadCount(int threads)
{
    if (threads < 1 || threads > maxThreadCount)
    {
        throw InputError("threads", "must be a whole number of threads from 1 to " + std::to_string(maxThreadCount) +
                                        " (got " + std::to_string(threads) + ")");
    }
}

int hardwareThreadCount()
{
    const unsigned cores = std::thread::hardware_concurrency();
    return cores > 0 ? int(std::min(cores, unsigned(maxThreadCount))) : 1;
}

PoolScope::PoolScope(TaskPool& pool) : m_previous(std::exchange(poolOfThisThread, &pool)) {}

PoolScope::~PoolScope()
{
    poolOfThisThread = m_previous;
}

TaskPool* boundPool()
{
    return poolOfThisThread;
}
} // namespace masse
