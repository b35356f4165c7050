//! The plan of the cold attempts: the Harris attempt first on large
//! problems, the diagonal covering vector above forty unknowns, and the
//! lower bound on the pivots of a cold path.

use super::{committed_dump, corpus, family_lcp, Family, FAMILIES};
use crate::common::max_abs;
use floebench::lcp::{
    residual, solve, solve_with, PivotRule, SolveCounters, SolveOptions, SolveStatus, Strategy,
    Termination, Workspace,
};
use floebench::rng::SplitMix64;

#[test]
fn large_problems_start_with_the_harris_attempt_and_the_lexicographic_one_follows() {
    // By default there is no Harris attempt. With `harris_from = 201` the
    // 271-unknown bay-jam group starts with it, and it solves it; with
    // `harris_from` above its size the plan is the lexicographic one.
    let lcp = committed_dump("lcp_bay/bay_jam_200_moreau_000064.json");
    let default = solve(&lcp, &SolveOptions::default());
    assert!(default
        .attempts
        .iter()
        .all(|a| a.strategy != Strategy::Harris));
    let opts = SolveOptions {
        harris_from: 201,
        ..SolveOptions::default()
    };
    assert!(lcp.n >= opts.harris_from);
    let s = solve(&lcp, &opts);
    assert_eq!(s.attempts[0].strategy, Strategy::Harris);
    assert_eq!(s.attempts[0].rule, PivotRule::Harris);
    assert_eq!(s.status, SolveStatus::Solved, "{:?}", s.attempts);
    assert_eq!(s.accepted_by, Some(Strategy::Harris));
    assert!(residual(&lcp.m, &lcp.q, &s.z) <= opts.tolerance);
    let mut counters = SolveCounters::default();
    counters.record(&s);
    assert_eq!((counters.by_harris, counters.solved), (1, 1));
    let old = solve(
        &lcp,
        &SolveOptions {
            harris_from: lcp.n + 1,
            ..opts.clone()
        },
    );
    assert_eq!(old.attempts[0].strategy, Strategy::Lexicographic);
    assert!(old.attempts.iter().all(|a| a.strategy != Strategy::Harris));

    // On the committed corpus with the Harris attempt first on every size:
    // every dump is solved on the original data; where the Harris attempt
    // is not accepted the lexicographic one follows, and an acceptance by
    // it is then a fallback.
    let harris_everywhere = SolveOptions {
        harris_from: 0,
        ..opts.clone()
    };
    let (mut by_harris, mut handed_over) = (0, 0);
    for (name, lcp) in corpus() {
        let s = solve(&lcp, &harris_everywhere);
        assert!(s.status.is_solved(), "{name}: {:?}", s.attempts);
        let r = residual(&lcp.m, &lcp.q, &s.z);
        assert!(r <= opts.tolerance, "{name}: residual {r:e}");
        if s.pivots == 0 {
            continue;
        }
        assert_eq!(s.attempts[0].strategy, Strategy::Harris, "{name}");
        if s.attempts[0].accepted {
            by_harris += 1;
            assert_eq!(s.status, SolveStatus::Solved, "{name}");
        } else {
            handed_over += 1;
            assert_eq!(s.attempts[1].strategy, Strategy::Lexicographic, "{name}");
            assert_eq!(s.status, SolveStatus::SolvedByFallback, "{name}");
        }
    }
    eprintln!("committed corpus, Harris first: {by_harris} accepted, {handed_over} handed over");
    assert!(by_harris > 0);
}

#[test]
fn diagonal_covering_vector_is_the_floored_diagonal_ratio_above_forty_unknowns() {
    use floebench::lcp::{Covering, DEFAULT_COVERING_FLOOR};
    assert_eq!(
        SolveOptions::default().covering,
        Covering::DiagonalRatio(DEFAULT_COVERING_FLOOR)
    );
    for n in [1, 8, 40] {
        let m: Vec<f64> = (0..n * n).map(|k| k as f64).collect();
        assert_eq!(Covering::DiagonalRatio(1e-3).vector(&m, n), None, "n = {n}");
    }
    // n = 41: diagonal 0, −1, 2, −3, … (a zero and negative entries).
    let n = 41;
    let mut m = vec![0.5; n * n];
    for i in 0..n {
        m[i * n + i] = if i % 2 == 0 { i as f64 } else { -(i as f64) };
    }
    let d = Covering::DiagonalRatio(1e-2)
        .vector(&m, n)
        .expect("a vector above 40 unknowns");
    for (i, &di) in d.iter().enumerate() {
        let want = (i as f64 / 40.0).max(1e-2);
        assert_eq!(di, want, "d_{i}");
    }
    // A zero diagonal gives d = e; a floor outside (0, 1] an invalid vector.
    let zero = vec![0.0; n * n];
    assert_eq!(Covering::DiagonalRatio(1e-3).vector(&zero, n), None);
    for floor in [0.0, -1.0, 1.5, f64::NAN] {
        let d = Covering::DiagonalRatio(floor)
            .vector(&m, n)
            .expect("vector");
        assert!(d.iter().all(|x| x.is_nan()), "floor {floor}");
    }
    assert_eq!(
        Covering::DiagonalRatio(1.0).vector(&m, n),
        Some(vec![1.0; n])
    );
}

#[test]
fn diagonal_covering_solves_every_family_above_forty_unknowns() {
    use floebench::lcp::Covering;
    let mut rng = SplitMix64::new(0x5EED_F10E_C0DE);
    let mut ws = Workspace::default();
    let opts = SolveOptions::default();
    let ones = SolveOptions {
        covering: Covering::Ones,
        ..SolveOptions::default()
    };
    let invalid = SolveOptions {
        covering: Covering::DiagonalRatio(0.0),
        ..SolveOptions::default()
    };
    let mut paths_differ = 0;
    for family in FAMILIES {
        for k in 0..12 {
            let n = 41 + (rng.next_u64() % 32) as usize;
            let lcp = family_lcp(&mut rng, family, n);
            let label = format!("{family:?} {k} (n = {})", lcp.n);
            let a = solve_with(&mut ws, &lcp, &opts);
            let b = solve_with(&mut ws, &lcp, &ones);
            for (s, which) in [(&a, "diagonal"), (&b, "ones")] {
                assert_eq!(s.status, SolveStatus::Solved, "{label} {which}");
                assert!(s.z.iter().all(|v| v.is_finite() && *v >= 0.0));
                let r = residual(&lcp.m, &lcp.q, &s.z);
                assert!(r <= opts.tolerance, "{label} {which}: residual {r:e}");
            }
            if matches!(family, Family::PMatrix | Family::Degenerate) {
                let scale = max_abs(&b.z).max(1.0);
                for (x, y) in a.z.iter().zip(&b.z) {
                    assert!((x - y).abs() <= 1e-8 * scale, "{label}: unique solution");
                }
            }
            if a.attempts.first().map(|t| t.pivots) != b.attempts.first().map(|t| t.pivots) {
                paths_differ += 1;
            }
            // An invalid floor: the attempts with that covering vector
            // refuse it (only the alternative attempt runs), never a panic
            // or a NaN.
            let c = solve_with(&mut ws, &lcp, &invalid);
            assert!(c.z.iter().all(|v| v.is_finite() && *v >= 0.0), "{label}");
            if lcp.n > 40 && lcp.q.iter().any(|&x| x < 0.0) {
                assert_eq!(
                    c.attempts[0].termination,
                    Termination::InvalidInput,
                    "{label}"
                );
            }
        }
    }
    // The diagonal is used: the first path differs from d = e's somewhere.
    assert!(paths_differ > 0, "no path changed with the covering vector");
    eprintln!("first paths that differ from d = e: {paths_differ} of 48");
}

#[test]
fn a_cold_lemke_path_takes_at_least_one_pivot_more_than_its_support() {
    // Every basic z_i > 0 of the end point entered the basis once, after
    // z0: a first attempt accepted without principal pivoting (its z is
    // Lemke's end point, refined on the same basis at most) cannot have
    // taken fewer pivots than `min_cold_pivots`. On every family and size,
    // both representations of the basis (dense below 41 unknowns, the
    // factorised basis above).
    use floebench::lcp::{min_cold_pivots, support};
    assert_eq!(support(&[0.0, 1e-300, -1.0, f64::NAN, 2.0]), 2);
    assert_eq!(min_cold_pivots(0), 0);
    assert_eq!(min_cold_pivots(3), 4);
    let mut rng = SplitMix64::new(0x5EED_F10E_0B0D);
    let opts = SolveOptions::default();
    let mut ws = Workspace::default();
    let (mut checked, mut tight) = (0, 0);
    for family in FAMILIES {
        for k in 0..60 {
            let n = [1, 2, 4, 8, 16, 40, 48, 72][k % 8];
            let lcp = family_lcp(&mut rng, family, n);
            let s = solve_with(&mut ws, &lcp, &opts);
            let first = &s.attempts[0];
            if !(first.accepted && first.basis_solves == 0) {
                continue;
            }
            let bound = min_cold_pivots(support(&s.z));
            assert!(
                s.pivots >= bound,
                "{family:?} n = {}: {} pivots, support {}",
                lcp.n,
                s.pivots,
                support(&s.z)
            );
            assert_eq!(bound == 0, s.pivots == 0, "{family:?}: z = 0 iff no pivot");
            checked += 1;
            if s.pivots == bound {
                tight += 1;
            }
        }
    }
    eprintln!("cold paths checked against their bound: {checked}, of them tight: {tight}");
    assert!(
        checked >= 150,
        "only {checked} first attempts accepted unpolished"
    );
    assert!(
        tight > 0,
        "the bound is never reached: is it counted right?"
    );
}
