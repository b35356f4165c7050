//! A group's contact problem in contact coordinates `(λ, β)`, as the cone
//! programs use it (docs/physics.md §3.4): read from the assembled LCP, and
//! back to the LCP's unknowns.

use super::ContactLcp;

/// The contact problem of a group in the contact coordinates `p = (λ, β)`
/// (normal impulses `λ_1..λ_m`, then signed tangential impulses
/// `β_1..β_m` along `T_j`, N·s), as used by cone formulations: the
/// post-contact relative velocities are `u = G p + b` with `G = HᵀM⁻¹H` the
/// Delassus matrix of `H = (J, B)` and `b = (JᵀW_free + c, BᵀW_free)`.
/// Without friction only the normal part is present (`dim = m`).
#[derive(Debug, Clone, PartialEq)]
pub struct NormalTangentProblem {
    /// Number of contacts `m`.
    pub m: usize,
    /// Whether the tangential unknowns are present (`dim = 2m`, else `m`).
    pub friction: bool,
    /// Friction coefficient `μ`.
    pub mu: f64,
    /// Delassus matrix `G`, `dim × dim`, row-major, 1/kg (or 1/(kg·m²)).
    pub g: Vec<f64>,
    /// Free relative velocities with the offset, `b`, m/s.
    pub b: Vec<f64>,
    /// Scale of the rounding of `b` ([`ContactLcp::v_scale`]), m/s.
    pub v_scale: f64,
    /// The crushing bound of each normal impulse `λ_j ≤ bounds[j]` (N·s,
    /// `+∞` rigid); empty: none (docs/physics.md §10).
    pub bounds: Vec<f64>,
}

impl NormalTangentProblem {
    /// Number of unknowns (`2m` with friction, `m` without).
    pub fn dim(&self) -> usize {
        self.b.len()
    }

    /// `u = G p + b`: normal and tangential relative velocities after the
    /// impulses `p`, m/s.
    pub fn velocities(&self, p: &[f64]) -> Vec<f64> {
        let n = self.dim();
        (0..n)
            .map(|r| {
                self.b[r]
                    + (0..n)
                        .map(|c| self.g[r * n + c] * p.get(c).copied().unwrap_or(0.0))
                        .sum::<f64>()
            })
            .collect()
    }
}

impl ContactLcp {
    /// The same problem in contact coordinates `(λ, β)`, read from the
    /// assembled LCP (no recomputation: `β_j` is the `+T_j` friction column).
    pub fn normal_tangent(&self) -> NormalTangentProblem {
        let m = self.m;
        let n = self.lcp.n;
        let idx: Vec<usize> = if self.friction {
            (0..m)
                .chain((0..m).map(|j| m + 2 * self.friction_group(j)))
                .collect()
        } else {
            (0..m).collect()
        };
        let dim = idx.len();
        let mut g = vec![0.0; dim * dim];
        for (r, &ir) in idx.iter().enumerate() {
            for (c, &ic) in idx.iter().enumerate() {
                // Undo the LCP's scaling: the Delassus matrix itself, 1/kg.
                g[r * dim + c] = self.lcp.m[ir * n + ic] * self.scale;
            }
        }
        NormalTangentProblem {
            m,
            friction: self.friction,
            mu: self.mu,
            g,
            b: idx.iter().map(|&i| self.lcp.q[i]).collect(),
            v_scale: self.v_scale,
            bounds: self.normal_bounds().to_vec(),
        }
    }

    /// The (scaled) LCP unknowns `z' = (g λ, g β̃⁺, g β̃⁻, α)` of contact
    /// impulses `λ`, `β` (N·s; `β` ignored without friction; `α = 0`, it does
    /// not enter the impulses), for [`ContactLcp::impulses`] and
    /// [`ContactLcp::velocity_changes`].
    ///
    /// A merged friction group takes the sum of its members' `β`.
    pub fn z_from_impulses(&self, lambda: &[f64], beta: &[f64]) -> Vec<f64> {
        let (m, nf) = (self.m, self.friction_groups);
        let mut z = vec![0.0; self.lcp.n];
        let mut bsum = vec![0.0; nf];
        for j in 0..m {
            z[j] = lambda.get(j).copied().unwrap_or(0.0) * self.scale;
            if self.friction {
                bsum[self.fgroup[j]] += beta.get(j).copied().unwrap_or(0.0);
            }
        }
        for (g, b) in bsum.into_iter().enumerate() {
            let b = b * self.scale;
            z[m + 2 * g] = b.max(0.0);
            z[m + 2 * g + 1] = (-b).max(0.0);
        }
        z
    }
}
