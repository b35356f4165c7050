//! The frictional contact problem of one group of floes in contact
//! coordinates, held sparse (docs/physics.md §3.5): per contact its normal
//! and tangential Jacobian rows on its (at most two) floes, per floe its
//! inverse mass. Nothing of size `m²` is ever formed: the Delassus operator
//! `W = HᵀM⁻¹H` is applied as `Hᵀ (M⁻¹ (H p))`, through the floes'
//! velocities, and only its `2 × 2` diagonal blocks are stored.
//!
//! The unknowns are `p_j = (λ_j, β_j)` (normal and signed tangential
//! impulse along `T_j`, N·s); the post-contact relative velocities are
//! `u = W p + q`, `q = (Jᵀ W_free + c, Tᵀ W_free)` (m/s), exactly the data
//! of the LCP assembly ([`crate::contact::problem::ContactLcp::assemble`])
//! with one friction pair per contact point.

// The three components (x, y, θ) of a floe's rows are indexed together.
#![allow(clippy::needless_range_loop)]

use super::operator::{self, Delassus};
use crate::contact::problem::{ContactGroup, Gen};
use crate::contact::{Contact, ContactKey};
use crate::geometry::{cross, Vec2};
use crate::model::Scenario;

/// The floor of the residual's normalisation `max(‖q‖₂, ε)`, m/s, with
/// `ε = ROUNDING_FRACTION · v_s + RESIDUAL_FLOOR`: `v_s` the largest single
/// term of `q` (one floe's velocity at a contact, or an offset), so that a
/// `q` that cancels to rounding (a touching row at rest: `‖q‖` = 1e-16 m/s
/// from terms of 1 m/s) is not taken as the scale; the absolute floor only
/// guards a problem whose free velocities are all zero (1e-12 m/s, far
/// below any speed of drifting ice, 1e-3 to 1 m/s).
pub const RESIDUAL_FLOOR: f64 = 1e-12;

/// See [`RESIDUAL_FLOOR`]: a `q` below a billionth of its largest term is
/// zero to rounding (an f64 sum of terms of size `v_s` rounds by about
/// 1e-16 `v_s` per term).
pub const ROUNDING_FRACTION: f64 = 1e-9;

/// One floe's share of a contact: its index in the group, and the normal
/// and tangential Jacobian rows `±(N, r × N)`, `±(T, r × T)` (the sign
/// `−` for body `a`, `+` for body `b`).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Side {
    floe: usize,
    jn: Gen,
    jt: Gen,
}

/// One contact's rows.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Rows {
    sides: [Option<Side>; 2],
    /// The diagonal block `W_jj`, row-major `[[W_NN, W_NT], [W_TN, W_TT]]`
    /// (1/kg).
    w: [f64; 4],
    /// `q_j = (q_N, q_T)`, m/s.
    q: [f64; 2],
}

/// The sparse contact problem of one group (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct SparseContacts {
    /// The group's floes (global indices, sorted).
    pub floes: Vec<usize>,
    /// Identity of each contact (warm starts).
    pub keys: Vec<ContactKey>,
    /// Friction coefficient `μ` (0: frictionless, `β = 0`).
    pub mu: f64,
    minv: Vec<Gen>,
    w_free: Vec<Gen>,
    rows: Vec<Rows>,
    /// The largest single term of `q`, m/s (see [`RESIDUAL_FLOOR`]).
    v_scale: f64,
    /// The bound `b_j` of each contact's normal impulse, N·s (empty: every
    /// contact rigid, `b_j = +∞`; see [`SparseContacts::with_normal_bounds`]).
    bounds: Vec<f64>,
}

fn dot(a: &Gen, b: &Gen) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The diagonal block `W_jj = H_jᵀ M⁻¹ H_j` of a contact's rows, row-major
/// (1/kg).
fn diagonal_block(sides: &[Option<Side>; 2], minv: &[Gen]) -> [f64; 4] {
    let mut w = [0.0; 4];
    for s in sides.iter().flatten() {
        let mi = &minv[s.floe];
        for d in 0..3 {
            w[0] += s.jn[d] * mi[d] * s.jn[d];
            w[1] += s.jn[d] * mi[d] * s.jt[d];
            w[3] += s.jt[d] * mi[d] * s.jt[d];
        }
    }
    w[2] = w[1];
    w
}

fn jac(n: &Vec2, r: &Vec2) -> Gen {
    [n.x, n.y, cross(r, n)]
}

impl SparseContacts {
    /// The problem of `group` (contacts indexing `contacts`): `centres[i]`
    /// the centre of mass of floe `i` (m), `w_free[i]` its free velocity,
    /// `offset[k]` the offset `c` of contact `k` (m/s), as
    /// [`crate::contact::problem::ContactLcp::assemble`] takes them.
    pub fn build(
        scn: &Scenario,
        centres: &[Vec2],
        contacts: &[Contact],
        group: &ContactGroup,
        w_free: &[Gen],
        offset: &[f64],
    ) -> SparseContacts {
        let n_floes = scn.floes.len();
        let mu = scn.contact.friction;
        let local = |i: usize| {
            (i < n_floes)
                .then(|| group.floes.binary_search(&i).ok())
                .flatten()
        };
        let minv: Vec<Gen> = group
            .floes
            .iter()
            .map(|&i| {
                let f = &scn.floes[i];
                [1.0 / f.mass, 1.0 / f.mass, 1.0 / f.inertia]
            })
            .collect();
        let w_free_g: Vec<Gen> = group.floes.iter().map(|&i| w_free[i]).collect();
        let mut v_scale = 0.0f64;
        let rows = group
            .contacts
            .iter()
            .map(|&k| {
                let c = &contacts[k];
                let sides = [(c.a, -1.0), (c.b, 1.0)].map(|(body, sign)| {
                    local(body).map(|l| {
                        let r = c.geom.point - centres[body];
                        let (jn, jt) = (jac(&c.geom.normal, &r), jac(&c.geom.tangent, &r));
                        Side {
                            floe: l,
                            jn: jn.map(|x| sign * x),
                            jt: jt.map(|x| sign * x),
                        }
                    })
                });
                let w = diagonal_block(&sides, &minv);
                let mut q = [offset[k], 0.0];
                for s in sides.iter().flatten() {
                    let wf = &w_free_g[s.floe];
                    for d in 0..3 {
                        let (tn, tt) = (s.jn[d] * wf[d], s.jt[d] * wf[d]);
                        q[0] += tn;
                        q[1] += tt;
                        v_scale = v_scale.max(tn.abs()).max(tt.abs());
                    }
                }
                v_scale = v_scale.max(offset[k].abs());
                Rows { sides, w, q }
            })
            .collect();
        SparseContacts {
            floes: group.floes.clone(),
            keys: group.contacts.iter().map(|&k| contacts[k].key()).collect(),
            mu,
            minv,
            w_free: w_free_g,
            rows,
            v_scale,
            bounds: Vec::new(),
        }
    }

    /// The same problem with a bound `b_j` on each contact's normal impulse
    /// (N·s, in the group's contact order; `f64::INFINITY`: a rigid contact,
    /// the default): `0 ≤ λ_j ≤ b_j`, `|β_j| ≤ μ λ_j`, and a contact at its
    /// bound may keep approaching (the ice crushes; docs/physics.md §3.5,
    /// [`super::operator`]). A negative or NaN bound is taken as 0 (the
    /// contact carries no impulse). With every bound infinite the solves
    /// are bit for bit those without bounds.
    ///
    /// # Panics
    ///
    /// If `bounds` does not hold one bound per contact (a caller's bug).
    pub fn with_normal_bounds(mut self, bounds: Vec<f64>) -> SparseContacts {
        assert_eq!(
            bounds.len(),
            self.rows.len(),
            "with_normal_bounds: one bound per contact"
        );
        self.bounds = bounds.into_iter().map(|b| b.max(0.0)).collect();
        self
    }

    /// The bound of contact `j`'s normal impulse, N·s (`+∞`: rigid).
    pub fn normal_bound(&self, j: usize) -> f64 {
        self.bounds.get(j).copied().unwrap_or(f64::INFINITY)
    }

    /// The same problem with the floes' rotations held (their inverse
    /// inertias set to 0): impulses translate the floes and do not turn
    /// them. Moreau–Jean's position projection solves this one
    /// (docs/physics.md §5.1 step 5).
    pub fn without_rotation(mut self) -> SparseContacts {
        for m in &mut self.minv {
            m[2] = 0.0;
        }
        for r in &mut self.rows {
            r.w = diagonal_block(&r.sides, &self.minv);
        }
        self
    }

    /// Number of contacts `m`.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// Whether the problem has no contact.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// Whether the tangential unknowns are present (`μ > 0`).
    pub fn friction(&self) -> bool {
        self.mu > 0.0
    }

    /// The diagonal block `W_jj` of contact `j`, row-major (1/kg).
    pub fn block(&self, j: usize) -> [f64; 4] {
        self.rows[j].w
    }

    /// The free relative velocities `q_j = (q_N, q_T)` of contact `j`, m/s.
    pub fn free(&self, j: usize) -> [f64; 2] {
        self.rows[j].q
    }

    /// The residual's normalisation `max(‖q‖₂, ROUNDING_FRACTION · v_s +
    /// RESIDUAL_FLOOR)`, m/s ([`RESIDUAL_FLOOR`]).
    pub fn residual_scale(&self) -> f64 {
        self.q_norm()
            .max(ROUNDING_FRACTION * self.v_scale + RESIDUAL_FLOOR)
    }

    /// `‖q‖₂` over every contact (the tangential part only with friction), m/s.
    pub fn q_norm(&self) -> f64 {
        let f = self.friction();
        self.rows
            .iter()
            .map(|r| r.q[0] * r.q[0] + if f { r.q[1] * r.q[1] } else { 0.0 })
            .sum::<f64>()
            .sqrt()
    }

    /// The tangential compliance `T_jᵀ M⁻¹ T_j` of contact `j` (1/kg; 0
    /// without friction), as [`crate::contact::problem::ContactLcp::tangential_compliance`].
    pub fn tangential_compliance(&self, j: usize) -> f64 {
        if self.friction() {
            self.rows[j].w[3]
        } else {
            0.0
        }
    }

    /// The floes' free velocities `W_free`, in group order.
    pub fn free_velocities(&self) -> Vec<Gen> {
        self.w_free.clone()
    }

    /// Adds the velocity change of the impulse `dp` at contact `j` to the
    /// floes' velocity changes `v` (group order): `v += M⁻¹ H_j dp`.
    ///
    /// The solvers carry the changes `M⁻¹ H p`, not the velocities
    /// `W_free + M⁻¹ H p`: `u = q + Hᵀ (M⁻¹ H p)` then rounds relative to
    /// the impulses' own effect, not to the floes' speeds (a row of floes
    /// at 1 m/s whose `q` cancels to 1e-16 m/s keeps a residual of
    /// rounding, not of 1e-16 m/s).
    #[inline]
    pub fn apply(&self, j: usize, dp: [f64; 2], v: &mut [Gen]) {
        for s in self.rows[j].sides.iter().flatten() {
            let mi = &self.minv[s.floe];
            let vl = &mut v[s.floe];
            for d in 0..3 {
                vl[d] += mi[d] * (s.jn[d] * dp[0] + s.jt[d] * dp[1]);
            }
        }
    }

    /// The relative velocities `u_j = q_j + H_jᵀ dv` of contact `j` for
    /// the floes' velocity changes `dv` (m/s; see [`SparseContacts::apply`]).
    #[inline]
    pub fn relative(&self, j: usize, dv: &[Gen]) -> [f64; 2] {
        let r = &self.rows[j];
        let mut u = [r.q[0], r.q[1]];
        for s in r.sides.iter().flatten() {
            let d = &dv[s.floe];
            u[0] += dot(&s.jn, d);
            u[1] += dot(&s.jt, d);
        }
        u
    }

    /// The group's kinetic energy at its free velocities and after the
    /// velocity changes `dv` (group order), `(before, after)`, J:
    /// `Σ ½ M |w|²` over the floes' three components (`M` the mass or the
    /// inertia).
    pub fn kinetic_energies(&self, dv: &[Gen]) -> (f64, f64) {
        let (mut before, mut after) = (0.0, 0.0);
        for ((mi, w), d) in self.minv.iter().zip(&self.w_free).zip(dv) {
            for k in 0..3 {
                if mi[k] > 0.0 {
                    before += 0.5 * w[k] * w[k] / mi[k];
                    after += 0.5 * (w[k] + d[k]) * (w[k] + d[k]) / mi[k];
                }
            }
        }
        (before, after)
    }

    /// The floes' velocity changes `M⁻¹ H p` of the impulses `p` (group
    /// order).
    pub fn velocity_changes(&self, p: &[[f64; 2]]) -> Vec<Gen> {
        let mut v = vec![[0.0; 3]; self.floes.len()];
        for (j, pj) in p.iter().enumerate() {
            self.apply(j, *pj, &mut v);
        }
        v
    }

    /// The generalised impulses `H p` per floe (group order), N·s and N·m·s.
    pub fn impulses(&self, p: &[[f64; 2]]) -> Vec<Gen> {
        let mut out = vec![[0.0; 3]; self.floes.len()];
        for (r, pj) in self.rows.iter().zip(p) {
            for s in r.sides.iter().flatten() {
                for d in 0..3 {
                    out[s.floe][d] += s.jn[d] * pj[0] + s.jt[d] * pj[1];
                }
            }
        }
        out
    }

    /// The natural-map residual of the impulses `p` on this problem
    /// (docs/physics.md §3.5):
    ///
    /// ```text
    /// F_j = (p_j − Π_K(p_j − ρ_j û_j)) / ρ_j,   ρ_j = 1 / W_NN,j,
    /// û_j = (u_N + μ |u_T|, u_T)      (coulomb = true: De Saxcé's change)
    /// û_j = u_j                        (coulomb = false: the cone relaxation)
    /// residual = ‖F‖₂ / max(‖q‖₂, ε)       (ε: RESIDUAL_FLOOR)
    /// ```
    ///
    /// with `u = W p + q` evaluated through the floes' velocities. Zero
    /// exactly at a solution of Coulomb's law with Newton's (or Signorini's)
    /// condition (`coulomb`), or of the Anitescu–Tasora relaxation; `F_j` is
    /// a velocity (m/s), so the residual is dimensionless like the LCP
    /// driver's `‖min(z, w)‖/‖q‖`. A non-finite impulse gives `+∞`.
    pub fn residual(&self, p: &[[f64; 2]], coulomb: bool) -> f64 {
        let dv = self.velocity_changes(p);
        self.residual_at(p, &dv, coulomb)
    }

    /// [`SparseContacts::residual`] with the velocity changes `v` of `p`
    /// already known.
    pub fn residual_at(&self, p: &[[f64; 2]], v: &[Gen], coulomb: bool) -> f64 {
        operator::residual_with(self, p, |j| self.relative(j, v), coulomb)
    }
}

impl Delassus for SparseContacts {
    /// The floes' velocity changes `M⁻¹ H p`, group order.
    type State = Vec<Gen>;

    #[inline]
    fn len(&self) -> usize {
        self.rows.len()
    }

    #[inline]
    fn block(&self, j: usize) -> [f64; 4] {
        self.rows[j].w
    }

    #[inline]
    fn mu(&self, _j: usize) -> f64 {
        self.mu
    }

    #[inline]
    fn bound(&self, j: usize) -> f64 {
        self.normal_bound(j)
    }

    #[inline]
    fn bounded(&self) -> bool {
        self.bounds.iter().any(|b| b.is_finite())
    }

    #[inline]
    fn free(&self, j: usize) -> [f64; 2] {
        self.rows[j].q
    }

    #[inline]
    fn state(&self, p: &[[f64; 2]]) -> Vec<Gen> {
        self.velocity_changes(p)
    }

    #[inline]
    fn relative(&self, j: usize, state: &Vec<Gen>) -> [f64; 2] {
        SparseContacts::relative(self, j, state)
    }

    #[inline]
    fn apply(&self, j: usize, dp: [f64; 2], state: &mut Vec<Gen>) {
        SparseContacts::apply(self, j, dp, state)
    }

    #[inline]
    fn residual_scale(&self) -> f64 {
        SparseContacts::residual_scale(self)
    }
}
