#include "TaskPool.h"

#include "InputError.h"

#include <cstdlib>
#include <memory>
#include <string>
#include <utility>

namespace masse
{
namespace
{
/// True on a pool's worker threads, and on any thread while it runs a chunk: a nested loop then runs inline.
thread_local bool insideChunk = false;

std::unique_ptr<TaskPool>& sharedPoolSlot()
{
    static std::unique_ptr<TaskPool> pool;
    return pool;
}

/// Guards the creation and replacement of the shared pool (the viewer's threads may ask for it first).
std::mutex& sharedPoolMutex()
{
    static std::mutex mutex;
    return mutex;
}
} // namespace

TaskPool::TaskPool(int threads)
{
    for (int i = 1; i < threads; ++i)
    {
        m_workers.emplace_back([this] { workerLoop(); });
    }
}

TaskPool::~TaskPool()
{
    m_stop = true;
    m_generation.fetch_add(1, std::memory_order_release);
    m_generation.notify_all();
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
        m_generation.wait(seen, std::memory_order_acquire);
        seen = m_generation.load(std::memory_order_acquire);
        if (m_stop)
        {
            return;
        }
        workOnJob();
        if (m_active.fetch_sub(1, std::memory_order_acq_rel) == 1)
        {
            m_active.notify_one();
        }
    }
}

void TaskPool::workOnJob()
{
    for (;;)
    {
        const std::size_t chunk = m_nextChunk.fetch_add(1, std::memory_order_relaxed);
        if (chunk >= m_chunkCount)
        {
            return;
        }
        try
        {
            m_call(m_context, chunk);
        }
        catch (...)
        {
            const std::lock_guard lock(m_errorMutex);
            if (!m_error)
            {
                m_error = std::current_exception();
            }
        }
    }
}

void TaskPool::runErased(std::size_t chunkCount, const void* context, ChunkFunction call)
{
    std::unique_lock lock(m_runMutex, std::try_to_lock);
    if (insideChunk || m_workers.empty() || !lock.owns_lock() || chunkCount <= 1)
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
    m_chunkCount = chunkCount;
    m_context = context;
    m_call = call;
    m_error = nullptr;
    m_nextChunk.store(0, std::memory_order_relaxed);
    m_active.store(int(m_workers.size()), std::memory_order_relaxed);
    m_generation.fetch_add(1, std::memory_order_release); // publishes the job to the workers
    m_generation.notify_all();
    insideChunk = true;
    workOnJob();
    insideChunk = false;
    // Every worker leaves the job before the next one may start, so none can miss a generation.
    for (int active = m_active.load(std::memory_order_acquire); active != 0;
         active = m_active.load(std::memory_order_acquire))
    {
        m_active.wait(active, std::memory_order_acquire);
    }
    if (m_error)
    {
        std::rethrow_exception(std::exchange(m_error, nullptr));
    }
}

int defaultThreadCount()
{
    if (const char* text = std::getenv("MASSE_THREADS"))
    {
        char* end = nullptr;
        const long threads = std::strtol(text, &end, 10);
        if (end == text || *end != '\0' || threads < 1 || threads > 1024)
        {
            throw InputError(std::string("MASSE_THREADS: must be a whole number of threads from 1 to 1024 (got \"") +
                             text + "\")");
        }
        return int(threads);
    }
    const unsigned cores = std::thread::hardware_concurrency();
    return cores > 0 ? int(cores) : 1;
}

TaskPool& sharedPool()
{
    const std::lock_guard lock(sharedPoolMutex());
    std::unique_ptr<TaskPool>& pool = sharedPoolSlot();
    if (!pool)
    {
        pool = std::make_unique<TaskPool>(defaultThreadCount());
    }
    return *pool;
}

int threadCount()
{
    return sharedPool().threadCount();
}

void setThreadCount(int threads)
{
    if (threads < 1 || threads > 1024)
    {
        throw InputError("--threads: must be a whole number of threads from 1 to 1024 (got " +
                         std::to_string(threads) + ")");
    }
    const std::lock_guard lock(sharedPoolMutex());
    std::unique_ptr<TaskPool>& pool = sharedPoolSlot();
    if (!pool || pool->threadCount() != threads)
    {
        pool.reset();
        pool = std::make_unique<TaskPool>(threads);
    }
}
} // namespace masse
