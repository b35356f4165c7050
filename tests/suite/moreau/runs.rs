//! Whole runs: every LCP dumped and re-solved, the solver chosen by name
//! and by the case's `solver` key, the 200-floe field against the coast
//! with both solvers.

use super::{run_checked, run_with, SOLVERS};
use crate::common::{case_text, counter, run, scenario, tempdir};
use floebench::formulation::contact_solver::SolverKind;
use floebench::formulation::moreau::MoreauSettings;
use floebench::formulation::{build, FormulationOptions};
use floebench::lcp::{residual, LcpDump};

#[test]
fn every_lcp_of_a_moreau_run_can_be_dumped_and_re_solved() {
    let dir = tempdir();
    let scn = scenario(&case_text("sliding_floe").replace("duration = 1000.0", "duration = 5.0"));
    let (r, _) = run_with(
        &scn,
        SolverKind::Lcp,
        0.05,
        FormulationOptions {
            dump_lcp: Some(dir.path().to_path_buf()),
            ..Default::default()
        },
    );
    let files: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(files.len() as f64, counter(&r, "lcp_solves"));
    assert_eq!(files.len(), 5, "one LCP per step");
    for f in &files {
        let d = LcpDump::read(f).unwrap();
        let lcp = d.to_lcp().unwrap();
        // Stewart–Trinkle: 4 unknowns per contact, 3 fewer per extra member
        // of a friction group (flush edge pairs, docs/physics.md §3.1).
        let groups = d.friction_groups.unwrap_or(d.contacts);
        assert!(groups <= d.contacts);
        assert_eq!(lcp.n, d.contacts + 3 * groups);
        assert!(residual(&lcp.m, &lcp.q, &d.z) < 1e-10);
    }
}

#[test]
fn names_and_the_case_solver_key_choose_the_solver() {
    let text = case_text("head_on");
    let scn = scenario(&text);
    let opts = FormulationOptions::default();
    assert_eq!(build("moreau", &scn, &opts).unwrap().name(), "moreau");
    assert_eq!(
        build("moreau-cone", &scn, &opts).unwrap().name(),
        "moreau-cone"
    );
    // The case has a [formulation.moreau] table (step = 0.5): its step and
    // solver replaced.
    let cone_case = scenario(&text.replacen("step = 0.5", "step = 0.25\nsolver = \"cone\"", 1));
    let s = MoreauSettings::of(&cone_case).unwrap();
    assert_eq!(s.solver, SolverKind::Cone);
    assert_eq!(s.step, 0.25);
    // The label comes from the registry entry, not from the solver in use:
    // `-f moreau` on a cone case is labelled `moreau` (its `solver` setting
    // says cone), so `-f moreau,moreau-cone` gives two labels.
    assert_eq!(build("moreau", &cone_case, &opts).unwrap().name(), "moreau");
    let r = run(&cone_case, "moreau");
    assert_eq!(r.summary.formulation, "moreau");
    assert!(counter(&r, "cone_solves") > 0.0);
}

#[test]
fn field_against_the_coast_runs_with_both_solvers_and_balances_its_ledger() {
    // 75 minutes of the 200-floe field (h = 1 s): the floes reach the coast
    // and pile up. Water drag and Coriolis make the ledger residual nonzero;
    // it measures the θ-method's energy error against the trapezoidal power
    // of each force.
    let scn = scenario(
        &case_text("fields/field_200_coast").replace("duration = 21600.0", "duration = 4500.0"),
    );
    for solver in SOLVERS {
        // Drift below 0.5 m/s: approach speeds below 1 m/s.
        let (r, mj) = run_checked(&scn, solver, 1.0);
        let e = &r.summary.energy;
        let groups = counter(&r, "contact_groups");
        let failed = counter(&r, "lcp_failed");
        // Kept by the cone solver only; none without it.
        let cone_fallbacks = if solver == SolverKind::Cone {
            counter(&r, "cone_fallback_lcp")
        } else {
            0.0
        };
        eprintln!(
            "field 75 min {solver:?}: {} contact steps, {groups} contact problems, {failed} Lemke failures (frictionless last resort), {} cone fallbacks, residual {:.3e} J of {:.3e} J exchanged, penetration {:.3} m",
            mj.contact_steps().len(),
            cone_fallbacks,
            e.max_abs_residual,
            e.exchanged,
            mj.max_penetration()
        );
        assert!(groups > 1000.0);
        assert!(e.max_abs_residual <= 1e-6 * e.exchanged);
        if solver == SolverKind::Lcp {
            // With the Coulomb rows in velocity units, Lemke's solutions pass
            // the residual check: measured 2 failures of 5,933 problems with
            // that row scaling alone (1,623 unscaled, all rejected on
            // rounding), 7 of 5,933 once the whole LCP is also scaled by the
            // mean Delassus diagonal (shared with the event-driven scheme,
            // where it took failures from 26 % to 0.05 %). Pinned at 0.2 %;
            // each failure goes to the counted frictionless last resort.
            assert!(failed * 500.0 <= groups, "{failed} of {groups} failed");
        }
    }
}
