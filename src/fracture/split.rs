//! The split: a straight chord cut of a convex floe into two convex pieces
//! that take the parent's rigid velocity field (docs/physics.md §9.1).
//!
//! The pieces partition the parent, so area and mass are conserved (to the
//! rounding of the polygon formulas); each piece gets the velocity of the
//! parent's material at its centre of mass, `v + ω k ∧ (G_k − G)`, and the
//! parent's `ω`: this is the parent's velocity field restricted to each
//! piece, so linear momentum, angular momentum about the parent's centre of
//! mass (parallel-axis theorem) and kinetic energy are those of the parent.

use crate::geometry::{area_properties, cross, perp, Vec2};
use crate::model::Floe;
use crate::state::BodyState;

/// Relative distance (to the floe's radius) within which a vertex counts as
/// on the chord: the chord then passes through it, and no sliver edge is
/// made next to it.
const ON_CHORD: f64 = 1e-9;

/// A cut of a convex polygon: the two pieces (counter-clockwise, world
/// frame) and the chord's length, m.
#[derive(Debug, Clone, PartialEq)]
pub struct Cut {
    /// The piece on the left of the chord's direction.
    pub left: Vec<Vec2>,
    /// The piece on its right.
    pub right: Vec<Vec2>,
    /// The chord's length `L`, m.
    pub length: f64,
}

/// Cuts `poly` (convex, counter-clockwise, world frame) by the line through
/// `point` along `dir`. `None` when the line leaves one side without area
/// (it misses the polygon, touches a vertex, or runs along an edge). The
/// chord's two ends are the same points in both pieces, so the pieces tile
/// the parent exactly.
pub fn cut(poly: &[Vec2], point: &Vec2, dir: &Vec2) -> Option<Cut> {
    let n = poly.len();
    let len = dir.norm();
    if n < 3 || len.is_nan() || len <= 0.0 || !len.is_finite() {
        return None;
    }
    let d = dir / len;
    let scale = poly.iter().map(|p| (p - point).norm()).fold(0.0, f64::max);
    let tol = ON_CHORD * scale;
    // Signed distance to the line, positive on the left; a vertex within
    // `tol` is on it.
    let s: Vec<f64> = poly
        .iter()
        .map(|p| {
            let v = cross(&d, &(p - point));
            if v.abs() <= tol {
                0.0
            } else {
                v
            }
        })
        .collect();
    if !(s.iter().any(|&v| v > 0.0) && s.iter().any(|&v| v < 0.0)) {
        return None;
    }
    let mut left = Vec::with_capacity(n + 2);
    let mut right = Vec::with_capacity(n + 2);
    let mut ends = Vec::with_capacity(2);
    for i in 0..n {
        let j = (i + 1) % n;
        let (p, q) = (poly[i], poly[j]);
        if s[i] >= 0.0 {
            left.push(p);
        }
        if s[i] <= 0.0 {
            right.push(p);
        }
        if s[i] == 0.0 {
            ends.push(p);
        }
        if (s[i] > 0.0 && s[j] < 0.0) || (s[i] < 0.0 && s[j] > 0.0) {
            let x = p + (q - p) * (s[i] / (s[i] - s[j]));
            left.push(x);
            right.push(x);
            ends.push(x);
        }
    }
    if ends.len() != 2 || left.len() < 3 || right.len() < 3 {
        return None;
    }
    Some(Cut {
        length: (ends[1] - ends[0]).norm(),
        left,
        right,
    })
}

/// One piece of a split floe: the floe (its outline about its own centre
/// of mass at angle 0, which is its orientation at birth) and its state.
#[derive(Debug, Clone)]
pub struct Piece {
    /// The piece as a floe (id, parent and birth set by the caller).
    pub floe: Floe,
    /// Its state at birth: centre of mass, angle 0, the parent's rigid
    /// velocity there, the parent's angular velocity.
    pub state: BodyState,
}

/// The cut of `floe` in state `b` by the line through `point` along `dir`
/// (world frame), or `None` (see [`cut`]). The cut's pieces are in the
/// parent's centre frame: world axes, origin at its centre of mass (so
/// that rounding does not grow with the distance to the world origin).
pub fn cut_floe(floe: &Floe, b: &BodyState, point: &Vec2, dir: &Vec2) -> Option<Cut> {
    let mut rel = Vec::with_capacity(floe.shape.len());
    floe.world_polygon(&Vec2::zeros(), b.angle, &mut rel);
    cut(&rel, &(point - b.position), dir)
}

/// The two pieces (left, then right) of `floe` in state `b` along the cut
/// `c` of its outline in its centre frame ([`cut_floe`]); `None` if a
/// piece has no area.
pub fn split(floe: &Floe, b: &BodyState, c: &Cut) -> Option<[Piece; 2]> {
    let piece = |poly: &[Vec2]| -> Option<Piece> {
        let props = area_properties(poly);
        if props.area.is_nan() || props.area <= 0.0 {
            return None;
        }
        // The centre of mass relative to the parent's: the lever arm of
        // the rigid velocity field.
        let r = props.centroid;
        let velocity = b.velocity + perp(&r) * b.angular_velocity;
        let mut f = Floe::from_world_polygon(
            poly,
            floe.thickness,
            floe.density,
            velocity,
            b.angular_velocity,
            floe.origin,
        );
        f.parent = Some(floe.id);
        f.position = b.position + f.position;
        Some(Piece {
            state: BodyState {
                position: f.position,
                angle: 0.0,
                velocity,
                angular_velocity: b.angular_velocity,
            },
            floe: f,
        })
    };
    Some([piece(&c.left)?, piece(&c.right)?])
}

/// The largest relative change that splitting `parent` (in state `b`) into
/// `pieces` makes to area, mass, linear momentum, angular momentum about the
/// parent's centre of mass and, if `kinetic`, kinetic energy (the measure of
/// [`crate::model::fracture::FractureRecord::conservation`]; the lattice
/// model's pieces change the kinetic energy, and the ledger books it).
/// Momenta are relative to `M (|v| + |ω| r)` (times `r` for the angular
/// one); without `kinetic` (the lattice model's pieces, which move apart)
/// that scale also takes the pieces' motion relative to the parent's rigid
/// field, `Σ m_j |v_j − v − ω k ∧ r_j| + Σ I_j |ω_j − ω| / r`: a floe at
/// rest that bursts into pieces has a zero rigid scale, and the rounding of
/// the pieces' opposite momenta would then read as an error of order one.
pub fn conservation_error(parent: &Floe, b: &BodyState, pieces: &[Piece], kinetic: bool) -> f64 {
    let (mut area, mut mass, mut p, mut l, mut e) = (0.0, 0.0, Vec2::zeros(), 0.0, 0.0);
    for q in pieces {
        area += q.floe.area;
        mass += q.floe.mass;
        p += q.state.velocity * q.floe.mass;
        let r = q.state.position - b.position;
        l += q.floe.inertia * q.state.angular_velocity + q.floe.mass * cross(&r, &q.state.velocity);
        e += q
            .floe
            .kinetic_energy(&q.state.velocity, q.state.angular_velocity);
    }
    let rel = |x: f64, x0: f64| (x - x0).abs() / x0.abs().max(f64::MIN_POSITIVE);
    let relative: f64 = if kinetic {
        0.0
    } else {
        pieces
            .iter()
            .map(|q| {
                let r = q.state.position - b.position;
                let rigid = b.velocity + perp(&r) * b.angular_velocity;
                q.floe.mass * (q.state.velocity - rigid).norm()
                    + q.floe.inertia * (q.state.angular_velocity - b.angular_velocity).abs()
                        / parent.radius
            })
            .sum()
    };
    let pscale = (parent.mass * (b.velocity.norm() + b.angular_velocity.abs() * parent.radius)
        + relative)
        .max(f64::MIN_POSITIVE);
    let e0 = parent.kinetic_energy(&b.velocity, b.angular_velocity);
    [
        rel(area, parent.area),
        rel(mass, parent.mass),
        (p - b.velocity * parent.mass).norm() / pscale,
        (l - parent.inertia * b.angular_velocity).abs() / (pscale * parent.radius),
        match (kinetic, e0 > 0.0) {
            (false, _) => 0.0,
            (true, true) => rel(e, e0),
            (true, false) => e,
        },
    ]
    .into_iter()
    .fold(0.0, f64::max)
}
