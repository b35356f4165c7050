//! The stress measure's closed forms: the window's mean stress of opposite
//! and shear impulses, its principal stresses, and the defining points of
//! the yield curves.

use super::rel;
use floebench::fracture::stress::{mean_stress, moment, principal, yield_measure};
use floebench::fracture::Load;
use floebench::geometry::Vec2;
use floebench::model::fracture::FractureSettings;

/// A square of side `a` centred at the origin, thickness `h`.
fn square_loads(a: f64, f: f64, shear: bool) -> Vec<Load> {
    let load = |x: f64, y: f64, px: f64, py: f64| Load {
        floe: 0,
        other: 1,
        point: Vec2::new(x, y),
        impulse: Vec2::new(px, py),
    };
    if shear {
        vec![
            load(a / 2.0, 0.0, 0.0, f),
            load(-a / 2.0, 0.0, 0.0, -f),
            load(0.0, a / 2.0, f, 0.0),
            load(0.0, -a / 2.0, -f, 0.0),
        ]
    } else {
        vec![load(a / 2.0, 0.0, -f, 0.0), load(-a / 2.0, 0.0, f, 0.0)]
    }
}

#[test]
fn equal_and_opposite_impulses_on_opposite_faces_give_the_uniaxial_stress() {
    let (a, h, p, window) = (20.0, 1.5, 3.0e4, 7.0);
    let m = moment(&Vec2::zeros(), square_loads(a, p, false).iter());
    let s = mean_stress(&m, a * a, h, window);
    // The mean force p/window on a face of area a h: σ_xx = −(p/W)/(a h).
    let want = -(p / window) / (a * h);
    assert!(rel(s[0], want) <= 1e-15, "{} vs {want}", s[0]);
    assert_eq!(s[1], 0.0);
    assert_eq!(s[2], 0.0);
    let (s1, s2) = principal(&s);
    assert_eq!(s1, 0.0);
    assert!(rel(s2, want) <= 1e-15);
}

#[test]
fn a_pure_shear_load_gives_the_closed_form_principal_stresses() {
    let (a, h, p, window) = (20.0, 1.5, 3.0e4, 7.0);
    let m = moment(&Vec2::zeros(), square_loads(a, p, true).iter());
    let s = mean_stress(&m, a * a, h, window);
    let tau = (p / window) / (a * h);
    assert!(s[0].abs() <= 1e-15 * tau && s[2].abs() <= 1e-15 * tau);
    assert!(rel(s[1], tau) <= 1e-15);
    let (s1, s2) = principal(&s);
    assert!(rel(s1, tau) <= 1e-15 && rel(s2, -tau) <= 1e-15, "{s1} {s2}");
}

#[test]
fn the_yield_curves_hold_their_defining_points() {
    let mut s = FractureSettings::default();
    // Mohr: no stress is inside; the biaxial vertex is on the curve.
    assert!(yield_measure(&s, &[0.0; 3]) < 1.0);
    let q = s.mohr_q;
    let v = -((1.0 / q + 1.0) * s.mohr_sigma_c / (1.0 / q - q));
    assert!((yield_measure(&s, &[v, 0.0, v]) - 1.0).abs() <= 1e-12);
    assert!(yield_measure(&s, &[1.01 * v, 0.0, 1.01 * v]) > 1.0);
    // Hibler: uniaxial compression fails at 0.4 p (e = 2), p = P* at A = 1.
    s.yield_curve = "hibler".parse().unwrap_or_else(|e: String| panic!("{e}"));
    let p = s.hibler_p_star;
    assert!((yield_measure(&s, &[0.0, 0.0, -0.4 * p]) - 1.0).abs() <= 1e-12);
    assert!(yield_measure(&s, &[0.0, 0.0, -0.39 * p]) < 1.0);
    assert!(yield_measure(&s, &[0.0, 0.0, -0.41 * p]) > 1.0);
}
