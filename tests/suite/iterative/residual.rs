//! On the frictional cradle's contact problems: the natural-map residual
//! (rounding at Lemke's answer, large at a spoiled one), the stop test that
//! reports the true residual of the answer it returns, and the continuation
//! of capped answers that would create energy.

use super::{frictional_cradle, lemke_answer, problems};
use floebench::iterative::{nsgs, Answer, IterativeOptions, IterativeSolver, Method, Outcome};

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
                interrupted: false,
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
fn a_stop_request_ends_nsgs_and_apgd_at_their_first_poll_with_a_finite_answer() {
    // The iterative solvers poll the thread's stop handle
    // (floebench::stop) every POLL_EVERY iterations, the first before any:
    // asked before, a solve takes no iteration, says `interrupted` and not
    // `converged`, and leaves finite impulses; a handle never set changes
    // nothing, to the bit.
    use floebench::iterative::apgd;
    use floebench::stop::{self, Interrupt};
    let scn = frictional_cradle();
    let probs = problems(&scn);
    assert!(!probs.is_empty());
    for (_, sp) in &probs {
        let solve = |method: Method| {
            let mut p = vec![[0.0; 2]; sp.len()];
            let (o, _) = match method {
                Method::Nsgs => nsgs::solve(sp, &mut p, 1e-14, 500, 1.0),
                Method::Apgd => apgd::solve(sp, &mut p, 1e-14, 500),
            };
            (o, p)
        };
        for method in [Method::Nsgs, Method::Apgd] {
            let (full, p_full) = solve(method);
            assert!(!full.interrupted);
            assert!(full.iterations > 0, "{method:?}");
            let quiet = Interrupt::own();
            let same = {
                let _current = stop::current(&quiet);
                solve(method)
            };
            assert_eq!(same, (full, p_full), "{method:?}");
            let stopped = Interrupt::own();
            stopped.request();
            let (cut, p) = {
                let _current = stop::current(&stopped);
                solve(method)
            };
            assert!(cut.interrupted && !cut.converged, "{method:?}: {cut:?}");
            assert_eq!(cut.iterations, 0, "{method:?}");
            assert!(cut.residual.is_finite());
            assert!(p.iter().flatten().all(|x| x.is_finite()));
        }
    }
}
