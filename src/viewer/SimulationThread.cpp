#include "SimulationThread.h"

#include <chrono>

namespace masse::viewer
{
SimulationThread::SimulationThread(ViewerSession& session, const MassScalarRegistry& scalars, bool realTime,
                                   Real computeBudget)
    : m_session(session), m_scalars(scalars), m_realTime(realTime), m_computeBudget(computeBudget)
{
}

SimulationThread::~SimulationThread()
{
    stop();
}

std::uint64_t SimulationThread::post(SessionCommand command)
{
    std::lock_guard lock(m_mutex);
    m_commands.push_back(std::move(command));
    const std::uint64_t ticket = ++m_posted;
    m_wake.notify_one();
    return ticket;
}

std::uint64_t SimulationThread::postSteps(int steps)
{
    // Runs on the simulation thread, which alone touches the totals.
    return post(
        [this, steps](ViewerSession& session)
        {
            const Advance advance = session.advanceSteps(steps);
            m_steps += std::uint64_t(advance.steps);
            m_stepSeconds += advance.stepSeconds;
        });
}

void SimulationThread::waitFor(std::uint64_t ticket)
{
    std::unique_lock lock(m_mutex);
    m_published.wait(lock, [&] { return m_front && m_front->appliedTicket >= ticket; });
}

void SimulationThread::setScalar(const std::string& name)
{
    std::lock_guard lock(m_mutex);
    if (name != m_scalar)
    {
        // Paused, no step would publish the new scalar's values and the sheet would stay grey ("waiting for
        // values"): the thread is woken to publish them now.
        m_scalar = name;
        m_scalarChanged = true;
        m_wake.notify_one();
    }
}

std::shared_ptr<const SceneSnapshot> SimulationThread::latest() const
{
    std::lock_guard lock(m_mutex);
    return m_front;
}

void SimulationThread::start()
{
    publish();
    m_thread = std::thread([this] { run(); });
}

void SimulationThread::stop()
{
    {
        std::lock_guard lock(m_mutex);
        m_stop = true;
        m_wake.notify_one();
    }
    if (m_thread.joinable())
    {
        m_thread.join();
    }
}

void SimulationThread::publish()
{
    std::string scalar;
    std::uint64_t applied = 0;
    {
        std::lock_guard lock(m_mutex);
        scalar = m_scalar;
        applied = m_applied;
        // The back buffer is free unless the window still holds it (it took it as the front before the last swap).
        if (!m_back || m_back.use_count() > 1)
        {
            m_back = std::make_shared<SceneSnapshot>();
        }
    }
    captureSnapshot(m_session, m_scalars, scalar, m_front.get(), *m_back);
    m_back->appliedTicket = applied;
    m_back->sequence = ++m_sequence;
    m_back->steps = m_steps;
    m_back->stepSeconds = m_stepSeconds;
    m_back->behind = m_behind;
    {
        std::lock_guard lock(m_mutex);
        std::swap(m_front, m_back);
    }
    m_published.notify_all();
}

void SimulationThread::run()
{
    using Clock = std::chrono::steady_clock;
    Clock::time_point last = Clock::now();
    for (;;)
    {
        std::vector<SessionCommand> commands;
        std::uint64_t ticket = 0;
        bool scalarChanged = false;
        {
            std::unique_lock lock(m_mutex);
            // Paused or following commands only, nothing is due until a command comes; running, the next step is
            // due within a few milliseconds (the scheduler takes as many as the clock owes).
            const bool idle = !m_realTime || m_session.paused();
            m_wake.wait_for(lock, std::chrono::milliseconds(idle ? 50 : 2),
                            [&] { return m_stop || !m_commands.empty() || m_scalarChanged; });
            if (m_stop)
            {
                return;
            }
            commands.swap(m_commands);
            ticket = m_posted;
            scalarChanged = m_scalarChanged;
            m_scalarChanged = false;
        }
        for (SessionCommand& command : commands)
        {
            command(m_session);
        }
        if (!commands.empty() || scalarChanged)
        {
            // What the commands did (a pick taken, a scene loaded) is published before the next step, not after it:
            // on a large sheet a step takes a good part of a second.
            {
                std::lock_guard lock(m_mutex);
                m_applied = ticket;
            }
            publish();
        }
        const Clock::time_point now = Clock::now();
        const Real wall = std::chrono::duration<Real>(now - last).count();
        last = now;
        Advance advance;
        if (m_realTime)
        {
            advance = m_session.advance(wall, m_computeBudget);
        }
        else
        {
            // Single-step requests still come through (the panel's Step button).
            advance = m_session.advanceSteps(0);
        }
        m_steps += std::uint64_t(advance.steps);
        m_stepSeconds += advance.stepSeconds;
        m_behind = advance.behind;
        if (advance.steps > 0)
        {
            publish();
        }
    }
}
} // namespace masse::viewer
