//! Random P-matrix LCPs (positive definite, symmetric or not, and
//! diagonally dominant): solved by the first attempt, equal to a brute-force
//! enumeration of the complementary bases, and solved by every pivot rule
//! and with a custom covering vector.

use super::{assert_valid_solution, brute_force, diag_dominant, nonsym_pd, random_q, spd};
use floebench::lcp::{
    lemke, solve, Lcp, LemkeOptions, PivotRule, SolveCounters, SolveOptions, SolveStatus, Strategy,
    Termination,
};
use floebench::rng::SplitMix64;
use std::time::Instant;

#[test]
fn random_p_matrix_lcps_solved_by_first_attempt() {
    let mut rng = SplitMix64::new(0x5EED_F10E_0001);
    let opts = SolveOptions::default();
    let mut counters = SolveCounters::default();
    let (mut pivots_sum, mut pivots_max, mut max_res) = (0usize, 0usize, 0.0_f64);
    let mut per_n_max = 0.0_f64; // max pivots / n
    let start = Instant::now();
    let count = 1000;
    for k in 0..count {
        let n = 1 + ((rng.next_u64() % 60) as usize);
        let family = k % 3;
        let mut m = match family {
            0 => spd(&mut rng, n),
            1 => nonsym_pd(&mut rng, n),
            _ => diag_dominant(&mut rng, n),
        };
        let mut q = random_q(&mut rng, n);
        // Random scales 10^-3..10^3 of M and q: the solver must be scale-free.
        let sm = 10f64.powi((rng.next_u64() % 7) as i32 - 3);
        let sq = 10f64.powi((rng.next_u64() % 7) as i32 - 3);
        m.iter_mut().for_each(|x| *x *= sm);
        q.iter_mut().for_each(|x| *x *= sq);
        let lcp = Lcp::new(n, m, q).expect("sizes");
        let sol = solve(&lcp, &opts);
        let label = format!("problem {k} (n = {n}, family {family})");
        assert_eq!(
            sol.status,
            SolveStatus::Solved,
            "{label}: {:?}",
            sol.attempts
        );
        assert_eq!(sol.attempts.len(), 1, "{label}");
        assert_eq!(sol.accepted_by, Some(Strategy::Lexicographic), "{label}");
        assert_eq!(sol.attempts[0].termination, Termination::Solved, "{label}");
        // Spec requirement: residual below 1e-10 (the default tolerance).
        assert!(sol.residual < 1e-10, "{label}: residual {}", sol.residual);
        // 1e-10 relative to the magnitudes entering w = Mz + q: ~1e5 ulps for n <= 60.
        assert_valid_solution(&lcp.m, &lcp.q, &sol.z, 1e-10, &label);
        pivots_sum += sol.pivots;
        pivots_max = pivots_max.max(sol.pivots);
        per_n_max = per_n_max.max(sol.pivots as f64 / n as f64);
        max_res = max_res.max(sol.residual);
        counters.record(&sol);
    }
    let elapsed = start.elapsed();
    assert_eq!(counters.solved, count as u64);
    eprintln!(
        "random P-matrix LCPs: {count} problems, n in 1..=60, pivots mean {:.1} max {} (max pivots/n {:.2}), \
         max residual {:.2e}, total {:.3} s",
        pivots_sum as f64 / count as f64,
        pivots_max,
        per_n_max,
        max_res,
        elapsed.as_secs_f64()
    );
    eprintln!(
        "counters: {}",
        serde_json::to_string(&counters).expect("json")
    );
}

#[test]
fn small_random_p_matrix_lcps_match_brute_force() {
    let mut rng = SplitMix64::new(0x5EED_F10E_0002);
    for k in 0..300 {
        let n = 1 + ((rng.next_u64() % 8) as usize);
        let m = if k % 2 == 0 {
            nonsym_pd(&mut rng, n)
        } else {
            diag_dominant(&mut rng, n)
        };
        let q = random_q(&mut rng, n);
        let expected = brute_force(&m, &q).expect("a P-matrix LCP has a solution");
        let sol = solve(&Lcp::new(n, m, q).expect("sizes"), &SolveOptions::default());
        assert_eq!(sol.status, SolveStatus::Solved);
        for (a, b) in sol.z.iter().zip(expected.iter()) {
            // 1e-8: the unique solution, both computed to ~1e-13 on these well-conditioned matrices.
            assert!(
                (a - b).abs() <= 1e-8 * (1.0 + b.abs()),
                "problem {k}: z {:?} vs {:?}",
                sol.z,
                expected
            );
        }
    }
}

#[test]
fn every_pivot_rule_and_custom_covering_vector_solve_p_matrix_lcps() {
    let mut rng = SplitMix64::new(0x5EED_F10E_0003);
    for k in 0..200 {
        let n = 1 + ((rng.next_u64() % 30) as usize);
        let m = nonsym_pd(&mut rng, n);
        let q = random_q(&mut rng, n);
        let reference = lemke(&m, &q, &LemkeOptions::default());
        assert_eq!(reference.termination, Termination::Solved, "problem {k}");
        let d: Vec<f64> = (0..n).map(|_| 0.1 + rng.uniform()).collect();
        for rule in [
            PivotRule::Lexicographic,
            PivotRule::MinRatioSmallestIndex,
            PivotRule::MinRatioLargestPivot,
            PivotRule::Harris,
        ] {
            for covering in [None, Some(d.clone())] {
                let opts = LemkeOptions {
                    rule,
                    covering,
                    ..LemkeOptions::default()
                };
                let r = lemke(&m, &q, &opts);
                assert_eq!(r.termination, Termination::Solved, "problem {k}, {rule:?}");
                // 1e-9: same unique solution, each within ~1e-13 relative.
                assert!(r.residual < 1e-9, "problem {k}: residual {}", r.residual);
                for (a, b) in r.z.iter().zip(reference.z.iter()) {
                    assert!(
                        (a - b).abs() <= 1e-8 * (1.0 + b.abs()),
                        "problem {k}, {rule:?}"
                    );
                }
            }
        }
    }
}
