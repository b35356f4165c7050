//! `floebench check`: the physical checks of docs/physics.md §6, measured
//! on a recorded run, with the expected values computed from the case's own
//! parameters (masses, `e`, `μ`, wind acceleration, gaps), never stored.
//!
//! [`check_run`] decides from the case's *structure* which checks apply
//! (no case names are used):
//!
//! | check | applies when | measured | tolerance |
//! | --- | --- | --- | --- |
//! | `run_completed` | always | 1 if the run reached its duration | – |
//! | `momentum` | no forcing (no air or water drag, `f = 0`), no obstacle | `max_t ‖P(t) − P(0)‖ / Σ M‖Ġ(0)‖` | [`MOMENTUM_TOLERANCE`] |
//! | `impact_energy` | the formulation records contact events | largest kinetic energy gained by one contact event / energy exchanged | [`IMPACT_ENERGY_TOLERANCE`] |
//! | `energy_conserved` | `e = 1`, `μ = 0`, no forcing | `max_t \|E(t) − E(0)\| / E(0)` | [`ENERGY_CONSERVED_TOLERANCE`] |
//! | `coulomb` | the formulation records contact impulses | largest [`cone_excess`](crate::record::ImpulseRecord::cone_excess) over every impulse: `(\|β\| − μ λ)` over the impulse's allowance `μ λ ·` [`COULOMB_SLACK`](crate::record::COULOMB_SLACK) `+` the impulse of the accepted LCP residual (0 when every impulse is inside the cone) | 1 |
//! | `penetration` | an obstacle or two floes, no crushing (its overlaps are crushed ice) | deepest overlap at the output times (minimum translation distance) and the formulation's own `max_penetration_m` | the event-driven tolerance of the case |
//! | `symmetry` | the initial configuration is a mirror image of itself about an axis, forcing parallel to it, `f = 0`, the impacts not resolved in the lattices (`impact = "rigid"`: their random meshes are not mirror images) | `max_t,i ‖G_P(i) − S G_i‖ + r_i \|θ_P(i) + θ_i\|` | [`SYMMETRY_TOLERANCE`] × extent |
//! | `head_on_v1`, `head_on_v2` | two floes, no forcing, no obstacle, no spin, velocities along the line of centres and approaching, symmetric about it, `impact = "rigid"` (the restitution law's closed form) | final velocities along the line | [`HEAD_ON_TOLERANCE`] × approach speed |
//! | `saint_venant` | the set-up of `head_on` with `impact = "lattice"` and no dashpots (`damping = 0`): two rectangular bars along the line, of one width, thickness and density, each at least [`SLENDER`] widths long | `e_eff = −u_N(after)/u_N(before)` from the final velocities | [`SAINT_VENANT_TOLERANCE`] × `min(L1, L2)/max(L1, L2)` |
//! | `bouncing_first_impact`, `bouncing_rest` | one floe at rest at a gap `d > 0` from an obstacle, constant wind, no water drag, `f = 0`, symmetric about the wind line | time the free flight from the last output before the first contact event reaches the obstacle; rest time | penetration tolerance / `v1`; one output interval (+ rest threshold) |
//! | `sliding_distance`, `sliding_stop` | one floe touching an obstacle face, wind into it, velocity across the wind, `μ > 0`, no water drag, `f = 0` | distance along `v0`; stop time | [`SLIDING_DISTANCE_TOLERANCE`]; one output interval |
//! | `cradle_outcome` (and `cradle_physical` when touching) | ≥ 3 equal floes in a row along the first one's velocity, the others at rest, `e = 1`, no forcing, no obstacle, symmetric | final velocities | [`CRADLE_TOLERANCE`] × `v0` |
//! | `cannon_velocities` | two floes in a row at the same velocity toward an obstacle, no forcing, symmetric; the front one rebounds before they meet and leaves the wall for good | final velocities | [`CRADLE_TOLERANCE`] × `v0` |
//! | `free_drift_velocity` | no obstacle, constant wind and current, water drag, duration ≥ 20 drag time constants | final velocity of each floe | [`FREE_DRIFT_TOLERANCE`] |
//! | `inertial_period` | one floe, no obstacle or spin, still ocean, `f ≠ 0`, a calm of at least one period after the wind stops | `2π Δt / Δφ` of the velocity's turning in the calm | [`INERTIAL_PERIOD_TOLERANCE`] × `2π/\|f\|` |
//! | `fracture_conservation` | the run broke a floe | the largest relative change a split made to area, mass, linear and angular momentum, kinetic energy | [`FRACTURE_CONSERVATION_TOLERANCE`] |
//! | `ram_critical_speed` | `[fracture] model = "energy"`, one floe moving without spin toward an obstacle it meets face-on (two contact rays), no forcing, the configuration symmetric about the line of motion, faster than the closed-form critical speed `v_c` | `v0 sqrt(threshold / measure)` of the run's first fracture | [`RAM_CRITICAL_SPEED_TOLERANCE`] × `v_c` |
//! | `lattice_spin_prestress` | `[fracture] model = "lattice"` | the largest centrifugal pre-strain `(3 + ν)/8 ρ (ω R)² / E` of a floe at its last output before a percussion that broke it, over its bonds' breaking strain | [`crate::fracture::strike::SPIN_PRESTRESS_LIMIT`] |
//! | `crush_volume`, `crush_peak_force` (a corner) or `crush_force` (a face), `crush_duration` | `crushing = { strength }`, `e = 0`, one floe without spin toward an obstacle, no forcing, symmetric about the line of motion (docs/physics.md §10.3) | crushed volume; largest mean force of an output interval; time from the first contact to the stop | [`CRUSH_VOLUME_TOLERANCE`], [`CRUSH_FORCE_TOLERANCE`] (relative) |
//! | `crush_mass` | `[contact] crushing` | `\|Σ m_floes(end) + Σ deposits − Σ m(0)\| / Σ m(0)` | [`CRUSH_MASS_TOLERANCE`] |
//! | `energy_ledger` | always | `max_t \|residual\| / exchanged` | [`LEDGER_TOLERANCE`] |
//!
//! Whether a formulation *claims* a check is decided by one table,
//! each formulation's registry entry ([`formulation::Entry::not_claimed`]): every check is claimed by every formulation unless
//! listed there, with the reason. A failing claimed check makes
//! `floebench check` exit non-zero; a failing unclaimed one is printed as
//! `fail (known)`, a finding.
//!
//! Which formulations run ([`crate::run::batch::default_formulations`]):
//! every formulation of [`crate::formulation::REGISTRY`], except
//! `free-drift` on a case where contacts can happen. A case is
//! *contact-free* ([`Scenario::contact_free`]) when it has no obstacle and every floe
//! starts at rest (only the environment moves them; the drift cases keep
//! their floes apart, which the `penetration` check verifies).
//!
//! This file holds the outcome, the tolerances, the claims and
//! [`check_run`]; the parts behind it are `structure.rs` (what a case's
//! structure is: forcing, mirror axes and pairings, rows of floes, gaps,
//! wind as gravity), `setup.rs` (the set-ups with a closed-form motion:
//! bouncing, sliding, drifting, inertial; recognising one is the
//! applicability rule of its checks), `exact.rs` (the closed forms),
//! `measure.rs` (measurements on a run shared by several checks), `ram.rs` (a floe
//! rammed into a coast whose ice crushes: its set-up, closed forms and measures),
//! `checks/` (each check) and [`curves`] (the exact curves of the set-ups
//! beside the runs, for the report's plots). Their public items are
//! re-exported here. A check against an exact answer carries its scale
//! ([`CheckOutcome::scale`]), on which the verdicts rank and tie.

mod checks;
pub mod curves;
mod exact;
mod measure;
mod ram;
mod setup;
mod structure;

pub use exact::{
    head_on_velocities, ram_critical_speed_of, steady_drift_velocity, wind_acceleration,
};
pub use measure::{rest_time, sampled_penetration};
pub use ram::{Ram, RamShape};
pub use setup::{Bouncing, Drift, Inertial, Sliding};
pub use structure::{find_symmetry, mirror_pairing, no_forcing, translation_gap, Axis};

use crate::formulation;
use crate::model::Scenario;
use crate::run::RunResult;
use serde::Serialize;

/// The result of one check on one run.
#[derive(Debug, Clone, Serialize)]
pub struct CheckOutcome {
    /// Case name.
    pub case: String,
    /// Formulation name.
    pub formulation: String,
    /// Short id of the check, e.g. `head_on_v1`.
    pub check: String,
    /// What is checked, in words.
    pub description: String,
    /// The measured value, in `unit`.
    pub measured: f64,
    /// The exact value where there is one, in `unit`.
    pub expected: Option<f64>,
    /// The tolerance on `|measured − expected|` (or the bound on `measured`
    /// when there is no expected value), in `unit`.
    pub tolerance: f64,
    /// Unit of `measured`, `expected`, `tolerance` (`1`: dimensionless).
    pub unit: String,
    /// Whether the run passes.
    pub pass: bool,
    /// Whether the formulation claims to pass ([`not_claimed`]).
    pub claimed: bool,
    /// A detail of the measurement; when the check fails and is not
    /// claimed, the reason first (`reason [detail]`).
    pub note: String,
    /// For a check against an exact answer (a closed form or a conserved
    /// quantity, docs/physics.md §6.1), the scale of that answer in `unit`:
    /// two errors closer than [`crate::analysis::ranking::ROUNDING`] × the
    /// scale are tied. `None` for a bound a scheme is held to (penetration,
    /// Coulomb, energy at impacts, the ledger, completion).
    pub scale: Option<f64>,
}

impl CheckOutcome {
    /// The error to the exact answer, in `unit`: `|measured − expected|`,
    /// or `measured` when there is no expected value (a deviation);
    /// infinite when not measured (NaN).
    pub fn error(&self) -> f64 {
        let e = match self.expected {
            Some(x) => (self.measured - x).abs(),
            None => self.measured.abs(),
        };
        if e.is_nan() {
            f64::INFINITY
        } else {
            e
        }
    }
}

/// Momentum conserved to this fraction of `Σ M ‖Ġ(0)‖`: impulses are applied
/// in equal and opposite pairs, so only rounding (1e-16 per impact) changes
/// the total; 1e-10 leaves room for thousands of impacts, and a missing
/// reaction (a one-sided impulse) changes it by order one.
pub const MOMENTUM_TOLERANCE: f64 = 1e-10;

/// Largest kinetic energy one contact event may create, as a fraction of the
/// energy exchanged in the run: the group energies round at 1e-16 and an LCP
/// solution is accepted at a residual of 1e-10 of the velocities (2e-10 of
/// the energy); an impact law that creates energy does so at the scale of
/// the impact's energy.
pub const IMPACT_ENERGY_TOLERANCE: f64 = 1e-9;

/// Kinetic energy conserved to this fraction of `E(0)` for `e = 1`, `μ = 0`
/// without forcing: the same rounding and LCP-residual argument as
/// [`IMPACT_ENERGY_TOLERANCE`], over hundreds of impacts.
pub const ENERGY_CONSERVED_TOLERANCE: f64 = 1e-9;

/// Trajectories stay mirror images to this fraction of the configuration's
/// extent: the initial data are mirror images to rounding (1e-16), each floe
/// is integrated at a relative tolerance of 1e-10 per step, summed over up to
/// 1e4 steps; a broken symmetry (a one-sided impulse, a spurious spin)
/// shows at the scale of the motion.
pub const SYMMETRY_TOLERANCE: f64 = 1e-6;

/// Head-on velocities to this fraction of the approach speed: an LCP
/// solution is accepted at a residual of 1e-10 of the velocities.
pub const HEAD_ON_TOLERANCE: f64 = 1e-9;

/// Saint-Venant's `e = min(L1, L2)/max(L1, L2)` to this fraction: the
/// lattices are 2D bars of finite width on a random mesh, not the 1D
/// theory's; through the runner (docs/results/2026-12-06-lattice-bars.md,
/// bars 10 m wide) they separate 2.6 % (L1/L2 = 1/2) and 4.7 % (1/3) above
/// it and 3.3 % below it (equal bars) at the finest spacing measured, 9.0 %
/// above it for 1/3 at the coarse 2.5 m of `cases/lattice_bars.toml`; the
/// restitution law in their place (e = 0.9 of the case) errs by 80 %.
pub const SAINT_VENANT_TOLERANCE: f64 = 0.1;

/// `saint_venant` applies to bars at least this many widths long (the 1D
/// theory's slender bars; at 10 widths the lattices are within 5 % of it).
pub const SLENDER: f64 = 5.0;

/// Cradle and cannon velocities to this fraction of `v0` (the same reason as
/// [`HEAD_ON_TOLERANCE`]).
pub const CRADLE_TOLERANCE: f64 = 1e-9;

/// The sliding distance to this fraction of `v0² / (2 μ a)`: a consistent
/// scheme at the bundled steps errs by `O(h²)` (`μ a h² / 8`, 1e-5 m at 1 s)
/// or `O(v0 h / n)` with substeps (0.6 mm of 17 m); a friction law off by
/// 1 % moves the stop by 1 %.
pub const SLIDING_DISTANCE_TOLERANCE: f64 = 1e-4;

/// A floe is at rest once its speed stays below this fraction of the
/// reference speed (`v1` bouncing, `v0` sliding): decelerating uniformly it
/// is that slow only in the last 1e-3 of its stopping time.
pub const REST_SPEED_FRACTION: f64 = 1e-3;

/// The inertial period to this fraction of `2π/|f|`: the velocity turns at
/// exactly `−f` whatever the water drag (docs/physics.md §2.2), so only the
/// integration errs: by about 1e-9 at the integrators' tolerance of 1e-10,
/// by `(f h)²/6` (3e-9 at `h` = 1 s) for Heun's method, by about `c |v| h`
/// per step for a first-order scheme holding the drag over the step (6e-5
/// for rapier's 0.1 s step at 0.2 m/s; measured on `inertial_oscillation`:
/// 4.4e-6); a wrong Coriolis term (sign, a factor, the mass) errs at order
/// one.
pub const INERTIAL_PERIOD_TOLERANCE: f64 = 1e-4;

/// The free-drift velocity to this fraction of the steady speed: the
/// integrators run at 1e-10 and after 20 drag time constants the transient
/// is `e^-20` = 2e-9 of the initial gap.
pub const FREE_DRIFT_TOLERANCE: f64 = 1e-6;

/// Drag time constants a run must last for the free-drift check to apply.
pub const FREE_DRIFT_TIME_CONSTANTS: f64 = 20.0;

/// The energy-ledger residual to this fraction of the energy exchanged: the
/// integrators run at 1e-10 relative; an energy term missing from the
/// ledger (unbooked dissipation, work of a force) is a sizeable fraction of
/// the exchanges.
pub const LEDGER_TOLERANCE: f64 = 1e-6;

/// `fracture_conservation`: a split partitions the parent and gives the
/// pieces its rigid velocity field, so only the rounding of the polygon
/// formulas (about 1e-15 relative, done in the parent's centre frame)
/// changes what it conserves; a piece given the parent's velocity instead
/// changes the angular momentum and the energy at order one.
pub const FRACTURE_CONSERVATION_TOLERANCE: f64 = 1e-12;

/// `ram_critical_speed`, relative to `v_c`: the run's measure is the impact
/// impulse, exact to the LCP's residual of 1e-10 of the velocities, so the
/// critical speed it implies is exact to about that; a criterion off by a
/// factor (the restitution forgotten, the impulse of one contact point
/// instead of the pair's) moves it at order one.
pub const RAM_CRITICAL_SPEED_TOLERANCE: f64 = 1e-6;

/// `crush_volume`, relative to the closed form `½ M V² / σ_c`
/// (docs/physics.md §10.3): all the normal kinetic energy is crushed ice;
/// the cuts remove it step by step, and the force lags the cut by one step
/// (O(h) of the crushing time).
pub const CRUSH_VOLUME_TOLERANCE: f64 = 0.02;

/// `crush_peak_force` and `crush_duration`, relative to their closed forms
/// (docs/physics.md §10.3): the force is measured as the mean of each
/// output interval, `M Δv / Δt` (the crushed mass, 1e-3 of the floe's in
/// the bundled cases, is neglected), which samples the peak to
/// `(ω Δt)²/24`.
pub const CRUSH_FORCE_TOLERANCE: f64 = 0.05;

/// `crush_mass`, relative: a cut moves the crushed mass to a floe's
/// thickness or a coast's deposit exactly but for the rounding of the
/// polygon areas (about 1e-16 relative per cut); a cut that lost its ice
/// would move it by the crushed fraction (1e-4 to 1e-3 in the bundled
/// cases).
pub const CRUSH_MASS_TOLERANCE: f64 = 1e-12;

/// The reason formulation `formulation` does not claim `check` on `case`
/// (its registry entry's [`formulation::NotClaimed`] list), or `None` when
/// it claims it; an unknown formulation claims nothing.
pub fn not_claimed(formulation: &str, check: &str, case: &str) -> Option<&'static str> {
    match formulation::entry(formulation) {
        Ok(e) => e.not_claimed(check, case),
        Err(_) => Some("not a formulation of the registry"),
    }
}

// ---------------------------------------------------------------------------
// Running the checks.

/// Every check that applies to `scn`, measured on `run` (see the module
/// doc); `claimed` and `note` from [`not_claimed`].
pub fn check_run(scn: &Scenario, run: &RunResult) -> Vec<CheckOutcome> {
    let mut out = checks::all(scn, run);
    for o in &mut out {
        if let Some(reason) = not_claimed(&o.formulation, &o.check, &o.case) {
            o.claimed = false;
            // The reason explains a failure: a passing row keeps its detail only.
            if !o.pass {
                o.note = if o.note.is_empty() {
                    reason.to_string()
                } else {
                    format!("{reason} [{}]", o.note)
                };
            }
        }
    }
    out
}

/// The checks of every run of `scn`, run by run ([`check_run`]).
pub fn check_runs(scn: &Scenario, runs: &[RunResult]) -> Vec<CheckOutcome> {
    runs.iter().flat_map(|r| check_run(scn, r)).collect()
}

// ---------------------------------------------------------------------------
// Outcomes.

/// Number of checks that fail although the formulation claims them.
pub fn claimed_failures(rows: &[CheckOutcome]) -> usize {
    rows.iter().filter(|o| o.claimed && !o.pass).count()
}

/// `pass`, `FAIL` (claimed) or `fail (known)` (not claimed).
pub fn verdict(o: &CheckOutcome) -> &'static str {
    match (o.pass, o.claimed) {
        (true, _) => "pass",
        (false, true) => "FAIL",
        (false, false) => "fail (known)",
    }
}
