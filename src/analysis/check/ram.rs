//! The set-up of a floe rammed into a coast whose ice crushes
//! (docs/physics.md §10.3): recognised from the case's structure, with its
//! closed forms, its exact force against time and the force measured on a
//! run, for the crushing checks and their curve ([`super::curves`]).
//!
//! Set-up: `[contact] crushing` (either law), `e = 0`, one floe without
//! spin moving toward an obstacle, no forcing, the configuration symmetric
//! about the line of motion. A corner: one vertex ray reaches the coast
//! first, the floe's foremost vertex; a face: two or more.

use super::exact::{corner_crush, flat_crush};
use super::structure::{initial_polygon, no_forcing, self_symmetric, translation_gap};
use crate::geometry::Vec2;
use crate::model::{Crushing, Scenario};
use crate::run::RunResult;

/// What meets the coast.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RamShape {
    /// A corner of interior angle `φ` (rad).
    Corner(f64),
    /// A face of width `w` (m).
    Face(f64),
}

/// A floe rammed into a coast, its ice crushing (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ram {
    /// The floe's id.
    pub floe: usize,
    /// Its mass, kg.
    pub mass: f64,
    /// Its speed, m/s.
    pub v0: f64,
    /// The unit direction of its motion.
    pub d: Vec2,
    /// The crushing law.
    pub law: Crushing,
    /// Its thickness, m.
    pub thickness: f64,
    /// The time of the first contact (gap / speed), s.
    pub t_contact: f64,
    /// What meets the coast.
    pub shape: RamShape,
}

impl Ram {
    /// The set-up, if `scn` is one.
    pub fn of(scn: &Scenario) -> Option<Ram> {
        let law = scn.contact.crushing?;
        if scn.floes.len() != 1
            || scn.obstacles.is_empty()
            || !no_forcing(scn)
            || scn.contact.restitution != 0.0
            || scn.floes[0].angular_velocity != 0.0
        {
            return None;
        }
        let f = &scn.floes[0];
        let v0 = f.velocity.norm();
        if v0 == 0.0 {
            return None;
        }
        let d = f.velocity / v0;
        let (gap, rays) = translation_gap(scn, 0, &d)?;
        if !self_symmetric(scn, f.position, d) {
            return None;
        }
        let poly = initial_polygon(scn, 0);
        let shape = if rays == 1 {
            RamShape::Corner(corner_angle(&poly, &d)?)
        } else {
            RamShape::Face(face_width(&poly, &d))
        };
        Some(Ram {
            floe: f.id,
            mass: f.mass,
            v0,
            d,
            law,
            thickness: f.thickness,
            t_contact: gap / v0,
            shape,
        })
    }

    /// The closed forms: crushed volume (m³), peak force (N) and duration
    /// of the crushing (s). Under the pressure–area law a corner's force is
    /// `C δ^n` (`n = 1 + ex`, `C = P0 (2 h tan(φ/2))^n`), a spring of
    /// power `n`: the energy `½ M V²` is crushed at the depth
    /// `δ* = ((n+1) ½ M V² / C)^(1/(n+1))`, volume `h tan(φ/2) δ*²`, peak
    /// force `C δ*^n`, duration `(δ*/V) ∫₀¹ (1 − x^(n+1))^(−1/2) dx`
    /// (`= π/2` for `n = 1`); a face's is the constant `P0 (h w)^n`.
    pub fn exact(&self) -> (f64, f64, f64) {
        let (m, v, h) = (self.mass, self.v0, self.thickness);
        match (self.law, self.shape) {
            (Crushing::Strength { strength }, RamShape::Corner(phi)) => {
                corner_crush(m, v, strength, h, phi)
            }
            (Crushing::Strength { strength }, RamShape::Face(w)) => {
                flat_crush(m, v, strength, h, w)
            }
            (law @ Crushing::PressureArea { .. }, RamShape::Face(w)) => {
                flat_crush(m, v, law.pressure(h * w), h, w)
            }
            (Crushing::PressureArea { p0, exponent }, RamShape::Corner(phi)) => {
                let n = 1.0 + exponent;
                let t = (0.5 * phi).tan();
                let c = p0 * (2.0 * h * t).powf(n);
                let energy = 0.5 * m * v * v;
                let depth = ((n + 1.0) * energy / c).powf(1.0 / (n + 1.0));
                let a = 1.0 / (n + 1.0);
                let integral =
                    std::f64::consts::PI.sqrt() * (ln_gamma(1.0 + a) - ln_gamma(0.5 + a)).exp();
                (
                    h * t * depth * depth,
                    c * depth.powf(n),
                    depth / v * integral,
                )
            }
        }
    }

    /// The exact crushing force at time `t` (s), N, where it has a closed
    /// form in time (a constant strength, or a face): `F_peak sin(ω τ)` for
    /// a corner (`ω = π / (2 T)`), `F` for a face, over the crushing
    /// `τ = t − t_contact` in `[0, T]`; 0 outside. `None` for a corner
    /// under the pressure–area law (its force is known against depth, not
    /// time).
    pub fn force_at(&self, t: f64) -> Option<f64> {
        let (_, peak, duration) = self.exact();
        let tau = t - self.t_contact;
        let corner = matches!(self.shape, RamShape::Corner(_));
        if corner && matches!(self.law, Crushing::PressureArea { .. }) {
            return None;
        }
        if !(0.0..=duration).contains(&tau) {
            return Some(0.0);
        }
        Some(match corner {
            true => peak * (0.5 * std::f64::consts::PI * tau / duration).sin(),
            false => peak,
        })
    }

    /// The mean force of each output interval of `run`, `M |Δv·d| / Δt`
    /// (N), at the interval's middle (s). The crushed mass, which leaves
    /// with the floe's velocity, is neglected (5e-4 of the floe in the
    /// bundled cases).
    pub fn interval_forces(&self, run: &RunResult) -> Vec<(f64, f64)> {
        let rows: Vec<(f64, f64)> = self.velocities(run);
        rows.windows(2)
            .filter(|w| w[1].0 > w[0].0)
            .map(|w| {
                let ((t0, v0), (t1, v1)) = (w[0], w[1]);
                (0.5 * (t0 + t1), self.mass * (v1 - v0).abs() / (t1 - t0))
            })
            .collect()
    }

    /// The floe's velocity along the motion at each output of `run`.
    fn velocities(&self, run: &RunResult) -> Vec<(f64, f64)> {
        run.trajectory
            .iter()
            .filter(|row| row.floe == self.floe)
            .map(|row| (row.t, Vec2::new(row.vx, row.vy).dot(&self.d)))
            .collect()
    }

    /// The time (s) from the first contact to the stop of the floe on
    /// `run` (NaN if it never stops): in the output interval where its
    /// velocity along the motion falls to [`STOPPED`] × `v0`, the last
    /// velocity above continued at the deceleration of the interval before
    /// (a floe stops and stays, so the end of the interval is no point of
    /// the line), within the interval.
    pub fn stop_time(&self, run: &RunResult) -> f64 {
        let rows = self.velocities(run);
        let stopped = STOPPED * self.v0;
        rows.windows(3)
            .find(|w| w[1].1 > stopped && w[2].1 <= stopped)
            .map_or(f64::NAN, |w| {
                let ((tp, vp), (t0, v0), (t1, _)) = (w[0], w[1], w[2]);
                let rate = (vp - v0) / (t0 - tp);
                let dt = if rate > 0.0 { v0 / rate } else { t1 - t0 };
                t0 + dt.min(t1 - t0) - self.t_contact
            })
    }
}

/// The fraction of the approach speed below which a floe has stopped (one
/// at rest against the coast keeps a velocity at the rounding of its last
/// impulse: 1e-77 m/s measured).
pub const STOPPED: f64 = 1e-9;

/// The interior angle (rad) of the floe's foremost vertex along `d`.
fn corner_angle(poly: &[Vec2], d: &Vec2) -> Option<f64> {
    let n = poly.len();
    let s: Vec<f64> = poly.iter().map(|p| p.dot(d)).collect();
    let front = (0..n).max_by(|&i, &j| s[i].total_cmp(&s[j]))?;
    let a = poly[(front + n - 1) % n] - poly[front];
    let b = poly[(front + 1) % n] - poly[front];
    let angle = a.angle(&b);
    (angle > 0.0 && angle < std::f64::consts::PI).then_some(angle)
}

/// The width (m) of the floe's foremost face across `d`: the extent across
/// `d` of its vertices within rounding of the foremost.
fn face_width(poly: &[Vec2], d: &Vec2) -> f64 {
    let s: Vec<f64> = poly.iter().map(|p| p.dot(d)).collect();
    let front = s.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let scale = poly.iter().map(|p| p.norm()).fold(0.0, f64::max);
    let across = Vec2::new(-d.y, d.x);
    let c: Vec<f64> = poly
        .iter()
        .zip(&s)
        .filter(|(_, &si)| front - si <= 1e-9 * scale)
        .map(|(p, _)| p.dot(&across))
        .collect();
    c.iter().copied().fold(f64::NEG_INFINITY, f64::max)
        - c.iter().copied().fold(f64::INFINITY, f64::min)
}

/// `ln Γ(x)` for `x > 0` (Lanczos, g = 7, nine terms: 1e-15 relative).
fn ln_gamma(x: f64) -> f64 {
    const G: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = G[0];
    let t = x + 7.5;
    for (i, g) in G.iter().enumerate().skip(1) {
        a += g / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

#[cfg(test)]
mod tests {
    use super::ln_gamma;

    #[test]
    fn ln_gamma_is_exact_where_gamma_is_known() {
        let pi = std::f64::consts::PI;
        assert!((ln_gamma(1.0)).abs() < 1e-14);
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-13);
        assert!((ln_gamma(0.5) - pi.sqrt().ln()).abs() < 1e-14);
        assert!((ln_gamma(1.5) - (0.5 * pi.sqrt()).ln()).abs() < 1e-14);
    }
}
