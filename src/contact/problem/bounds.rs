//! The crushing bound of the normal impulses as rows of the LCP
//! (docs/physics.md §10; the bounds from [`crate::contact::crush`]).
//!
//! A bound `0 ≤ λ_j ≤ b_j` is a box; Lemke takes it as one more
//! complementarity pair per bounded contact: an unknown `ν_j ≥ 0` (m/s)
//! added to the contact's Signorini row, and its row `b_j − λ_j ≥ 0`:
//!
//! ```text
//! w_j = (A z + q)_j + ν_j ≥ 0 ⟂ z_j ≥ 0
//! w_ν = g b_j − z_j        ≥ 0 ⟂ ν_j ≥ 0
//! ```
//!
//! (`z_j = g λ_j`, scaled like every impulse of the LCP). Below the bound
//! `ν_j = 0` and Signorini holds; at it `ν_j = −u_N ≥ 0`: the contact
//! keeps approaching, which is the crushing. The matrix stays
//! copositive-plus (the added block `[[0, I], [−I, 0]]` is skew), so
//! Lemke's path ends at a solution whenever the unbounded LCP had one.
//! The unknowns `ν` come after `(λ, β̃, α)`, so every reader of `z`
//! (impulses, velocity changes, the Coulomb check) is unchanged.

use super::ContactLcp;
use crate::lcp::Lcp;

impl ContactLcp {
    /// This LCP with the normal impulse of contact `j` bounded by
    /// `bounds[j]` (N·s; `+∞` or a missing entry: rigid), as bound rows
    /// (module doc). Unchanged, bit for bit, when no bound is finite.
    pub fn with_normal_bounds(mut self, bounds: &[f64]) -> ContactLcp {
        let bounded: Vec<usize> = (0..self.m)
            .filter(|&j| bounds.get(j).is_some_and(|b| b.is_finite()))
            .collect();
        if bounded.is_empty() {
            return self;
        }
        let n = self.lcp.n;
        let nb = bounded.len();
        let n2 = n + nb;
        let mut a = vec![0.0; n2 * n2];
        for r in 0..n {
            a[r * n2..r * n2 + n].copy_from_slice(&self.lcp.m[r * n..(r + 1) * n]);
        }
        let mut q = self.lcp.q.clone();
        q.resize(n2, 0.0);
        for (k, &j) in bounded.iter().enumerate() {
            let nu = n + k;
            a[j * n2 + nu] = 1.0;
            a[nu * n2 + j] = -1.0;
            q[nu] = bounds[j].max(0.0) * self.scale;
        }
        // The compressed columns and the recycled buffer belong to the
        // assembled pattern: a bounded LCP goes without them.
        self.columns = None;
        self.lcp = Lcp { n: n2, m: a, q };
        self.bounds = (0..self.m)
            .map(|j| bounds.get(j).copied().unwrap_or(f64::INFINITY))
            .collect();
        self
    }

    /// The crushing bound of each contact's normal impulse (N·s, `+∞`
    /// rigid); empty when the LCP has none.
    pub fn normal_bounds(&self) -> &[f64] {
        &self.bounds
    }

    /// Whether the LCP has bound rows ([`ContactLcp::with_normal_bounds`]).
    pub fn bounded(&self) -> bool {
        !self.bounds.is_empty()
    }
}
