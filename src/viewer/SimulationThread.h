#pragma once
/// The viewer's simulation on its own thread: it runs the session in real time (or only on request, for captures),
/// carries out the window's commands (picks, edits, loads, resets) between steps, and publishes a snapshot of the
/// scene after each batch. The window takes the latest snapshot whenever it draws and never waits for a step.
///
/// Snapshots are double buffered: the thread fills the one the window is not holding and swaps it in under a short
/// lock; when the window still holds both (a slow frame), a third is made rather than waiting.

#include "SceneSnapshot.h"
#include "ViewerSession.h"

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace masse::viewer
{
using SessionCommand = std::function<void(ViewerSession&)>;

class SimulationThread
{
public:
    /// realTime: follow the clock; false: step only on command (advanceSteps, deterministic captures).
    /// computeBudget: s of stepping per batch at most, between which commands are carried out.
    SimulationThread(ViewerSession& session, const MassScalarRegistry& scalars, bool realTime, Real computeBudget);
    ~SimulationThread();
    SimulationThread(const SimulationThread&) = delete;
    SimulationThread& operator=(const SimulationThread&) = delete;

    /// Queues a command for the simulation thread; returns its ticket (see SceneSnapshot::appliedTicket).
    std::uint64_t post(SessionCommand command);
    /// Queues exactly `steps` steps (none while paused; captures); returns the ticket.
    std::uint64_t postSteps(int steps);
    /// Blocks until the commands up to `ticket` are carried out and published (captures only: the window otherwise
    /// never waits).
    void waitFor(std::uint64_t ticket);
    /// The scalar the snapshots carry values of ("" for none).
    void setScalar(const std::string& name);

    std::shared_ptr<const SceneSnapshot> latest() const;
    /// Starts the thread (the first snapshot is published before it runs, so latest() is never empty).
    void start();
    /// Stops and joins the thread; the session is the caller's again afterwards.
    void stop();

private:
    void run();
    void publish();

    ViewerSession& m_session;
    const MassScalarRegistry& m_scalars;
    bool m_realTime;
    Real m_computeBudget;

    mutable std::mutex m_mutex;          ///< guards everything below, held only briefly (never over a step)
    std::condition_variable m_wake;      ///< the simulation thread: a command came, or stop
    std::condition_variable m_published; ///< waitFor
    std::vector<SessionCommand> m_commands;
    std::uint64_t m_posted = 0;
    std::uint64_t m_applied = 0;
    std::string m_scalar;
    bool m_scalarChanged = false; ///< a new scalar was asked for: published at once, also while paused
    bool m_stop = false;
    std::shared_ptr<SceneSnapshot> m_front; ///< the latest, handed to the window
    std::shared_ptr<SceneSnapshot> m_back;  ///< filled by the simulation thread

    std::uint64_t m_sequence = 0; ///< publications so far
    std::uint64_t m_steps = 0;
    Real m_stepSeconds = 0;
    bool m_behind = false;
    std::thread m_thread;
};
} // namespace masse::viewer
