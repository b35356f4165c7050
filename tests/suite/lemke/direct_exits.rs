//! The problems answered without a path: `q ≥ 0` (z = 0, no pivot, and the
//! record the shortcut leaves), the empty problem and 1×1 problems.

use super::random_matrix;
use floebench::lcp::{
    lemke, residual, solve, Lcp, LemkeOptions, SolveOptions, SolveStatus, Strategy, Termination,
};
use floebench::rng::SplitMix64;

#[test]
fn trivial_case_q_nonnegative_needs_no_pivot() {
    let lcp = Lcp::new(2, vec![1.0, -3.0, 2.0, 1.0], vec![0.0, 2.0]).expect("sizes");
    let r = lemke(&lcp.m, &lcp.q, &LemkeOptions::default());
    assert_eq!((r.termination, r.pivots), (Termination::Solved, 0));
    assert_eq!(r.z, vec![0.0, 0.0]);
    let s = solve(&lcp, &SolveOptions::default());
    assert_eq!(
        (s.status, s.pivots, s.residual),
        (SolveStatus::Solved, 0, 0.0)
    );
    // Empty problem.
    let s = solve(
        &Lcp::new(0, vec![], vec![]).expect("sizes"),
        &SolveOptions::default(),
    );
    assert_eq!(s.status, SolveStatus::Solved);
    assert!(s.z.is_empty());
}

#[test]
fn one_by_one_and_nonnegative_q_lcps() {
    let mut rng = SplitMix64::new(0x5EED_F10E_0013);
    for k in 0..2000 {
        let a = rng.range(1e-3, 10.0) * 10f64.powi((rng.next_u64() % 20) as i32 - 10);
        let b = rng.range(-1.0, 1.0) * 10f64.powi((rng.next_u64() % 20) as i32 - 10);
        let s = solve(
            &Lcp::new(1, vec![a], vec![b]).expect("sizes"),
            &SolveOptions::default(),
        );
        assert_eq!(s.status, SolveStatus::Solved, "{k}: a = {a}, b = {b}");
        let expected = if b < 0.0 { -b / a } else { 0.0 };
        assert!(
            (s.z[0] - expected).abs() <= 1e-15 * expected,
            "{k}: {} vs {expected}",
            s.z[0]
        );
        assert!(residual(&[a], &[b], &s.z) <= 1e-15);
    }
    // q >= 0 for any M (even non-finite-free garbage of the right size):
    // z = 0, no pivot, residual 0.
    for n in 1..20 {
        let m = random_matrix(&mut rng, n);
        let q: Vec<f64> = (0..n).map(|_| rng.uniform()).collect();
        let s = solve(&Lcp::new(n, m, q).expect("sizes"), &SolveOptions::default());
        assert_eq!(
            (s.status, s.pivots, s.residual),
            (SolveStatus::Solved, 0, 0.0)
        );
        assert!(s.z.iter().all(|&x| x == 0.0));
    }
}

#[test]
fn nonnegative_q_shortcut_keeps_the_record_and_refuses_non_finite_data() {
    // q >= 0 (with signed zeros) and finite M: z = 0 at once, recorded as
    // one accepted lexicographic attempt of 0 pivots, as Lemke reports it.
    let lcp = Lcp::new(
        3,
        vec![1.0, -2.0, 0.5, 3.0, 1.0, -1.0, 0.0, 2.0, 1.0],
        vec![0.0, -0.0, 1.5],
    )
    .expect("sizes");
    let s = solve(&lcp, &SolveOptions::default());
    assert_eq!(
        (s.status, s.pivots, s.residual, s.accepted_by),
        (SolveStatus::Solved, 0, 0.0, Some(Strategy::Lexicographic))
    );
    assert_eq!(s.z, vec![0.0; 3]);
    assert_eq!(s.w, lcp.q);
    assert_eq!(s.attempts.len(), 1);
    let a = &s.attempts[0];
    assert!(a.accepted && !a.revised && !a.polished);
    assert_eq!(
        (a.termination, a.pivots, a.residual),
        (Termination::Solved, 0, 0.0)
    );
    // q >= 0 but a non-finite M: no shortcut, a failure (w = M·0 + q is not
    // finite), never a solution.
    for bad in [f64::NAN, f64::INFINITY] {
        let mut m = lcp.m.clone();
        m[4] = bad;
        let s = solve(
            &Lcp::new(3, m, lcp.q.clone()).expect("sizes"),
            &SolveOptions::default(),
        );
        assert_eq!(s.status, SolveStatus::Failed, "M with {bad}");
        assert_eq!(s.residual, f64::INFINITY);
        assert!(s.z.iter().all(|x| *x == 0.0));
    }
    // A single negative entry of q: Lemke pivots.
    let s = solve(
        &Lcp::new(2, vec![2.0, 0.0, 0.0, 2.0], vec![1.0, -1e-300]).expect("sizes"),
        &SolveOptions::default(),
    );
    assert_eq!(s.status, SolveStatus::Solved);
    assert!(s.pivots > 0 && s.z[1] > 0.0);
}
