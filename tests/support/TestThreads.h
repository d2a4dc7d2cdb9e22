#pragma once
// Thread counts for tests. The engine has no pool of its own: a test that runs a scene sets its spec's
// engine.threads, and a test that calls kernels directly binds a pool with BoundPool (without one they run on the
// test's thread alone).

#include "scene/EngineEnvironment.h"

#include "core/parallel/TaskPool.h"

namespace masse::test
{
/// The kernel threads of a test that names none: $MASSE_THREADS, else every core, as for the `masse` command.
/// `MASSE_THREADS=1 ctest -j2` then runs each such test on one thread, so tests run side by side do not fight for
/// the cores.
inline int testThreadCount()
{
    return scene::threadsFromEnvironment();
}

/// A pool of `threads` threads bound to the calling thread for the object's life: the kernels the test calls
/// meanwhile run on it.
class BoundPool
{
public:
    explicit BoundPool(int threads = testThreadCount()) : m_pool(threads), m_scope(m_pool) {}
    TaskPool& pool() { return m_pool; }

private:
    TaskPool m_pool;
    PoolScope m_scope;
};
} // namespace masse::test
