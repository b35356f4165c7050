//! Accelerated projected gradient descent (APGD) on the Anitescu–Tasora
//! cone relaxation (docs/physics.md §3.5; Mazhar, Heyn, Negrut & Tasora
//! 2015): `min f(p) = ½ pᵀ W p + pᵀ q` over `p_j ∈ K_j`, whose gradient is
//! the relative velocity `u = W p + q`, applied through the floes'
//! velocities (O(m) per evaluation).
//!
//! Nesterov's scheme with the step `1/L` found by backtracking (`L` doubled
//! until the quadratic upper bound holds, then shrunk by 0.9 each
//! iteration), the momentum `β = θ_k (1 − θ_k) / (θ_k² + θ_{k+1})`, and the
//! gradient restart (momentum dropped when `∇f · (x_{k+1} − x_k) > 0`).
//! It runs in the variables `x_j = p_j / d_j`, `d_j = W_NN,j^{-1/2}` (a
//! per-contact scaling leaves every cone unchanged and brings the Delassus
//! diagonal to one: a floe 100 times heavier than its neighbour no longer
//! sets the step of every contact). It stops when the relaxation's own
//! natural-map residual (without De Saxcé's term) is at most the tolerance,
//! or after `max_iterations`; the best iterate is returned. The reported
//! [`Outcome::residual`] is the Coulomb one, as for every solver: on a
//! sliding contact it measures the relaxation's departure from Coulomb's law
//! (the contact separates at `μ |u_T|`), not the solve's error.
//!
//! The solver runs on any [`Delassus`] operator, with a friction
//! coefficient and a bound `b_j` of the normal impulse per contact: the
//! projection is onto the truncated cone ([`project_boxed`]; in the scaled
//! variables the bound is `b_j / d_j`).

use super::nsgs::Outcome;
use super::operator::{project_boxed, residual_at, Delassus};

/// Shrink factor of `L` after each iteration (Mazhar et al. 2015).
const SHRINK: f64 = 0.9;

/// Most doublings of `L` in one backtracking.
const MAX_DOUBLINGS: u32 = 60;

/// `f(p)`, the velocity changes of `p`, and the gradient `u(p)` per contact.
fn evaluate<D: Delassus>(prob: &D, p: &[[f64; 2]]) -> (f64, D::State, Vec<[f64; 2]>) {
    let v = prob.state(p);
    let mut f = 0.0;
    let u: Vec<[f64; 2]> = (0..prob.len())
        .map(|j| {
            let u = prob.relative(j, &v);
            let q = prob.free(j);
            // ½ pᵀ W p + pᵀ q = ½ pᵀ (u + q).
            f += 0.5 * (p[j][0] * (u[0] + q[0]) + p[j][1] * (u[1] + q[1]));
            u
        })
        .collect();
    (f, v, u)
}

/// APGD from `p` (warm start or zeros), in place, to the relaxation's
/// residual `tolerance` or `max_iterations` iterations. Returns the outcome
/// and the floes' velocity changes of the answer; `p` holds the best iterate.
pub fn solve<D: Delassus>(
    prob: &D,
    p: &mut [[f64; 2]],
    tolerance: f64,
    max_iterations: u64,
) -> (Outcome, D::State) {
    let m = prob.len();
    let d: Vec<f64> = (0..m)
        .map(|j| {
            let w = prob.block(j)[0];
            if w > 0.0 && w.is_finite() {
                1.0 / w.sqrt()
            } else {
                1.0
            }
        })
        .collect();
    // The cones of the scaled variables x = p / d: the bound is b / d.
    let bounds: Vec<f64> = (0..m).map(|j| prob.bound(j) / d[j]).collect();
    let proj = |j: usize, x: [f64; 2]| project_boxed(x, prob.mu(j), bounds[j]);
    for (j, pj) in p.iter_mut().enumerate() {
        if !(pj[0].is_finite() && pj[1].is_finite()) {
            *pj = [0.0; 2];
        }
        *pj = project_boxed(*pj, prob.mu(j), prob.bound(j));
    }
    let (mut f_y, v0, mut g_y) = evaluate(prob, p);
    let mut best = p.to_vec();
    let mut best_res = residual_at(prob, p, &v0, false);
    let mut best_v = v0;
    // L from W on the scaled ones vector: ‖D W D e‖ / ‖e‖.
    let ones: Vec<[f64; 2]> = d.iter().map(|&dj| [dj, dj]).collect();
    let v1 = prob.state(&ones);
    let mut num = 0.0;
    for (j, dj) in d.iter().enumerate() {
        let u = prob.relative(j, &v1);
        let q = prob.free(j);
        num += (dj * (u[0] - q[0])).powi(2) + (dj * (u[1] - q[1])).powi(2);
    }
    let mut l = (num / (2.0 * m.max(1) as f64)).sqrt();
    if !(l > 0.0 && l.is_finite()) {
        l = 1.0;
    }
    let mut x = p.to_vec();
    let mut y = p.to_vec();
    let mut theta: f64 = 1.0;
    let mut iterations = 0;
    let mut interrupted = false;
    while best_res > tolerance && iterations < max_iterations {
        if crate::stop::poll(iterations) {
            interrupted = true;
            break;
        }
        iterations += 1;
        // Backtracking on L at y.
        let mut cand = vec![[0.0; 2]; m];
        let mut eval = None;
        for _ in 0..=MAX_DOUBLINGS {
            let t = 1.0 / l;
            let mut lin = 0.0;
            let mut sq = 0.0;
            for j in 0..m {
                // Step in x = p / d: x − t ∇ₓf, ∇ₓf = d u.
                let dj = d[j];
                let xn = [
                    y[j][0] / dj - t * dj * g_y[j][0],
                    y[j][1] / dj - t * dj * g_y[j][1],
                ];
                let c = proj(j, xn);
                cand[j] = [c[0] * dj, c[1] * dj];
                let dx = [(cand[j][0] - y[j][0]) / dj, (cand[j][1] - y[j][1]) / dj];
                lin += dj * (g_y[j][0] * dx[0] + g_y[j][1] * dx[1]);
                sq += dx[0] * dx[0] + dx[1] * dx[1];
            }
            let e = evaluate(prob, &cand);
            let bound = f_y + lin + 0.5 * l * sq;
            if e.0 <= bound + 1e-14 * (f_y.abs() + bound.abs()) {
                eval = Some(e);
                break;
            }
            l *= 2.0;
        }
        let Some((_, v_c, _)) = eval else { break };
        let res = residual_at(prob, &cand, &v_c, false);
        if res < best_res {
            best_res = res;
            best.copy_from_slice(&cand);
            best_v = v_c;
        }
        let theta_n = 0.5 * (-theta * theta + theta * (theta * theta + 4.0).sqrt());
        let beta = theta * (1.0 - theta) / (theta * theta + theta_n);
        // Restart test: ∇f(y) · (x_{k+1} − x_k) > 0.
        let mut restart = 0.0;
        for j in 0..m {
            restart += g_y[j][0] * (cand[j][0] - x[j][0]) + g_y[j][1] * (cand[j][1] - x[j][1]);
        }
        let (theta_next, momentum) = if restart > 0.0 {
            (1.0, 0.0)
        } else {
            (theta_n, beta)
        };
        for j in 0..m {
            for k in 0..2 {
                y[j][k] = cand[j][k] + momentum * (cand[j][k] - x[j][k]);
            }
        }
        x = cand;
        theta = theta_next;
        let e = evaluate(prob, &y);
        f_y = e.0;
        g_y = e.2;
        l *= SHRINK;
    }
    p.copy_from_slice(&best);
    let converged = best_res <= tolerance;
    let residual = residual_at(prob, p, &best_v, true);
    (
        Outcome {
            iterations,
            residual,
            converged,
            interrupted,
        },
        best_v,
    )
}
