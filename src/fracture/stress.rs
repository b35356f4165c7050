//! The floe-averaged stress of the `stress` criterion and its yield curves
//! (docs/physics.md §9.3).
//!
//! From the impulses `P_c` delivered at points `x_c` to a floe of area `A`,
//! thickness `h` and centre of mass `x̄` over the window `W` (s), the mean
//! stress over the window is
//! `σ̄ = (1/(A h W)) Σ_c sym((x_c − x̄) ⊗ P_c)` (Pa, tension positive): the
//! impulses of the window divided by its duration are its mean forces, so an
//! impact (an impulse in no time) and a sustained force count alike. The
//! impulse of a solve is spread over the span the formulation attributes to
//! it (an instant for an impact, the step for a step's impulse), and the
//! window counts the share of that span inside it ([`Window`]).

use super::Load;
use crate::geometry::Vec2;
use crate::model::fracture::{FractureSettings, YieldCurve};
use std::collections::VecDeque;

/// A symmetric 2×2 tensor `[[xx, xy], [xy, yy]]`.
pub type Sym2 = [f64; 3];

/// `Σ sym((x_c − x̄) ⊗ P_c)` of `loads` about `centre` (N·s·m).
pub fn moment<'a>(centre: &Vec2, loads: impl Iterator<Item = &'a Load>) -> Sym2 {
    let mut m = [0.0; 3];
    for l in loads {
        let r = l.point - centre;
        m[0] += r.x * l.impulse.x;
        m[1] += 0.5 * (r.x * l.impulse.y + r.y * l.impulse.x);
        m[2] += r.y * l.impulse.y;
    }
    m
}

/// The mean stress (Pa) of the moment `m` (N·s·m, [`moment`]) delivered
/// over `duration` (s) to a floe of area `area` (m²) and thickness
/// `thickness` (m): `m / (A h duration)`.
pub fn mean_stress(m: &Sym2, area: f64, thickness: f64, duration: f64) -> Sym2 {
    let k = 1.0 / (area * thickness * duration);
    [m[0] * k, m[1] * k, m[2] * k]
}

/// The principal stresses `(σ1, σ2)` of `s`, `σ1 ≥ σ2` (Pa).
pub fn principal(s: &Sym2) -> (f64, f64) {
    let c = 0.5 * (s[0] + s[2]);
    let r = (0.5 * (s[0] - s[2])).hypot(s[1]);
    (c + r, c - r)
}

/// The moments of the recent solves of one floe, to average over a window.
///
/// Each solve's moment is delivered over the span the formulation attributes
/// to it, `[from, to]` (s): an instant (`from = to`) for an impact, the step
/// for the impulse of a step (docs/physics.md §9.3). The window `[t − W, t]`
/// counts the share of each span inside it, the impulse being spread
/// uniformly over its span (a constant force), so that a step longer than
/// the window does not count its whole impulse as the window's.
#[derive(Debug, Clone, Default)]
pub struct Window {
    items: VecDeque<(f64, f64, Sym2)>,
}

impl Window {
    /// Adds the moment `m` delivered over `[from, to]` (s, `from ≤ to`) and
    /// forgets the solves that ended before `to − window`.
    pub fn push(&mut self, from: f64, to: f64, m: Sym2, window: f64) {
        self.items.push_back((from, to, m));
        while self.items.front().is_some_and(|&(_, e, _)| e < to - window) {
            self.items.pop_front();
        }
    }

    /// The mean stress (Pa) over the window `[now − window, now]` of a
    /// floe of `area` (m²) and `thickness` (m): each solve's moment counts by
    /// the share of its span inside the window (all of it for an instant).
    pub fn mean_stress(&self, now: f64, area: f64, thickness: f64, window: f64) -> Sym2 {
        let start = now - window;
        let mut m = [0.0; 3];
        for &(from, to, x) in &self.items {
            let share = if to > from {
                ((to - from.max(start)) / (to - from)).clamp(0.0, 1.0)
            } else {
                1.0
            };
            for (a, b) in m.iter_mut().zip(x) {
                *a += share * b;
            }
        }
        mean_stress(&m, area, thickness, window)
    }
}

/// The vertices of the Mohr–Coulomb triangle in principal stress space
/// (Pa, tension positive): the biaxial vertex `(s, s)` with
/// `s = −(1/q + 1) σ_c / (1/q − q)`, and `(−σ_11, −(q σ_11 + σ_c))` with its
/// mirror image (SubZero's construction, after Weiss & Schulson 2009).
pub fn mohr_vertices(q: f64, sigma_c: f64, sigma_11: f64) -> [(f64, f64); 3] {
    let s = -((1.0 / q + 1.0) * sigma_c / (1.0 / q - q));
    let b = (-sigma_11, -(q * sigma_11 + sigma_c));
    [(s, s), b, (b.1, b.0)]
}

/// How far the stress `s` is outside the yield curve of `settings`: above 1
/// outside, 1 on it (docs/physics.md §9.3).
///
/// - `mohr`: the ratio by which `(σ1, σ2)` is beyond the triangle along the
///   ray from its interior point `0`: the largest `n_k · σ / d_k` over its
///   sides (`n_k` the outward normal, `d_k > 0` the side's distance to the
///   origin);
/// - `hibler`: `((σ_I + p/2)/(p/2))² + (σ_II/(p/(2e)))²` with
///   `σ_I = (σ1 + σ2)/2`, `σ_II = (σ1 − σ2)/2`, `e = 2`, and the strength
///   per unit thickness `p = P* exp(−C (1 − A))` (Pa).
pub fn yield_measure(settings: &FractureSettings, s: &Sym2) -> f64 {
    let (s1, s2) = principal(s);
    match settings.yield_curve {
        YieldCurve::Mohr => {
            let v = mohr_vertices(
                settings.mohr_q,
                settings.mohr_sigma_c,
                settings.mohr_sigma_11,
            );
            let mut worst = f64::NEG_INFINITY;
            for k in 0..3 {
                let (a, b) = (v[k], v[(k + 1) % 3]);
                // Outward normal of a counter-clockwise or clockwise side:
                // orient it away from the origin.
                let mut n = (b.1 - a.1, a.0 - b.0);
                let mut d = n.0 * a.0 + n.1 * a.1;
                if d < 0.0 {
                    n = (-n.0, -n.1);
                    d = -d;
                }
                worst = worst.max((n.0 * s1 + n.1 * s2) / d);
            }
            worst
        }
        YieldCurve::Hibler => {
            let p = settings.hibler_p_star
                * (-settings.hibler_c * (1.0 - settings.concentration)).exp();
            let e = 2.0;
            let si = 0.5 * (s1 + s2);
            let sii = 0.5 * (s1 - s2);
            ((si + 0.5 * p) / (0.5 * p)).powi(2) + (sii / (p / (2.0 * e))).powi(2)
        }
    }
}
