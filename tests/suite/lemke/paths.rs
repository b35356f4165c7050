//! Every path of the driver: cold (dense tableau and factorised basis,
//! Harris attempt first), warm from the right basis, warm from a wrong
//! basis, each checked independently of the driver on every problem family.

use super::{family_lcp, Family, FAMILIES};
use crate::common::max_abs;
use floebench::lcp::{
    residual, solve_warm_with, solve_with, BasisGuess, Lcp, SolveOptions, SolveStatus, Strategy,
    Workspace,
};
use floebench::rng::SplitMix64;

/// What the paths of one problem gave.
#[derive(Debug, Default)]
struct PathTally {
    problems: usize,
    right_hits: usize,
    /// Right-basis hits with the sparse basis solves (`revised_from = 0`).
    sparse_right_hits: usize,
    /// Right-basis hits from the starting point `z = 0`, dense and sparse
    /// basis solves.
    zero_start_hits: usize,
    sparse_zero_start_hits: usize,
    wrong_hits: usize,
    warm_lemke_hits: usize,
}

/// Solves `lcp` cold, warm from the right basis (the cold solution's
/// support and values), warm from two wrong ones (the complement of the
/// right basis with a random starting point, a random basis) and with a
/// guess of the wrong size, and checks each result independently of the
/// driver: solved, `z ≥ 0` finite, the residual recomputed from `(M, q, z)`
/// within the tolerance and, when the solution is `unique`, equal to the
/// cold one. A warm start is also never accepted on a non-solution.
fn check_every_path(
    lcp: &Lcp,
    unique: bool,
    rng: &mut SplitMix64,
    ws: &mut Workspace,
    tally: &mut PathTally,
    label: &str,
) {
    // The warm Lemke path (off by default) is one of the paths checked.
    let opts = SolveOptions {
        warm_lemke: true,
        ..SolveOptions::default()
    };
    let n = lcp.n;
    let judge = |s: &floebench::lcp::LcpSolution, path: &str| {
        assert!(s.status.is_solved(), "{label} {path}: {s:?}");
        assert!(
            s.z.iter().all(|v| v.is_finite() && *v >= 0.0),
            "{label} {path}: z = {:?}",
            s.z
        );
        let r = residual(&lcp.m, &lcp.q, &s.z);
        assert!(r <= opts.tolerance, "{label} {path}: residual {r:e}");
        assert_eq!(r, s.residual, "{label} {path}: reported residual");
    };
    let cold = solve_with(ws, lcp, &opts);
    judge(&cold, "cold");
    assert_eq!(cold.warm, None, "{label}: cold solve has no warm start");
    tally.problems += 1;
    let same_as_cold = |s: &floebench::lcp::LcpSolution, path: &str| {
        if unique {
            // The scale of z: the solution, or q over M (ε_mach when q = 0,
            // as the residual's denominator floor).
            let mmax = max_abs(&lcp.m).max(f64::MIN_POSITIVE);
            let scale = max_abs(&cold.z).max(max_abs(&lcp.q).max(f64::EPSILON) / mmax);
            for (a, b) in s.z.iter().zip(&cold.z) {
                // 1e-8: unique solution, both within the 1e-10 residual.
                assert!(
                    (a - b).abs() <= 1e-8 * scale,
                    "{label} {path}: z = {:?}, cold {:?}",
                    s.z,
                    cold.z
                );
            }
        }
    };

    // The factorised (revised) basis instead of the dense tableau.
    let revised = solve_with(
        ws,
        lcp,
        &SolveOptions {
            revised_from: 0,
            ..opts.clone()
        },
    );
    judge(&revised, "cold, revised");
    same_as_cold(&revised, "cold, revised");
    assert!(
        revised.attempts.iter().all(|a| a.revised == (a.pivots > 0)),
        "{label}: every attempt that pivoted ran on the revised basis: {:?}",
        revised.attempts
    );

    // The Harris attempt first (`harris_from`, off by default), on the
    // dense tableau and on the factorised basis; the lexicographic
    // attempt follows when it is not accepted.
    for revised_from in [usize::MAX, 0] {
        let path = format!("cold, Harris first, revised_from = {revised_from}");
        let s = solve_with(
            ws,
            lcp,
            &SolveOptions {
                harris_from: 0,
                revised_from,
                ..opts.clone()
            },
        );
        judge(&s, &path);
        same_as_cold(&s, &path);
        if s.pivots > 0 {
            assert_eq!(s.attempts[0].strategy, Strategy::Harris, "{label} {path}");
            if !s.attempts[0].accepted {
                assert_eq!(s.attempts[1].strategy, Strategy::Lexicographic, "{label}");
            }
        }
    }

    let right = BasisGuess {
        basic: cold.z.iter().map(|&v| v > 0.0).collect(),
        z: cold.z.clone(),
    };
    let s = solve_warm_with(ws, lcp, &opts, &right);
    judge(&s, "warm from the right basis");
    same_as_cold(&s, "warm from the right basis");
    let w = s.warm.expect("a warm start was tried");
    if w.accepted {
        tally.right_hits += 1;
        assert_eq!(s.accepted_by, Some(Strategy::WarmStart), "{label}");
        assert_eq!((s.pivots, s.attempts.len()), (0, 0), "{label}");
        assert_eq!(s.status, SolveStatus::Solved, "{label}");
    }

    // The sparse basis solves of principal pivoting (used from
    // `revised_from` unknowns, here from 0), from the right basis and from
    // a random one.
    let sparse = SolveOptions {
        revised_from: 0,
        ..opts.clone()
    };
    let s = solve_warm_with(ws, lcp, &sparse, &right);
    judge(&s, "warm from the right basis, sparse bases");
    same_as_cold(&s, "warm from the right basis, sparse bases");
    if s.warm.expect("a warm start was tried").accepted {
        tally.sparse_right_hits += 1;
        assert_eq!(s.accepted_by, Some(Strategy::WarmStart), "{label}");
    }
    // From the right basis but z = 0: the basis solve itself must be right.
    let zero_start = BasisGuess {
        basic: right.basic.clone(),
        z: vec![0.0; n],
    };
    for (o, hits, path) in [
        (
            &opts,
            &mut tally.zero_start_hits,
            "warm from the right basis and z = 0",
        ),
        (
            &sparse,
            &mut tally.sparse_zero_start_hits,
            "warm from the right basis and z = 0, sparse bases",
        ),
    ] {
        let s = solve_warm_with(ws, lcp, o, &zero_start);
        judge(&s, path);
        same_as_cold(&s, path);
        if s.warm.expect("a warm start was tried").accepted {
            *hits += 1;
        }
    }
    let random_sparse = BasisGuess {
        basic: (0..n).map(|_| rng.uniform() < 0.5).collect(),
        z: (0..n).map(|_| rng.range(-1.0, 1.0)).collect(),
    };
    let s = solve_warm_with(ws, lcp, &sparse, &random_sparse);
    judge(&s, "warm from a random basis, sparse bases");
    same_as_cold(&s, "warm from a random basis, sparse bases");

    let complement = BasisGuess {
        basic: right.basic.iter().map(|b| !b).collect(),
        z: (0..n).map(|_| rng.uniform()).collect(),
    };
    let random = BasisGuess {
        basic: (0..n).map(|_| rng.uniform() < 0.5).collect(),
        z: (0..n).map(|_| rng.range(-1.0, 1.0)).collect(),
    };
    for (guess, path) in [
        (&complement, "warm from the complement"),
        (&random, "warm from a random basis"),
    ] {
        let s = solve_warm_with(ws, lcp, &opts, guess);
        judge(&s, path);
        same_as_cold(&s, path);
        let w = s.warm.expect("a warm start was tried");
        assert_eq!(
            w.accepted,
            s.accepted_by == Some(Strategy::WarmStart),
            "{label} {path}"
        );
        if w.accepted {
            tally.wrong_hits += 1;
        } else if s.accepted_by == Some(Strategy::WarmLemke) {
            // Rejected, then solved by Lemke's path from the guessed basis.
            tally.warm_lemke_hits += 1;
            assert_eq!(s.status, SolveStatus::Solved, "{label} {path}");
        } else {
            // Rejected: the cold attempts follow (after a warm Lemke path
            // that was not accepted), as without warm start.
            assert_eq!(s.z, cold.z, "{label} {path}: cold after a miss");
        }
        // Without the warm Lemke path a miss is bit for bit the cold solve.
        let old = SolveOptions {
            warm_lemke: false,
            ..opts.clone()
        };
        let s = solve_warm_with(ws, lcp, &old, guess);
        judge(&s, path);
        assert!(
            s.attempts.iter().all(|a| a.strategy != Strategy::WarmLemke),
            "{label} {path}"
        );
        if !s.warm.expect("a warm start was tried").accepted {
            assert_eq!(s.z, cold.z, "{label} {path}: cold after a miss");
        }
    }

    // A guess of the wrong size is not used: bit for bit the cold solve.
    let short = BasisGuess {
        basic: vec![true; n + 1],
        z: vec![1.0; n + 1],
    };
    let s = solve_warm_with(ws, lcp, &opts, &short);
    assert_eq!((&s.z, s.warm), (&cold.z, None), "{label}: wrong size");
}

#[test]
fn every_path_solves_random_p_psd_degenerate_and_stewart_trinkle_lcps() {
    let mut rng = SplitMix64::new(0x5EED_F10E_0020);
    let mut ws = Workspace::default();
    for family in FAMILIES {
        let mut tally = PathTally::default();
        for k in 0..150 {
            let n = 1 + (rng.next_u64() % 24) as usize;
            let lcp = family_lcp(&mut rng, family, n);
            let unique = matches!(family, Family::PMatrix | Family::Degenerate);
            let label = format!("{family:?} {k} (n = {})", lcp.n);
            check_every_path(&lcp, unique, &mut rng, &mut ws, &mut tally, &label);
        }
        eprintln!("{family:?}: {tally:?}");
        // The right basis is a hit on every problem (measured: all of them
        // in every family); the wrong ones are completed or handed over.
        assert_eq!(tally.right_hits, tally.problems, "{family:?}: {tally:?}");
        // So is it from z = 0, where the basis solve must be right
        // (measured: all of them, dense and sparse).
        for hits in [
            tally.sparse_right_hits,
            tally.zero_start_hits,
            tally.sparse_zero_start_hits,
        ] {
            assert_eq!(hits, tally.problems, "{family:?}: {tally:?}");
        }
    }
}

#[test]
fn every_path_solves_one_by_one_and_nonnegative_q_lcps() {
    let mut rng = SplitMix64::new(0x5EED_F10E_0021);
    let mut ws = Workspace::default();
    let mut tally = PathTally::default();
    // 1×1: z = max(0, −q/m) for m > 0; m = 0 with q ≥ 0 has z = 0.
    for (m, q) in [(2.0, -1.0), (0.5, -3.0), (2.0, 0.0), (2.0, 1.0), (0.0, 1.0)] {
        let lcp = Lcp::new(1, vec![m], vec![q]).expect("sizes");
        let label = format!("1x1 m = {m}, q = {q}");
        check_every_path(&lcp, m > 0.0, &mut rng, &mut ws, &mut tally, &label);
        let cold = solve_with(&mut ws, &lcp, &SolveOptions::default());
        let expected = if m > 0.0 { (-q / m).max(0.0) } else { 0.0 };
        assert_eq!(cold.z, vec![expected], "{label}");
    }
    // q ≥ 0: z = 0 solves every LCP and is the only solution for a P-matrix;
    // a warm start from a wrong basis must get there too.
    for k in 0..100 {
        let n = 1 + (rng.next_u64() % 20) as usize;
        let mut lcp = family_lcp(&mut rng, Family::PMatrix, n);
        for v in lcp.q.iter_mut() {
            *v = v.abs() * (rng.next_u64() % 2) as f64;
        }
        let label = format!("q >= 0 {k} (n = {n})");
        check_every_path(&lcp, true, &mut rng, &mut ws, &mut tally, &label);
        let cold = solve_with(&mut ws, &lcp, &SolveOptions::default());
        assert!(
            cold.z.iter().all(|&v| v == 0.0) && cold.pivots == 0,
            "{label}"
        );
    }
    eprintln!("1x1 and q >= 0: {tally:?}");
}
