//! The two residuals of every contact solve (issue 55, docs/output-format.md
//! "Residuals"): the solver's own error on the problem it solved, apart from
//! the departure of the impulses from Coulomb's law, and the flag of the
//! solves that missed their solver's tolerance.

use crate::common::{case_text, counter, run, scenario, with_formulation_table};

/// The cone relaxation departs from Coulomb's law by design on the channel
/// (a sliding contact lifts off), while clarabel solves its own problem to
/// its accuracy: the law's residual is large, the solver's small, and no
/// solve missed.
#[test]
fn the_relaxation_departs_from_the_law_not_from_its_solver() {
    let scn = scenario(&case_text("narrow_channel"));
    let r = run(&scn, "moreau-cone");
    let law = counter(&r, "contact_residual_max");
    let own = counter(&r, "contact_solver_residual_max");
    assert!(law > 0.1, "the relaxation's lift: {law}");
    assert!(own < 1e-4, "clarabel's own residual: {own}");
    assert_eq!(counter(&r, "contact_solver_missed"), 0.0);
    // Lemke's own residual is its accepted LCP residual.
    let e = run(&scn, "event-driven");
    assert_eq!(
        counter(&e, "contact_solver_residual_max"),
        counter(&e, "lcp_max_accepted_residual")
    );
    assert!(counter(&e, "contact_solver_residual_max") <= 1e-10);
}

/// NSGS capped at one sweep misses its tolerance: the solves are counted as
/// missed, and the solver's residual is then above the tolerance.
#[test]
fn a_solver_that_missed_its_tolerance_is_flagged() {
    let text = with_formulation_table(
        &case_text("narrow_channel"),
        "moreau",
        "solver = \"nsgs\"\ntolerance = 1e-8\nmax_iterations = 1",
    );
    let r = run(&scenario(&text), "moreau");
    let missed = counter(&r, "contact_solver_missed");
    assert!(missed > 0.0, "{missed}");
    assert_eq!(missed, counter(&r, "contact_unconverged"));
    assert!(counter(&r, "contact_solver_residual_max") > 1e-8);
}
