//! The iterative solvers in runs: impacts solved by NSGS, the exact polish
//! of a loose answer, the contact cache, and the counted unconverged solve.

use super::with_settings;
use crate::common::{case_text, counter, run, scenario};

#[test]
fn impacts_are_solved_by_nsgs_when_it_is_the_solver_and_by_lemke_under_apgd() {
    // docs/physics.md §3.5: with solver = "nsgs" the event-driven scheme's
    // compression problems go to NSGS (no LCP is solved); APGD's cone
    // relaxation is not Poisson's law, so its impacts stay on Lemke.
    for (solver, lcp) in [("nsgs", false), ("apgd", true)] {
        let text = with_settings(
            "head_on",
            "event-driven",
            &format!("solver = \"{solver}\"\ntolerance = 1e-10"),
        );
        let r = run(&scenario(&text), "event-driven");
        assert!(counter(&r, "impacts") >= 1.0, "{solver}: no impact");
        let lcps = counter(&r, "lcp_solves");
        assert_eq!(lcps > 0.0, lcp, "{solver}: {lcps} LCPs");
        assert!(counter(&r, "contact_solves_measured") >= 1.0);
        if solver == "nsgs" {
            assert!(counter(&r, "contact_residual_max") <= 1e-10);
            assert_eq!(counter(&r, "contact_unconverged"), 0.0);
        }
    }
}

/// The largest distance between the centres of mass of `a` and `b` at
/// their common output times, m.
fn largest_distance(a: &floebench::run::RunResult, b: &floebench::run::RunResult) -> f64 {
    a.trajectory
        .iter()
        .zip(&b.trajectory)
        .map(|(p, q)| {
            assert_eq!((p.t, p.floe), (q.t, q.floe));
            (p.x - q.x).hypot(p.y - q.y)
        })
        .fold(0.0, f64::max)
}

#[test]
fn polish_finishes_a_loose_nsgs_answer_on_lemkes() {
    // docs/physics.md §3.5, "Exact polish": NSGS stopped at a loose 1e-2,
    // then finished by the pivoting solver from its active set, gives
    // Lemke's trajectories (these problems have one solution); without the
    // polish it misses them by the tolerance's effect.
    for (case, formulation) in [
        ("newtons_cannon", "moreau"),
        ("newtons_cannon", "event-driven"),
        ("cradle_touching", "moreau"),
        ("cradle_touching", "event-driven"),
    ] {
        let lemke = run(&scenario(&case_text(case)), formulation);
        let loose = "solver = \"nsgs\"\ntolerance = 1e-2";
        let raw = run(
            &scenario(&with_settings(case, formulation, loose)),
            formulation,
        );
        let polished = run(
            &scenario(&with_settings(
                case,
                formulation,
                &format!("{loose}\npolish = true"),
            )),
            formulation,
        );
        let solves = counter(&polished, "polish_solves");
        assert!(solves >= 1.0, "{case} {formulation}: no polish");
        assert_eq!(counter(&polished, "polish_failed"), 0.0);
        assert_eq!(
            solves,
            counter(&polished, "contact_solves_measured"),
            "{case} {formulation}: every answer polished"
        );
        let res = counter(&polished, "contact_residual_max");
        assert!(
            res <= 1e-9,
            "{case} {formulation}: polished residual {res:e}"
        );
        let (d_polished, d_raw) = (
            largest_distance(&lemke, &polished),
            largest_distance(&lemke, &raw),
        );
        eprintln!("{case} {formulation}: off Lemke by {d_polished:e} m polished, {d_raw:e} m not");
        assert!(
            d_polished <= 1e-9,
            "{case} {formulation}: polished answer {d_polished:e} m off Lemke's"
        );
        assert!(d_raw > 1e3 * d_polished.max(1e-12), "{case} {formulation}");
    }
}

#[test]
fn the_contact_cache_starts_sustained_contacts_warm() {
    let scn = scenario(&with_settings(
        "sliding_floe",
        "moreau",
        "solver = \"nsgs\"",
    ));
    let r = run(&scn, "moreau");
    let rate = counter(&r, "contact_warm_hit_rate");
    assert!(rate > 0.5, "hit rate {rate}");
    // A warm start of a sustained contact needs at most a sweep or two.
    assert!(counter(&r, "contact_iterations_median") <= 2.0);
}

#[test]
fn an_unconverged_solve_is_counted_and_its_answer_kept_finite() {
    let text = with_settings(
        "narrow_channel",
        "moreau",
        "solver = \"nsgs\"\ntolerance = 1e-14\nmax_iterations = 1",
    );
    let r = run(&scenario(&text), "moreau");
    assert!(counter(&r, "contact_unconverged") > 0.0);
    // One sweep leaves answers that would throw floes apart (43 solves
    // gave their group energy, up to 129 J, before the guard): each is
    // continued until it gives none.
    assert!(counter(&r, "contact_solves_continued") > 0.0);
    assert_eq!(counter(&r, "contact_energy_increases"), 0.0);
    let res = counter(&r, "contact_residual_max");
    assert!(res.is_finite() && res > 1e-14, "{res:e}");
    assert!(r
        .trajectory
        .iter()
        .all(|row| row.x.is_finite() && row.y.is_finite()));
}
