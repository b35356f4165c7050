//! The set-ups with a closed-form motion, recognised from a case's
//! structure (docs/physics.md §6.1): each one holds what its checks and its
//! exact curve ([`super::curves`]) need, computed once from the case's own
//! parameters. Recognising a set-up is the applicability rule of its checks.

use super::exact::{steady_drift_velocity, wind_acceleration};
use super::structure::{self_symmetric, translation_gap, wind_as_gravity, GEOMETRY_MATCH};
use crate::geometry::Vec2;
use crate::model::{Scenario, VelocitySeries};

/// A floe at rest at gap `d > 0` from an obstacle, pushed toward it by a
/// constant wind with no water drag and no Coriolis, symmetric about the
/// wind line: a bouncing ball under the gravity `a`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bouncing {
    /// Unit direction of the wind (toward the obstacle).
    pub dir: Vec2,
    /// Gap to the obstacle along `dir` at t = 0, m.
    pub gap: f64,
    /// Wind acceleration, m/s².
    pub a: f64,
    /// Restitution `e`.
    pub e: f64,
    /// First impact time `sqrt(2 d / a)`, s.
    pub t1: f64,
    /// First impact speed `a t1`, m/s.
    pub v1: f64,
    /// Centre of mass at t = 0, m.
    pub start: Vec2,
}

impl Bouncing {
    /// The set-up, if `scn` is one (floe 0).
    pub fn of(scn: &Scenario) -> Option<Bouncing> {
        let dir = wind_as_gravity(scn)?;
        let f = &scn.floes[0];
        if f.velocity.norm() != 0.0
            || f.angular_velocity != 0.0
            || !self_symmetric(scn, f.position, dir)
        {
            return None;
        }
        let (gap, _) = translation_gap(scn, 0, &dir)?;
        if gap <= GEOMETRY_MATCH * f.radius {
            return None;
        }
        let a = wind_acceleration(scn, 0);
        let t1 = (2.0 * gap / a).sqrt();
        Some(Bouncing {
            dir,
            gap,
            a,
            e: scn.contact.restitution,
            t1,
            v1: a * t1,
            start: f.position,
        })
    }

    /// The accumulation time `t1 (1 + e)/(1 − e)` at which the floe comes
    /// to rest (`None` for `e = 1`), s.
    pub fn rest_time(&self) -> Option<f64> {
        (self.e < 1.0).then(|| self.t1 * (1.0 + self.e) / (1.0 - self.e))
    }

    /// The impact times `t_k = t1 + (2 v1 / a) Σ_{j=1}^{k−1} e^j` up to
    /// `until`, and at most `max` of them, s.
    pub fn impact_times(&self, until: f64, max: usize) -> Vec<f64> {
        let mut out = Vec::new();
        let (mut t, mut v) = (self.t1, self.v1);
        while t <= until && out.len() < max && v > 0.0 {
            out.push(t);
            v *= self.e;
            t += 2.0 * v / self.a;
        }
        out
    }

    /// The exact gap to the obstacle at `t` (m): free flight to `t1`, then
    /// arcs of rebound speed `e^k v1` between the impacts, 0 after the
    /// accumulation time.
    pub fn gap_at(&self, t: f64) -> f64 {
        if t <= self.t1 {
            return self.gap - 0.5 * self.a * t * t;
        }
        if self.rest_time().is_some_and(|tr| t >= tr) {
            return 0.0;
        }
        let (mut tk, mut v) = (self.t1, self.v1 * self.e);
        // Arcs shorter than rounding are the accumulation: gap 0.
        while v > 0.0 && 2.0 * v / self.a > 1e-12 * self.t1 {
            let flight = 2.0 * v / self.a;
            if t <= tk + flight {
                let s = t - tk;
                return (v * s - 0.5 * self.a * s * s).max(0.0);
            }
            tk += flight;
            v *= self.e;
        }
        0.0
    }

    /// The gap to the obstacle of a floe whose centre of mass is at `p`
    /// (translated along `dir` from the start), m.
    pub fn gap_of(&self, p: Vec2) -> f64 {
        self.gap - (p - self.start).dot(&self.dir)
    }
}

/// A floe touching an obstacle face, pressed on it by a constant wind, with
/// a velocity across the wind and friction: it decelerates at `μ a`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sliding {
    /// Unit direction of the initial velocity.
    pub dir: Vec2,
    /// Initial speed, m/s.
    pub v0: f64,
    /// Friction coefficient.
    pub mu: f64,
    /// Wind acceleration, m/s².
    pub a: f64,
    /// Stop time `v0 / (μ a)`, s.
    pub t_stop: f64,
    /// Distance `v0² / (2 μ a)`, m.
    pub distance: f64,
    /// Centre of mass at t = 0, m.
    pub start: Vec2,
}

impl Sliding {
    /// The set-up, if `scn` is one (floe 0) and lasts past the stop by an
    /// output interval.
    pub fn of(scn: &Scenario) -> Option<Sliding> {
        let d = wind_as_gravity(scn)?;
        let f = &scn.floes[0];
        let mu = scn.contact.friction;
        let v0 = f.velocity.norm();
        if mu <= 0.0
            || v0 == 0.0
            || f.angular_velocity != 0.0
            || f.velocity.dot(&d).abs() > 1e-12 * v0
        {
            return None;
        }
        let (gap, rays) = translation_gap(scn, 0, &d)?;
        if gap > GEOMETRY_MATCH * f.radius || rays < 2 {
            return None;
        }
        let a = wind_acceleration(scn, 0);
        let t_stop = v0 / (mu * a);
        if scn.duration < t_stop + scn.output_interval {
            return None;
        }
        Some(Sliding {
            dir: f.velocity / v0,
            v0,
            mu,
            a,
            t_stop,
            distance: v0 * v0 / (2.0 * mu * a),
            start: f.position,
        })
    }

    /// The exact distance slid by `t`, m.
    pub fn distance_at(&self, t: f64) -> f64 {
        let s = t.clamp(0.0, self.t_stop);
        self.v0 * s - 0.5 * self.mu * self.a * s * s
    }
}

/// Floes drifting freely (no obstacle) under constant wind and current with
/// water drag, for at least [`super::FREE_DRIFT_TIME_CONSTANTS`] drag time
/// constants: each tends to the steady velocity of docs/physics.md §2.2.
#[derive(Debug, Clone, PartialEq)]
pub struct Drift {
    /// Per floe that qualifies: its index, the steady velocity (m/s) and
    /// the drag time constant `ρ_i h / (2 ρ_w C_w |u − U_w|)` (s).
    pub floes: Vec<(usize, Vec2, f64)>,
}

impl Drift {
    /// The set-up, if `scn` is one (`None` when no floe qualifies).
    pub fn of(scn: &Scenario) -> Option<Drift> {
        if !scn.obstacles.is_empty() {
            return None;
        }
        let kw = scn.environment.water.drag_factor();
        // Only a constant current has a steady drift (steady_drift_velocity).
        let uw = scn.environment.water.velocity.constant_value()?;
        let mut floes = Vec::new();
        for i in 0..scn.floes.len() {
            let u = steady_drift_velocity(scn, i)?;
            let rel = (u - uw).norm();
            let tau = scn.floes[i].surface_density() / (2.0 * kw * rel.max(f64::MIN_POSITIVE));
            if scn.duration < super::FREE_DRIFT_TIME_CONSTANTS * tau || u.norm() == 0.0 {
                continue;
            }
            floes.push((i, u, tau));
        }
        (!floes.is_empty()).then_some(Drift { floes })
    }
}

/// One floe without obstacle or spin, over a still ocean (`U_w = 0`), with
/// Coriolis, once the wind has stopped for good: the water drag is along
/// `−v`, so it changes only the speed, and the velocity turns at exactly
/// `−f` (clockwise for `f > 0`): inertial circles of period `2π/|f|`,
/// whatever the drag (docs/physics.md §2.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inertial {
    /// Coriolis parameter `f`, 1/s.
    pub f: f64,
    /// The time from which the wind is zero, s.
    pub t_calm: f64,
    /// The period `2π/|f|`, s.
    pub period: f64,
    /// `ρ_w C_w / (ρ_i h)`, 1/m: the water drag decelerates at `c |v|²`.
    pub c: f64,
}

impl Inertial {
    /// The set-up, if `scn` is one: the calm lasts at least one period and
    /// the outputs sample the turning finely (`|f| Δt_out < π/2`, so the
    /// phase can be followed from one output to the next).
    pub fn of(scn: &Scenario) -> Option<Inertial> {
        let env = &scn.environment;
        let f = env.coriolis;
        let one = scn.floes.first()?;
        let still = matches!(env.water.velocity.constant_value(), Some(u) if u.norm() == 0.0);
        if scn.floes.len() != 1
            || !scn.obstacles.is_empty()
            || f == 0.0
            || !still
            || one.angular_velocity != 0.0
            || f.abs() * scn.output_interval >= std::f64::consts::FRAC_PI_2
        {
            return None;
        }
        let t_calm = if env.air.drag_factor() == 0.0 {
            0.0
        } else {
            match env.air.velocity.uniform()? {
                VelocitySeries::Constant(u) if u.norm() == 0.0 => 0.0,
                VelocitySeries::Constant(_) => return None,
                VelocitySeries::Series(points) => {
                    let last_wind = points.iter().rposition(|p| p.1.norm() != 0.0);
                    match last_wind {
                        None => 0.0,
                        Some(k) => points.get(k + 1)?.0,
                    }
                }
            }
        };
        let period = std::f64::consts::TAU / f.abs();
        if scn.duration - t_calm < period {
            return None;
        }
        Some(Inertial {
            f,
            t_calm,
            period,
            c: env.water.drag_factor() / one.surface_density(),
        })
    }

    /// The exact velocity `s` seconds after the velocity `v0` in the calm:
    /// speed `|v0| / (1 + c |v0| s)`, turned by `−f s`, m/s.
    pub fn velocity_after(&self, v0: Vec2, s: f64) -> Vec2 {
        let speed = v0.norm() / (1.0 + self.c * v0.norm() * s);
        let phi = v0.y.atan2(v0.x) - self.f * s;
        Vec2::new(phi.cos(), phi.sin()) * speed
    }
}
