//! A Siconos 2D frictional contact problem ([`Fc2dProblem`], read by
//! [`crate::model::fc2d`]) as a [`Delassus`] operator, so that NSGS and
//! APGD solve it unchanged, and Siconos' own accuracy measure of an answer
//! ([`Fc2dOperator::siconos_error`]).
//!
//! The state of the impulses `p` is `W p` (2 entries per contact): a
//! contact's relative velocity is `q_j + (W p)_j`, read in O(1), and a
//! change `dp` at contact `j` adds `W_{·j} dp`, the contact's block column
//! (kept by column here: the file's `W` is stored by row, and is symmetric
//! only to its printed digits, so the transpose of its row would not be its
//! column). A sweep thus costs the number of stored blocks, as Siconos'
//! `fc2d_nsgs` (which forms each contact's local velocity from its block
//! row).
//!
//! The residual's scale is `max(‖q‖₂, ROUNDING_FRACTION · max|q_i| +
//! RESIDUAL_FLOOR)`, the floor of the floes' problem
//! ([`super::RESIDUAL_FLOOR`]) with the largest entry of `q` as its largest
//! term.

use super::operator::{project_boxed, Delassus};
use super::problem::{RESIDUAL_FLOOR, ROUNDING_FRACTION};
use crate::model::fc2d::Fc2dProblem;

/// A file's problem by block column (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Fc2dOperator {
    /// The diagonal blocks, row-major `[W_NN, W_NT, W_TN, W_TT]` (1/kg; zero
    /// when the file stores none).
    diag: Vec<[f64; 4]>,
    /// `q_j = (q_N, q_T)`, m/s.
    q: Vec<[f64; 2]>,
    /// `μ_j`, dimensionless.
    mu: Vec<f64>,
    /// The blocks of column `j` are `col_ptr[j]..col_ptr[j + 1]`.
    col_ptr: Vec<usize>,
    /// The block row (contact) of each stored block.
    row: Vec<usize>,
    /// The blocks by column, each row-major `[W_NN, W_NT, W_TN, W_TT]`.
    blocks: Vec<[f64; 4]>,
    /// The residual's normalisation, m/s.
    scale: f64,
}

impl Fc2dOperator {
    /// The operator of `prob` (its `W` copied by block column: O(blocks)).
    pub fn new(prob: &Fc2dProblem) -> Fc2dOperator {
        let w = &prob.w;
        let n = w.n;
        let mut col_ptr = vec![0usize; n + 1];
        for &j in &w.col {
            col_ptr[j + 1] += 1;
        }
        for j in 0..n {
            col_ptr[j + 1] += col_ptr[j];
        }
        let mut next = col_ptr.clone();
        let mut row = vec![0usize; w.col.len()];
        let mut blocks = vec![[0.0; 4]; w.col.len()];
        for i in 0..n {
            for k in w.row_ptr[i]..w.row_ptr[i + 1] {
                let j = w.col[k];
                row[next[j]] = i;
                blocks[next[j]] = w.blocks[k];
                next[j] += 1;
            }
        }
        let diag = (0..n)
            .map(|j| w.block(j, j).copied().unwrap_or([0.0; 4]))
            .collect();
        let q: Vec<[f64; 2]> = prob.q.chunks(2).map(|c| [c[0], c[1]]).collect();
        let q_norm = prob.q.iter().map(|x| x * x).sum::<f64>().sqrt();
        let q_max = prob.q.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        Fc2dOperator {
            diag,
            q,
            mu: prob.mu.clone(),
            col_ptr,
            row,
            blocks,
            scale: q_norm.max(ROUNDING_FRACTION * q_max + RESIDUAL_FLOOR),
        }
    }

    /// Siconos' error of the impulses `r` with state `w_r = W r`
    /// (`fc2d_nsgs`'s stop test; tests/data/fc2d/README.md):
    /// `F = r − Π_K(r − û)`, `û_j = (u_N + μ_j |u_T|, u_T)`, unscaled, over
    /// all contacts, divided by `max(‖r‖₂, ‖u‖₂, ‖q‖₂)` unless that is below
    /// the machine epsilon. Dimensionally mixed (N·s minus m/s), as
    /// Siconos': it is comparable to Siconos' figures, not across problems.
    pub fn siconos_error(&self, r: &[[f64; 2]], w_r: &[[f64; 2]]) -> f64 {
        let (mut f2, mut r2, mut u2, mut q2) = (0.0, 0.0, 0.0, 0.0);
        for j in 0..self.q.len() {
            let (rj, q) = (r[j], self.q[j]);
            let u = [q[0] + w_r[j][0], q[1] + w_r[j][1]];
            let mu = self.mu[j];
            let x = [rj[0] - (u[0] + mu * u[1].abs()), rj[1] - u[1]];
            let pr = project_boxed(x, mu, f64::INFINITY);
            f2 += (rj[0] - pr[0]).powi(2) + (rj[1] - pr[1]).powi(2);
            r2 += rj[0] * rj[0] + rj[1] * rj[1];
            u2 += u[0] * u[0] + u[1] * u[1];
            q2 += q[0] * q[0] + q[1] * q[1];
        }
        let norm = r2.sqrt().max(u2.sqrt()).max(q2.sqrt());
        let f = f2.sqrt();
        let err = if norm >= f64::EPSILON { f / norm } else { f };
        if err.is_finite() {
            err
        } else {
            f64::INFINITY
        }
    }
}

impl Delassus for Fc2dOperator {
    /// `W p`, `(N, T)` per contact, m/s.
    type State = Vec<[f64; 2]>;

    #[inline]
    fn len(&self) -> usize {
        self.q.len()
    }

    #[inline]
    fn block(&self, j: usize) -> [f64; 4] {
        self.diag[j]
    }

    #[inline]
    fn mu(&self, j: usize) -> f64 {
        self.mu[j]
    }

    #[inline]
    fn free(&self, j: usize) -> [f64; 2] {
        self.q[j]
    }

    #[inline]
    fn state(&self, p: &[[f64; 2]]) -> Vec<[f64; 2]> {
        let mut s = vec![[0.0; 2]; self.q.len()];
        for (j, pj) in p.iter().enumerate() {
            self.apply(j, *pj, &mut s);
        }
        s
    }

    #[inline]
    fn relative(&self, j: usize, state: &Vec<[f64; 2]>) -> [f64; 2] {
        [self.q[j][0] + state[j][0], self.q[j][1] + state[j][1]]
    }

    #[inline]
    fn apply(&self, j: usize, dp: [f64; 2], state: &mut Vec<[f64; 2]>) {
        for k in self.col_ptr[j]..self.col_ptr[j + 1] {
            let (b, s) = (&self.blocks[k], &mut state[self.row[k]]);
            s[0] += b[0] * dp[0] + b[1] * dp[1];
            s[1] += b[2] * dp[0] + b[3] * dp[1];
        }
    }

    #[inline]
    fn residual_scale(&self) -> f64 {
        self.scale
    }
}

/// The solvers of `floebench fc2d`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fc2dSolver {
    /// NSGS ([`super::nsgs`]) on Coulomb's law, stopped on the natural-map
    /// residual.
    Nsgs,
    /// APGD ([`super::apgd`]) on the cone relaxation, stopped on the
    /// relaxation's residual.
    Apgd,
    /// Lemke ([`crate::lcp::solve()`]) on the Stewart–Trinkle LCP of `W`
    /// ([`super::fc2d_lcp`]).
    Lemke,
}

impl Fc2dSolver {
    /// Every solver, in the order of `--solver`'s help.
    pub const ALL: [Fc2dSolver; 3] = [Fc2dSolver::Nsgs, Fc2dSolver::Apgd, Fc2dSolver::Lemke];

    /// The name on the command line and in the tables.
    pub fn name(self) -> &'static str {
        match self {
            Fc2dSolver::Nsgs => "nsgs",
            Fc2dSolver::Apgd => "apgd",
            Fc2dSolver::Lemke => "lemke",
        }
    }
}

/// What a solve of a file's problem returns.
#[derive(Debug, Clone, PartialEq)]
pub struct Fc2dAnswer {
    /// The reactions `r_j = (r_N, r_T)`, N·s (finite).
    pub r: Vec<[f64; 2]>,
    /// Sweeps (NSGS), iterations (APGD) or pivots (Lemke).
    pub iterations: u64,
    /// Whether the solver's own stop test was met (NSGS: the residual at
    /// most the tolerance; APGD: the relaxation's; Lemke: the LCP solved).
    pub converged: bool,
}

/// Solves `prob` (its operator `op`) by `solver` from zero reactions, to
/// `tolerance` (NSGS, APGD) within `max_iterations` sweeps or iterations.
/// An error only for a problem Lemke does not take
/// ([`super::fc2d_lcp::MAX_LEMKE_CONTACTS`]).
pub fn solve_fc2d(
    prob: &Fc2dProblem,
    op: &Fc2dOperator,
    solver: Fc2dSolver,
    tolerance: f64,
    max_iterations: u64,
) -> Result<Fc2dAnswer, String> {
    let mut r = vec![[0.0; 2]; op.len()];
    let outcome = match solver {
        Fc2dSolver::Nsgs => super::nsgs::solve(op, &mut r, tolerance, max_iterations, 1.0).0,
        Fc2dSolver::Apgd => super::apgd::solve(op, &mut r, tolerance, max_iterations).0,
        Fc2dSolver::Lemke => {
            let (r, pivots, solved) = super::fc2d_lcp::solve_lemke(prob)?;
            return Ok(Fc2dAnswer {
                r,
                iterations: pivots as u64,
                converged: solved,
            });
        }
    };
    Ok(Fc2dAnswer {
        r,
        iterations: outcome.iterations,
        converged: outcome.converged,
    })
}

impl Fc2dOperator {
    /// The two accuracy measures of the reactions `r`: the natural-map
    /// residual (Coulomb form, [`super::residual_at`]) and Siconos' error
    /// ([`Fc2dOperator::siconos_error`]).
    pub fn measures(&self, r: &[[f64; 2]]) -> (f64, f64) {
        let s = self.state(r);
        (
            super::residual_at(self, r, &s, true),
            self.siconos_error(r, &s),
        )
    }
}
