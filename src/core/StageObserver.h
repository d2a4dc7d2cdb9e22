#pragma once
/// The step's stage boundaries, for a profiler outside the core: the engine reads no clock itself (`masse bench`
/// times the contact stages through this; a program embedding the engine can attach its own profiler the same way).

namespace masse
{
enum class Stage
{
    ContactDetection,  ///< finding every mass's planes with the detector, once per frame
    ContactProjection, ///< applying the planes after every substep
    ContactSweep,      ///< the end-of-frame sweep and reports
    SelfContactPairs,  ///< the sheet's self-contact broadphase: each frame's start and when a mass outruns its skin
    SelfContactSolve,  ///< the sheet's self-contact narrowphase and response after every substep
    EdgeContactPairs,  ///< listing the sheet's edges and triangles near obstacle edges and corners
    EdgeContactSolve,  ///< their narrowphase and response after every substep
};

inline constexpr int stageCount = 7;

class StageObserver
{
public:
    virtual ~StageObserver() = default;
    virtual void begin(Stage stage) = 0;
    virtual void end(Stage stage) = 0;
};

/// Tells an observer (if any) that a stage runs for the lifetime of this object.
class StageScope
{
public:
    StageScope(StageObserver* observer, Stage stage) : m_observer(observer), m_stage(stage)
    {
        if (m_observer)
        {
            m_observer->begin(m_stage);
        }
    }
    ~StageScope()
    {
        if (m_observer)
        {
            m_observer->end(m_stage);
        }
    }
    StageScope(const StageScope&) = delete;
    StageScope& operator=(const StageScope&) = delete;

private:
    StageObserver* m_observer;
    Stage m_stage;
};
} // namespace masse
