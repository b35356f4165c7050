//! The reused work space and output: one `Workspace` (and one output for
//! `solve_into`) gives the same results as fresh ones.

use super::{nonsym_pd, random_q, spd, stewart_trinkle};
use floebench::lcp::{
    lemke, solve, solve_into, solve_warm_into, solve_warm_with, solve_with, BasisGuess, Lcp,
    LcpSolution, LemkeOptions, SolveOptions, Workspace,
};
use floebench::rng::SplitMix64;

#[test]
fn one_workspace_gives_the_same_solutions_as_fresh_ones() {
    // Buffers of a larger problem left in the work space must not leak into
    // a smaller one: same z bit for bit, same attempts.
    let mut rng = SplitMix64::new(0x5EED_F10E_0012);
    let mut ws = Workspace::default();
    let opts = SolveOptions::default();
    for k in 0..300 {
        let n = 1 + (rng.next_u64() % 30) as usize;
        let m = match k % 3 {
            0 => spd(&mut rng, n),
            1 => nonsym_pd(&mut rng, n),
            _ => {
                let nb = 1 + n / 4;
                stewart_trinkle(&mut rng, nb, 1 + n / 4, 0.5).m
            }
        };
        let n = (m.len() as f64).sqrt() as usize;
        let q = random_q(&mut rng, n);
        let lcp = Lcp::new(n, m, q).expect("sizes");
        let a = solve_with(&mut ws, &lcp, &opts);
        let b = solve_with(&mut Workspace::default(), &lcp, &opts);
        assert_eq!(a, b, "problem {k}");
        let c = solve(&lcp, &opts);
        assert_eq!(a, c, "problem {k}");
        let la = floebench::lcp::lemke_with(&mut ws, &lcp.m, &lcp.q, &LemkeOptions::default());
        let lb = lemke(&lcp.m, &lcp.q, &LemkeOptions::default());
        assert_eq!(la, lb, "problem {k}");
    }
}

#[test]
fn solve_into_reuses_its_output_and_equals_fresh_solves() {
    // One work space and one output through problems of every size and
    // outcome (solved, q >= 0, non-finite, invalid tolerance, warm right
    // and wrong): each result equals a fresh solve's, field for field (NaN
    // compared as NaN through the Debug text).
    let mut rng = SplitMix64::new(0x5EED_F10E_0031);
    let mut ws = Workspace::default();
    let mut out = LcpSolution::empty();
    let opts = SolveOptions::default();
    let bad_tol = SolveOptions {
        tolerance: f64::NAN,
        ..SolveOptions::default()
    };
    for k in 0..400 {
        let n = 1 + (rng.next_u64() % 24) as usize;
        let m = if k % 2 == 0 {
            spd(&mut rng, n)
        } else {
            nonsym_pd(&mut rng, n)
        };
        let mut q = random_q(&mut rng, n);
        match k % 7 {
            0 => q.iter_mut().for_each(|x| *x = x.abs()),
            1 => q[0] = f64::NAN,
            _ => {}
        }
        let lcp = Lcp::new(n, m, q).expect("sizes");
        let o = if k % 11 == 0 { &bad_tol } else { &opts };
        solve_into(&mut ws, &lcp, o, &mut out);
        let fresh = solve_with(&mut Workspace::default(), &lcp, o);
        assert_eq!(format!("{out:?}"), format!("{fresh:?}"), "problem {k}");
        if k % 5 == 0 {
            let z = &fresh.z;
            let guess = if k % 10 == 0 {
                BasisGuess {
                    basic: z.iter().map(|v| *v > 0.0).collect(),
                    z: z.clone(),
                }
            } else {
                BasisGuess {
                    basic: z.iter().map(|v| *v == 0.0).collect(),
                    z: vec![1.0; n],
                }
            };
            solve_warm_into(&mut ws, &lcp, &opts, &guess, &mut out);
            let fresh = solve_warm_with(&mut Workspace::default(), &lcp, &opts, &guess);
            assert_eq!(format!("{out:?}"), format!("{fresh:?}"), "warm problem {k}");
        }
    }
}
