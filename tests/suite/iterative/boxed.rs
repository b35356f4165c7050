//! The bounded normal impulse of crushing ice (`0 ≤ λ ≤ b`): the exact
//! local solve against a brute-force enumeration of the boxed law's cases,
//! a two-contact problem with a known boxed answer (NSGS, APGD, the
//! residual zero at it), infinite bounds bit for bit the rigid solve, and
//! finite bounds on a bundled case's contacts.

use super::{frictional_cradle, problems};
use floebench::iterative::{
    apgd, local_coulomb, local_coulomb_boxed, nsgs, project_boxed, residual_at, Delassus,
};
use floebench::rng::SplitMix64;

/// `u = W p + r` for a 2 × 2 row-major `W`.
fn velocity(w: [f64; 4], p: [f64; 2], r: [f64; 2]) -> [f64; 2] {
    [
        w[0] * p[0] + w[1] * p[1] + r[0],
        w[2] * p[0] + w[3] * p[1] + r[1],
    ]
}

/// Every case of the boxed law, each solved on its own and kept if it
/// satisfies its conditions (to `tol` in velocity, relative `1e-9` in
/// impulse): take-off, stick and slide below the bound, stick and slide at
/// it. Returns the admissible answers and the name of each.
fn enumerate(w: [f64; 4], r: [f64; 2], mu: f64, b: f64, tol: f64) -> Vec<([f64; 2], &'static str)> {
    let mut out = Vec::new();
    let slack = 1e-9;
    let le = |a: f64, c: f64| a <= c + slack * c.abs().max(1e-300);
    // Take-off.
    if r[0] >= -tol {
        out.push(([0.0, 0.0], "take-off"));
    }
    // Stick, 0 < λ < b: W p = −r.
    let det = w[0] * w[3] - w[1] * w[2];
    let stick = [
        (-r[0] * w[3] + r[1] * w[1]) / det,
        (-r[1] * w[0] + r[0] * w[2]) / det,
    ];
    if stick[0] > 0.0 && le(stick[0], b) && le(stick[1].abs(), mu * stick[0]) {
        out.push((stick, "stick"));
    }
    // Slide, 0 < λ < b: β = −s μ λ, u_N = 0.
    for s in [1.0, -1.0] {
        let lam = -r[0] / (w[0] - s * mu * w[1]);
        let p = [lam, -s * mu * lam];
        let u = velocity(w, p, r);
        if lam > 0.0 && le(lam, b) && s * u[1] >= -tol {
            out.push((p, "slide"));
        }
    }
    // At the bound: stick (u_T = 0, |β| ≤ μ b) or slide (β = −s μ b), u_N ≤ 0.
    let beta = -(r[1] + w[2] * b) / w[3];
    let p = [b, beta];
    if le(beta.abs(), mu * b) && velocity(w, p, r)[0] <= tol {
        out.push((p, "bound stick"));
    }
    for s in [1.0, -1.0] {
        let p = [b, -s * mu * b];
        let u = velocity(w, p, r);
        if s * u[1] >= -tol && u[0] <= tol {
            out.push((p, "bound slide"));
        }
    }
    out
}

#[test]
fn the_boxed_local_solve_is_a_case_of_the_brute_force_enumeration() {
    let mut rng = SplitMix64::new(54);
    let mut seen = std::collections::BTreeMap::new();
    for _ in 0..20_000 {
        // Outside the uniqueness condition: skipped.
        let Some((w, mu, r)) = super::random_contact(&mut rng) else {
            continue;
        };
        // A bound around the rigid answer's λ: active about half the time.
        let rigid = local_coulomb(w, r, mu, mu > 0.0);
        let b = rigid[0] * rng.range(0.0, 2.0) + rng.range(0.0, 1e3);
        let p = local_coulomb_boxed(w, r, mu, mu > 0.0, b);
        let tol = 1e-9 * (r[0].abs() + r[1].abs());
        let cases = enumerate(w, r, mu, b, tol);
        let near = |a: [f64; 2], c: [f64; 2]| {
            (a[0] - c[0]).abs() <= 1e-8 * (b + a[0].abs())
                && (a[1] - c[1]).abs() <= 1e-8 * (b + a[0].abs())
        };
        let hit = cases.iter().find(|(c, _)| near(p, *c));
        let Some((_, name)) = hit else {
            panic!("W {w:?}, r {r:?}, μ {mu}, b {b}: {p:?} is none of {cases:?}");
        };
        assert!(p[0] <= b, "λ = {} above the bound {b}", p[0]);
        *seen.entry(*name).or_insert(0) += 1;
    }
    eprintln!("boxed local solves: {seen:?}");
    for name in ["take-off", "stick", "slide", "bound stick", "bound slide"] {
        assert!(
            seen.get(name).copied().unwrap_or(0) > 200,
            "{name}: {seen:?}"
        );
    }
}

#[test]
fn infinite_bounds_project_and_solve_as_the_rigid_cone_bit_for_bit() {
    let mut rng = SplitMix64::new(7);
    for _ in 0..1000 {
        let x = [rng.range(-2.0, 2.0), rng.range(-2.0, 2.0)];
        let mu = rng.range(0.0, 1.0);
        let c = floebench::iterative::project_cone(x, mu);
        assert_eq!(project_boxed(x, mu, f64::INFINITY), c);
        let b = rng.range(0.0, 2.0);
        let p = project_boxed(x, mu, b);
        assert!(p[0] <= b && p[1].abs() <= mu * p[0] * (1.0 + 1e-15));
    }
}

/// A dense problem of two contacts with bounds, written out here: the
/// trait is all the solvers need.
struct Dense2 {
    w: [[f64; 4]; 4],
    q: [f64; 4],
    mu: f64,
    b: [f64; 2],
}

impl Delassus for Dense2 {
    type State = [f64; 4];
    fn len(&self) -> usize {
        2
    }
    fn block(&self, j: usize) -> [f64; 4] {
        let (a, c) = (2 * j, 2 * j + 1);
        [self.w[a][a], self.w[a][c], self.w[c][a], self.w[c][c]]
    }
    fn mu(&self, _j: usize) -> f64 {
        self.mu
    }
    fn bound(&self, j: usize) -> f64 {
        self.b[j]
    }
    fn bounded(&self) -> bool {
        self.b.iter().any(|b| b.is_finite())
    }
    fn free(&self, j: usize) -> [f64; 2] {
        [self.q[2 * j], self.q[2 * j + 1]]
    }
    fn state(&self, p: &[[f64; 2]]) -> [f64; 4] {
        let mut s = [0.0; 4];
        for (j, pj) in p.iter().enumerate() {
            self.apply(j, *pj, &mut s);
        }
        s
    }
    fn relative(&self, j: usize, s: &[f64; 4]) -> [f64; 2] {
        [self.q[2 * j] + s[2 * j], self.q[2 * j + 1] + s[2 * j + 1]]
    }
    fn apply(&self, j: usize, dp: [f64; 2], s: &mut [f64; 4]) {
        for (i, si) in s.iter_mut().enumerate() {
            *si += self.w[i][2 * j] * dp[0] + self.w[i][2 * j + 1] * dp[1];
        }
    }
    fn residual_scale(&self) -> f64 {
        self.q.iter().map(|x| x * x).sum::<f64>().sqrt()
    }
}

/// Normals coupled (`W_N1N2 = 1`), tangents apart: rigid, `λ = (5/3, 2/3)`;
/// with `b_1 = 1`, contact 1 crushes at its bound (`u_N1 = −1`) and
/// contact 2 takes `λ_2 = 1`; contact 1 sticks (`β_1 = −0.2`), contact 2
/// slides (`β_2 = μ λ_2 = 0.5`, `u_T2 = −1.5`).
fn two_contacts(b1: f64) -> Dense2 {
    Dense2 {
        w: [
            [2.0, 0.0, 1.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [1.0, 0.0, 2.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ],
        q: [-4.0, 0.2, -3.0, -2.0],
        mu: 0.5,
        b: [b1, f64::INFINITY],
    }
}

#[test]
fn two_contacts_with_a_bound_take_the_boxed_answer() {
    let answer = [[1.0, -0.2], [1.0, 0.5]];
    let prob = two_contacts(1.0);
    let s = prob.state(&answer);
    assert!(residual_at(&prob, &answer, &s, true) <= 1e-15);
    assert_eq!(prob.relative(0, &s), [-1.0, 0.0]);
    // The rigid answer violates the bound's law (λ_1 = 5/3 > 1).
    let rigid = [[5.0 / 3.0, -0.2], [2.0 / 3.0, 1.0 / 3.0]];
    assert!(residual_at(&prob, &rigid, &prob.state(&rigid), true) > 0.1);
    // …and is the answer without the bound.
    let free = two_contacts(f64::INFINITY);
    assert!(residual_at(&free, &rigid, &free.state(&rigid), true) <= 1e-15);
    let mut p = vec![[0.0; 2]; 2];
    let (o, _) = nsgs::solve(&prob, &mut p, 1e-12, 1000, 1.0);
    assert!(o.converged, "{o:?}");
    for (a, e) in p.iter().zip(&answer) {
        assert!(
            (a[0] - e[0]).abs() < 1e-10 && (a[1] - e[1]).abs() < 1e-10,
            "{p:?}"
        );
    }
    // APGD solves the cone relaxation: the same answer without friction.
    let mut frictionless = two_contacts(1.0);
    frictionless.mu = 0.0;
    let mut p = vec![[0.0; 2]; 2];
    let (o, _) = apgd::solve(&frictionless, &mut p, 1e-10, 5000);
    assert!(o.converged, "{o:?}");
    assert!(
        (p[0][0] - 1.0).abs() < 1e-8 && (p[1][0] - 1.0).abs() < 1e-8,
        "{p:?}"
    );
}

#[test]
fn bounds_on_a_bundled_case_hold_and_infinite_ones_change_nothing() {
    for (_, sp) in problems(&frictional_cradle()) {
        let m = sp.len();
        let mut p0 = vec![[0.0; 2]; m];
        let (o0, v0) = nsgs::solve(&sp, &mut p0, 1e-10, 2000, 1.0);
        assert!(o0.converged);
        let rigid = sp.clone().with_normal_bounds(vec![f64::INFINITY; m]);
        let mut p1 = vec![[0.0; 2]; m];
        let (o1, v1) = nsgs::solve(&rigid, &mut p1, 1e-10, 2000, 1.0);
        assert_eq!((p0.clone(), v0, o0), (p1, v1, o1));
        // Half the rigid answer's largest impulse as every contact's bound.
        let top = p0.iter().fold(0.0f64, |a, p| a.max(p[0]));
        let b = 0.5 * top;
        let boxed = sp.clone().with_normal_bounds(vec![b; m]);
        for method in ["nsgs", "apgd"] {
            let mut p = vec![[0.0; 2]; m];
            let (o, _) = match method {
                "nsgs" => nsgs::solve(&boxed, &mut p, 1e-10, 5000, 1.0),
                _ => apgd::solve(&boxed, &mut p, 1e-10, 5000),
            };
            assert!(p.iter().all(|p| p[0] <= b), "{method}: {p:?} above {b}");
            if method == "nsgs" {
                assert!(o.converged, "{o:?}");
                assert!(p.iter().any(|p| p[0] == b), "no contact at its bound");
                assert!(boxed.residual(&p, true) <= 1e-10);
                assert!(sp.residual(&p, true) > 1e-6, "the rigid law holds too");
            }
        }
    }
}
