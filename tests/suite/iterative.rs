//! The iterative contact solvers (`solver = "nsgs"` and `"apgd"`,
//! docs/physics.md §3.5): the exact local Coulomb solve, the natural-map
//! residual (zero at Lemke's answers, large at a spoiled one), NSGS and
//! APGD against Lemke on the bundled cases and the closed-form checks, the
//! contact cache, the counted unconverged solve, the stop test that
//! evaluates the residual only when a sweep's change bound allows, the
//! impacts solved by NSGS, the continuation of capped answers that would
//! create energy, and the settings' refusals.

use crate::common::{case_text, counter, run, scenario, with_formulation_table};
use floebench::analysis::check::check_run;
use floebench::contact::problem::{groups, ContactLcp, Friction, Gen};
use floebench::contact::BroadPhase;
use floebench::iterative::{
    local_coulomb, nsgs, Answer, IterativeOptions, IterativeSolver, Method, Outcome, SparseContacts,
};
use floebench::lcp::{solve, SolveOptions};
use floebench::model::Scenario;
use floebench::rng::SplitMix64;
use floebench::state::{detect_contacts, normal_velocity, System};

/// `u = W p + r` for a 2 × 2 row-major `W`.
fn velocity(w: [f64; 4], p: [f64; 2], r: [f64; 2]) -> [f64; 2] {
    [
        w[0] * p[0] + w[1] * p[1] + r[0],
        w[2] * p[0] + w[3] * p[1] + r[1],
    ]
}

#[test]
fn the_local_solve_satisfies_signorini_and_coulomb_on_random_contacts() {
    let mut rng = SplitMix64::new(38);
    let (mut stick, mut slide, mut off) = (0, 0, 0);
    for _ in 0..20_000 {
        // A contact's block: J M⁻¹ Jᵀ of two random floes' rows.
        let mut w = [0.0; 4];
        for _ in 0..2 {
            let (mi, ii) = (rng.range(1e-6, 1e-4), rng.range(1e-10, 1e-8));
            let (rn, rt) = (rng.range(-30.0, 30.0), rng.range(-30.0, 30.0));
            let jn = [1.0, 0.0, rn];
            let jt = [0.0, 1.0, rt];
            let m = [mi, mi, ii];
            for d in 0..3 {
                w[0] += jn[d] * m[d] * jn[d];
                w[1] += jn[d] * m[d] * jt[d];
                w[3] += jt[d] * m[d] * jt[d];
            }
        }
        w[2] = w[1];
        let mu = rng.range(0.0, 1.0);
        if w[0] <= mu * w[1].abs() {
            continue; // outside the uniqueness condition of the doc
        }
        let r = [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)];
        let p = local_coulomb(w, r, mu, mu > 0.0);
        let u = velocity(w, p, r);
        let scale = r[0].abs() + r[1].abs();
        let tol = 1e-10 * scale;
        assert!(p[0] >= 0.0, "λ = {} < 0", p[0]);
        assert!(u[0] >= -tol, "u_N = {} < 0 (W {w:?}, r {r:?})", u[0]);
        assert!(
            (p[0] * u[0]).abs() <= tol * p[0].max(1e-300),
            "λ u_N = {}",
            p[0] * u[0]
        );
        assert!(
            p[1].abs() <= mu * p[0] * (1.0 + 1e-9),
            "|β| = {} > μλ = {}",
            p[1].abs(),
            mu * p[0]
        );
        if p[0] == 0.0 {
            off += 1;
        } else if p[1].abs() < mu * p[0] * (1.0 - 1e-9) {
            stick += 1;
            assert!(u[1].abs() <= tol, "stick with u_T = {}", u[1]);
        } else {
            slide += 1;
            assert!(p[1] * u[1] <= tol * p[1].abs(), "friction along the slip");
        }
    }
    eprintln!("local solves: {off} off, {stick} stick, {slide} slide");
    assert!(off > 1000 && stick > 1000 && slide > 1000);
}

/// The contact groups of the active contacts of `scn` at its initial
/// state, with the free velocities and zero offsets (an impact problem).
fn problems(scn: &Scenario) -> Vec<(ContactLcp, SparseContacts)> {
    let sys = System::initial(scn);
    let mut bp = BroadPhase::new();
    let mut contacts = Vec::new();
    detect_contacts(scn, &sys.bodies, 1e-3, &mut bp, &mut contacts);
    let w: Vec<Gen> = sys.velocities();
    let offsets: Vec<f64> = contacts.iter().map(|_| 0.0).collect();
    assert!(contacts
        .iter()
        .any(|c| normal_velocity(scn, &sys.bodies, c) < 0.0));
    let centres = sys.centres();
    groups(&contacts, scn.floes.len())
        .iter()
        .map(|g| {
            let lcp = ContactLcp::assemble(
                scn,
                &centres,
                &contacts,
                g,
                &w,
                &offsets,
                Friction::PerPoint,
            );
            let sp = SparseContacts::build(scn, &centres, &contacts, g, &w, &offsets);
            (lcp, sp)
        })
        .collect()
}

/// Lemke's solution of `lcp` (asserted solved) and its impulses `(λ, β)`
/// per contact.
fn lemke_answer(lcp: &ContactLcp) -> (floebench::lcp::LcpSolution, Vec<[f64; 2]>) {
    let sol = solve(lcp.lcp(), &SolveOptions::default());
    assert!(sol.status.is_solved());
    let (l, b) = (lcp.normal(&sol.z), lcp.tangential(&sol.z));
    let p = l.iter().zip(&b).map(|(l, b)| [*l, *b]).collect();
    (sol, p)
}

/// A frictional touching row: the cradle with friction and a sideways speed.
fn frictional_cradle() -> Scenario {
    scenario(
        &case_text("cradle_touching")
            .replace("friction = 0.0", "friction = 0.5")
            .replace("velocity = [0.5, 0.0]", "velocity = [0.5, 0.2]"),
    )
}

#[test]
fn the_residual_is_rounding_at_lemkes_answer_and_large_when_spoiled() {
    let scn = frictional_cradle();
    let mut checked = 0;
    for (lcp, sp) in problems(&scn) {
        let (sol, p) = lemke_answer(&lcp);
        let exact = sp.residual(&p, true);
        assert!(exact < 1e-12, "residual of Lemke's answer {exact:e}");
        // 1 % more normal impulse everywhere: an error the residual must see.
        let spoiled: Vec<[f64; 2]> = p.iter().map(|p| [p[0] * 1.01, p[1]]).collect();
        let bad = sp.residual(&spoiled, true);
        assert!(bad > 1e-3, "spoiled residual {bad:e}");
        // The velocities of the sparse product equal the LCP's.
        let dv = lcp.velocity_changes(&sol.z);
        let v = sp.velocity_changes(&p);
        for (l, d) in dv.iter().enumerate() {
            for k in 0..3 {
                let got = v[l][k];
                assert!(
                    (got - d[k]).abs() <= 1e-12 * (1.0 + d[k].abs()),
                    "{got} vs {}",
                    d[k]
                );
            }
        }
        checked += 1;
    }
    assert!(checked >= 1);
}

#[test]
fn the_stop_test_reports_the_true_residual_of_the_answer_it_returns() {
    // NSGS evaluates the residual only when a sweep's change bound reaches
    // the tolerance, every CHECK_EVERY sweeps, and after the last sweep: at
    // every tolerance and cap (caps off the 16-sweep grid included) the
    // outcome's residual must be that of the impulses returned, recomputed
    // from scratch, and a converged answer's at most the tolerance.
    let scn = frictional_cradle();
    let probs = problems(&scn);
    let mut solves = 0;
    let mut capped = 0;
    for (_, sp) in &probs {
        for tol in [1e-3, 1e-6, 1e-10, 1e-13] {
            for cap in [1, 5, 17, 2000] {
                let mut p = vec![[0.0; 2]; sp.len()];
                let (o, dv) = nsgs::solve(sp, &mut p, tol, cap, 1.0);
                let truth = sp.residual(&p, true);
                assert!(o.iterations <= cap);
                assert!(
                    (o.residual - truth).abs() <= 1e-9 * truth + 1e-15,
                    "tol {tol:e} cap {cap}: reported {:e}, true {truth:e}",
                    o.residual
                );
                assert_eq!(o.converged, o.residual <= tol);
                if o.converged {
                    assert!(truth <= tol * (1.0 + 1e-9), "{truth:e} > {tol:e}");
                } else {
                    assert_eq!(o.iterations, cap);
                    capped += 1;
                }
                // The velocity changes returned are those of the answer.
                let v = sp.velocity_changes(&p);
                for (a, b) in v.iter().zip(&dv) {
                    for k in 0..3 {
                        assert!((a[k] - b[k]).abs() <= 1e-12 * (1.0 + a[k].abs()));
                    }
                }
                solves += 1;
            }
        }
    }
    assert!(
        solves >= 16 && capped >= 1,
        "{solves} solves, {capped} capped"
    );
}

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

/// The case `name` with `settings` in `[formulation.<table>]` (added to an
/// existing table of that name, or appended).
fn with_settings(name: &str, table: &str, settings: &str) -> String {
    let text = case_text(name);
    let header = format!("[formulation.{table}]");
    if text.contains(&header) {
        text.replace(&header, &format!("{header}\n{settings}"))
    } else {
        with_formulation_table(&text, table, settings)
    }
}

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

/// A capped answer whose impulses would give the group kinetic energy is
/// continued until it gives none (or converges), and one that gives none is
/// returned as it is: Lemke's answer on the frictional cradle with three
/// times its normal impulses throws the floes apart (it creates energy),
/// and zero impulses leave the energy as it is.
#[test]
fn a_capped_answer_that_creates_energy_is_continued_until_it_does_not() {
    let scn = frictional_cradle();
    let mut continued = 0;
    for (lcp, sp) in problems(&scn) {
        let (_, exact) = lemke_answer(&lcp);
        let unconverged = |p: Vec<[f64; 2]>| Answer {
            dv: sp.velocity_changes(&p),
            p,
            outcome: Outcome {
                iterations: 1,
                residual: 1.0,
                converged: false,
            },
            warm_hits: 0,
        };
        let opts = IterativeOptions {
            max_iterations: 5,
            ..IterativeOptions::new(Method::Nsgs)
        };
        let mut solver = IterativeSolver::new(opts);
        let thrown = unconverged(exact.iter().map(|p| [3.0 * p[0], 3.0 * p[1]]).collect());
        let (before, after) = sp.kinetic_energies(&thrown.dv);
        assert!(
            after > before * 1.01,
            "{after} J against {before} J: no gain to remove"
        );
        let (a, rounds) = solver.continue_while_creating_energy(&sp, thrown, 1.0);
        let (before, after) = sp.kinetic_energies(&a.dv);
        assert!(rounds >= 1);
        assert!(a.outcome.iterations > 1 && a.outcome.iterations <= 2000);
        assert!(
            a.outcome.converged || after <= before * (1.0 + 1e-12),
            "{after} J against {before} J after {} sweeps",
            a.outcome.iterations
        );
        assert!(
            (a.outcome.residual - sp.residual(&a.p, true)).abs()
                <= 1e-9 * a.outcome.residual + 1e-15
        );
        let rest = unconverged(vec![[0.0; 2]; sp.len()]);
        let (b2, rounds) = solver.continue_while_creating_energy(&sp, rest.clone(), 1.0);
        assert_eq!((b2, rounds), (rest, 0));
        continued += 1;
    }
    assert!(continued >= 1);
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

#[test]
fn bad_iterative_settings_are_refused_with_their_line() {
    let base = case_text("sliding_floe");
    for (table, settings, says) in [
        ("moreau", "solver = \"nsgs\"\ntolerance = 0.0", "tolerance"),
        ("moreau", "solver = \"nsgs\"\ntolerance = nan", "tolerance"),
        ("moreau", "solver = \"nsgs\"\ntolerance = 1.0", "tolerance"),
        (
            "moreau",
            "solver = \"nsgs\"\nmax_iterations = 0",
            "max_iterations",
        ),
        (
            "moreau",
            "solver = \"nsgs\"\nmax_iterations = 100000000000",
            "max_iterations",
        ),
        (
            "moreau",
            "solver = \"nsgs\"\nrelaxation = 2.5",
            "relaxation",
        ),
        (
            "moreau",
            "solver = \"apgd\"\nrelaxation = 1.2",
            "apgd chooses",
        ),
        (
            "moreau",
            "solver = \"lcp\"\ntolerance = 1e-6",
            "not of solver = \"lcp\"",
        ),
        (
            "moreau",
            "solver = \"apgd\"\npolish = true",
            "apgd's answer solves the cone relaxation",
        ),
        (
            "moreau",
            "solver = \"lcp\"\npolish = true",
            "polish is a setting of the iterative solvers",
        ),
        (
            "moreau",
            "solver = \"nsgs\"\npolish = 1",
            "must be true or false",
        ),
        ("event-driven", "tolerance = 1e-6", "iterative solvers"),
        ("event-driven", "solver = \"gauss\"", "`nsgs` or `apgd`"),
        ("rapier", "solver = \"nsgs\"", "solver"),
    ] {
        let text = with_formulation_table(&base, table, settings);
        let path = std::env::temp_dir().join(format!("iterative_bad_{}.toml", std::process::id()));
        std::fs::write(&path, &text).unwrap();
        let err = floebench::formulation::load_case(&path)
            .err()
            .unwrap_or_else(|| panic!("{table}: `{settings}` was accepted"))
            .to_string();
        let _ = std::fs::remove_file(&path);
        assert!(err.contains(says), "{settings}: {err}");
        assert!(err.contains(".toml:"), "{settings}: no file:line in {err}");
    }
}
