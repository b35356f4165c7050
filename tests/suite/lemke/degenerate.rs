//! Degenerate problems: ties in the ratio test and zeros in `q`; the
//! lexicographic rule terminates where the plain minimum-ratio rules cycle,
//! and follows the path of the ε-perturbed `q`.

use super::{assert_valid_solution, brute_force};
use floebench::lcp::{
    lemke, solve, Lcp, LemkeOptions, PivotRule, SolveOptions, SolveStatus, Termination,
};
use floebench::rng::SplitMix64;

#[test]
fn degenerate_ties_in_first_ratio_test() {
    // q = −e: all n rows tie in the first (z0) ratio test.
    // M is a P-matrix (principal minors 1, 1, 1, 1, 1, 1, 9).
    let m = vec![1.0, 2.0, 0.0, 0.0, 1.0, 2.0, 2.0, 0.0, 1.0];
    let q = vec![-1.0, -1.0, -1.0];
    for rule in [
        PivotRule::Lexicographic,
        PivotRule::MinRatioSmallestIndex,
        PivotRule::MinRatioLargestPivot,
    ] {
        let r = lemke(
            &m,
            &q,
            &LemkeOptions {
                rule,
                ..LemkeOptions::default()
            },
        );
        assert_eq!(r.termination, Termination::Solved, "{rule:?}");
        // Exact data, few pivots: 1e-12 covers rounding.
        assert_valid_solution(&m, &q, &r.z, 1e-12, "ties in first ratio test");
    }
    // Solution is z = (1/3, 1/3, 1/3) (w = 0): check the value itself.
    let r = lemke(&m, &q, &LemkeOptions::default());
    for &zi in &r.z {
        assert!((zi - 1.0 / 3.0).abs() < 1e-14, "z = {:?}", r.z); // 1e-14: a few roundings of 1/3.
    }
}

#[test]
fn degenerate_zero_entries_in_q() {
    // q has zeros (degenerate basic w's at 0) and ties.
    let m = vec![
        2.0, -1.0, 0.0, 1.0, //
        -1.0, 2.0, -1.0, 0.0, //
        0.0, -1.0, 2.0, -1.0, //
        1.0, 0.0, -1.0, 2.0,
    ];
    let q = vec![0.0, -1.0, 0.0, -1.0];
    let expected = brute_force(&m, &q).expect("solvable");
    let sol = solve(
        &Lcp::new(4, m.clone(), q.clone()).expect("sizes"),
        &SolveOptions::default(),
    );
    assert_eq!(sol.status, SolveStatus::Solved);
    assert_valid_solution(&m, &q, &sol.z, 1e-12, "zeros in q"); // exact small data
    for (a, b) in sol.z.iter().zip(expected.iter()) {
        assert!((a - b).abs() < 1e-12, "{:?} vs {:?}", sol.z, expected); // unique (P-matrix)
    }
}

#[test]
fn random_degenerate_integer_lcps_solved_by_lexicographic_rule() {
    // Small integer P-matrices (strictly diagonally dominant) with q in
    // {-1, 0, 1}: ratio ties and zero right-hand sides are the rule here.
    let mut rng = SplitMix64::new(0x5EED_F10E_0004);
    let mut pivots_max = 0;
    for k in 0..2000 {
        let n = 2 + ((rng.next_u64() % 7) as usize);
        let mut m: Vec<f64> = (0..n * n)
            .map(|_| (rng.next_u64() % 3) as f64 - 1.0)
            .collect();
        for i in 0..n {
            let off: f64 = (0..n).filter(|&j| j != i).map(|j| m[i * n + j].abs()).sum();
            m[i * n + i] = off + 1.0;
        }
        let q: Vec<f64> = (0..n).map(|_| (rng.next_u64() % 3) as f64 - 1.0).collect();
        let r = lemke(&m, &q, &LemkeOptions::default());
        assert_eq!(
            r.termination,
            Termination::Solved,
            "problem {k}: M = {m:?}, q = {q:?}"
        );
        pivots_max = pivots_max.max(r.pivots);
        let expected = brute_force(&m, &q).expect("P-matrix");
        for (a, b) in r.z.iter().zip(expected.iter()) {
            // 1e-10: exact small integer data, unique solution.
            assert!(
                (a - b).abs() < 1e-10,
                "problem {k}: {:?} vs {:?}",
                r.z,
                expected
            );
        }
    }
    eprintln!("degenerate integer LCPs: max pivots {pivots_max}");
}

/// Number of ways to choose k of n (bases of the augmented system).
fn binomial(n: u64, k: u64) -> u64 {
    (0..k).fold(1, |acc, i| acc * (n - i) / (i + 1))
}

#[test]
fn lexicographic_rule_terminates_where_plain_min_ratio_cycles() {
    // Honest provenance: these are NOT published examples (I could not recall
    // Kostreva's 1979 cycling example exactly). They were found by a computer
    // search over seeded random 3×3 LCPs with entries in {−2..2} and q = −e.
    // Every ratio test after the first is degenerate. The augmented system
    // has C(7, 3) = 35 bases, so more than 35 pivots prove a basis repeated,
    // i.e. the plain rule cycles; the lexicographic rule cannot repeat a
    // basis and must stop within 35 pivots.
    let cases: [(PivotRule, [f64; 9], [f64; 3]); 2] = [
        // Ties to the smallest variable index cycle; solution z = (2, 0, 5/2).
        (
            PivotRule::MinRatioSmallestIndex,
            [3.0, 0.0, -2.0, 2.0, 1.0, 1.0, -2.0, 2.0, 2.0],
            [-1.0, -1.0, -1.0],
        ),
        // Ties to the largest pivot cycle; solution z = (0, 1, 0).
        (
            PivotRule::MinRatioLargestPivot,
            [1.0, 2.0, 1.0, 2.0, 1.0, -1.0, -1.0, 1.0, 0.0],
            [-1.0, -1.0, -1.0],
        ),
    ];
    let bases = binomial(7, 3) as usize;
    for (plain, m, q) in cases {
        let cap = 10 * bases;
        let r = lemke(
            &m,
            &q,
            &LemkeOptions {
                rule: plain,
                max_pivots: Some(cap),
                ..LemkeOptions::default()
            },
        );
        assert_eq!(
            (r.termination, r.pivots),
            (Termination::MaxPivots, cap),
            "{plain:?} should cycle"
        );
        // On the dense tableau and on the factorised basis.
        for revised_from in [usize::MAX, 0] {
            let opts = LemkeOptions {
                revised_from,
                ..LemkeOptions::default()
            };
            let r = lemke(&m, &q, &opts);
            assert_eq!(r.termination, Termination::Solved, "lexicographic on {m:?}");
            assert!(r.pivots <= bases, "pivots {}", r.pivots);
            assert_valid_solution(&m, &q, &r.z, 1e-12, "cycling example"); // exact small data
        }
        let s = solve(
            &Lcp::new(3, m.to_vec(), q.to_vec()).expect("sizes"),
            &SolveOptions::default(),
        );
        assert_eq!(s.status, SolveStatus::Solved);
    }
}

#[test]
fn lexicographic_path_equals_plain_path_on_epsilon_perturbed_q() {
    // Characterisation of the lexicographic rule (CPS §4.9): it follows the
    // path that the plain minimum-ratio rule follows on the perturbed,
    // nondegenerate q(ε) = q + (ε, ε², …, εⁿ) for all small ε > 0, because the
    // right-hand side becomes B⁻¹q(ε) = b + Σ_k ε^k (B⁻¹)_{·k}. We compare the
    // pivot counts, terminations and solutions on heavily degenerate random
    // 3×3 integer LCPs (z0 preference off on both sides, since it is a
    // deliberate shortcut that the perturbed path does not take).
    let mut rng = SplitMix64::new(0x5EED_F10E_0009);
    let eps: f64 = 1e-4; // small against the 1/48-scale gaps of these integer tableaus; ε³ = 1e-12 still resolvable
    let mut compared = 0;
    for k in 0..20_000 {
        let n = 3;
        let m: Vec<f64> = (0..n * n)
            .map(|_| (rng.next_u64() % 5) as f64 - 2.0)
            .collect();
        let q: Vec<f64> = (0..n).map(|_| (rng.next_u64() % 3) as f64 - 1.0).collect();
        if q.iter().all(|&x| x >= 0.0) {
            continue;
        }
        let lex = lemke(
            &m,
            &q,
            &LemkeOptions {
                prefer_z0: false,
                ..LemkeOptions::default()
            },
        );
        let q_eps: Vec<f64> = (0..n).map(|i| q[i] + eps.powi(i as i32 + 1)).collect();
        let plain = lemke(
            &m,
            &q_eps,
            &LemkeOptions {
                rule: PivotRule::MinRatioSmallestIndex,
                tie_tol: 0.0,
                prefer_z0: false,
                ..LemkeOptions::default()
            },
        );
        if q_eps.iter().all(|&x| x >= 0.0) {
            continue; // q(ε) >= 0 needs no pivot while q does: not comparable
        }
        assert_eq!(
            (lex.termination, lex.pivots),
            (plain.termination, plain.pivots),
            "problem {k}: M = {m:?}, q = {q:?}"
        );
        if lex.termination == Termination::Solved {
            for (a, b) in lex.z.iter().zip(plain.z.iter()) {
                // The solutions differ by O(ε) times entries of B⁻¹ (<= ~50 here).
                assert!(
                    (a - b).abs() <= 100.0 * eps,
                    "problem {k}: {:?} vs {:?}",
                    lex.z,
                    plain.z
                );
            }
        }
        compared += 1;
    }
    assert!(compared > 10_000);
}

#[test]
fn lexicographic_rule_never_cycles_on_random_degenerate_lcps() {
    // Arbitrary small integer matrices (no structure: P, copositive or not)
    // with q in {−1, 0, 1}: heavily degenerate. The lexicographic rule must
    // always stop by a solution or a ray, within the number of bases
    // C(2n+1, n); the plain rules are counted to show cycling does occur here.
    let mut rng = SplitMix64::new(0x5EED_F10E_0008);
    let (mut plain_cycles, mut solved, mut lex_max) = (0, 0, 0);
    let count = 30_000;
    for k in 0..count {
        let n = 3 + ((rng.next_u64() % 2) as usize);
        let m: Vec<f64> = (0..n * n)
            .map(|_| (rng.next_u64() % 5) as f64 - 2.0)
            .collect();
        let q: Vec<f64> = (0..n).map(|_| (rng.next_u64() % 3) as f64 - 1.0).collect();
        let bases = binomial(2 * n as u64 + 1, n as u64) as usize;
        let r = lemke(&m, &q, &LemkeOptions::default());
        assert!(
            matches!(
                r.termination,
                Termination::Solved | Termination::RayTermination
            ),
            "problem {k}: {:?} after {} pivots, M = {m:?}, q = {q:?}",
            r.termination,
            r.pivots
        );
        assert!(
            r.pivots <= bases,
            "problem {k}: {} pivots > {bases} bases",
            r.pivots
        );
        lex_max = lex_max.max(r.pivots);
        // The factorised basis takes the same path: same termination and
        // pivot count on these exact integer data (its lexicographic rows
        // of B⁻¹ come from transposed solves through the eta file).
        let rev = lemke(
            &m,
            &q,
            &LemkeOptions {
                revised_from: 0,
                ..LemkeOptions::default()
            },
        );
        assert_eq!(
            (rev.termination, rev.pivots),
            (r.termination, r.pivots),
            "problem {k}: revised path, M = {m:?}, q = {q:?}"
        );
        if r.termination == Termination::Solved {
            solved += 1;
            assert_valid_solution(&m, &q, &r.z, 1e-10, &format!("problem {k}"));
            // exact small data
        }
        for rule in [
            PivotRule::MinRatioSmallestIndex,
            PivotRule::MinRatioLargestPivot,
        ] {
            let p = lemke(
                &m,
                &q,
                &LemkeOptions {
                    rule,
                    max_pivots: Some(bases + 1),
                    ..LemkeOptions::default()
                },
            );
            if p.termination == Termination::MaxPivots {
                plain_cycles += 1;
            }
        }
    }
    eprintln!(
        "random degenerate 3×3/4×4 LCPs: {count} problems, lexicographic solved {solved} (max pivots {lex_max}), \
         plain-rule runs that cycled: {plain_cycles}"
    );
    assert!(
        plain_cycles > 0,
        "the generator no longer produces cycling instances"
    );
}
