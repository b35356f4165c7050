//! The strikers of a percussion (docs/physics.md §7.3, §9.8): each a rigid
//! half-plane of effective mass along its impact's normal ([`Impact`]),
//! pushing the outline nodes through compression-only penalty links; the
//! floe's rigid motion at the impact ([`RigidMotion`]); the bound on the
//! energy several strikers can put into the floe ([`impact_energy_bound`]);
//! the gaps, the contact impulse and work, and the strikers' kicks.

use super::Percussion;
use crate::fracture::chain::Link;
use crate::geometry::{cross, perp, Vec2};

/// The rigid impact that starts a percussion, in the lattice's frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impact {
    /// The contact point, m.
    pub point: Vec2,
    /// The unit normal, pointing into the struck floe (the striker pushes
    /// along it).
    pub normal: Vec2,
    /// The striker's effective mass along the normal, kg (`f64::INFINITY`
    /// for an obstacle or a coast).
    pub mass: f64,
    /// The relative normal speed of approach, m/s (> 0).
    pub speed: f64,
}

/// The floe's rigid motion at the impact: velocity of its centre of mass
/// (m/s) and angular velocity (rad/s).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RigidMotion {
    /// Velocity of the centre of mass, m/s.
    pub velocity: Vec2,
    /// Angular velocity, rad/s.
    pub angular_velocity: f64,
}

/// One striker of a percussion: a rigid half-plane along its impact's
/// normal, in unilateral contact with every outline node.
#[derive(Debug, Clone)]
pub(super) struct Striker {
    pub(super) impact: Impact,
    /// The outline nodes and their contact links with this striker.
    pub(super) contacts: Vec<(usize, Link)>,
    /// Its position along the normal (its face is the line
    /// `n · (x − point) = position`), m.
    pub(super) position: f64,
    /// Its velocity along the normal, m/s.
    pub(super) velocity: f64,
    /// The force of its contacts (along `−n` on the nodes), N.
    pub(super) force: f64,
}

impl Striker {
    /// Its kinetic energy along the normal (0 for an infinite mass), J.
    pub(super) fn energy(&self) -> f64 {
        if self.impact.mass.is_finite() {
            0.5 * self.impact.mass * self.velocity * self.velocity
        } else {
            0.0
        }
    }
}

/// The bound `B` (J) on the energy a percussion of a floe (mass `mass`, kg;
/// polar inertia `inertia` about its centre of mass, kg·m²; rigid motion
/// `motion`) by several strikers can put into its deformation, dashpots
/// and broken bonds (docs/physics.md §9.8): each striker `k` moves along
/// its normal `n_k` at `s_k` (`velocity[k]`, m/s, in the lattice's frame).
/// In an inertial frame moving at `W` in which every infinite striker is
/// at rest along its normal (`n_k · W = s_k`), no striker does work (a
/// half-plane pushes along its normal only), so the energy there,
/// `½ M |V − W|² + ½ I ω² + Σ_finite ½ m_k (s_k − n_k · W)²` at the start,
/// bounds `V + D + F` for ever. `B` is its least value over the admissible
/// `W`; `∞` when the infinite strikers admit no common frame (rigid walls
/// closing on the floe crush it without limit). One finite striker and a
/// floe at rest give `½ μ_G u²`, `μ_G = m M/(m + M)`; one infinite, `½ M u²`.
pub fn impact_energy_bound(
    mass: f64,
    inertia: f64,
    motion: RigidMotion,
    impacts: &[Impact],
    velocity: &[f64],
) -> f64 {
    let v = motion.velocity;
    let energy = |w: &Vec2| {
        let mut e = 0.5 * mass * (v - w).norm_squared()
            + 0.5 * inertia * motion.angular_velocity * motion.angular_velocity;
        for (i, s) in impacts.iter().zip(velocity) {
            if i.mass.is_finite() {
                let d = s - i.normal.dot(w);
                e += 0.5 * i.mass * d * d;
            }
        }
        e
    };
    let walls: Vec<(Vec2, f64)> = impacts
        .iter()
        .zip(velocity)
        .filter(|(i, _)| i.mass.is_infinite())
        .map(|(i, &s)| (i.normal, s))
        .collect();
    // The quadratic's matrix M 1 + Σ m n nᵀ and right-hand side M V + Σ m s n.
    let (mut a, mut b) = (nalgebra::Matrix2::identity() * mass, v * mass);
    for (i, &s) in impacts.iter().zip(velocity) {
        if i.mass.is_finite() {
            a += i.normal * i.normal.transpose() * i.mass;
            b += i.normal * (i.mass * s);
        }
    }
    let w = match walls.first() {
        None => match a.try_inverse() {
            Some(inv) => inv * b,
            None => return f64::INFINITY,
        },
        Some(&(n0, s0)) => {
            let other = walls.iter().find(|(n, _)| cross(&n0, n).abs() > 1e-9);
            match other {
                // Two walls that are not parallel fix W.
                Some(&(n1, s1)) => {
                    let det = cross(&n0, &n1);
                    Vec2::new(s0 * n1.y - s1 * n0.y, n0.x * s1 - n1.x * s0) / det
                }
                // Parallel walls fix W along n0; the rest minimises.
                None => {
                    let t = perp(&n0);
                    let base = n0 * s0;
                    let along = (t.transpose() * a * t)[0];
                    let rhs = t.dot(&(b - a * base));
                    base + t * (rhs / along)
                }
            }
        }
    };
    let scale = walls.iter().map(|(_, s)| s.abs()).fold(0.0, f64::max);
    if walls
        .iter()
        .any(|(n, s)| (n.dot(&w) - s).abs() > 1e-9 * scale.max(f64::MIN_POSITIVE))
    {
        return f64::INFINITY;
    }
    energy(&w)
}

impl Percussion<'_> {
    /// Gap (m) and its rate (m/s) between striker `k` and node `i`.
    pub(super) fn gap(&self, k: usize, i: usize) -> (f64, f64) {
        let s = &self.strikers[k];
        let n = s.impact.normal;
        (
            n.dot(&(self.x[i] - s.impact.point)) - s.position,
            n.dot(&self.v[i]) - s.velocity,
        )
    }

    /// Whether an outline node touches a striker.
    pub(in crate::fracture::lattice) fn touching(&self) -> bool {
        self.strikers
            .iter()
            .enumerate()
            .any(|(k, s)| s.contacts.iter().any(|&(i, _)| self.gap(k, i).0 < 0.0))
    }

    /// The impulse of the contact forces of the last [`Self::forces`]
    /// over `h` seconds, added to the running totals.
    pub(super) fn book_contact(&mut self, h: f64) {
        for s in &self.strikers {
            self.impulse -= s.impact.normal * (s.force * h);
        }
        self.impulse_moment += self.contact_moment * h;
        for s in &self.strikers {
            if s.impact.mass.is_infinite() {
                self.work -= s.velocity * s.force * h;
            }
        }
    }

    /// Half a kick of the strikers.
    pub(super) fn kick_striker(&mut self, h: f64) {
        for s in &mut self.strikers {
            if s.impact.mass.is_finite() {
                s.velocity += h * s.force / s.impact.mass;
            }
        }
    }

    /// The strikers' kinetic energy along their normals, J.
    pub(super) fn striker_energy(&self) -> f64 {
        self.strikers.iter().map(Striker::energy).sum()
    }
}
