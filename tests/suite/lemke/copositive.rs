//! Copositive-plus (not P) matrices: singular PSD LCPs and random feasible
//! copositive-plus LCPs are solved.

use super::{assert_valid_solution, feasible_psd};
use floebench::lcp::{lemke, solve, Lcp, LemkeOptions, SolveOptions, SolveStatus, Termination};
use floebench::rng::SplitMix64;

#[test]
fn psd_singular_lcps_are_solved() {
    // M = [[1, 1], [1, 1]] (PSD, singular, not P): solutions z1 + z2 = 1.
    let m = vec![1.0, 1.0, 1.0, 1.0];
    let q = vec![-1.0, -1.0];
    let s = solve(
        &Lcp::new(2, m.clone(), q.clone()).expect("sizes"),
        &SolveOptions::default(),
    );
    assert!(s.status.is_solved(), "{:?}", s.attempts);
    assert_valid_solution(&m, &q, &s.z, 1e-12, "[[1,1],[1,1]]"); // exact tiny data
    assert!((s.z[0] + s.z[1] - 1.0).abs() < 1e-12); // same reason

    // M = [[1, −1], [−1, 1]], q = (−1, 1): z = (1, 0), w = 0 (unique up to z1 − z2 = 1).
    let m = vec![1.0, -1.0, -1.0, 1.0];
    let q = vec![-1.0, 1.0];
    let r = lemke(&m, &q, &LemkeOptions::default());
    assert_eq!(r.termination, Termination::Solved);
    assert_valid_solution(&m, &q, &r.z, 1e-12, "[[1,-1],[-1,1]]"); // exact tiny data
}

#[test]
fn random_feasible_copositive_plus_lcps_are_solved() {
    // M = B Bᵀ + (S − Sᵀ) with B n×r, r < n: positive semidefinite, singular,
    // non-symmetric, hence copositive-plus but not P. q = w* − M z* with a
    // complementary pair (z*, w*) >= 0 makes the LCP feasible, so Lemke with
    // the lexicographic rule cannot end on a ray (CPS Thm 4.4.13).
    let mut rng = SplitMix64::new(0x5EED_F10E_0006);
    let mut fallback = 0;
    let mut pivots_sum = 0;
    let count = 300;
    for k in 0..count {
        let n = 2 + ((rng.next_u64() % 29) as usize);
        let rank = 1 + ((rng.next_u64() % n as u64 - 1) as usize);
        let (m, q) = feasible_psd(&mut rng, n, rank);
        let sol = solve(
            &Lcp::new(n, m.clone(), q.clone()).expect("sizes"),
            &SolveOptions::default(),
        );
        assert!(
            sol.status.is_solved(),
            "problem {k} (n = {n}, rank {rank}): {:?}",
            sol.attempts
        );
        assert!(sol.residual <= 1e-10, "problem {k}"); // default acceptance tolerance
        assert_valid_solution(&m, &q, &sol.z, 1e-9, &format!("copositive-plus {k}")); // singular M: looser
        if sol.status == SolveStatus::SolvedByFallback {
            fallback += 1;
        }
        pivots_sum += sol.pivots;
    }
    eprintln!(
        "copositive-plus PSD LCPs: {count} problems, {fallback} needed a fallback, mean pivots {:.1}",
        pivots_sum as f64 / count as f64
    );
}
