//! The exact local Coulomb solve: Signorini and Coulomb on random
//! contacts, sticking, sliding and off.

use floebench::iterative::local_coulomb;
use floebench::rng::SplitMix64;

/// `u = W p + r` for a 2 × 2 row-major `W`.
fn velocity(w: [f64; 4], p: [f64; 2], r: [f64; 2]) -> [f64; 2] {
    [
        w[0] * p[0] + w[1] * p[1] + r[0],
        w[2] * p[0] + w[3] * p[1] + r[1],
    ]
}

#[test]
fn the_local_solve_satisfies_signorini_and_coulomb_on_random_contacts() {
    let mut rng = SplitMix64::new(38);
    let (mut stick, mut slide, mut off) = (0, 0, 0);
    for _ in 0..20_000 {
        // A contact's block: J M⁻¹ Jᵀ of two random floes' rows.
        // Outside the uniqueness condition: skipped.
        let Some((w, mu, r)) = super::random_contact(&mut rng) else {
            continue;
        };
        let p = local_coulomb(w, r, mu, mu > 0.0);
        let u = velocity(w, p, r);
        let scale = r[0].abs() + r[1].abs();
        let tol = 1e-10 * scale;
        assert!(p[0] >= 0.0, "λ = {} < 0", p[0]);
        assert!(u[0] >= -tol, "u_N = {} < 0 (W {w:?}, r {r:?})", u[0]);
        assert!(
            (p[0] * u[0]).abs() <= tol * p[0].max(1e-300),
            "λ u_N = {}",
            p[0] * u[0]
        );
        assert!(
            p[1].abs() <= mu * p[0] * (1.0 + 1e-9),
            "|β| = {} > μλ = {}",
            p[1].abs(),
            mu * p[0]
        );
        if p[0] == 0.0 {
            off += 1;
        } else if p[1].abs() < mu * p[0] * (1.0 - 1e-9) {
            stick += 1;
            assert!(u[1].abs() <= tol, "stick with u_T = {}", u[1]);
        } else {
            slide += 1;
            assert!(p[1] * u[1] <= tol * p[1].abs(), "friction along the slip");
        }
    }
    eprintln!("local solves: {off} off, {stick} stick, {slide} slide");
    assert!(off > 1000 && stick > 1000 && slide > 1000);
}
