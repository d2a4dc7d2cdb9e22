#pragma once
/// A fixed pool of worker threads that runs the chunks of an index range, and the binding that tells the kernels which
/// pool to run on.
///
/// Kernels split their range into chunks of a fixed size (a constant of the kernel, never derived from the thread
/// count), so a reduction summed chunk by chunk in chunk order gives the same bits at any thread count. The calling
/// thread works too; a call from inside a chunk, or while another thread is using the pool, runs inline. Workers sleep
/// on a futex (std::atomic::wait) between jobs: the machine is shared, and a spinning worker would steal a core.
/// After Box2D v3's and Jolt's job systems, kept to what MaSSE's kernels need: one parallel loop at a time.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace masse
{
class TaskPool
{
public:
    /// A pool for `threads` threads in all, the caller included (so threads - 1 workers; 1 means no workers). Throws
    /// InputError for field "threads" when the system cannot start that many (a memory or process limit).
    explicit TaskPool(int threads);
    ~TaskPool();
    TaskPool(const TaskPool&) = delete;
    TaskPool& operator=(const TaskPool&) = delete;

    int threadCount() const { return int(m_workers.size()) + 1; }

    /// Calls body(chunk) for every chunk in [0, chunkCount), spread over the threads, and returns when all are done.
    /// The first exception thrown by a chunk is rethrown here (the other chunks still run).
    template <class Body> void run(std::size_t chunkCount, const Body& body)
    {
        runErased(chunkCount, &body,
                  [](const void* context, std::size_t chunk) { (*static_cast<const Body*>(context))(chunk); });
    }

private:
    using ChunkFunction = void (*)(const void* context, std::size_t chunk);
    void runErased(std::size_t chunkCount, const void* context, ChunkFunction call);
    void workerLoop();
    /// Wakes every worker to stop, and joins them.
    void stopWorkers();
    /// Claims and runs chunks of job `job` until none is left or a newer job has started.
    void workOn(std::uint32_t job);

    std::vector<std::thread> m_workers;
    std::mutex m_runMutex; ///< one job at a time; a second caller runs its chunks inline
    /// The job number (high 32 bits) and its next unclaimed chunk (low 32 bits), in one word: a worker that wakes
    /// late, after its job ended, fails to claim anything and goes back to sleep, so nobody waits for a worker the
    /// scheduler has not run yet (on a loaded machine that wait cost milliseconds per loop).
    std::atomic<std::uint64_t> m_claim{0};
    std::atomic<std::uint32_t> m_jobNumber{0}; ///< what sleeping workers wait on
    std::atomic<std::size_t> m_done{0};        ///< chunks of the current job finished
    std::atomic<std::size_t> m_chunkCount{0};
    std::atomic<const void*> m_context{nullptr};
    std::atomic<ChunkFunction> m_call{nullptr};
    std::atomic<bool> m_stop{false};
    std::mutex m_errorMutex;
    std::exception_ptr m_error;
};

/// The thread counts a pool may have; a count outside throws InputError for field "threads".
inline constexpr int maxThreadCount = 1024;
void requireThreadCount(int threads);
/// The processor's core count (at least 1): what a program asks for when its user names no thread count.
int hardwareThreadCount();

/// Binds a pool to the calling thread for the scope's life: the kernels this thread calls meanwhile split their loops
/// over it. The engine holds no pool of its own: a Simulator binds the pool it owns or was given for the length of
/// each call that runs kernels, so two simulators, in one thread or in several, never share one unless a program
/// gives them the same. A binding rather than a parameter: it reaches the kernels several calls below the step
/// (forces, solvers, factorisations, the bridge's contact queries) without every signature on the way carrying it.
/// Scopes nest; the innermost wins, and leaving one restores the pool bound before it.
class PoolScope
{
public:
    explicit PoolScope(TaskPool& pool);
    ~PoolScope();
    PoolScope(const PoolScope&) = delete;
    PoolScope& operator=(const PoolScope&) = delete;

private:
    TaskPool* m_previous;
};

/// The pool bound to the calling thread, or nullptr: the kernels then run on the calling thread alone.
TaskPool* boundPool();

/// Calls body(chunk) for every chunk in [0, chunkCount): on the bound pool, or in order on this thread without one.
template <class Body> void runChunks(std::size_t chunkCount, const Body& body)
{
    if (TaskPool* pool = boundPool())
    {
        pool->run(chunkCount, body);
        return;
    }
    for (std::size_t chunk = 0; chunk < chunkCount; ++chunk)
    {
        body(chunk);
    }
}

/// Runs body(begin, end) over [0, count) in chunks of `chunkSize` (the last one shorter), in parallel on the bound
/// pool. Chunk k is [k * chunkSize, min(count, (k + 1) * chunkSize)), whatever the thread count.
template <class Body> void parallelFor(std::size_t count, std::size_t chunkSize, const Body& body)
{
    const std::size_t chunks = (count + chunkSize - 1) / chunkSize;
    if (chunks <= 1)
    {
        if (count > 0)
        {
            body(std::size_t(0), count);
        }
        return;
    }
    runChunks(chunks,
              [&](std::size_t chunk)
              {
                  const std::size_t begin = chunk * chunkSize;
                  body(begin, std::min(count, begin + chunkSize));
              });
}

/// Masses per chunk of the per-mass kernels (integrators, contact projection, checks): a few hundred KB of state,
/// enough work to pay for waking a thread, and many chunks for two threads to share evenly.
inline constexpr std::size_t massChunkSize = 4096;

/// Number of chunks parallelFor makes of `count` items (for per-chunk partial results of a reduction).
inline std::size_t chunkCount(std::size_t count, std::size_t chunkSize)
{
    return (count + chunkSize - 1) / chunkSize;
}
} // namespace masse
