//! Data at the edges of the floating-point range: PSD LCPs scaled by up to
//! 1e±300 and into the subnormals, the exact power-of-two scaling, and a
//! dump with a 1e308 entry judged on the scaled problem.

use super::committed_dump;
use crate::common::lcp_violation;
use floebench::lcp::{residual, solve, Lcp, SolveOptions, SolveStatus};

/// `2^e`, exact for `-1074 <= e <= 1023` (subnormal below −1022).
fn pow2(e: i32) -> f64 {
    if e >= -1022 {
        f64::from_bits(((e + 1023) as u64) << 52)
    } else {
        f64::from_bits(1u64 << (e + 1074))
    }
}

#[test]
fn psd_lcps_near_the_floating_point_range_are_solved() {
    // 2×2 positive semidefinite LCPs with q < 0 that have a solution, with
    // M and q scaled together by 1e300, 2^1020, 1e-300 and 2^-1060
    // (subnormal range): the power-of-two scaling is exact over the whole
    // exponent range and the compensated w does not overflow.
    let cases: [([f64; 4], [f64; 2]); 4] = [
        ([1.0, 1.0, 1.0, 1.0], [-1.0, -1.0]),   // singular: z1 + z2 = 1
        ([2.0, -1.0, -1.0, 2.0], [-1.0, -0.5]), // definite
        ([1.0, 2.0, 2.0, 4.0], [-1.0, -2.0]),   // rank 1: z = (0, 1/2)
        ([4.0, 2.0, 2.0, 1.0], [-1.0, -1.0]),   // rank 1
    ];
    for s in [1e300, pow2(1020), 1.0, 1e-300, pow2(-1030)] {
        for (m, q) in &cases {
            let ms: Vec<f64> = m.iter().map(|x| x * s).collect();
            let qs: Vec<f64> = q.iter().map(|x| x * s).collect();
            let lcp = Lcp::new(2, ms.clone(), qs.clone()).expect("sizes");
            let sol = solve(&lcp, &SolveOptions::default());
            assert_eq!(
                sol.status,
                SolveStatus::Solved,
                "scale {s:e}, M = {m:?}: {:?}",
                sol.attempts
            );
            assert!(
                residual(&ms, &qs, &sol.z) <= 1e-14,
                "scale {s:e}, M = {m:?}"
            );
            assert!(sol.z.iter().all(|z| z.is_finite() && *z >= 0.0));
        }
    }
    // M near the top of the range, q of order 1: z of order 1e-300.
    let lcp = Lcp::new(2, vec![1e300, 1e300, 1e300, 1e300], vec![-1.0, -1.0]).expect("sizes");
    let sol = solve(&lcp, &SolveOptions::default());
    assert_eq!(sol.status, SolveStatus::Solved);
    assert!(((sol.z[0] + sol.z[1]) * 1e300 - 1.0).abs() < 1e-15);
    // The exponent of the scaling is exact over the whole range.
    for e in -1074..=1023 {
        assert_eq!(floebench::lcp::scaling::pow2_exponent(pow2(e)), e, "2^{e}");
    }
    assert_eq!(floebench::lcp::scaling::pow2_exponent(f64::MAX), 1024);
    assert_eq!(floebench::lcp::scaling::pow2_exponent(1.5), 1); // 1.5 > √2
    assert_eq!(floebench::lcp::scaling::pow2_exponent(1.4), 0);
    assert_eq!(floebench::lcp::scaling::pow2_exponent(0.0), 0);
}

#[test]
fn a_dump_at_the_edge_of_the_f64_range_is_solved_and_judged_scaled() {
    // Found by the long fuzz run (seed 17, input 10800): a coast dump with
    // one q entry mutated to 1e308. The driver solves it; a check that
    // formed M z and zᵀw unscaled overflowed (zᵀw = NaN) and called it a
    // false solve. z/σ solves LCP(M, q/σ): judged that way it holds.
    let lcp = committed_dump("lcp_edge/fuzz_q_1e308.json");
    assert!(lcp.q.iter().any(|v| v.abs() == 1e308));
    let s = solve(&lcp, &SolveOptions::default());
    assert!(s.status.is_solved(), "{:?}", s.status);
    assert!(s.z.iter().all(|x| x.is_finite() && *x >= 0.0));
    assert_eq!(lcp_violation(&lcp.m, &lcp.q, &s.z, 1e-8), None);
}
