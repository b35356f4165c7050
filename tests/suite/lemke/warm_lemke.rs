//! Lemke's path from a guessed basis (the warm Lemke attempt): pivots that
//! follow the flipped indices, never a wrong answer, its counters.

use super::{family_lcp, Family, FAMILIES};
use crate::common::max_abs;
use floebench::lcp::{
    residual, solve_warm_with, solve_with, BasisGuess, Lcp, LcpSolution, SolveCounters,
    SolveOptions, SolveStatus, Strategy, Termination, Workspace,
};
use floebench::rng::SplitMix64;

/// The warm Lemke attempt alone (no principal pivoting first) from `basic`.
fn warm_lemke_only(ws: &mut Workspace, lcp: &Lcp, basic: Vec<bool>) -> LcpSolution {
    let opts = SolveOptions {
        warm_solves: 0,
        warm_lemke: true,
        ..SolveOptions::default()
    };
    let guess = BasisGuess {
        z: vec![0.0; lcp.n],
        basic,
    };
    solve_warm_with(ws, lcp, &opts, &guess)
}

#[test]
fn warm_lemke_pivots_grow_with_the_flipped_indices_not_with_n() {
    // P-matrices (unique solution; the principal pivot transform of a
    // P-matrix is one, so the warm path cannot end on a ray): from the
    // right basis 0 pivots; from the right basis with k indices flipped,
    // solved by the warm path in a number of pivots that follows k, far
    // below the cold path's, which follows n.
    let mut rng = SplitMix64::new(0x5EED_3A4B_0001);
    let mut ws = Workspace::default();
    let n = 80;
    let mut cold_pivots = 0usize;
    let mut warm_pivots = [0usize; 4];
    let flips = [1usize, 2, 4, 8];
    let problems = 20;
    for k in 0..problems {
        let lcp = family_lcp(&mut rng, Family::PMatrix, n);
        let label = format!("P-matrix {k}");
        let cold = solve_with(&mut ws, &lcp, &SolveOptions::default());
        assert_eq!(cold.status, SolveStatus::Solved, "{label}");
        cold_pivots += cold.pivots;
        let right: Vec<bool> = cold.z.iter().map(|&v| v > 0.0).collect();
        let s = warm_lemke_only(&mut ws, &lcp, right.clone());
        assert_eq!(s.accepted_by, Some(Strategy::WarmLemke), "{label}: {s:?}");
        assert_eq!(s.pivots, 0, "{label}: from the right basis");
        assert!(residual(&lcp.m, &lcp.q, &s.z) <= 1e-10, "{label}");
        for (f, &kf) in flips.iter().enumerate() {
            let mut basic = right.clone();
            for _ in 0..kf {
                let i = (rng.next_u64() % n as u64) as usize;
                basic[i] = !basic[i];
            }
            let s = warm_lemke_only(&mut ws, &lcp, basic);
            assert_eq!(
                s.accepted_by,
                Some(Strategy::WarmLemke),
                "{label}, {kf} flipped: {s:?}"
            );
            let r = residual(&lcp.m, &lcp.q, &s.z);
            assert!(r <= 1e-10, "{label}, {kf} flipped: residual {r:e}");
            let scale = max_abs(&cold.z).max(1.0);
            for (a, b) in s.z.iter().zip(&cold.z) {
                assert!((a - b).abs() <= 1e-8 * scale, "{label}, {kf} flipped");
            }
            warm_pivots[f] += s.pivots;
        }
    }
    let mean = |p: usize| p as f64 / problems as f64;
    eprintln!(
        "n = {n}: cold {:.1} pivots; warm with 1, 2, 4, 8 flipped: {:?}",
        mean(cold_pivots),
        warm_pivots.map(mean)
    );
    // Measured (n = 80): cold 54.1 pivots; warm 2.6, 4.0, 5.9, 11.4.
    for (f, &kf) in flips.iter().enumerate() {
        let w = mean(warm_pivots[f]);
        assert!(w <= 2.0 * kf as f64 + 1.0, "{kf} flipped: {w} pivots");
    }
    assert!(mean(warm_pivots[3]) < 0.5 * mean(cold_pivots));
}

#[test]
fn warm_lemke_from_any_basis_never_accepts_a_wrong_answer() {
    // Every family, from the right basis, a basis with a few flipped
    // indices and a random one: solved (by the warm path or by the cold
    // attempts after it), the residual recomputed here within the
    // tolerance, the unique solutions equal to the cold ones; a warm path
    // that is not accepted is followed by the cold attempts bit for bit.
    let mut rng = SplitMix64::new(0x5EED_3A4B_0002);
    let mut ws = Workspace::default();
    for family in FAMILIES {
        let (mut hits, mut misses, mut pivots) = (0, 0, 0);
        for k in 0..80 {
            let n = 1 + (rng.next_u64() % 60) as usize;
            let lcp = family_lcp(&mut rng, family, n);
            let n = lcp.n;
            let unique = matches!(family, Family::PMatrix | Family::Degenerate);
            let label = format!("{family:?} {k} (n = {n})");
            let cold = solve_with(&mut ws, &lcp, &SolveOptions::default());
            assert!(cold.status.is_solved(), "{label}");
            let right: Vec<bool> = cold.z.iter().map(|&v| v > 0.0).collect();
            let mut flipped = right.clone();
            for _ in 0..3 {
                let i = (rng.next_u64() % n as u64) as usize;
                flipped[i] = !flipped[i];
            }
            let random: Vec<bool> = (0..n).map(|_| rng.uniform() < 0.5).collect();
            for (basic, path) in [(right, "right"), (flipped, "flipped"), (random, "random")] {
                let s = warm_lemke_only(&mut ws, &lcp, basic);
                assert!(s.status.is_solved(), "{label} {path}: {s:?}");
                assert!(s.z.iter().all(|v| v.is_finite() && *v >= 0.0));
                let r = residual(&lcp.m, &lcp.q, &s.z);
                assert!(r <= 1e-10, "{label} {path}: residual {r:e}");
                assert_eq!(r, s.residual, "{label} {path}");
                if unique {
                    let scale = max_abs(&cold.z).max(1.0);
                    for (a, b) in s.z.iter().zip(&cold.z) {
                        assert!((a - b).abs() <= 1e-8 * scale, "{label} {path}");
                    }
                }
                let Some(a) = s.warm_lemke_attempt() else {
                    // q >= 0: z = 0 before any attempt.
                    assert!(lcp.q.iter().all(|&v| v >= 0.0), "{label} {path}");
                    continue;
                };
                pivots += a.pivots;
                if a.accepted {
                    hits += 1;
                    assert_eq!(s.accepted_by, Some(Strategy::WarmLemke));
                    assert!(a.revised, "{label} {path}: on the factorised basis");
                } else {
                    misses += 1;
                    if unique {
                        // The principal pivot transform of a P-matrix is a
                        // P-matrix: no ray, only the warm pivot cap (n + 1)
                        // can stop the path, and only from a random basis.
                        assert_eq!(a.termination, Termination::MaxPivots, "{label} {path}");
                        assert_eq!(path, "random", "{label}: {a:?}");
                    }
                    assert_eq!(s.z, cold.z, "{label} {path}: the cold attempts");
                }
            }
        }
        eprintln!("{family:?}: warm Lemke {hits} hits, {misses} misses, {pivots} pivots");
        assert!(hits > misses, "{family:?}: {hits} hits, {misses} misses");
    }
}

#[test]
fn warm_lemke_counters_and_infeasible_problems() {
    // An infeasible PSD LCP: the warm path (from a singular guess, which the
    // crash reduces) and the cold attempts all fail; counted as a miss.
    let mut ws = Workspace::default();
    let lcp = Lcp::new(2, vec![1.0, -1.0, -1.0, 1.0], vec![-1.0, -1.0]).expect("sizes");
    let mut counters = SolveCounters::default();
    for basic in [vec![true, true], vec![true, false], vec![false, false]] {
        let s = warm_lemke_only(&mut ws, &lcp, basic);
        assert_eq!(s.status, SolveStatus::Failed, "{s:?}");
        assert!(s.z.iter().all(|v| v.is_finite() && *v >= 0.0));
        counters.record(&s);
    }
    assert_eq!(
        (counters.warm_lemke_hits, counters.warm_lemke_misses),
        (0, 3)
    );
    // A P-matrix from a wrong basis: a hit, its pivots counted.
    let lcp = Lcp::new(2, vec![2.0, 1.0, 1.0, 2.0], vec![-1.0, -1.0]).expect("sizes");
    let s = warm_lemke_only(&mut ws, &lcp, vec![true, false]);
    assert_eq!(s.accepted_by, Some(Strategy::WarmLemke), "{s:?}");
    let before = counters.warm_lemke_pivots;
    counters.record(&s);
    assert_eq!(counters.warm_lemke_hits, 1);
    let p = counters.warm_lemke_pivots - before;
    assert!(p >= 1 && p == s.pivots as u64, "{p} {s:?}");
    let r = residual(&lcp.m, &lcp.q, &s.z);
    assert!(r <= 1e-10 && (s.z[0] - 1.0 / 3.0).abs() < 1e-12, "{s:?}");
}
