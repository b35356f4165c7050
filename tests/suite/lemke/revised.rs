//! The factorised (revised) basis against the dense tableau: the same path,
//! large sparse Stewart–Trinkle LCPs through many refactorisations, and a
//! bay-jam dump.

use super::{committed_dump, family_lcp, stewart_trinkle, Family};
use crate::common::{lcp_violation, max_abs};
use floebench::lcp::{
    lemke, residual, solve, solve_with, Lcp, LemkeOptions, PivotRule, SolveCounters, SolveOptions,
    SolveStatus, Termination, Workspace,
};
use floebench::rng::SplitMix64;

/// Lemke's method alone on the dense tableau and on the factorised basis.
fn lemke_both(
    lcp: &Lcp,
    rule: PivotRule,
) -> (floebench::lcp::LemkeResult, floebench::lcp::LemkeResult) {
    let opts = |revised_from| LemkeOptions {
        rule,
        revised_from,
        ..LemkeOptions::default()
    };
    (
        lemke(&lcp.m, &lcp.q, &opts(usize::MAX)),
        lemke(&lcp.m, &lcp.q, &opts(0)),
    )
}

#[test]
fn revised_path_follows_the_dense_path_on_p_matrix_and_degenerate_lcps() {
    // Same rules, same data: the two representations take the same path up
    // to rounding. On P-matrices (unique solution) both must solve, with z
    // equal to 1e-8 of its scale; the pivot counts are compared as a
    // measured figure (a tie broken differently by rounding may change them).
    let mut rng = SplitMix64::new(0x5EED_F10E_0030);
    let (mut problems, mut same_pivots) = (0, 0);
    for family in [Family::PMatrix, Family::Degenerate] {
        for k in 0..150 {
            let n = 1 + (rng.next_u64() % 60) as usize;
            let lcp = family_lcp(&mut rng, family, n);
            for rule in [
                PivotRule::Lexicographic,
                PivotRule::MinRatioLargestPivot,
                PivotRule::Harris,
            ] {
                let (dense, rev) = lemke_both(&lcp, rule);
                let label = format!("{family:?} {k} (n = {n}) {rule:?}");
                if rule == PivotRule::Lexicographic {
                    assert_eq!(dense.termination, Termination::Solved, "{label}");
                }
                if dense.termination != Termination::Solved {
                    continue;
                }
                assert_eq!(rev.termination, Termination::Solved, "{label}: {rev:?}");
                let scale = max_abs(&dense.z).max(1.0);
                for (a, b) in rev.z.iter().zip(&dense.z) {
                    assert!(
                        (a - b).abs() <= 1e-8 * scale,
                        "{label}: {:?} vs {:?}",
                        rev.z,
                        dense.z
                    );
                }
                assert!(
                    rev.residual <= 1e-10,
                    "{label}: residual {:e}",
                    rev.residual
                );
                problems += 1;
                same_pivots += usize::from(rev.pivots == dense.pivots);
            }
        }
    }
    eprintln!("revised vs dense: {same_pivots} of {problems} with the same pivot count");
    assert!(
        same_pivots * 100 >= 95 * problems,
        "{same_pivots} of {problems}"
    );
}

#[test]
fn revised_path_solves_large_sparse_stewart_trinkle_lcps_through_many_refactorisations() {
    // 60–120 bodies and as many contacts (240–480 unknowns, each contact
    // coupled only with those sharing a body): hundreds of pivots, so the
    // basis is refactorised several times and the eta file is full between.
    // The driver on the factorised basis must solve every one, with a
    // residual on the original data within the tolerance, like the dense one.
    let mut rng = SplitMix64::new(0x5EED_F10E_0031);
    let opts = SolveOptions::default();
    let revised = SolveOptions {
        revised_from: 0,
        ..opts.clone()
    };
    let mut ws = Workspace::default();
    for k in 0..6 {
        let nb = 60 + (rng.next_u64() % 60) as usize;
        let m = nb + (rng.next_u64() % 20) as usize;
        let mu = [0.3, 0.7][k % 2];
        let lcp = stewart_trinkle(&mut rng, nb, m, mu);
        let d = solve_with(&mut ws, &lcp, &opts);
        let r = solve_with(&mut ws, &lcp, &revised);
        let label = format!("problem {k} (n = {})", lcp.n);
        assert!(d.status.is_solved(), "{label} dense: {:?}", d.attempts);
        assert!(r.status.is_solved(), "{label} revised: {:?}", r.attempts);
        assert!(r.attempts.iter().all(|a| a.revised), "{label}");
        let res = residual(&lcp.m, &lcp.q, &r.z);
        assert!(res <= opts.tolerance, "{label}: residual {res:e}");
        assert!(r.pivots > 100, "{label}: {} pivots", r.pivots);
        eprintln!(
            "{label}: dense {} pivots ({:?}), revised {} pivots ({:?})",
            d.pivots, d.accepted_by, r.pivots, r.accepted_by
        );
    }
}

#[test]
fn a_bay_jam_dump_is_solved_by_the_revised_path_like_the_dense_path() {
    // A contact group of the jammed 200-floe bay (moreau, 271 unknowns,
    // cases/fields/bay_jam_200.toml started at t = 5000 s of a rapier run):
    // the driver picks the factorised basis by default at this size, and
    // both paths solve it by the first attempt to the rounding level.
    let lcp = committed_dump("lcp_bay/bay_jam_200_moreau_000064.json");
    assert_eq!(lcp.n, 271);
    let opts = SolveOptions::default();
    assert!(
        lcp.n >= opts.revised_from,
        "the default picks the revised path"
    );
    let rev = solve(&lcp, &opts);
    let dense = solve(
        &lcp,
        &SolveOptions {
            revised_from: usize::MAX,
            ..opts.clone()
        },
    );
    for (s, name) in [(&rev, "revised"), (&dense, "dense")] {
        assert_eq!(s.status, SolveStatus::Solved, "{name}: {:?}", s.attempts);
        let r = residual(&lcp.m, &lcp.q, &s.z);
        assert!(r <= 1e-14, "{name}: residual {r:e}");
        assert_eq!(lcp_violation(&lcp.m, &lcp.q, &s.z, 1e-8), None, "{name}");
    }
    assert!(rev.attempts[0].revised && !dense.attempts[0].revised);
    let mut counters = SolveCounters::default();
    counters.record(&rev);
    counters.record(&dense);
    assert_eq!(counters.revised, 1);
}
