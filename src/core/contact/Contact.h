#pragma once
/// Contact between sheet masses (spheres of one radius) and obstacles: the settings, the planes a detector finds,
/// and the detector interface that the Bullet bridge implements. The core knows obstacles only by index.

#include "core/NamedEnum.h"
#include "core/Types.h"
#include "core/parallel/PerChunk.h"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace masse
{
/// What happens to a mass that touches an obstacle.
enum class ContactResponse
{
    Sticky,       ///< the paper's: it stays where it touched until pulled off the surface by more than a set force
    Friction,     ///< Coulomb friction with coefficient mu
    Frictionless, ///< only the approach is stopped
};

/// The registry of responses, one entry each in the order menus and messages list them: the scene reader's choices,
/// the viewer's menu and data/scenes/README.md's `contact` table (SceneReference) follow it.
inline constexpr EnumName<ContactResponse> contactResponseTable[] = {
    {ContactResponse::Sticky, "sticky"},
    {ContactResponse::Friction, "friction"},
    {ContactResponse::Frictionless, "frictionless"},
};

/// Parses a registered name (any case); throws InputError naming the allowed names.
ContactResponse parseContactResponse(std::string_view name);
std::string_view contactResponseName(ContactResponse response);
/// The registered names, for the scene reader's choices.
std::vector<std::string> contactResponseNames();

/// An obstacle's own contact response, instead of the scene's (a plug that slides over the sheet while the mould
/// grips it).
struct ObstacleContact
{
    bool own = false; ///< false: the obstacle uses ContactSettings::response and friction
    ContactResponse response = ContactResponse::Friction;
    Real friction = 0.3;
};

struct ContactSettings
{
    ContactResponse response = ContactResponse::Friction;
    Real radius = 0.01;           ///< m, every mass is a sphere of this radius
    Real friction = 0.3;          ///< Coulomb coefficient mu (Friction)
    Real stickReleaseForce = 0.0; ///< N, pull away from the surface that frees a stuck mass (Sticky); 0 never frees
    /// m/s. Below this slip the implicit integrator's friction turns viscous (regularised Coulomb), so a mass under
    /// static friction creeps at less than this fraction of it: (push / (mu press)) times this speed.
    Real slipRegularization = 1e-4;
    /// m. The most a mass's force is taken to carry it in one frame when the contact search reaches ahead of it (its
    /// velocity's travel is added in full); 0: no cap. Set to the motion limit of an implicit integrator, which splits
    /// a frame that would carry a mass further. A mass that outruns its search is swept at the end of the frame.
    Real drivenReach = 0;
    /// Per obstacle (the detector's index): a response of its own, where `own` is set; obstacles past the end use
    /// the response above.
    std::vector<ObstacleContact> perObstacle;

    ContactResponse responseOf(int obstacle) const
    {
        return obstacle >= 0 && std::size_t(obstacle) < perObstacle.size() && perObstacle[std::size_t(obstacle)].own
                   ? perObstacle[std::size_t(obstacle)].response
                   : response;
    }
    Real frictionOf(int obstacle) const
    {
        return obstacle >= 0 && std::size_t(obstacle) < perObstacle.size() && perObstacle[std::size_t(obstacle)].own
                   ? perObstacle[std::size_t(obstacle)].friction
                   : friction;
    }
};

/// Throws InputError naming the first bad value (non-positive radius, negative friction or release force).
void validate(const ContactSettings& settings);

/// An obstacle's surface near one mass, found at the start of a frame: the supporting plane through the closest
/// surface point. A convex obstacle lies wholly behind it, so keeping the mass's sphere in front keeps it outside.
struct ContactPlane
{
    Index mass = 0;
    int obstacle = -1;
    int face = -1;                ///< index among the obstacle's own faces, -1 if unknown
    Vec3 normal = Vec3::UnitY();  ///< unit, from the obstacle toward the mass
    Real offset = 0;              ///< normal . x of the surface point, at the start of the frame
    Vec3 velocity = Vec3::Zero(); ///< m/s, the surface's own velocity (kinematic obstacles)

    /// m, how far a sphere of `radius` at `x` is in front of the surface as it was at the frame's start (negative:
    /// through it).
    Real separation(const Vec3& x, Real radius) const { return normal.dot(x) - offset - radius; }
};

/// The first crossing of an obstacle's surface by a sphere moving along a segment.
struct SweepHit
{
    Real fraction = 1; ///< along the segment, 0 at its start
    Vec3 normal = Vec3::UnitY();
    int obstacle = -1;
    int face = -1;
};

/// Signed distance from a point to the nearest obstacle surface (negative inside a solid obstacle).
struct SurfaceDistance
{
    Real distance = 0;
    int obstacle = -1;
    int face = -1;
};

/// A detector's planes, in lists per chunk of masses (ContactDetector::findContacts).
using ContactPlaneLists = PerChunk<std::vector<ContactPlane>>;

/// Finds obstacles near masses. Implemented by the Bullet bridge (broadphase plus narrowphase); tests may implement
/// it with analytic shapes.
class ContactDetector
{
public:
    virtual ~ContactDetector() = default;
    virtual int obstacleCount() const = 0;
    /// Places moving (kinematic) obstacles where they are at `time`.
    virtual void setTime(Real time) = 0;
    /// Fills `out`, replacing what it held, with a plane for every pair of a mass i and an obstacle whose surfaces may
    /// meet during the next `dt` seconds: the mass's sphere of `radius` may move anywhere within reach[i] of x[i], the
    /// obstacle along its own path. The planes come in lists (one per chunk of masses a thread searched, or a single
    /// one): `out` is resized to the lists used and each is replaced. Joined in order, the lists give a mass's planes
    /// together. (Lists kept from frame to frame keep their capacity, and are joined once, by ContactPlanes::index,
    /// into the arrays the projection reads: joining them here too would copy every plane once more a frame.)
    virtual void findContacts(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, Real dt,
                              ContactPlaneLists& out) = 0;
    /// The first surface a sphere of `radius` meets moving from `from` to `to`, if any.
    virtual std::optional<SweepHit> sweep(const Vec3& from, const Vec3& to, Real radius) = 0;
    /// Distance from x to the nearest obstacle surface, searching no farther than maxDistance (returns a distance of
    /// at least maxDistance and obstacle -1 when nothing is that close).
    virtual SurfaceDistance nearestSurface(const Vec3& x, Real maxDistance) = 0;
    /// Mean velocity over the next `dt` seconds of the obstacle's point now at `point` (zero for a static obstacle):
    /// a mass stuck to a moving surface follows it with this.
    virtual Vec3 pointVelocity(int obstacle, const Vec3& point, Real dt) = 0;
};
} // namespace masse
