//! Problems the solver must refuse or fail cleanly: infeasible LCPs (ray
//! termination), the pivot cap, non-finite input, bad options; and the
//! driver never accepting a non-solution while its fallbacks rescue some.

use super::{assert_valid_solution, diag_dominant, nonsym_pd};
use floebench::lcp::{
    lemke, residual, solve, Lcp, LemkeOptions, SolveOptions, SolveStatus, Strategy, Termination,
};
use floebench::rng::SplitMix64;

#[test]
fn infeasible_1x1_reports_ray_termination() {
    let lcp = Lcp::new(1, vec![-1.0], vec![-1.0]).expect("sizes");
    let r = lemke(&lcp.m, &lcp.q, &LemkeOptions::default());
    assert_eq!(r.termination, Termination::RayTermination);
    assert!(r.pivots <= 2, "pivots {}", r.pivots);
    let s = solve(&lcp, &SolveOptions::default());
    assert_eq!(s.status, SolveStatus::Failed);
    assert_eq!(s.accepted_by, None);
    assert_eq!(s.attempts.len(), 5, "{:?}", s.attempts); // lexicographic, alternative, 3 perturbed
    assert!(s.attempts.iter().all(|a| !a.accepted));
    assert!(s.z.iter().all(|x| x.is_finite() && *x >= 0.0));
    assert!(
        s.residual.is_finite() && s.residual > 0.1,
        "residual {}",
        s.residual
    );
}

#[test]
fn infeasible_2x2_psd_reports_ray_termination() {
    // M = [[1, −1], [−1, 1]] is PSD (copositive-plus); w1 + w2 = −2 < 0 for
    // every z, so the LCP is infeasible and Lemke must end on a ray.
    let lcp = Lcp::new(2, vec![1.0, -1.0, -1.0, 1.0], vec![-1.0, -1.0]).expect("sizes");
    let r = lemke(&lcp.m, &lcp.q, &LemkeOptions::default());
    assert_eq!(r.termination, Termination::RayTermination);
    let cap = LemkeOptions::default().max_pivots.unwrap_or(50 * 3);
    assert!(r.pivots < cap);
    let s = solve(&lcp, &SolveOptions::default());
    assert_eq!(s.status, SolveStatus::Failed);
    assert_eq!(s.attempts.len(), 5);
    for a in &s.attempts {
        assert!(a.pivots <= 50 * 3, "{a:?}");
        assert!(!a.accepted && a.residual > 0.1, "{a:?}");
        if a.strategy == Strategy::Perturbed {
            // M + εI is positive definite, so Lemke solves the perturbed
            // problem (ε_rel = 1e-9, 1e-6), but that z is rejected on the
            // original data; with ε_rel = 1e-12 the blocking entries (~ε) are
            // below the pivot tolerance: "pivot too small".
            let expected = if a.epsilon_rel < 1e-11 {
                Termination::NumericalFailure
            } else {
                Termination::Solved
            };
            assert_eq!(a.termination, expected, "{a:?}");
        } else {
            assert_eq!(a.termination, Termination::RayTermination, "{a:?}");
        }
    }
    assert!(s.z.iter().all(|x| x.is_finite() && *x >= 0.0));
}

#[test]
fn pivot_cap_reports_max_pivots() {
    let mut rng = SplitMix64::new(0x5EED_F10E_0005);
    let n = 20;
    let m = diag_dominant(&mut rng, n);
    let q = vec![-1.0; n];
    let full = lemke(&m, &q, &LemkeOptions::default());
    assert_eq!(full.termination, Termination::Solved);
    assert!(full.pivots > 3);
    let r = lemke(
        &m,
        &q,
        &LemkeOptions {
            max_pivots: Some(3),
            ..LemkeOptions::default()
        },
    );
    assert_eq!((r.termination, r.pivots), (Termination::MaxPivots, 3));
    assert!(r.z.iter().all(|x| x.is_finite()));
    let s = solve(
        &Lcp::new(n, m, q).expect("sizes"),
        &SolveOptions {
            max_pivots: Some(3),
            polish: false,
            ..SolveOptions::default()
        },
    );
    assert_eq!(s.status, SolveStatus::Failed);
    assert!(s
        .attempts
        .iter()
        .all(|a| a.termination == Termination::MaxPivots && a.pivots == 3));
}

#[test]
fn non_finite_input_gives_failure_status_not_panic() {
    let mut q = vec![-1.0, 0.5, f64::NAN];
    let m = vec![2.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 2.0];
    let r = lemke(&m, &q, &LemkeOptions::default());
    assert_eq!(r.termination, Termination::NumericalFailure);
    assert!(r.z.iter().all(|x| x.is_finite()));
    assert_eq!(r.residual, f64::INFINITY);
    let s = solve(
        &Lcp::new(3, m.clone(), q.clone()).expect("sizes"),
        &SolveOptions::default(),
    );
    assert_eq!(s.status, SolveStatus::Failed);
    assert_eq!(s.z, vec![0.0; 3]);
    assert_eq!(
        s.attempts.len(),
        1,
        "non-finite data: no pointless fallbacks"
    );
    assert_eq!(s.residual, f64::INFINITY);
    // The summary serialises (Infinity as a string) and reads back.
    let json = serde_json::to_string(&s).expect("serialise");
    let back: floebench::lcp::LcpSolution = serde_json::from_str(&json).expect("deserialise");
    assert_eq!(back.residual, f64::INFINITY);
    assert_eq!(back.status, SolveStatus::Failed);

    q[2] = 1.0;
    let mut m_inf = m.clone();
    m_inf[4] = f64::INFINITY;
    let s = solve(
        &Lcp::new(3, m_inf, q.clone()).expect("sizes"),
        &SolveOptions::default(),
    );
    assert_eq!(s.status, SolveStatus::Failed);
    assert!(s.z.iter().all(|x| x.is_finite()));

    // Bad covering vector / sizes / options: InvalidInput, no panic.
    let bad = LemkeOptions {
        covering: Some(vec![1.0, -1.0, 1.0]),
        ..LemkeOptions::default()
    };
    assert_eq!(lemke(&m, &q, &bad).termination, Termination::InvalidInput);
    let bad = LemkeOptions {
        covering: Some(vec![1.0]),
        ..LemkeOptions::default()
    };
    assert_eq!(lemke(&m, &q, &bad).termination, Termination::InvalidInput);
    let bad = LemkeOptions {
        pivot_tol: f64::NAN,
        ..LemkeOptions::default()
    };
    assert_eq!(lemke(&m, &q, &bad).termination, Termination::InvalidInput);
    assert_eq!(
        lemke(&m[..8], &q, &LemkeOptions::default()).termination,
        Termination::InvalidInput
    );
    let inconsistent = Lcp {
        n: 3,
        m: vec![1.0; 4],
        q: q.clone(),
    };
    let s = solve(&inconsistent, &SolveOptions::default());
    assert_eq!((s.status, s.attempts.len()), (SolveStatus::Failed, 0));
    let s = solve(
        &Lcp::new(3, m, q).expect("sizes"),
        &SolveOptions {
            tolerance: f64::NAN,
            ..SolveOptions::default()
        },
    );
    assert_eq!(s.status, SolveStatus::Failed);
}

#[test]
fn a_non_finite_entry_anywhere_is_refused_by_the_one_pass_scan() {
    // The driver reads M and q once, four entries at a time: a NaN or an
    // infinity in any position (including the remainder of the four-lane
    // scan) makes the solve fail with z = 0, never a NaN.
    let mut rng = SplitMix64::new(0x5EED_5A11_0003);
    for n in 1..=6 {
        let m = nonsym_pd(&mut rng, n);
        let q: Vec<f64> = (0..n).map(|_| -rng.uniform() - 0.1).collect();
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for k in 0..n * n + n {
                let (mut m2, mut q2) = (m.clone(), q.clone());
                if k < n * n {
                    m2[k] = bad;
                } else {
                    q2[k - n * n] = bad;
                }
                let s = solve(
                    &Lcp::new(n, m2, q2).expect("sizes"),
                    &SolveOptions::default(),
                );
                assert_eq!(s.status, SolveStatus::Failed, "n = {n}, entry {k}, {bad}");
                assert!(s.z.iter().all(|&x| x == 0.0), "n = {n}, entry {k}");
            }
        }
        let s = solve(&Lcp::new(n, m, q).expect("sizes"), &SolveOptions::default());
        assert_eq!(s.status, SolveStatus::Solved, "n = {n}");
    }
}

#[test]
fn driver_never_accepts_a_non_solution_and_fallbacks_do_work() {
    // Arbitrary small integer LCPs (mostly neither P nor copositive: Lemke may
    // end on a ray although a solution exists, or the LCP may be infeasible).
    // Whatever happens, an accepted z must pass an independent check, and the
    // fallback strategies must rescue some instances.
    let mut rng = SplitMix64::new(0x5EED_F10E_000A);
    let mut by = std::collections::BTreeMap::new();
    let count = 20_000;
    for k in 0..count {
        let n = 2 + ((rng.next_u64() % 2) as usize);
        let m: Vec<f64> = (0..n * n)
            .map(|_| (rng.next_u64() % 9) as f64 - 4.0)
            .collect();
        let q: Vec<f64> = (0..n).map(|_| (rng.next_u64() % 5) as f64 - 2.0).collect();
        let sol = solve(
            &Lcp::new(n, m.clone(), q.clone()).expect("sizes"),
            &SolveOptions::default(),
        );
        assert!(
            sol.z.iter().all(|x| x.is_finite() && *x >= 0.0),
            "problem {k}"
        );
        if sol.status.is_solved() {
            // 1e-9: accepted residual <= 1e-10 on small integer data.
            assert_valid_solution(
                &m,
                &q,
                &sol.z,
                1e-9,
                &format!("problem {k}: M = {m:?}, q = {q:?}"),
            );
        }
        *by.entry(format!("{:?}", sol.accepted_by)).or_insert(0) += 1;
    }
    eprintln!("arbitrary 2×2/3×3 integer LCPs ({count}): accepted by {by:?}");
    assert!(
        by.get("Some(AlternativeRule)").copied().unwrap_or(0) > 0,
        "{by:?}"
    );
    assert!(
        by.get("Some(Perturbed)").copied().unwrap_or(0) > 0,
        "{by:?}"
    );

    // Regression: Lemke (largest-pivot rule) returns z ≈ 3e16·(1, 2, 1), on
    // the ray Mz = 0, with w3 = −1. The literal residual z − max(0, z − w)
    // rounds to 0 there and once accepted it; this LCP has no solution
    // (z1 w1 = 0 and z2 w2 = 0 force w3 = −1).
    let m = vec![4.0, -2.0, 0.0, 2.0, 0.0, -2.0, 1.0, -1.0, 1.0];
    let q = vec![0.0, 0.0, -1.0];
    let sol = solve(
        &Lcp::new(3, m.clone(), q.clone()).expect("sizes"),
        &SolveOptions::default(),
    );
    assert_eq!(sol.status, SolveStatus::Failed, "{:?}", sol.attempts);
    assert!(
        residual(
            &m,
            &q,
            &[
                3.0701474676908772e16,
                6.1402949353817544e16,
                3.0701474676908772e16
            ]
        ) >= 1.0
    );
}
