//! The frictional contact problem of a group of touching floes, as the
//! velocity–impulse LCP of docs/physics.md §3.1 (Rabatel 2015;
//! Stewart & Trinkle 1996), shared by the event-driven and the Moreau–Jean
//! formulations.
//!
//! For `m` contacts between the floes of one connected group, with `J` (`D`)
//! the normal (tangential, both directions `±T_j`) Jacobians, `M` the block
//! mass matrix (obstacles have no rows: zero inverse mass), `E` summing the
//! two friction entries of a contact and `W_free` the velocities the floes
//! would have without contact:
//!
//! ```text
//! W⁺ = W_free + M⁻¹ (J λ + D β̃)
//! w = Jᵀ W⁺ + c     ≥ 0 ⟂ λ ≥ 0        (Signorini, with an offset c)
//! γ = Dᵀ W⁺ + E α   ≥ 0 ⟂ β̃ ≥ 0       (friction directions)
//! σ = μ λ − Eᵀ β̃    ≥ 0 ⟂ α ≥ 0       (Coulomb cone, facets ±T)
//! ```
//!
//! so `z = (λ, β̃, α)` (size `4m`) solves `w = A z + q ≥ 0 ⟂ z ≥ 0` with
//! `A = [[JᵀM⁻¹J, JᵀM⁻¹D, 0], [DᵀM⁻¹J, DᵀM⁻¹D, E], [μ, −Eᵀ, 0]]` and
//! `q = (JᵀW_free + c, DᵀW_free, 0)` (the Coulomb rows then scaled to
//! velocities, below), with `H = (J, D)`. Without friction (`μ = 0`) only the
//! normal block is kept (size `m`): the friction unknowns would be zero and
//! the slack `α` undetermined.
//!
//! **Flush edge pairs** ([`Friction::Merged`]). The two points of a
//! nearly flush edge pair have tangential columns equal up to the angle
//! between the edges; the contacts of one body pair whose columns
//! agree to [`FRICTION_MERGE_TOLERANCE`] form one friction group with one
//! friction pair (along the mean of their columns) and one Coulomb row
//! `σ_G = μ Σ_{j∈G} λ_j − β̃⁺_G − β̃⁻_G`: `z = (λ, β̃_G, α_G)` of size
//! `m + 3G`. A lone contact keeps its own column and row, bit for bit
//! (docs/physics.md §3.1, "Flush edge pairs").
//!
//! **Coulomb rows in velocity units.** Each Coulomb row
//! `σ_j = μ λ_j − β̃⁺_j − β̃⁻_j` is assembled multiplied by the contact's
//! scaled normal Delassus diagonal `(JᵀM⁻¹J)_jj / g` (left as it is if that
//! diagonal is not positive and finite), so that every row of `w` is a
//! velocity (m/s). A positive row scaling keeps the solutions (`z`
//! unchanged, `w ≥ 0 ⟂ z ≥ 0` row by row) but makes the residual
//! `‖min(z, w)‖ / ‖q‖` of [`crate::lcp::solve()`] consistent in units:
//! unscaled, `σ` is in N·s while `q` is in m/s, and the rounding of impulses
//! of 1e6 N·s (`σ` ≈ −2e-11 N·s) alone exceeds the acceptance threshold
//! 1e-10 ‖q‖ — measured: a third of the frictional LCPs of
//! `field_200_coast` were rejected after Lemke solved them. (The scaling
//! was a copy of the assembled LCP made before each solve; it is now part
//! of the assembly, the same numbers without the copy.)
//!
//! **Block-sparse Delassus matrix.** A contact couples only with the
//! contacts that share one of its floes, so `HᵀM⁻¹H` can be summed floe
//! by floe over the columns touching each floe (`Σ_l 3 k_l²` fused
//! multiply–adds for `k_l` columns touching floe `l`) instead of as a dense
//! product over every floe of the group; each entry is then the fused sum
//! of its non-zero terms in row order. This is what the assembly computes
//! (the dense product it replaced differs at the last bit on about 1 % of
//! the entries of a 200-floe group, where faer adds its sums by cache
//! blocks of rows: docs/physics.md §3.1).
//!
//! **Scaling.** Delassus entries are inverse masses (1e-8 /kg for a
//! 100 m floe) while `μ` and `E` are of order one; unscaled, Lemke's rounding
//! on the friction rows would swamp the normal rows. The LCP is therefore
//! solved for `z' = (g λ, g β̃, α)` with `g` the mean diagonal of the
//! Delassus matrix: the blocks `HᵀM⁻¹H` are divided by `g`, `q` (velocities)
//! is unchanged, so `w` keeps its unit (m/s) and so does `z'` for the
//! impulses. Dumps hold this scaled LCP; [`ContactLcp::physical`] undoes it.
//!
//! The offset `c` is Rabatel's relaxed Signorini condition `Jᵀ W⁺ ≥ −c`:
//! zero at an impact; for a penetrating sustained contact `c = g / h < 0`
//! asks the contact to separate by `−g` over the step.
//!
//! The parts, each its own file: this one the groups ([`groups`]), the
//! [`ContactLcp`] and what its solution gives (impulses, velocity
//! changes); `assemble.rs` its assembly and the friction layout
//! ([`Friction`]); `delassus.rs` the block-sparse Delassus sum and its
//! dense references; `pattern.rs` the pattern of the assembled matrix,
//! its compressed columns and the reuse of large matrices' buffers;
//! `normal_tangent.rs` the problem in contact coordinates
//! ([`NormalTangentProblem`]) of the cone programs; `bounds.rs` the
//! crushing bound of the normal impulses, as bound rows of the LCP.

mod assemble;
mod bounds;
mod delassus;
mod normal_tangent;
mod pattern;

pub use assemble::{Friction, FRICTION_MERGE_TOLERANCE};
pub use normal_tangent::NormalTangentProblem;
pub use pattern::spare_matrix_capacity;

use super::{Contact, ContactKey};
use crate::lcp::sparse::Columns;
use crate::lcp::{BasisGuess, Lcp};
use faer::Mat;

/// Generalised velocity (or impulse) of one floe: `(x, y, θ)` components.
pub type Gen = [f64; 3];

/// A connected group of floes linked by contacts (obstacles do not link).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ContactGroup {
    /// Floe indices, sorted.
    pub floes: Vec<usize>,
    /// Indices into the contact list, sorted.
    pub contacts: Vec<usize>,
}

/// Splits `contacts` into connected groups of floes (union–find). Bodies
/// with index `>= n_floes` are obstacles and link nothing.
pub fn groups(contacts: &[Contact], n_floes: usize) -> Vec<ContactGroup> {
    fn find(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    let mut parent: Vec<usize> = (0..n_floes).collect();
    for c in contacts {
        if c.a < n_floes && c.b < n_floes {
            let (ra, rb) = (find(&mut parent, c.a), find(&mut parent, c.b));
            if ra != rb {
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
    }
    let mut by_root: std::collections::BTreeMap<usize, ContactGroup> = Default::default();
    for (k, c) in contacts.iter().enumerate() {
        let floe = if c.a < n_floes { c.a } else { c.b };
        if floe >= n_floes {
            continue; // obstacle–obstacle: never reported by detection
        }
        let root = find(&mut parent, floe);
        let g = by_root.entry(root).or_default();
        g.contacts.push(k);
        for body in [c.a, c.b] {
            if body < n_floes {
                g.floes.push(body);
            }
        }
    }
    by_root
        .into_values()
        .map(|mut g| {
            g.floes.sort_unstable();
            g.floes.dedup();
            g
        })
        .collect()
}

/// The assembled LCP of one group, with what is needed to turn its solution
/// into velocity changes.
#[derive(Debug, Clone)]
pub struct ContactLcp {
    /// The LCP `w = A z + q` ([`ContactLcp::lcp`]; private so that it
    /// keeps the pattern of the assembly, which [`Drop`] relies on).
    lcp: Lcp,
    /// Number of contacts `m`.
    pub m: usize,
    /// Whether friction unknowns are present (size `4m`, else `m`).
    pub friction: bool,
    /// Friction coefficient `μ`.
    pub mu: f64,
    /// The scale `g` (kg⁻¹): mean diagonal of the Delassus matrix; the LCP
    /// unknowns for impulses are `g λ`, `g β̃` (m/s).
    pub scale: f64,
    /// `H = (J, D)`: `3 n_g × (m + 2m)` (or `× m` without friction).
    h: Mat<f64>,
    /// Inverse mass per generalised coordinate of the group (`3 n_g`).
    minv: Vec<f64>,
    /// The columns of `H` that may be non-zero in the rows of each floe of
    /// the group (those of its contacts), in increasing order.
    touching: Vec<Vec<usize>>,
    /// The compressed columns of `lcp.m`, built from the known pattern for
    /// a large LCP (at least [`COLUMNS_FROM`](pattern::COLUMNS_FROM) unknowns), so that the solver
    /// does not read all of `M` to find its non-zeros.
    columns: Option<Columns>,
    /// Floe indices of the group.
    pub floes: Vec<usize>,
    /// Largest term of the free relative velocities `q` (a single body's
    /// contribution or an offset), m/s: the scale of their rounding.
    pub v_scale: f64,
    /// Identity of each contact, in LCP order (for warm starts).
    pub keys: Vec<ContactKey>,
    /// The friction group of each contact (length `m` with friction, empty
    /// without): contacts of one body pair whose friction columns agree
    /// share one friction resultant (see the module doc).
    fgroup: Vec<usize>,
    /// Number of friction groups `G` (`m` when nothing is merged, 0
    /// without friction); `n = m + 3G`.
    pub friction_groups: usize,
    /// The crushing bound of each contact's normal impulse (N·s, in LCP
    /// order; `+∞` rigid), empty when none is finite: then the LCP has no
    /// bound rows (`bounds.rs`).
    bounds: Vec<f64>,
}

impl ContactLcp {
    /// The assembled LCP `w = A z + q` (scaled: see the module doc).
    pub fn lcp(&self) -> &Lcp {
        &self.lcp
    }

    /// The number of friction groups when some contacts share one
    /// (`n = m + 3G`), `None` when each contact has its own or there is no
    /// friction (what an LCP dump records, [`crate::lcp::LcpDump`]).
    pub fn merged_groups(&self) -> Option<usize> {
        (self.friction && self.friction_groups != self.m).then_some(self.friction_groups)
    }

    /// The friction group of contact `j` (`j` itself without merging).
    pub fn friction_group(&self, j: usize) -> usize {
        self.fgroup.get(j).copied().unwrap_or(j)
    }

    /// The indices of contact `j`'s unknowns `(λ_j, β̃⁺, β̃⁻, α)` (the last
    /// three its friction group's; only `λ_j` without friction).
    pub fn unknowns(&self, j: usize) -> impl Iterator<Item = usize> {
        let (m, nf, g) = (self.m, self.friction_groups, self.friction_group(j));
        [j, m + 2 * g, m + 2 * g + 1, m + 2 * nf + g]
            .into_iter()
            .take(if self.friction { 4 } else { 1 })
    }

    /// The unknowns of each friction group (its members' `λ`, then its
    /// `β̃⁺`, `β̃⁻`, `α`), or of each contact (`λ_j`) without friction: the
    /// blocks of a block Gauss–Seidel sweep.
    pub fn blocks(&self) -> Vec<Vec<usize>> {
        if !self.friction {
            return (0..self.m).map(|j| vec![j]).collect();
        }
        let (m, nf) = (self.m, self.friction_groups);
        let mut out: Vec<Vec<usize>> = vec![Vec::new(); nf];
        for (j, &g) in self.fgroup.iter().enumerate() {
            out[g].push(j);
        }
        for (g, b) in out.iter_mut().enumerate() {
            b.extend([m + 2 * g, m + 2 * g + 1, m + 2 * nf + g]);
        }
        out
    }

    /// The compressed columns of `lcp.m` built at assembly, if the LCP is
    /// large enough to have them.
    pub(crate) fn columns(&self) -> Option<&Columns> {
        self.columns.as_ref()
    }

    /// The physical unknowns `(λ, β̃, α)` (N·s, N·s, m/s) of an LCP
    /// solution `z' = (g λ, g β̃, α)`.
    pub fn physical(&self, z: &[f64]) -> Vec<f64> {
        let cols = self.h.ncols();
        z.iter()
            .enumerate()
            .map(|(k, v)| if k < cols { v / self.scale } else { *v })
            .collect()
    }

    /// The generalised impulses `H (λ, β̃)` per floe of the group, in group
    /// order, from an LCP solution `z'`.
    ///
    /// Each floe's sums run over the columns of its own contacts, in
    /// increasing order: the terms of the other columns are exact zeros
    /// (`H` is zero there and `z'` finite), so this is the row sum over
    /// every column, up to the sign of a zero.
    pub fn impulses(&self, z: &[f64]) -> Vec<Gen> {
        let zp = self.physical(z);
        let mut out = vec![[0.0; 3]; self.floes.len()];
        for ((l, o), cols) in out.iter_mut().enumerate().zip(&self.touching) {
            for (d, od) in o.iter_mut().enumerate() {
                let r = 3 * l + d;
                *od = cols.iter().map(|&c| self.h[(r, c)] * zp[c]).sum();
            }
        }
        out
    }

    /// The velocity changes `M⁻¹ H (λ, β̃)` per floe of the group.
    pub fn velocity_changes(&self, z: &[f64]) -> Vec<Gen> {
        let mut p = self.impulses(z);
        for (l, g) in p.iter_mut().enumerate() {
            for (d, gd) in g.iter_mut().enumerate() {
                *gd *= self.minv[3 * l + d];
            }
        }
        p
    }

    /// Normal impulses `λ` (N·s) from an LCP solution `z'`.
    pub fn normal(&self, z: &[f64]) -> Vec<f64> {
        z.iter().take(self.m).map(|v| v / self.scale).collect()
    }

    /// Signed tangential impulses `β_j = β̃⁺_j − β̃⁻_j` along `T_j` (N·s).
    /// A merged friction group's resultant is shared among its members in
    /// proportion to their normal impulses (equally if none pushes), which
    /// keeps each member within its own cone `|β_j| ≤ μ λ_j`.
    pub fn tangential(&self, z: &[f64]) -> Vec<f64> {
        let (m, nf) = (self.m, self.friction_groups);
        if !self.friction || z.len() < m + 2 * nf {
            return vec![0.0; m];
        }
        let mut lam = vec![0.0; nf];
        let mut count = vec![0usize; nf];
        for (j, &g) in self.fgroup.iter().enumerate() {
            lam[g] += z[j].max(0.0);
            count[g] += 1;
        }
        (0..m)
            .map(|j| {
                let g = self.fgroup[j];
                let b = (z[m + 2 * g] - z[m + 2 * g + 1]) / self.scale;
                if count[g] == 1 {
                    b
                } else if lam[g] > 0.0 {
                    b * (z[j].max(0.0) / lam[g])
                } else {
                    b / count[g] as f64
                }
            })
            .collect()
    }

    /// The tangential compliance of contact `j`: the change of its
    /// tangential relative velocity per unit tangential impulse at it,
    /// `T_jᵀ M⁻¹ T_j` over the floes of the group (1/kg; 0 without
    /// friction). For a merged friction group, that of its resultant.
    pub fn tangential_compliance(&self, j: usize) -> f64 {
        if !self.friction {
            return 0.0;
        }
        let (n, r) = (self.lcp.n, self.m + 2 * self.friction_group(j));
        self.lcp.m[r * n + r] * self.scale
    }

    /// The basis and starting point that the impulses `normal`, `tangential`
    /// (N·s per contact, e.g. an iterative answer) give this LCP: `λ_j > 0`
    /// basic; a friction group's resultant `β = Σ β_j` in `β̃⁺` (positive)
    /// or `β̃⁻` (negative); its slip `α` basic when `|β|` reaches the cone
    /// `μ Σ λ_j` (to 1e-6 of it: sliding), else its slack. The exact
    /// finish of an iterative answer starts there (docs/physics.md §3.5).
    pub fn guess_from(&self, normal: &[f64], tangential: &[f64]) -> BasisGuess {
        let n = self.lcp.n;
        let mut g = BasisGuess {
            basic: vec![false; n],
            z: vec![0.0; n],
        };
        for (j, &l) in normal.iter().enumerate().take(self.m) {
            if l > 0.0 {
                g.basic[j] = true;
                g.z[j] = l * self.scale;
            }
        }
        if !self.friction {
            return g;
        }
        let (m, nf) = (self.m, self.friction_groups);
        let mut lam = vec![0.0; nf];
        let mut beta = vec![0.0; nf];
        for j in 0..m {
            let k = self.friction_group(j);
            lam[k] += normal.get(j).copied().unwrap_or(0.0).max(0.0);
            beta[k] += tangential.get(j).copied().unwrap_or(0.0);
        }
        for k in 0..nf {
            let (plus, minus, alpha) = (m + 2 * k, m + 2 * k + 1, m + 2 * nf + k);
            let b = beta[k] * self.scale;
            if b > 0.0 {
                (g.basic[plus], g.z[plus]) = (true, b);
            } else if b < 0.0 {
                (g.basic[minus], g.z[minus]) = (true, -b);
            }
            g.basic[alpha] = lam[k] > 0.0 && beta[k].abs() >= (1.0 - 1e-6) * self.mu * lam[k];
        }
        g
    }

    /// The frictionless sub-problem (normal block only), for the last resort
    /// when the frictional LCP cannot be solved.
    pub fn frictionless(&self) -> ContactLcp {
        let m = self.m;
        let n = self.lcp.n;
        let mut a = vec![0.0; m * m];
        for r in 0..m {
            for c in 0..m {
                a[r * m + c] = self.lcp.m[r * n + c];
            }
        }
        let mut h = Mat::<f64>::zeros(self.h.nrows(), m);
        for r in 0..self.h.nrows() {
            for c in 0..m {
                h[(r, c)] = self.h[(r, c)];
            }
        }
        ContactLcp {
            lcp: Lcp {
                n: m,
                m: a,
                q: self.lcp.q[..m].to_vec(),
            },
            m,
            friction: false,
            mu: self.mu,
            scale: self.scale,
            h,
            minv: self.minv.clone(),
            // The normal columns only.
            touching: self
                .touching
                .iter()
                .map(|t| t.iter().copied().filter(|&c| c < m).collect())
                .collect(),
            columns: None,
            floes: self.floes.clone(),
            v_scale: self.v_scale,
            keys: self.keys.clone(),
            fgroup: Vec::new(),
            friction_groups: 0,
            bounds: Vec::new(),
        }
        .with_normal_bounds(&self.bounds)
    }
}
