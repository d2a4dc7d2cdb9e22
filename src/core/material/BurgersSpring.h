#pragma once
/// One Burgers spring (the paper's "advanced damping model", section 10): a Maxwell element (spring k_M in series
/// with dashpot c_M) in series with a Kelvin-Voigt element (spring k_K beside dashpot c_K), as a stateless kernel.
///
/// State: tension F, extension u (length minus the original rest length) and the Kelvin element's extension u_K;
/// the dashpot's extension, the permanent set, is u_D = u - u_K - F/k_M. Over a step dt with constant coefficients,
/// the trapezoidal rule (Itasca PFC's Burgers contact model; physics.md section 2) gives the new force as a linear
/// function of the new extension u':
///     F' = (u' - u + Y F + Z u_K) / X,        u_K' = P u_K + Q (F + F')
///     X = 1/k_M + b dt/c_M + Q,  Y = 1/k_M - a dt/c_M - Q,  Z = 1 - P
/// where the dashpot moves by dt (a F + b F') / c_M and, for the Kelvin element, A = 1 + k_K dt/(2 c_K),
/// B = 1 - k_K dt/(2 c_K):
///     Kelvin, trapezoidal  (B >= 0):           P = B/A,                Q = dt / (2 A c_K)
///     Kelvin, exponential  (B <  0):           P = exp(-k_K dt / c_K), Q = (1 - P) / (2 k_K)
///     Maxwell, trapezoidal (dt <= 2 c_M/k_M):  a = b = 1/2
///     Maxwell, exponential (dt >  2 c_M/k_M):  with x = k_M dt / c_M, e = exp(-x), phi = (1 - e)/x:
///                                              b = (1 - phi)/(1 - e), a = phi - b e
/// The exponential forms are used where the trapezoidal ones would flip sign from step to step: B/A < 0 makes u_K
/// oscillate, and a step longer than twice the Maxwell time makes the force of a relaxing spring alternate in sign
/// (the trapezoidal factor (1 - x/2)/(1 + x/2) tends to -1), which a hot, runny sheet at the frame's 0.03 s would
/// feel as a flickering tension. Both exponential forms are the exact solutions over a step of constant force (for
/// the Kelvin element, u_K' = F_mean/k_K + (u_K - F_mean/k_K) exp(-k_K dt/c_K) with F_mean = (F + F')/2) or, for
/// the Maxwell element, of constant stretching rate; so creep under a constant force and relaxation of a Maxwell
/// spring are exact at any dt. All forms agree to second order in dt.
///
/// Because F' is linear in u' with slope 1/X, over the next step the spring is an ordinary elastic spring of
/// stiffness k_eff = 1/X and rest length L0 + u_0 with u_0 = u - Y F - Z u_K (the extension at which F' = 0): the
/// force kernel and the implicit integrator's Jacobian take it unchanged.
///
/// Limits: c_M = infinity removes the flow (no permanent set), k_K = infinity removes the Kelvin element (a Maxwell
/// spring), both together leave a linear spring k_M. dt = 0 gives the instantaneous (elastic) response 1/k_M.

#include "core/Types.h"

#include <cmath>
#include <limits>

namespace masse
{
struct BurgersParams
{
    Real maxwellStiffness = 0; ///< k_M, N/m, > 0
    Real maxwellDamping = 0;   ///< c_M, N s/m, > 0 (infinity: no flow)
    Real kelvinStiffness = 0;  ///< k_K, N/m, > 0 (infinity: no Kelvin element)
    Real kelvinDamping = 0;    ///< c_K, N s/m, > 0
};

struct BurgersState
{
    Real force = 0;           ///< F, N, tension positive
    Real extension = 0;       ///< u, m, length minus the original rest length
    Real kelvinExtension = 0; ///< u_K, m
};

/// Coefficients of one step (see the header comment).
struct BurgersStep
{
    Real compliance = 0; ///< X, m/N
    Real carry = 0;      ///< Y, m/N
    Real kelvinPull = 0; ///< Z = 1 - P
    Real kelvinKeep = 1; ///< P
    Real kelvinGain = 0; ///< Q, m/N
};

inline BurgersStep burgersStep(const BurgersParams& p, Real dt)
{
    BurgersStep c;
    constexpr Real infinity = std::numeric_limits<Real>::infinity();
    if (dt > 0 && p.kelvinStiffness < infinity)
    {
        const Real half = p.kelvinStiffness * dt / (Real(2) * p.kelvinDamping); // k_K dt / (2 c_K)
        if (half <= Real(1))
        {
            const Real a = Real(1) + half;
            c.kelvinKeep = (Real(1) - half) / a;
            c.kelvinGain = dt / (Real(2) * a * p.kelvinDamping);
        }
        else
        {
            c.kelvinKeep = std::exp(Real(-2) * half);
            c.kelvinGain = -std::expm1(Real(-2) * half) / (Real(2) * p.kelvinStiffness);
        }
    }
    else if (dt > 0)
    {
        c.kelvinKeep = 0; // a rigid Kelvin element: u_K stays 0
    }
    const Real elastic = Real(1) / p.maxwellStiffness;
    Real flowOld = 0; // a dt / c_M
    Real flowNew = 0; // b dt / c_M
    if (dt > 0)
    {
        const Real x = p.maxwellStiffness * dt / p.maxwellDamping;
        const Real flow = dt / p.maxwellDamping;
        if (x <= Real(2))
        {
            flowOld = Real(0.5) * flow;
            flowNew = Real(0.5) * flow;
        }
        else
        {
            const Real e = std::exp(-x);
            const Real phi = -std::expm1(-x) / x;
            const Real b = (Real(1) - phi) / (-std::expm1(-x));
            flowNew = b * flow;
            flowOld = (phi - b * e) * flow;
        }
    }
    c.compliance = elastic + flowNew + c.kelvinGain;
    c.carry = elastic - flowOld - c.kelvinGain;
    c.kelvinPull = Real(1) - c.kelvinKeep;
    return c;
}

/// Extension at which the next step's force is zero: the effective rest length is the original one plus this.
inline Real burgersFreeExtension(const BurgersStep& c, const BurgersState& s)
{
    return s.extension - c.carry * s.force - c.kelvinPull * s.kelvinExtension;
}

/// Strain driven: the force at the end of the step for the extension u' reached there.
inline Real burgersForce(const BurgersStep& c, const BurgersState& s, Real newExtension)
{
    return (newExtension - burgersFreeExtension(c, s)) / c.compliance;
}

/// Stress driven: the extension at the end of the step for the force F' there.
inline Real burgersExtension(const BurgersStep& c, const BurgersState& s, Real newForce)
{
    return burgersFreeExtension(c, s) + c.compliance * newForce;
}

/// Moves the state to the end of the step, given its force and extension there (related by burgersForce).
inline void burgersAdvance(const BurgersStep& c, BurgersState& s, Real newForce, Real newExtension)
{
    s.kelvinExtension = c.kelvinKeep * s.kelvinExtension + c.kelvinGain * (s.force + newForce);
    s.force = newForce;
    s.extension = newExtension;
}

/// The dashpot's extension u_D = u - u_K - F/k_M: the part of the extension that stays when the force is removed.
inline Real burgersPermanentSet(const BurgersParams& p, const BurgersState& s)
{
    return s.extension - s.kelvinExtension - s.force / p.maxwellStiffness;
}
} // namespace masse
