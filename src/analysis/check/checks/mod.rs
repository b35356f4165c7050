//! The checks, one function each: whether it applies (the case's
//! structure), what it measures on the run, the exact answer and the
//! tolerance it is held to (see the table of the module doc of
//! [`super`]).
//!
//! Here the row builder, the list of every check ([`all`]) and the checks
//! of the whole run (momentum, impact energy, energy conservation, Coulomb,
//! penetration, the energy ledger); `motion.rs` the checks against exact
//! motions (symmetry, head-on, Saint-Venant's bars, bouncing, sliding,
//! cradle, cannon, free drift, inertial oscillation); `fracture.rs` the checks of fracture;
//! `crushing.rs` the closed forms of crushing ice.

mod crushing;
mod fracture;
mod motion;

use super::measure::sampled_penetration;
use super::structure::no_forcing;
use super::{
    CheckOutcome, ENERGY_CONSERVED_TOLERANCE, IMPACT_ENERGY_TOLERANCE, LEDGER_TOLERANCE,
    MOMENTUM_TOLERANCE,
};
use crate::analysis::divergence::row_frames;
use crate::formulation::event_driven::{
    floe_length_scale, EventDrivenSettings, DEFAULT_PENETRATION_FRACTION,
};
use crate::geometry::Vec2;
use crate::model::Scenario;
use crate::record::counters::common::MAX_PENETRATION;
use crate::record::COULOMB_SLACK;
use crate::run::{EndReason, RunResult};
use fracture::{fracture_conservation, lattice_spin, ram_critical_speed};
use motion::{
    bouncing, cannon, cradle, free_drift, head_on, inertial, saint_venant, sliding, symmetry,
};

struct Rows<'a> {
    scn: &'a Scenario,
    run: &'a RunResult,
    out: Vec<CheckOutcome>,
}

impl Rows<'_> {
    #[allow(clippy::too_many_arguments)]
    fn push(
        &mut self,
        check: &str,
        description: &str,
        measured: f64,
        expected: Option<f64>,
        tolerance: f64,
        unit: &str,
        note: String,
    ) -> &mut CheckOutcome {
        // A check against an exact answer sets `scale` on the row returned.
        let pass = match expected {
            Some(x) => (measured - x).abs() <= tolerance,
            None => measured <= tolerance,
        };
        self.out.push(CheckOutcome {
            case: self.scn.name.clone(),
            formulation: self.run.summary.formulation.clone(),
            check: check.to_string(),
            description: description.to_string(),
            measured,
            expected,
            tolerance,
            unit: unit.to_string(),
            pass,
            claimed: true,
            note,
            scale: None,
        });
        let last = self.out.len() - 1;
        &mut self.out[last]
    }
}

/// Every check that applies to `scn`, measured on `run`, each claimed
/// (the claims are [`super::check_run`]'s).
pub(super) fn all(scn: &Scenario, run: &RunResult) -> Vec<CheckOutcome> {
    let mut r = Rows {
        scn,
        run,
        out: Vec::new(),
    };
    let completed = run.summary.end == EndReason::Completed;
    r.push(
        "run_completed",
        "the run reaches the case's duration",
        if completed { 1.0 } else { 0.0 },
        Some(1.0),
        0.0,
        "1",
        match &run.summary.end {
            EndReason::Completed => String::new(),
            other => format!("{other}; reached t = {} s", run.summary.t_reached),
        },
    );
    momentum(&mut r);
    impact_energy(&mut r);
    energy_conserved(&mut r);
    coulomb(&mut r);
    penetration(&mut r);
    // The checks of final velocities after impacts without forcing follow
    // each initial floe's material through its pieces when floes broke (a
    // split conserves momentum; `final_velocity`, docs/physics.md §9.7).
    head_on(&mut r);
    saint_venant(&mut r);
    cradle(&mut r);
    cannon(&mut r);
    // The other checks read from the case's initial floes follow those floes
    // through the run: they apply to a run whose floes did not break.
    if run.fractures.is_empty() {
        symmetry(&mut r);
        bouncing(&mut r);
        sliding(&mut r);
        free_drift(&mut r);
        inertial(&mut r);
    }
    fracture_conservation(&mut r);
    ram_critical_speed(&mut r);
    crushing::crushing(&mut r);
    crushing::crush_mass(&mut r);
    lattice_spin(&mut r);
    ledger(&mut r);
    r.out
}

fn momentum(r: &mut Rows) {
    let scn = r.scn;
    if !no_forcing(scn) || !scn.obstacles.is_empty() || scn.floes.len() < 2 {
        return;
    }
    let scale: f64 = scn.floes.iter().map(|f| f.mass * f.velocity.norm()).sum();
    if scale == 0.0 {
        return;
    }
    let p0 = scn
        .floes
        .iter()
        .fold(Vec2::zeros(), |s, f| s + f.velocity * f.mass);
    // Each floe alive at an output, with its own mass (the pieces of broken
    // floes included).
    let mass = |id: usize| r.run.floes.get(id).map_or(f64::NAN, |f| f.mass);
    let worst = row_frames(&r.run.trajectory)
        .map(|rows| {
            let p = rows.iter().fold(Vec2::zeros(), |s, row| {
                s + Vec2::new(row.vx, row.vy) * mass(row.floe)
            });
            (p - p0).norm() / scale
        })
        .fold(0.0, f64::max);
    r.push(
        "momentum",
        "total momentum conserved across impacts (no forcing, no obstacle)",
        worst,
        None,
        MOMENTUM_TOLERANCE,
        "1",
        "max_t |P(t) - P(0)| / sum M |v(0)|".into(),
    )
    .scale = Some(1.0);
}

fn impact_energy(r: &mut Rows) {
    let log = &r.run.contacts;
    let Some(gain) = log.max_energy_gain() else {
        return;
    };
    let scale = r.run.summary.energy.exchanged.max(f64::MIN_POSITIVE);
    r.push(
        "impact_energy",
        "no contact event creates kinetic energy (e <= 1)",
        gain.max(0.0) / scale,
        None,
        IMPACT_ENERGY_TOLERANCE,
        "1",
        if gain > 0.0 {
            format!(
                "largest gain {gain:.3e} J over {} events / {scale:.3e} J exchanged",
                log.event_count()
            )
        } else if gain == 0.0 {
            format!(
                "no event gained energy (the largest change is 0 J) over {} events / {scale:.3e} J exchanged",
                log.event_count()
            )
        } else {
            format!(
                "every event lost energy: the smallest loss is {:.3e} J over {} events / {scale:.3e} J exchanged",
                -gain,
                log.event_count()
            )
        },
    );
}

fn energy_conserved(r: &mut Rows) {
    let scn = r.scn;
    if scn.contact.restitution != 1.0 || scn.contact.friction != 0.0 || !no_forcing(scn) {
        return;
    }
    let e0 = r.run.summary.energy.initial_kinetic;
    if e0 <= 0.0 {
        return;
    }
    let worst = r
        .run
        .energy
        .iter()
        .map(|s| (s.kinetic - e0).abs() / e0)
        .fold(0.0, f64::max);
    r.push(
        "energy_conserved",
        "kinetic energy conserved (e = 1, mu = 0, no forcing)",
        worst,
        None,
        ENERGY_CONSERVED_TOLERANCE,
        "1",
        "max_t |E(t) - E(0)| / E(0)".into(),
    )
    .scale = Some(1.0);
}

fn coulomb(r: &mut Rows) {
    let log = &r.run.contacts;
    if log.impulse_count() == 0 {
        return;
    }
    let ratio = log.max_coulomb_ratio();
    let ratio_text = if ratio.is_finite() && (ratio - 1.0).abs() < 1e-3 {
        format!(
            "1 {} {:.2e}",
            if ratio < 1.0 { "-" } else { "+" },
            (ratio - 1.0).abs()
        )
    } else {
        format!("{ratio:.4}")
    };
    r.push(
        "coulomb",
        "every contact impulse in the Coulomb cone |beta| <= mu lambda, to the solver's accuracy",
        log.max_cone_excess.unwrap_or(0.0).max(0.0),
        None,
        1.0,
        "excess/allowance",
        format!(
            "{} impulses, {} outside the cone beyond their allowance (mu lambda {COULOMB_SLACK:.0e} plus the impulse of the accepted LCP residual); largest |beta|/(mu lambda) = {ratio_text}",
            log.impulse_count(),
            log.impulses_outside_cone,
        ),
    );
}

fn penetration(r: &mut Rows) {
    let scn = r.scn;
    // With crushing, an overlap is crushed ice (cut at the next safe
    // point, docs/physics.md §10.1), not a penetration of rigid bodies.
    if (scn.floes.len() < 2 && scn.obstacles.is_empty()) || scn.contact.crushing.is_some() {
        return;
    }
    let sampled = sampled_penetration(scn, r.run);
    let own = r
        .run
        .summary
        .counters
        .value(&MAX_PENETRATION)
        .ok()
        .flatten();
    let tol = penetration_tolerance(scn);
    r.push(
        "penetration",
        "deepest overlap, at the outputs and as the formulation saw it",
        own.unwrap_or(0.0).max(sampled),
        Some(0.0),
        tol,
        "m",
        format!(
            "outputs {sampled:.3e} m, formulation {}; tolerance: the event-driven one of the case",
            own.map_or("n/a".to_string(), |v| format!("{v:.3e} m"))
        ),
    );
}

/// The event-driven penetration tolerance of the case, m (the bound of the
/// `penetration` check).
fn penetration_tolerance(scn: &Scenario) -> f64 {
    EventDrivenSettings::of(scn)
        .map_or(DEFAULT_PENETRATION_FRACTION * floe_length_scale(scn), |s| {
            s.penetration_tolerance(scn)
        })
}

fn ledger(r: &mut Rows) {
    let e = &r.run.summary.energy;
    let scale = e.exchanged.max(f64::MIN_POSITIVE);
    r.push(
        "energy_ledger",
        "energy ledger balances: |E - E0 - W_ext + D| at every output",
        e.max_abs_residual / scale,
        None,
        LEDGER_TOLERANCE,
        "1",
        format!(
            "largest residual {:.3e} J of {:.3e} J exchanged",
            e.max_abs_residual, e.exchanged
        ),
    );
}
