//! Nonsmooth block Gauss–Seidel (NSGS) on the sparse contact problem
//! (docs/physics.md §3.5; Jean 1999; Acary, Brémond & Huber 2018).
//!
//! A sweep visits the contacts in the group's order (the detection order:
//! by body pair, then by point) and solves each contact's own 2D problem
//! **exactly** with the others held at their current impulses (their
//! latest values of the same sweep: Gauss–Seidel), in closed form
//! ([`local_coulomb`]); with `relaxation ω ≠ 1` the new impulse is
//! `(1 − ω) p_old + ω p_local`, projected back onto the cone. The floes'
//! velocity changes are updated after each contact, so a sweep costs O(m).
//! The natural-map residual ([`super::operator::residual_at`],
//! Coulomb form) is evaluated when a sweep's impulse changes are small
//! enough for it to be at the tolerance, and at least every
//! [`CHECK_EVERY`] sweeps (see [`solve`]); the sweeps stop when it is at
//! most the tolerance, or after `max_iterations` sweeps (an unconverged
//! solve, counted, its answer kept: it is finite).
//!
//! The solver runs on any [`Delassus`] operator (floes, or a file's `W`),
//! with a friction coefficient and a bound of the normal impulse per contact
//! ([`local_coulomb_boxed`]: the boxed law of crushing ice).

use super::operator::{project_boxed, project_cone, residual_at, Delassus};

/// Relative tolerance of the tests of the local enumeration (stick inside
/// the cone, non-negative normal impulse): rounding of a 2 × 2 solve.
const LOCAL_SLACK: f64 = 1e-12;

/// The exact solution of one contact's problem: `u = W p + r` with
/// Signorini's condition `0 ≤ λ ⟂ u_N ≥ 0` and Coulomb's law on
/// `K = {|β| ≤ μ λ}` (stick `u_T = 0`, or slide `β = −μ λ sign(u_T)`),
/// `W` the contact's `2 × 2` Delassus block (row-major, 1/kg), `r` its
/// relative velocity without its own impulse (m/s). Enumerates the cases
/// in order: take-off (`r_N ≥ 0`), stick, slide against the stick
/// solution's excess. For a positive definite `W` with `W_NN > μ |W_NT|`
/// the solution is unique and found; otherwise the stick solution
/// projected onto `K` is returned (finite whenever `W` and `r` are). Without
/// friction (`friction = false`) `β = 0` and `λ = max(−r_N / W_NN, 0)`.
pub fn local_coulomb(w: [f64; 4], r: [f64; 2], mu: f64, friction: bool) -> [f64; 2] {
    if r[0] >= 0.0 || w[0] <= 0.0 || !w[0].is_finite() {
        return [0.0, 0.0];
    }
    let lam_free = -r[0] / w[0];
    if !friction {
        return [lam_free, 0.0];
    }
    let det = w[0] * w[3] - w[1] * w[2];
    let stick = if det > 0.0 {
        [
            (-r[0] * w[3] + r[1] * w[1]) / det,
            (-r[1] * w[0] + r[0] * w[2]) / det,
        ]
    } else {
        [lam_free, 0.0]
    };
    if det > 0.0 && stick[0] >= 0.0 && stick[1].abs() <= mu * stick[0] * (1.0 + LOCAL_SLACK) {
        return stick;
    }
    // Slide: the friction stops at the cone on the side of the stick
    // solution's excess, s = the sliding direction (β = −s μ λ).
    let s_first = if stick[1] > 0.0 { -1.0 } else { 1.0 };
    for s in [s_first, -s_first] {
        let den = w[0] - s * mu * w[1];
        if den <= 0.0 {
            continue;
        }
        let lam = -r[0] / den;
        let beta = -s * mu * lam;
        let u_t = w[2] * lam + w[3] * beta + r[1];
        if lam >= 0.0 && s * u_t >= -LOCAL_SLACK * (r[1].abs() + w[2].abs() * lam) {
            return [lam, beta];
        }
    }
    let p = project_cone(stick, mu);
    if p[0].is_finite() && p[1].is_finite() {
        p
    } else {
        [0.0, 0.0]
    }
}

/// The exact solution of one contact's problem with its normal impulse
/// bounded by `b` (N·s; see [`super::operator`]): `0 ≤ λ ≤ b`,
/// `|β| ≤ μ λ`, `u_N ≥ 0` at `λ = 0`, `u_N = 0` for `0 < λ < b`,
/// `u_N ≤ 0` at `λ = b` (crushing), Coulomb in the tangent. The cases, in
/// order: the rigid contact's answer ([`local_coulomb`]: take-off, stick,
/// slide) when its `λ ≤ b` (it satisfies the boxed law; for `b = +∞`
/// always, so this is [`local_coulomb`] bit for bit); otherwise `λ = b`
/// with the tangential stick `β = −(r_T + W_TN b) / W_TT` when
/// `|β| ≤ μ b`, or the slide `β = ±μ b` on the side of the stick's excess
/// (`u_T` is increasing in `β`, so the side is the one where the slip
/// opposes `β`). Unique and found for a positive definite `W` with
/// `W_NN > μ |W_NT|` (the rigid answer is then unique, so a boxed answer
/// below the bound would be it).
#[inline]
pub fn local_coulomb_boxed(w: [f64; 4], r: [f64; 2], mu: f64, friction: bool, b: f64) -> [f64; 2] {
    let rigid = local_coulomb(w, r, mu, friction);
    if rigid[0] <= b {
        return rigid;
    }
    if !friction {
        return [b, 0.0];
    }
    let t = mu * b;
    // u_T at λ = b, β = 0.
    let u_t0 = w[2] * b + r[1];
    let beta = if w[3] > 0.0 && w[3].is_finite() {
        // max/min, not clamp: no panic on a NaN bound.
        (-u_t0 / w[3]).max(-t).min(t)
    } else if u_t0 > 0.0 {
        -t
    } else if u_t0 < 0.0 {
        t
    } else {
        0.0
    };
    [b, beta]
}

/// What one iterative solve did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outcome {
    /// Sweeps (NSGS) or iterations (APGD) taken.
    pub iterations: u64,
    /// The natural-map residual (Coulomb form) of the answer.
    pub residual: f64,
    /// Whether the residual reached the tolerance.
    pub converged: bool,
    /// Whether a stop request ([`crate::stop`], polled every
    /// [`crate::stop::POLL_EVERY`] sweeps or iterations) ended the solve
    /// early: its answer is finite but no solution, and the run that asked
    /// discards it.
    pub interrupted: bool,
}

/// The most sweeps between two evaluations of the true residual when the
/// sweeps' change bound stays above the tolerance (see [`solve`]).
pub const CHECK_EVERY: u64 = 16;

/// The change bound, in tolerances of the residual's scale, below which the
/// true residual is evaluated (near convergence the bound is 1.2–1.4 times
/// the residual: a margin, so that a solve stops at, or within a sweep or
/// two of, the first sweep whose residual reaches the tolerance).
pub const CHANGE_FACTOR: f64 = 10.0;

/// One sweep in the group's order, in place; returns the change bound
/// `‖(W_NN,j |Δp_j|)_j‖₂` (m/s), the relative velocities the sweep's
/// impulse changes made at their own contacts. With `bounded` false (no
/// finite bound, [`Delassus::bounded`]) the bounds are not read.
fn sweep<D: Delassus>(
    prob: &D,
    p: &mut [[f64; 2]],
    v: &mut D::State,
    relaxation: f64,
    bounded: bool,
) -> f64 {
    if bounded {
        sweep_with(prob, p, v, relaxation, |j| prob.bound(j))
    } else {
        sweep_with(prob, p, v, relaxation, |_| f64::INFINITY)
    }
}

/// [`sweep`] with the bounds `bound(j)` (N·s).
#[inline(always)]
fn sweep_with<D: Delassus>(
    prob: &D,
    p: &mut [[f64; 2]],
    v: &mut D::State,
    relaxation: f64,
    bound: impl Fn(usize) -> f64,
) -> f64 {
    let mut change = 0.0;
    for (j, pj) in p.iter_mut().enumerate() {
        let (mu, friction, bound) = (prob.mu(j), prob.friction(j), bound(j));
        let w = prob.block(j);
        let u = prob.relative(j, v);
        // Velocity without the contact's own impulse: r = u − W p_j.
        let r = [
            u[0] - w[0] * pj[0] - w[1] * pj[1],
            u[1] - w[2] * pj[0] - w[3] * pj[1],
        ];
        let mut new = local_coulomb_boxed(w, r, mu, friction, bound);
        if relaxation != 1.0 {
            new = project_boxed(
                [
                    (1.0 - relaxation) * pj[0] + relaxation * new[0],
                    (1.0 - relaxation) * pj[1] + relaxation * new[1],
                ],
                mu,
                bound,
            );
        }
        let dp = [new[0] - pj[0], new[1] - pj[1]];
        if dp[0] != 0.0 || dp[1] != 0.0 {
            prob.apply(j, dp, v);
            *pj = new;
            change += w[0] * w[0] * (dp[0] * dp[0] + dp[1] * dp[1]);
        }
    }
    change.sqrt()
}

/// NSGS from the impulses `p` (the warm start, or zeros), in place, to the
/// relative residual `tolerance` or `max_iterations` sweeps, with
/// over-relaxation `relaxation` (1: plain Gauss–Seidel). Returns the
/// outcome and the floes' velocity changes `M⁻¹ H p`; `p` holds the answer
/// (finite).
///
/// The stop test: the true residual (a pass over the contacts, about the
/// cost of a sweep) is evaluated at the start, then after a sweep only when
/// the sweep's change bound, relative to the residual's scale, is at most
/// [`CHANGE_FACTOR`] × `tolerance` (after such an evaluation that did not
/// stop, at most half that sweep's bound), or [`CHECK_EVERY`] sweeps after
/// the last evaluation, or after the last sweep. A solve stops only on a true residual at most
/// `tolerance`, and the outcome's residual is always the true residual of
/// the answer returned.
pub fn solve<D: Delassus>(
    prob: &D,
    p: &mut [[f64; 2]],
    tolerance: f64,
    max_iterations: u64,
    relaxation: f64,
) -> (Outcome, D::State) {
    for (j, pj) in p.iter_mut().enumerate() {
        if !(pj[0].is_finite() && pj[1].is_finite()) {
            *pj = [0.0, 0.0];
        }
        if !prob.friction(j) {
            pj[1] = 0.0;
        }
        *pj = project_boxed(*pj, prob.mu(j), prob.bound(j));
    }
    let mut v = prob.state(p);
    let bounded = prob.bounded();
    let mut residual = residual_at(prob, p, &v, true);
    let scale = prob.residual_scale();
    let mut iterations = 0;
    let mut since_check = 0;
    let mut trigger = CHANGE_FACTOR * tolerance * scale;
    let mut interrupted = false;
    while residual > tolerance && iterations < max_iterations {
        if crate::stop::poll(iterations) {
            interrupted = true;
            break;
        }
        let change = sweep(prob, p, &mut v, relaxation, bounded);
        iterations += 1;
        since_check += 1;
        let small = change <= trigger;
        if small || since_check >= CHECK_EVERY || iterations == max_iterations {
            residual = residual_at(prob, p, &v, true);
            since_check = 0;
            if small {
                // Not yet at the tolerance: the next check by the bound
                // waits for the change to halve.
                trigger = 0.5 * change;
            }
        }
    }
    (
        Outcome {
            iterations,
            residual,
            converged: residual <= tolerance,
            interrupted,
        },
        v,
    )
}
