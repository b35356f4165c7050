//! Small problems (at most `SMALL_N` unknowns) and `unpolished_below`:
//! Lemke's pivots, no refinement of an accepted candidate already within
//! the switch, the direct exits.

use super::{corpus, family_lcp, random_matrix, FAMILIES};
use floebench::lcp::{
    lemke, residual, solve, solve_with, Lcp, LemkeOptions, SolveOptions, SolveStatus, Termination,
    Workspace,
};
use floebench::rng::SplitMix64;

#[test]
fn a_candidate_is_kept_unpolished_only_when_its_residual_is_below_the_switch() {
    // With `unpolished_below = 1e-13` the driver keeps a solved Lemke
    // candidate without the polish only when its compensated residual on
    // the original data is at most 1e-13; every other accepted candidate
    // went through the polish. Over the path
    // families, 1×1, q ≥ 0 and the committed corpus.
    let mut rng = SplitMix64::new(0x5EED_F10E_0040);
    let mut ws = Workspace::default();
    let opts = SolveOptions {
        unpolished_below: 1e-13,
        ..SolveOptions::default()
    };
    let mut problems: Vec<(String, Lcp)> = corpus();
    for family in FAMILIES {
        for k in 0..100 {
            let n = 1 + (rng.next_u64() % 40) as usize;
            problems.push((format!("{family:?} {k}"), family_lcp(&mut rng, family, n)));
        }
    }
    for (m, q) in [(2.0, -1.0), (0.5, -3.0), (2.0, 1.0)] {
        problems.push((
            format!("1x1 {m} {q}"),
            Lcp::new(1, vec![m], vec![q]).expect("sizes"),
        ));
    }
    let (mut unpolished, mut polished) = (0, 0);
    for (label, lcp) in &problems {
        let s = solve_with(&mut ws, lcp, &opts);
        let r = residual(&lcp.m, &lcp.q, &s.z);
        assert_eq!(r, s.residual, "{label}");
        for a in s.attempts.iter().filter(|a| a.accepted && a.pivots > 0) {
            if a.polished {
                polished += 1;
            } else {
                unpolished += 1;
                assert!(
                    a.termination == Termination::Solved && a.residual <= 1e-13,
                    "{label}: kept unpolished at {:e} ({:?})",
                    a.residual,
                    a.termination
                );
            }
        }
        if s.status.is_solved() {
            assert!(r <= opts.tolerance, "{label}: residual {r:e}");
        }
    }
    eprintln!("unpolished {unpolished}, polished {polished}");
    assert!(unpolished > 0, "the unpolished exit is exercised");
}

/// The problems of the small-path tests: every path family at 1 to 48
/// unknowns (both sides of `SMALL_N`), 1×1 problems of either sign, `q ≥ 0`
/// and the committed corpus.
fn small_path_problems(seed: u64) -> Vec<(String, Lcp)> {
    let mut rng = SplitMix64::new(seed);
    let mut problems: Vec<(String, Lcp)> = corpus();
    for family in FAMILIES {
        for k in 0..120 {
            let n = 1 + (rng.next_u64() % 48) as usize;
            problems.push((format!("{family:?} {k}"), family_lcp(&mut rng, family, n)));
        }
    }
    for k in 0..40 {
        let a = rng.range(-1.0, 10.0) * 10f64.powi((rng.next_u64() % 20) as i32 - 10);
        let b = rng.range(-1.0, 1.0) * 10f64.powi((rng.next_u64() % 20) as i32 - 10);
        problems.push((
            format!("1x1 {k}: {a} {b}"),
            Lcp::new(1, vec![a], vec![b]).expect("sizes"),
        ));
    }
    for n in [1, 4, 8, 40] {
        let m = random_matrix(&mut rng, n);
        let q = (0..n).map(|_| rng.uniform()).collect();
        problems.push((
            format!("q >= 0, n = {n}"),
            Lcp::new(n, m, q).expect("sizes"),
        ));
    }
    problems
}

#[test]
fn small_problems_take_the_same_pivots_and_skip_only_an_unneeded_refinement() {
    use floebench::lcp::solve_options::SMALL_N;
    // The small-problem rule (`unpolished_below = 1e-13`, the default)
    // against the refining driver (`0`: every candidate polished, as before):
    // the same attempts with the same pivots and terminations on every
    // problem; an accepted candidate left unpolished is exactly Lemke's own
    // `z` (read from the tableau, no refinement) with a residual, recomputed
    // here, at most 1e-13; above `SMALL_N` unknowns both drivers give the
    // same bits.
    let mut ws = Workspace::default();
    let mut ws_old = Workspace::default();
    let new_opts = SolveOptions::default();
    assert_eq!(new_opts.unpolished_below, 1e-13, "on by default");
    let old_opts = SolveOptions {
        unpolished_below: 0.0,
        ..SolveOptions::default()
    };
    let (mut skipped, mut large) = (0, 0);
    for (label, lcp) in small_path_problems(0x5EED_5A11_0001) {
        let new = solve_with(&mut ws, &lcp, &new_opts);
        let old = solve_with(&mut ws_old, &lcp, &old_opts);
        assert_eq!(new.status, old.status, "{label}");
        assert_eq!(new.attempts.len(), old.attempts.len(), "{label}");
        for (a, b) in new.attempts.iter().zip(&old.attempts) {
            assert_eq!(
                (a.strategy, a.termination, a.pivots),
                (b.strategy, b.termination, b.pivots),
                "{label}"
            );
        }
        let r = residual(&lcp.m, &lcp.q, &new.z);
        assert_eq!(r, new.residual, "{label}");
        assert!(new.z.iter().all(|x| x.is_finite() && *x >= 0.0), "{label}");
        if new.status.is_solved() {
            assert!(r <= new_opts.tolerance, "{label}: residual {r:e}");
        }
        if lcp.n > SMALL_N {
            large += 1;
            assert_eq!(new.z, old.z, "{label}: above SMALL_N nothing changes");
            assert_eq!(new.residual, old.residual, "{label}");
            continue;
        }
        let first = &new.attempts[0];
        if first.accepted && first.pivots > 0 && !first.polished {
            assert!(r <= 1e-13, "{label}: kept unpolished at {r:e}");
            let raw = lemke(&lcp.m, &lcp.q, &LemkeOptions::default());
            assert_eq!(raw.termination, Termination::Solved, "{label}");
            assert_eq!(new.z, raw.z, "{label}: not Lemke's own z");
            if old.attempts[0].polished {
                skipped += 1;
            }
        }
    }
    eprintln!("refinements skipped {skipped}, problems above SMALL_N {large}");
    // The rule is exercised: the old driver refined candidates that the
    // small path kept as Lemke left them.
    assert!(skipped > 100, "only {skipped} refinements skipped");
    assert!(large > 20);
}

#[test]
fn small_problems_one_by_one_and_nonnegative_q_on_the_direct_exits() {
    // 1×1: z = −q/a exactly (the scalings are powers of two and the one
    // division of the path is correctly rounded) when a > 0 > q; no
    // solution when a ≤ 0 > q (failed, z finite); q ≥ 0: z = 0, w = q,
    // residual 0, no pivot. With the small-problem rule on (the default).
    let opts = SolveOptions::default();
    for (label, lcp) in small_path_problems(0x5EED_5A11_0002) {
        let s = solve(&lcp, &opts);
        if lcp.q.iter().all(|&x| x >= 0.0) {
            assert_eq!(
                (s.status, s.pivots, s.residual),
                (SolveStatus::Solved, 0, 0.0),
                "{label}"
            );
            assert!(s.z.iter().all(|&x| x == 0.0), "{label}");
            assert_eq!(s.w, lcp.q, "{label}");
        } else if lcp.n == 1 {
            let (a, b) = (lcp.m[0], lcp.q[0]);
            if a > 0.0 {
                assert_eq!(s.status, SolveStatus::Solved, "{label}");
                assert_eq!(s.z[0], -b / a, "{label}");
            } else {
                assert_eq!(s.status, SolveStatus::Failed, "{label}");
                assert!(s.z[0].is_finite(), "{label}");
            }
        }
    }
}
