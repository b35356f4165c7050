//! The Delassus operator the iterative solvers run on ([`Delassus`]), the
//! boxed Coulomb cone of a contact whose normal impulse is bounded
//! ([`project_boxed`]), and the natural-map residual of an answer
//! ([`residual_at`]), written once for every problem.
//!
//! A frictional contact problem of `m` contacts, unknowns `p_j = (λ_j, β_j)`
//! (N·s), relative velocities `u = W p + q` (m/s), is given to NSGS and
//! APGD through what they read of it: per contact the `2 × 2` diagonal
//! block `W_jj`, the friction coefficient `μ_j`, the bound `b_j` of the
//! normal impulse and the free velocity `q_j`; and a *state* from which a
//! contact's current relative velocity is read in O(1) and that one
//! contact's impulse change updates in O(its couplings). Two problems
//! implement it:
//!
//! - [`super::SparseContacts`] (floes): the state is the floes' velocity
//!   changes `M⁻¹ H p`; `u_j = q_j + H_jᵀ (M⁻¹ H p)`;
//! - [`super::Fc2dOperator`] (a Siconos file's `W`): the state is `W p`,
//!   kept by adding a changed contact's block column.
//!
//! The solvers are generic over the trait (monomorphised: no dynamic
//! dispatch in a sweep).
//!
//! # The boxed law (crushing ice)
//!
//! With a bound `b_j` (N·s; `+∞`, the default, is a rigid contact) the
//! contact law is `0 ≤ λ ≤ b`, `|β| ≤ μ λ`, and: `u_N ≥ 0` if `λ = 0`,
//! `u_N = 0` if `0 < λ < b`, `u_N ≤ 0` if `λ = b` (the contact keeps
//! approaching: the ice crushes); Coulomb in the tangent. The admissible
//! set is the truncated cone `K_b = {0 ≤ λ ≤ b, |β| ≤ μ λ}` (a triangle),
//! and the natural map with De Saxcé's change, projected onto `K_b`, is
//! zero exactly at a solution of this law (at the top edge its normal cone
//! holds `(−u_N, 0)` with `u_N ≤ 0`).

/// A frictional contact problem `u = W p + q` as the iterative solvers see
/// it (see the module doc). Contact indices run over `0..len()`.
pub trait Delassus {
    /// What a contact's current relative velocity is read from (the
    /// floes' velocity changes, or `W p`).
    type State;

    /// Number of contacts `m`.
    fn len(&self) -> usize;

    /// Whether the problem has no contact.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The diagonal block `W_jj`, row-major `[W_NN, W_NT, W_TN, W_TT]`
    /// (1/kg).
    fn block(&self, j: usize) -> [f64; 4];

    /// The friction coefficient `μ_j` (dimensionless, `≥ 0`; 0:
    /// frictionless, `β_j = 0`).
    fn mu(&self, j: usize) -> f64;

    /// Whether contact `j` has a tangential unknown (`μ_j > 0`).
    fn friction(&self, j: usize) -> bool {
        self.mu(j) > 0.0
    }

    /// The bound `b_j ≥ 0` of the normal impulse (N·s; `+∞`: a rigid
    /// contact, the default).
    fn bound(&self, _j: usize) -> f64 {
        f64::INFINITY
    }

    /// Whether some contact's normal impulse is bounded (a finite
    /// [`Delassus::bound`]; by default, a scan of the bounds); `false` lets
    /// the solvers skip the boxed law's tests.
    fn bounded(&self) -> bool {
        (0..self.len()).any(|j| self.bound(j).is_finite())
    }

    /// The free relative velocity `q_j = (q_N, q_T)`, m/s.
    fn free(&self, j: usize) -> [f64; 2];

    /// The state of the impulses `p` (one per contact).
    fn state(&self, p: &[[f64; 2]]) -> Self::State;

    /// The relative velocity `u_j` of contact `j` in `state`, m/s.
    fn relative(&self, j: usize, state: &Self::State) -> [f64; 2];

    /// Adds the effect of the impulse change `dp` (N·s) at contact `j` to
    /// `state`.
    fn apply(&self, j: usize, dp: [f64; 2], state: &mut Self::State);

    /// The residual's normalisation (m/s): `max(‖q‖₂, floor)`.
    fn residual_scale(&self) -> f64;
}

/// The projection onto the Coulomb cone `K = {(λ, β): |β| ≤ μ λ}`.
pub fn project_cone(x: [f64; 2], mu: f64) -> [f64; 2] {
    let (n, t) = (x[0], x[1]);
    if n >= 0.0 && t.abs() <= mu * n {
        [n, t]
    } else if mu * t.abs() <= -n {
        [0.0, 0.0]
    } else {
        let l = (n + mu * t.abs()) / (1.0 + mu * mu);
        [l, mu * l * t.signum()]
    }
}

/// The projection of `x` onto the truncated cone
/// `K_b = {0 ≤ λ ≤ b, |β| ≤ μ λ}`. The cone's projection when its `λ` is at
/// most `b` (always, for `b = +∞`: then this is [`project_cone`], bit for
/// bit); otherwise the point of the top edge `λ = b` nearest to `x`,
/// `(b, clamp(β, −μ b, μ b))` (the projection onto an intersection with a
/// half-plane that the cone's projection leaves lies on the half-plane's
/// edge).
#[inline]
pub fn project_boxed(x: [f64; 2], mu: f64, b: f64) -> [f64; 2] {
    let p = project_cone(x, mu);
    if p[0] <= b {
        p
    } else {
        let t = mu * b;
        // max/min, not clamp: no panic on a NaN bound.
        [b, x[1].max(-t).min(t)]
    }
}

/// The natural-map residual of the impulses `p` on `prob`, the state
/// `state` being that of `p` (docs/physics.md §3.5):
///
/// ```text
/// F_j = (p_j − Π_{K_b}(p_j − ρ_j û_j)) / ρ_j,   ρ_j = 1 / W_NN,j,
/// û_j = (u_N + μ_j |u_T|, u_T)      (coulomb = true: De Saxcé's change)
/// û_j = u_j                          (coulomb = false: the cone relaxation)
/// residual = ‖F‖₂ / residual_scale
/// ```
///
/// `Π_{K_b}` the projection onto the contact's truncated cone
/// ([`project_boxed`]; the cone itself for a rigid contact). Zero exactly at
/// a solution of the (boxed) Coulomb law, or of the Anitescu–Tasora
/// relaxation; `F_j` is a velocity (m/s), so the residual is dimensionless.
/// A non-finite impulse gives `+∞`.
pub fn residual_at<D: Delassus>(prob: &D, p: &[[f64; 2]], state: &D::State, coulomb: bool) -> f64 {
    residual_with(prob, p, |j| prob.relative(j, state), coulomb)
}

/// [`residual_at`] with the relative velocities read by `relative(j)`.
pub(super) fn residual_with<D: Delassus>(
    prob: &D,
    p: &[[f64; 2]],
    relative: impl Fn(usize) -> [f64; 2],
    coulomb: bool,
) -> f64 {
    let mut sum = 0.0;
    for j in 0..prob.len() {
        let (mu, friction, w_nn) = (prob.mu(j), prob.friction(j), prob.block(j)[0]);
        let pj = p.get(j).copied().unwrap_or([0.0; 2]);
        let pj = if friction { pj } else { [pj[0], 0.0] };
        let u = relative(j);
        let rho = if w_nn > 0.0 && w_nn.is_finite() {
            1.0 / w_nn
        } else {
            1.0
        };
        let u_hat = if friction {
            [u[0] + if coulomb { mu * u[1].abs() } else { 0.0 }, u[1]]
        } else {
            [u[0], 0.0]
        };
        let x = [pj[0] - rho * u_hat[0], pj[1] - rho * u_hat[1]];
        let pr = project_boxed(x, mu, prob.bound(j));
        let f = [(pj[0] - pr[0]) / rho, (pj[1] - pr[1]) / rho];
        sum += f[0] * f[0] + f[1] * f[1];
    }
    let res = sum.sqrt() / prob.residual_scale();
    if res.is_finite() {
        res
    } else {
        f64::INFINITY
    }
}
