//! NSGS and APGD against Lemke on the closed-form checks of the bundled
//! cases: at a tight tolerance, at the default one, and APGD on the
//! frictionless problems; the pinned findings (`KNOWN`).

use super::with_settings;
use crate::common::{case_text, counter, run, scenario};
use floebench::analysis::check::check_run;

/// The cases whose checks compare NSGS with Lemke (the small bundled ones
/// with contacts, without fracture).
const CASES: [&str; 9] = [
    "head_on",
    "bouncing_floe",
    "sliding_floe",
    "cradle_touching",
    "cradle_gaps",
    "newtons_cannon",
    "mirror_collision",
    "elastic_pool",
    "l_shaped_corner",
];

/// One check that Lemke passes, with NSGS's outcome: case, formulation,
/// check, Lemke's error, NSGS's error, the answer's scale, NSGS passes.
type Compared = (String, String, String, f64, f64, Option<f64>, bool);

/// Runs every case of [`CASES`] under `moreau` and `event-driven`, with
/// Lemke and with NSGS (`settings` added), and returns the checks Lemke
/// passes with NSGS's outcome on them.
fn checks_against_lemke(settings: &str) -> Vec<Compared> {
    let mut out = Vec::new();
    for case in CASES {
        for formulation in ["moreau", "event-driven"] {
            let lemke = scenario(&case_text(case));
            let nsgs = scenario(&with_settings(case, formulation, settings));
            let (a, b) = (run(&lemke, formulation), run(&nsgs, formulation));
            assert_eq!(b.summary.settings.get_text("solver"), Some("nsgs"));
            let tol = b.summary.settings.get("tolerance").unwrap();
            let res = counter(&b, "contact_residual_max");
            assert!(
                res <= tol,
                "{case} {formulation}: residual {res:e} > {tol:e}"
            );
            assert_eq!(counter(&b, "contact_unconverged"), 0.0, "{case}");
            let (ca, cb) = (check_run(&lemke, &a), check_run(&nsgs, &b));
            for o in ca.iter().filter(|o| o.pass) {
                let Some(n) = cb.iter().find(|x| x.check == o.check) else {
                    panic!("{case} {formulation}: no {} check for nsgs", o.check)
                };
                out.push((
                    case.to_string(),
                    formulation.to_string(),
                    o.check.clone(),
                    o.error(),
                    n.error(),
                    o.scale,
                    n.pass,
                ));
            }
        }
    }
    out
}

/// The finding of docs/physics.md §3.5, pinned: under `moreau` with NSGS,
/// once the sliding floe has stopped against the wall, its flush contact is
/// detected with one point instead of two and it rocks into the wall
/// (0.27 m at the default tolerance, 0.058 m at 1e-12: Moreau–Jean's
/// detection margin `2hγ v_max` leaves out a contact at a gap of +1e-13 m
/// beside a floe at rest; Lemke's answers happen to leave that gap ≤ 0).
/// The floe never comes to rest, so its stop time and distance miss too.
/// And under `event-driven` one impulse of the NSGS run leaves the cone by
/// 2.3e-9 of `μλ` (above the check's 1e-9), not traced to NSGS or to the
/// impacts' Lemke LCPs of that run.
const KNOWN: [(&str, &str, &str); 4] = [
    ("sliding_floe", "moreau", "penetration"),
    ("sliding_floe", "moreau", "sliding_stop"),
    ("sliding_floe", "moreau", "sliding_distance"),
    ("sliding_floe", "event-driven", "coulomb"),
];

#[test]
fn nsgs_passes_every_closed_form_check_that_lemke_passes_at_a_tight_tolerance() {
    let rows = checks_against_lemke("solver = \"nsgs\"\ntolerance = 1e-12");
    assert!(rows.len() > 50, "{} checks compared", rows.len());
    for (case, f, check, _, err, _, pass) in &rows {
        let known = KNOWN.contains(&(case.as_str(), f.as_str(), check.as_str()));
        if known {
            eprintln!("{case} {f} {check}: nsgs error {err:e}, passes: {pass} (KNOWN)");
        } else {
            assert!(pass, "{case} {f} {check}: nsgs error {err:e}");
        }
    }
}

#[test]
fn at_its_default_tolerance_nsgs_misses_only_exact_answers_by_the_tolerance() {
    // The finding of docs/physics.md §3.5: a Gauss-Seidel stopped at a
    // residual of 1e-6 leaves errors of that order in the closed-form
    // velocities, above their 1e-9 tolerances, and in the bounds it is held
    // to (an elastic impact's energy); beyond that only the pinned findings
    // of KNOWN.
    let rows = checks_against_lemke("solver = \"nsgs\"");
    let tol = floebench::iterative::DEFAULT_TOLERANCE;
    let mut missed = 0;
    for (case, f, check, lemke, err, scale, pass) in &rows {
        if *pass {
            continue;
        }
        missed += 1;
        eprintln!("{case:16} {f:12} {check:22} lemke {lemke:.2e} nsgs {err:.2e} (scale {scale:?})");
        if KNOWN.contains(&(case.as_str(), f.as_str(), check.as_str())) {
            continue;
        }
        // A bound (no exact answer): missed by at most ten tolerances (an
        // elastic impact's energy gain of 1.3e-7 on elastic_pool).
        let scale = scale.unwrap_or(1.0);
        assert!(
            *err <= 10.0 * tol * scale,
            "{case} {f} {check}: error {err:e} beyond 10 × tolerance × {scale:e}"
        );
    }
    eprintln!(
        "{missed} of {} checks Lemke passes are missed by nsgs at {tol:e}",
        rows.len()
    );
}

#[test]
fn apgd_solves_the_frictionless_problems_as_lemke_does() {
    // Without friction the cone relaxation is the exact problem.
    for case in ["head_on", "cradle_touching", "elastic_pool"] {
        let apgd = scenario(&with_settings(
            case,
            "moreau",
            "solver = \"apgd\"\ntolerance = 1e-10",
        ));
        if apgd.contact.friction > 0.0 {
            continue;
        }
        let lemke = scenario(&case_text(case));
        let (a, b) = (run(&lemke, "moreau"), run(&apgd, "moreau"));
        assert_eq!(b.summary.settings.get_text("solver"), Some("apgd"));
        let res = counter(&b, "contact_residual_max");
        assert!(res <= 1e-10, "{case}: apgd residual {res:e}");
        let (ea, eb) = (
            a.energy.last().unwrap().kinetic,
            b.energy.last().unwrap().kinetic,
        );
        assert!(
            (ea - eb).abs() <= 1e-7 * ea.abs().max(1e-300),
            "{case}: kinetic energy {ea} (lemke) vs {eb} (apgd)"
        );
    }
}
