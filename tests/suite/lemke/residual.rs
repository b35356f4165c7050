//! The residual against a hand computation, and the size checks of the
//! `Lcp` constructors.

use floebench::lcp::{residual, Lcp};

#[test]
fn residual_matches_hand_computation() {
    // M = I, q = (−1, 2); z = (1, 0) is the solution; z = (0, 0) gives
    // min(z, w) = (min(0, −1), min(0, 2)) = (−1, 0): residual 1 / √5.
    let m = vec![1.0, 0.0, 0.0, 1.0];
    let q = vec![-1.0, 2.0];
    assert_eq!(residual(&m, &q, &[1.0, 0.0]), 0.0);
    assert!((residual(&m, &q, &[0.0, 0.0]) - 1.0 / 5f64.sqrt()).abs() < 1e-15); // one rounding
    assert_eq!(residual(&m, &q, &[1.0]), f64::INFINITY);
    assert_eq!(residual(&m, &q, &[f64::NAN, 0.0]), f64::INFINITY);
    // q = 0: denominator floor f64::EPSILON, z = 0 has residual 0.
    assert_eq!(residual(&m, &[0.0, 0.0], &[0.0, 0.0]), 0.0);
    // Huge but finite data do not overflow the norms.
    assert!(residual(&m, &[-1e200, 1e200], &[1e200, 0.0]) == 0.0);
}

#[test]
fn lcp_constructors_validate_sizes() {
    assert!(Lcp::new(2, vec![1.0; 4], vec![0.0; 2]).is_ok());
    let e = Lcp::new(2, vec![1.0; 3], vec![0.0; 2]).expect_err("bad M");
    assert!(e.to_string().contains("matrix M has 3 entries"), "{e}");
    let e = Lcp::new(2, vec![1.0; 4], vec![0.0; 3]).expect_err("bad q");
    assert!(e.to_string().contains("vector q has 3 entries"), "{e}");
    let e = Lcp::from_rows(&[vec![1.0, 2.0], vec![3.0]], vec![0.0; 2]).expect_err("ragged");
    assert!(e.to_string().contains("row 1 of M has 1 entries"), "{e}");
    let lcp = Lcp::from_rows(&[vec![1.0, 2.0], vec![3.0, 4.0]], vec![5.0, 6.0]).expect("ok");
    assert_eq!(lcp.m, vec![1.0, 2.0, 3.0, 4.0]);
    assert_eq!(lcp.w(&[1.0, 1.0]).expect("sizes"), vec![8.0, 13.0]);
}
