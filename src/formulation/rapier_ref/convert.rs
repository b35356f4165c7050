//! The one boundary between rapier's math types (glam `DVec2`, `DRot2`,
//! `DPose2` via glamx) and the project's types ([`Vec2`] =
//! `nalgebra::Vector2<f64>`, angles as `f64` radians, [`BodyState`]).
//!
//! Nothing else in the crate names a glam type: the rapier formulation reads
//! and writes bodies, builds colliders and applies forces through these
//! functions only.

use crate::geometry::Vec2;
use crate::state::BodyState;
use rapier2d_f64::math::{Pose, Rot2, Vector as RVec};
use rapier2d_f64::prelude::{
    Collider, ColliderBuilder, ContactManifold, MassProperties, RigidBody, RigidBodyBuilder,
    SharedShape,
};

/// A project vector as a rapier vector.
#[inline]
fn to_rapier(v: &Vec2) -> RVec {
    RVec::new(v.x, v.y)
}

/// A rapier vector as a project vector.
#[inline]
fn from_rapier(v: RVec) -> Vec2 {
    Vec2::new(v.x, v.y)
}

/// Position, rotation angle in (−π, π], velocity and angular velocity of a
/// rapier body, in the project's types: `(G m, angle rad, Ġ m/s, θ̇ rad/s)`.
/// The body frame's origin is the centre of mass (colliders are built about it).
pub(super) fn read_body(rb: &RigidBody) -> (Vec2, f64, Vec2, f64) {
    (
        from_rapier(rb.translation()),
        rb.rotation().angle(),
        from_rapier(rb.linvel()),
        rb.angvel(),
    )
}

/// Writes a project state into a rapier body (pose and velocities), waking it.
pub(super) fn write_body(rb: &mut RigidBody, b: &BodyState) {
    rb.set_translation(to_rapier(&b.position), true);
    rb.set_rotation(Rot2::new(b.angle), true);
    rb.set_linvel(to_rapier(&b.velocity), true);
    rb.set_angvel(b.angular_velocity, true);
}

/// Replaces the user force (N) and torque (N·m) of a body: rapier keeps
/// forces until they are reset, so the previous step's are cleared first.
pub(super) fn set_wrench(rb: &mut RigidBody, force: &Vec2, torque: f64) {
    rb.reset_forces(false);
    rb.reset_torques(false);
    rb.add_force(to_rapier(force), true);
    rb.add_torque(torque, true);
}

/// A dynamic body at centre of mass `g` (m), angle `angle` (rad), velocity
/// `v` (m/s) and angular velocity `omega` (rad/s).
pub(super) fn dynamic_body(g: &Vec2, angle: f64, v: &Vec2, omega: f64) -> RigidBodyBuilder {
    RigidBodyBuilder::dynamic()
        .translation(to_rapier(g))
        .rotation(angle)
        .linvel(to_rapier(v))
        .angvel(omega)
}

/// A convex polygon collider from counter-clockwise vertices (m) in the
/// body frame, taken as they are (no convex hull is recomputed); `None` if
/// parry rejects the outline.
pub(super) fn convex_polygon(vertices: &[Vec2]) -> Option<ColliderBuilder> {
    ColliderBuilder::convex_polyline(vertices.iter().map(to_rapier).collect())
}

/// The collider of an outline (m, counter-clockwise, in the body frame for
/// a floe, the world frame for an obstacle) split into convex `parts`
/// (indices into `outline`, [`crate::geometry::decompose`]): the convex
/// polygon itself for one part ([`convex_polygon`], unchanged for convex
/// bodies), else a compound of one convex polygon per part, every part at
/// the identity pose (its vertices are already in the collider's frame, so
/// contact points read in a part's frame are in the collider's). `None` if
/// parry rejects a part.
pub(super) fn polygon_collider(outline: &[Vec2], parts: &[Vec<usize>]) -> Option<ColliderBuilder> {
    if parts.len() <= 1 {
        return convex_polygon(outline);
    }
    let shapes = parts
        .iter()
        .map(|ids| {
            let pts = ids.iter().map(|&k| to_rapier(&outline[k])).collect();
            SharedShape::convex_polyline(pts).map(|s| (Pose::IDENTITY, s))
        })
        .collect::<Option<Vec<_>>>()?;
    Some(ColliderBuilder::compound(shapes))
}

/// Mass properties with the centre of mass at the body origin: mass `m` (kg),
/// polar moment of inertia `inertia` about it (kg·m²).
pub(super) fn mass_properties(m: f64, inertia: f64) -> MassProperties {
    MassProperties::new(RVec::ZERO, m, inertia)
}

/// The contact impulses of one manifold between colliders `c1` and `c2`:
/// for each point with an impulse, its world position midway between the
/// two surfaces (m), the manifold's world normal (from `c1` to `c2`), and
/// the normal and tangential impulses (N·s) rapier applied over the last
/// step (the impulse `λ n + β t` acts on `c2`, its opposite on `c1`; `t` is
/// the normal turned by +90°, the 2-D basis rapier builds on the normal).
pub(super) fn manifold_impulses(
    m: &ContactManifold,
    c1: &Collider,
    c2: &Collider,
) -> Vec<(Vec2, Vec2, Vec2, f64, f64)> {
    let n = from_rapier(m.data.normal);
    let t = Vec2::new(-n.y, n.x);
    m.points
        .iter()
        .filter(|p| p.data.impulse != 0.0 || p.data.tangent_impulse[0] != 0.0)
        .map(|p| {
            let a = from_rapier(c1.position().transform_point(p.local_p1));
            let b = from_rapier(c2.position().transform_point(p.local_p2));
            (
                (a + b) * 0.5,
                n,
                t,
                p.data.impulse,
                p.data.tangent_impulse[0],
            )
        })
        .collect()
}
