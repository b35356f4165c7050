//! Is a case chaotic? The reference formulation is run a second time from
//! an initial state perturbed by [`PERTURBATION`] (relative), and the growth
//! of the divergence between the two runs is measured (docs/physics.md §6.5).
//!
//! - **Perturbation** ([`perturbed`]): every floe's centre of mass moves by
//!   [`PERTURBATION`] × `d_med` (the median floe diameter,
//!   [`Scenario::median_floe_diameter`]) in a direction drawn by
//!   the seeded generator, so the RMS position difference between the runs
//!   starts at `D(0)` = 1e-12 (in units of `d_med`, the unit of every
//!   divergence of the report).
//! - **Growth window**: from the last output where `D ≤ 10 D(0)` to the
//!   first output after it where `D ≥` [`SATURATION`] (or the end). In a
//!   chaotic case `D` grows like `D(0) e^{λt}` there; once it is a sizeable
//!   fraction of a floe it saturates (the floes are in different places,
//!   the difference stops growing exponentially).
//! - **Rate** `λ` (1/s): the least-squares slope of `ln D` against `t` over
//!   the window, a finite-time largest-Lyapunov-like exponent.
//! - **Chaotic** when the perturbation grew by at least [`MIN_GROWTH`]
//!   (`max D / D(0)`), over a window of at least [`MIN_WINDOW_SAMPLES`]
//!   outputs, with `λ > 0` and the exponential fit explaining at least
//!   [`MIN_FIT_R2`] of the variance of `ln D`. A regular case keeps `D` at
//!   the perturbation's order (a shifted impact time moves the floes by
//!   `O(D(0))`), or jumps once when a discrete decision flips (an
//!   activation test, the order of two nearly simultaneous impacts), which
//!   the sample count and the fit exclude.

use super::divergence::{self, TimeMismatch};
use crate::geometry::Vec2;
use crate::model::Scenario;
use crate::rng::SplitMix64;
use crate::run::RunResult;
use serde::Serialize;

/// The relative size of the perturbation of the initial positions (of the
/// median floe diameter): a thousand times the rounding of `f64` positions
/// of order `d_med`, far below any physical scale.
pub const PERTURBATION: f64 = 1e-12;

/// Seed of the perturbation's directions.
pub const SEED: u64 = 0x5EED_C4A0;

/// The divergence (of `d_med`) beyond which growth is no longer exponential.
pub const SATURATION: f64 = 1e-2;

/// Smallest growth `max D / D(0)` called chaotic: six decades, which no
/// regular case reaches (its divergence stays within a few orders of the
/// perturbation).
pub const MIN_GROWTH: f64 = 1e6;

/// Smallest number of outputs in the growth window: a growth seen at fewer
/// outputs is a jump, not a rate.
pub const MIN_WINDOW_SAMPLES: usize = 5;

/// Smallest coefficient of determination of the fit of `ln D` against `t`.
pub const MIN_FIT_R2: f64 = 0.8;

/// `scn` with every floe's centre of mass moved by [`PERTURBATION`] × `d_med`
/// in a seeded random direction (see the module doc).
pub fn perturbed(scn: &Scenario) -> Scenario {
    let size = PERTURBATION * scn.median_floe_diameter();
    let mut rng = SplitMix64::new(SEED);
    let mut out = scn.clone();
    for f in &mut out.floes {
        let phi = rng.range(0.0, std::f64::consts::TAU);
        f.position += Vec2::new(phi.cos(), phi.sin()) * size;
    }
    out
}

/// The outcome of the chaos probe of a case.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChaosProbe {
    /// The formulation run twice.
    pub formulation: String,
    /// The relative perturbation of the initial positions.
    pub perturbation: f64,
    /// `(t, D(t))`: the RMS position difference between the two runs, of `d_med`.
    pub samples: Vec<(f64, f64)>,
    /// `max D / D(0)`.
    pub growth: f64,
    /// The growth window, s (see the module doc).
    pub window: (f64, f64),
    /// Outputs in the window.
    pub window_samples: usize,
    /// The fitted rate `λ`, 1/s (`None` with fewer than two samples).
    pub rate: Option<f64>,
    /// Coefficient of determination of the fit.
    pub fit_r2: Option<f64>,
    /// Whether the case is chaotic by the test of the module doc.
    pub chaotic: bool,
}

/// The least-squares slope of `y` against `x` and the coefficient of
/// determination; `None` with fewer than two points or no spread in `x`.
fn fit(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let n = points.len() as f64;
    if points.len() < 2 {
        return None;
    }
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), p| (a + p.0 / n, b + p.1 / n));
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for (x, y) in points {
        sxx += (x - mx) * (x - mx);
        sxy += (x - mx) * (y - my);
        syy += (y - my) * (y - my);
    }
    if sxx <= 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    let r2 = if syy > 0.0 {
        sxy * sxy / (sxx * syy)
    } else {
        1.0
    };
    Some((slope, r2))
}

/// The chaos probe from the reference run `a` and the run `b` of the same
/// formulation from [`perturbed`] initial positions.
pub fn probe(scn: &Scenario, a: &RunResult, b: &RunResult) -> Result<ChaosProbe, TimeMismatch> {
    let d = divergence::divergence(scn, a, b, f64::INFINITY)?;
    let samples: Vec<(f64, f64)> = d
        .samples
        .iter()
        .map(|s| (s.t, s.rms_position_rel))
        .collect();
    if samples.is_empty() {
        return Ok(ChaosProbe {
            formulation: a.summary.formulation.clone(),
            perturbation: PERTURBATION,
            samples,
            growth: 1.0,
            window: (0.0, 0.0),
            window_samples: 0,
            rate: None,
            fit_r2: None,
            chaotic: false,
        });
    }
    let d0 = samples
        .first()
        .map_or(PERTURBATION, |s| s.1)
        .max(f64::MIN_POSITIVE);
    let growth = samples.iter().map(|s| s.1).fold(0.0, f64::max) / d0;
    let end = samples
        .iter()
        .position(|s| s.1 >= SATURATION)
        .unwrap_or(samples.len() - 1);
    let start = samples[..=end]
        .iter()
        .rposition(|s| s.1 <= 10.0 * d0)
        .unwrap_or(0);
    let window: Vec<(f64, f64)> = samples
        .get(start..=end)
        .unwrap_or(&[])
        .iter()
        .filter(|s| s.1 > 0.0)
        .map(|s| (s.0, s.1.ln()))
        .collect();
    let fitted = fit(&window);
    let chaotic = growth >= MIN_GROWTH
        && window.len() >= MIN_WINDOW_SAMPLES
        && fitted.is_some_and(|(rate, r2)| rate > 0.0 && r2 >= MIN_FIT_R2);
    Ok(ChaosProbe {
        formulation: a.summary.formulation.clone(),
        perturbation: PERTURBATION,
        window: (
            samples.get(start).map_or(0.0, |s| s.0),
            samples.get(end).map_or(0.0, |s| s.0),
        ),
        window_samples: window.len(),
        rate: fitted.map(|f| f.0),
        fit_r2: fitted.map(|f| f.1),
        growth,
        chaotic,
        samples,
    })
}
