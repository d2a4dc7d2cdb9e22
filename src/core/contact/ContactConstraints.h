#pragma once
/// The contact's part in the implicit solve: at a frame's start, stuck masses become held constraints and masses
/// resting on a surface become normal constraints with friction as a tangential damping (VelocityConstraint.h); after
/// each substep the solve's reactions become the contact's impulses. A mass rests if it touches the surface and is not
/// leaving it, and the surface pushed on it in the last solve (its reaction), or, for a new contact, its forces press
/// it in. When the solve's reaction would pull, it lets go. A mass near a surface it does not touch yet gets a
/// speculative constraint: if the solve finds the frame would carry it through, it arrives at the surface instead.

#include "core/MassSpringSystem.h"
#include "core/StepContext.h"
#include "core/contact/ContactPlanes.h"
#include "core/contact/ContactReport.h"
#include "core/contact/StuckContacts.h"

#include <cstdint>
#include <vector>

namespace masse
{
class ContactConstraints
{
public:
    /// Sizes the per-mass arrays for `masses`, if they are not that size already.
    void resize(std::size_t masses);
    /// Starts a frame: this frame's resting set is empty (the last frame's is kept to tell new contacts from held
    /// ones). With `constrain` (the integrator honours constraints), adds the stuck, the resting and the arriving
    /// masses to context.constraints, which the caller has cleared.
    void beginFrame(const Particles& p, const ContactPlanes& planes, const StuckContacts& stuck,
                    const ContactSettings& settings, Real dt, bool constrain, StepContext& context);
    /// After a substep of h: each resting mass's reaction and friction become its contact impulse in `report`, and
    /// it touches its surface at `time`.
    void afterSubstep(const Particles& p, const StepContext& context, const StuckContacts& stuck, Real h, Real time,
                      ContactReport& report);

    /// Whether any mass rests or arrives this frame (if not, resting() and arrived() are false for every mass).
    bool any() const { return !m_restingMasses.empty() || !m_arrivingMasses.empty(); }
    bool resting(std::size_t i) const { return m_resting[i] != 0; }
    /// Whether mass i, not touching its surface at the frame's start, arrived there in the last substep's solve
    /// (restingPlane(i) is that surface's plane).
    bool arrived(std::size_t i) const { return m_arrived[i] != 0; }
    /// N s, the impulse along the normal with which the solve stopped mass i at its surface (when arrived(i)).
    Real arrivalImpulse(std::size_t i) const { return m_arrivalImpulse[i]; }
    /// The index into the frame's planes of the surface mass i rests on (when resting(i)).
    std::size_t restingPlane(std::size_t i) const { return m_plane[i]; }

private:
    std::vector<std::uint8_t> m_resting;
    std::vector<std::uint8_t> m_wasResting;
    std::vector<Index> m_restingMasses;
    std::vector<std::uint8_t> m_arriving; ///< has a speculative constraint this frame
    std::vector<std::uint8_t> m_arrived;  ///< its speculative constraint held in the last solve
    /// N s, m_arrivalImpulse of the masses that arrived in the last frame (m_lastArrivedMasses), 0 for the others
    std::vector<Real> m_lastArrivalImpulse;
    std::vector<Index> m_arrivingMasses;
    std::vector<Index> m_lastArrivedMasses;
    std::vector<Real> m_arrivalImpulse;
    std::vector<Vec3> m_normal;
    std::vector<Vec3> m_velocity;
    std::vector<int> m_obstacle;
    std::vector<int> m_face;
    std::vector<std::size_t> m_constraint; ///< index into StepContext::constraints
    std::vector<std::size_t> m_plane;      ///< index into the frame's planes
    std::vector<Vec3> m_lastReaction;      ///< N s, from the previous solve
};
} // namespace masse
