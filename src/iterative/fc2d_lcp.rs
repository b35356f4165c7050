//! A Siconos 2D frictional contact problem as the Stewart–Trinkle LCP that
//! Lemke solves ([`crate::lcp::solve()`]), with the layout of the floes'
//! LCP ([`crate::contact::problem`], docs/physics.md §3.1): for `m`
//! contacts, `z = (λ, β̃, α)` of size `4m`, `β̃_j = (β⁺_j, β⁻_j)` the
//! friction impulses along `±T_j` (`r_T = β⁺ − β⁻`), `α_j` the sliding
//! speed:
//!
//! ```text
//! w_N  = W_NN λ + W_NT (β⁺ − β⁻) + q_N       ≥ 0 ⟂ λ  ≥ 0
//! γ⁺   = W_TN λ + W_TT (β⁺ − β⁻) + q_T + α   ≥ 0 ⟂ β⁺ ≥ 0
//! γ⁻   = −(W_TN λ + W_TT (β⁺ − β⁻) + q_T) + α ≥ 0 ⟂ β⁻ ≥ 0
//! σ    = μ λ − β⁺ − β⁻                        ≥ 0 ⟂ α  ≥ 0
//! ```
//!
//! (`W_NT` etc. the block rows of `W`, all contacts). As for the floes, it
//! is solved for `z' = (g λ, g β̃, α)` with `g` the mean diagonal of `W`,
//! so that every row of `w` is a velocity (m/s), and each Coulomb row is
//! multiplied by the contact's `W_NN,jj / g`. The matrix is dense: `4m × 4m`
//! reals, so at most [`MAX_LEMKE_CONTACTS`] contacts.

use crate::lcp::{solve, Lcp, SolveOptions};
use crate::model::fc2d::Fc2dProblem;

/// The most contacts Lemke takes: a dense LCP of 8,000 unknowns, 512 MB
/// (Siconos' `fc2d_lexicolemke` already takes 1.15 s at 376 contacts).
pub const MAX_LEMKE_CONTACTS: usize = 2000;

/// The LCP of `prob` (see the module doc) and its scale `g` (1/kg).
pub fn lcp_of(prob: &Fc2dProblem) -> (Lcp, f64) {
    let m = prob.contacts;
    let n = 4 * m;
    let w = &prob.w;
    let diag: Vec<[f64; 4]> = (0..m)
        .map(|j| w.block(j, j).copied().unwrap_or([0.0; 4]))
        .collect();
    let sum: f64 = diag.iter().map(|b| b[0] + b[3]).sum();
    let g = sum / (2 * m).max(1) as f64;
    let g = if g > 0.0 && g.is_finite() { g } else { 1.0 };
    let mut a = vec![0.0; n * n];
    let mut q = vec![0.0; n];
    let (lam, bp, bm, al) = (
        |j: usize| j,
        |j: usize| m + 2 * j,
        |j: usize| m + 2 * j + 1,
        |j: usize| 3 * m + j,
    );
    for i in 0..m {
        for k in w.row_ptr[i]..w.row_ptr[i + 1] {
            let (j, b) = (w.col[k], w.blocks[k]);
            let (nn, nt, tn, tt) = (b[0] / g, b[1] / g, b[2] / g, b[3] / g);
            for (row, s) in [(lam(i), None), (bp(i), Some(1.0)), (bm(i), Some(-1.0))] {
                let (x, y) = match s {
                    None => (nn, nt),
                    Some(s) => (s * tn, s * tt),
                };
                a[row * n + lam(j)] += x;
                a[row * n + bp(j)] += y;
                a[row * n + bm(j)] -= y;
            }
        }
        q[lam(i)] = prob.q[2 * i];
        q[bp(i)] = prob.q[2 * i + 1];
        q[bm(i)] = -prob.q[2 * i + 1];
        a[bp(i) * n + al(i)] = 1.0;
        a[bm(i) * n + al(i)] = 1.0;
        let d = diag[i][0] / g;
        let d = if d > 0.0 && d.is_finite() { d } else { 1.0 };
        a[al(i) * n + lam(i)] = d * prob.mu[i];
        a[al(i) * n + bp(i)] = -d;
        a[al(i) * n + bm(i)] = -d;
    }
    (Lcp { n, m: a, q }, g)
}

/// Lemke's answer to `prob`: the reactions `(λ, β⁺ − β⁻)` (N·s; zero if
/// the LCP was not solved), the pivots, and whether it was solved. An
/// error when `prob` has more than [`MAX_LEMKE_CONTACTS`] contacts.
pub fn solve_lemke(prob: &Fc2dProblem) -> Result<(Vec<[f64; 2]>, usize, bool), String> {
    let m = prob.contacts;
    if m > MAX_LEMKE_CONTACTS {
        return Err(format!(
            "lemke takes at most {MAX_LEMKE_CONTACTS} contacts (a dense LCP of 4 × contacts unknowns); this problem has {m}"
        ));
    }
    let (lcp, g) = lcp_of(prob);
    let sol = solve(&lcp, &SolveOptions::default());
    let solved = sol.status.is_solved() && sol.z.len() == 4 * m;
    let r = (0..m)
        .map(|j| {
            if solved {
                [sol.z[j] / g, (sol.z[m + 2 * j] - sol.z[m + 2 * j + 1]) / g]
            } else {
                [0.0; 2]
            }
        })
        .collect();
    Ok((r, sol.pivots, solved))
}
