//! The Moreau–Jean formulation (`moreau`, `moreau-cone`) against the closed
//! forms of docs/physics.md §6. Every run also goes through the shared
//! physical checks: completed, Coulomb on every contact impulse, no
//! unresolved contact problem, and a penetration within the scheme's
//! `O(h × approach speed)` (Moreau–Jean does not project positions).
//!
//! Measured figures are printed (`cargo test --release --test suite
//! moreau:: -- --nocapture`) and pinned where they are findings rather
//! than tolerances.
//!
//! This file holds what the submodules share: the checked runs and the
//! contact problems of a case at its start (also used by other modules).
//! The tests are in the submodules, one topic each.

mod assembly;
mod closed_forms;
mod cone;
mod flush_pairs;
mod runs;

use crate::common::{counter, setting, with_formulation_table};
use floebench::contact::problem::{groups, ContactLcp, Friction, Gen};
use floebench::contact::{BroadPhase, NarrowOptions};
use floebench::formulation::contact_solver::SolverKind;
use floebench::formulation::moreau::Moreau;
use floebench::formulation::FormulationOptions;
use floebench::model::Scenario;
use floebench::record::SettingValue;
use floebench::run::{EndReason, RunOptions, RunResult, Runner};
use floebench::state::{detect_contacts_with, normal_velocity, System};

const SOLVERS: [SolverKind; 2] = [SolverKind::Lcp, SolverKind::Cone];

/// The case text with a `[formulation.moreau]` table (step `h`, s).
fn with_step(text: &str, h: f64) -> String {
    with_formulation_table(text, "moreau", &format!("step = {h:?}"))
}

/// Runs `scn` with the given solver; `v_approach` bounds the normal approach
/// speed of any contact in the case (m/s), for the penetration check.
fn run_checked(scn: &Scenario, solver: SolverKind, v_approach: f64) -> (RunResult, Moreau) {
    run_with(scn, solver, v_approach, FormulationOptions::default())
}

fn run_with(
    scn: &Scenario,
    solver: SolverKind,
    v_approach: f64,
    opts: FormulationOptions,
) -> (RunResult, Moreau) {
    let mut mj = Moreau::new(scn, &opts, Some(solver)).unwrap();
    let label = match solver {
        SolverKind::Lcp => "moreau",
        SolverKind::Cone => "moreau-cone",
    };
    let r = Runner::new(RunOptions::default()).run(scn, label, &mut mj);
    physical_checks(&r, solver, v_approach);
    (r, mj)
}

/// Checks that apply to every run.
fn physical_checks(r: &RunResult, solver: SolverKind, v_approach: f64) {
    let s = &r.summary;
    let name = format!("{} / {}", s.case, s.formulation);
    assert_eq!(s.end, EndReason::Completed, "{name}");
    let mut bad = vec!["coulomb_violations", "lcp_unresolved"];
    if solver == SolverKind::Cone {
        bad.push("cone_failed");
    }
    for bad in bad {
        assert_eq!(counter(r, bad), 0.0, "{name}: {bad}");
    }
    // |β| ≤ μ λ for every contact impulse: Lemke's accepted solutions to 1e-9
    // relative; the cone's are projected onto the cone.
    let ratio = counter(r, "max_coulomb_ratio");
    assert!(ratio <= 1.0 + 1e-9, "{name}: Coulomb ratio {ratio}");
    assert_eq!(
        s.settings
            .0
            .iter()
            .find(|x| x.name == "solver")
            .map(|x| &x.value),
        Some(&SettingValue::Text(solver.name().to_string())),
        "{name}"
    );
    // Moreau–Jean does not project positions: a contact activated at a
    // predicted gap g + hγu_N ≤ 0 ends its step at most h |u_N| deep.
    let h = setting(r, "step_s");
    let pen = counter(r, "max_penetration_m");
    assert!(
        pen <= h * v_approach,
        "{name}: penetration {pen} m beyond h v = {}",
        h * v_approach
    );
}

/// The largest difference between two lists of generalised velocities.
fn largest_difference(a: &[Gen], b: &[Gen]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0f64, f64::max)
}

/// The contact problems of a scenario's floes at t = 0 within `distance` m
/// (gaps ignored), with the case velocities as free velocities, friction
/// assembled per point.
pub(crate) fn problems_at_start(scn: &Scenario, distance: f64) -> (Vec<ContactLcp>, Vec<Gen>) {
    problems_with(scn, distance, Friction::PerPoint, &NarrowOptions::default())
}

/// [`problems_at_start`] with the friction `layout` and the contact point
/// tolerances `options`.
pub(crate) fn problems_with(
    scn: &Scenario,
    distance: f64,
    layout: Friction,
    options: &NarrowOptions,
) -> (Vec<ContactLcp>, Vec<Gen>) {
    let n = scn.floes.len();
    let sys = System::initial(scn);
    let mut cs = Vec::new();
    detect_contacts_with(
        scn,
        &sys.bodies,
        distance,
        options,
        &mut BroadPhase::new(),
        &mut cs,
    );
    let centres = sys.centres();
    let w: Vec<Gen> = sys.velocities();
    // A Newton offset e u_N on every contact, as in the formulation.
    let offsets: Vec<f64> = cs
        .iter()
        .map(|c| 0.5 * normal_velocity(scn, &sys.bodies, c))
        .collect();
    let lcps = groups(&cs, n)
        .iter()
        .map(|g| ContactLcp::assemble(scn, &centres, &cs, g, &w, &offsets, layout))
        .collect();
    (lcps, w)
}
