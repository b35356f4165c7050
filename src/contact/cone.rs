//! The Anitescu–Tasora convex relaxation of the frictional contact problem,
//! as a second-order-cone program solved by clarabel (interior point).
//!
//! # Problem
//!
//! For a group's [`NormalTangentProblem`] (`u = G p + b`, `p = (λ, β)` the
//! contact impulses, `G` the Delassus matrix, `b` the free relative
//! velocities with the Newton offset on the normal rows):
//!
//! ```text
//! minimise ½ pᵀ G p + bᵀ p   subject to   p_j = (λ_j, β_j) ∈ K_μ = {|β_j| ≤ μ λ_j}
//! ```
//!
//! Its KKT conditions are the cone complementarity problem
//! `K_μ ∋ p ⟂ u ∈ K_μ*` with the dual cone `K_μ* = {u_N ≥ μ |u_T|}`
//! (Anitescu 2006; Tasora & Anitescu 2011): the Coulomb cone is exact (no
//! facet linearisation), friction opposes sliding with `|β| = μ λ`, but
//! Signorini's `u_N ≥ 0` becomes `u_N ≥ μ |u_T|` with equality while the
//! contact pushes: a **sliding contact separates at normal speed `μ |u_T|`**.
//! This is the known artefact of the relaxation (it is the price of a convex
//! problem), documented and measured by the tests, not corrected. Without
//! sliding (`u_T = 0`) or without friction the answer is the LCP's.
//!
//! # Clarabel form
//!
//! Clarabel solves `min ½ xᵀ P x + qᵀ x` s.t. `A x + s = b_c`, `s ∈ K`. The
//! unknowns are scaled per contact, `x_j = p_j / d_j` with
//! `d_j = 1 / sqrt(G_{λ_j λ_j})` (the same scale for `λ_j` and `β_j`, so
//! the cone is unchanged), which makes `P = D G D` of unit diagonal: the
//! impulses (N·s, of order `M v`) and the velocities (m/s) are otherwise
//! ten orders apart. `P` is its upper triangle in CSC form, `q = D b`. Each
//! contact contributes `s_j = (μ λ_j, β_j) ∈ SecondOrderConeT(2)`, i.e.
//! rows `−μ` and `−1` of `A` with `b_c = 0`. Without friction (`μ = 0`) the
//! cone degenerates to `λ ≥ 0` and `β = 0`: the tangential unknowns are
//! dropped and `λ` lies in `NonnegativeConeT(m)`.
//!
//! The solution is projected back onto `K_μ` (`λ ← max(λ, 0)`, `|β| ≤ μλ`),
//! a change within the solver tolerance whose size is reported
//! ([`ConeSolution::cone_excess`]). A status other than `Solved` or
//! `AlmostSolved`, or a non-finite solution, is a failure: the caller
//! counts it and falls back (the Moreau–Jean formulation falls back to the
//! Lemke LCP); this module never panics.
//!
//! # References
//!
//! - M. Anitescu (2006), *Optimization-based simulation of nonsmooth rigid
//!   multibody dynamics*, Math. Program. 105, 113–143.
//! - A. Tasora, M. Anitescu (2011), *A matrix-free cone complementarity
//!   approach for solving large-scale, nonsmooth, rigid body dynamics*,
//!   CMAME 200, 439–453.
//! - P. Goulart, Y. Chen (2024), *Clarabel: An interior-point solver for
//!   conic programs with quadratic objectives*, arXiv:2405.12762.

use super::problem::NormalTangentProblem;
use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};

/// Options of [`solve_cone`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConeOptions {
    /// Absolute and relative duality-gap and feasibility tolerance of
    /// clarabel on the scaled problem (default 1e-11; clarabel's own default
    /// is 1e-8, too loose to compare with Lemke at 1e-8).
    pub tolerance: f64,
    /// Interior-point iteration cap (default 200).
    pub max_iter: u32,
}

impl Default for ConeOptions {
    fn default() -> Self {
        ConeOptions {
            tolerance: 1e-11,
            max_iter: 200,
        }
    }
}

/// How a cone solve ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConeStatus {
    /// Clarabel reports `Solved`.
    Solved,
    /// Clarabel reports `AlmostSolved` (reduced accuracy); accepted, counted.
    AlmostSolved,
    /// Anything else (infeasible, iteration cap, numerical error, setup
    /// error, non-finite solution): the caller falls back.
    Failed,
}

/// The result of [`solve_cone`].
#[derive(Debug, Clone, PartialEq)]
pub struct ConeSolution {
    /// Normal impulses `λ_j ≥ 0`, N·s (zeros on failure).
    pub lambda: Vec<f64>,
    /// Tangential impulses `β_j`, `|β_j| ≤ μ λ_j`, N·s (zeros without friction
    /// or on failure).
    pub beta: Vec<f64>,
    /// Outcome.
    pub status: ConeStatus,
    /// Clarabel's status, for messages.
    pub solver_status: String,
    /// Interior-point iterations.
    pub iterations: u32,
    /// Largest distance of the raw solution outside `K_μ`, relative to the
    /// largest `λ` (removed by the projection).
    pub cone_excess: f64,
}

impl ConeSolution {
    fn failed(m: usize, status: String) -> ConeSolution {
        ConeSolution {
            lambda: vec![0.0; m],
            beta: vec![0.0; m],
            status: ConeStatus::Failed,
            solver_status: status,
            iterations: 0,
            cone_excess: 0.0,
        }
    }
}

/// Solves the Anitescu–Tasora cone program of `p` with clarabel (see the
/// module doc). Never panics; the solution is finite.
pub fn solve_cone(p: &NormalTangentProblem, opts: &ConeOptions) -> ConeSolution {
    let m = p.m;
    let dim = p.dim();
    if m == 0 {
        return ConeSolution {
            lambda: Vec::new(),
            beta: Vec::new(),
            status: ConeStatus::Solved,
            solver_status: "empty".into(),
            iterations: 0,
            cone_excess: 0.0,
        };
    }
    let friction = p.friction && p.mu > 0.0;
    if dim != if p.friction { 2 * m } else { m } || p.g.len() != dim * dim {
        return ConeSolution::failed(m, "inconsistent problem sizes".into());
    }
    // Per-contact scale d_j = 1/sqrt(G_jj).
    let d_contact: Vec<f64> = (0..m)
        .map(|j| {
            let gjj = p.g[j * dim + j];
            if gjj.is_finite() && gjj > 0.0 {
                1.0 / gjj.sqrt()
            } else {
                1.0
            }
        })
        .collect();
    let d: Vec<f64> = (0..dim).map(|r| d_contact[r % m]).collect();
    // Variables: the λ's, then (with friction) the β's.
    let nv = if friction { 2 * m } else { m };
    // P = D G D, upper triangle, CSC.
    let mut colptr = Vec::with_capacity(nv + 1);
    let mut rowval = Vec::new();
    let mut nzval = Vec::new();
    colptr.push(0);
    for c in 0..nv {
        for r in 0..=c {
            let v = d[r] * p.g[r * dim + c] * d[c];
            if v != 0.0 {
                rowval.push(r);
                nzval.push(v);
            }
        }
        colptr.push(rowval.len());
    }
    let pm = CscMatrix::new(nv, nv, colptr, rowval, nzval);
    let q: Vec<f64> = (0..nv).map(|r| d[r] * p.b[r]).collect();
    // Constraints.
    let (a, bc, cones) = if friction {
        // Rows (2j, 2j+1) = (μ λ_j, β_j) ∈ SOC(2).
        let mut colptr = Vec::with_capacity(nv + 1);
        let mut rowval = Vec::with_capacity(nv);
        let mut nzval = Vec::with_capacity(nv);
        colptr.push(0);
        for c in 0..nv {
            if c < m {
                rowval.push(2 * c);
                nzval.push(-p.mu);
            } else {
                rowval.push(2 * (c - m) + 1);
                nzval.push(-1.0);
            }
            colptr.push(rowval.len());
        }
        let a = CscMatrix::new(2 * m, nv, colptr, rowval, nzval);
        let cones: Vec<SupportedConeT<f64>> = (0..m)
            .map(|_| SupportedConeT::SecondOrderConeT(2))
            .collect();
        (a, vec![0.0; 2 * m], cones)
    } else {
        let a = CscMatrix::new(m, m, (0..=m).collect(), (0..m).collect(), vec![-1.0; m]);
        (a, vec![0.0; m], vec![SupportedConeT::NonnegativeConeT(m)])
    };
    let settings = DefaultSettings::<f64> {
        verbose: false,
        max_iter: opts.max_iter,
        tol_gap_abs: opts.tolerance,
        tol_gap_rel: opts.tolerance,
        tol_feas: opts.tolerance,
        tol_ktratio: opts.tolerance.max(1e-8),
        ..DefaultSettings::default()
    };
    let mut solver = match DefaultSolver::new(&pm, &q, &a, &bc, &cones, settings) {
        Ok(s) => s,
        Err(e) => return ConeSolution::failed(m, format!("setup: {e}")),
    };
    solver.solve();
    let sol = &solver.solution;
    let status = match sol.status {
        SolverStatus::Solved => ConeStatus::Solved,
        SolverStatus::AlmostSolved => ConeStatus::AlmostSolved,
        _ => ConeStatus::Failed,
    };
    let name = format!("{:?}", sol.status);
    if status == ConeStatus::Failed || sol.x.iter().any(|v| !v.is_finite()) {
        let mut f = ConeSolution::failed(m, name);
        f.iterations = sol.iterations;
        return f;
    }
    let mut lambda: Vec<f64> = (0..m).map(|j| d[j] * sol.x[j]).collect();
    let mut beta: Vec<f64> = if friction {
        (0..m).map(|j| d[m + j] * sol.x[m + j]).collect()
    } else {
        vec![0.0; m]
    };
    // Project onto K_μ, measuring how far outside the raw point was.
    let scale = lambda.iter().fold(0.0f64, |s, l| s.max(l.abs()));
    let mut excess = 0.0f64;
    for j in 0..m {
        if lambda[j] < 0.0 {
            excess = excess.max(-lambda[j]);
            lambda[j] = 0.0;
        }
        let bound = p.mu * lambda[j];
        if beta[j].abs() > bound {
            excess = excess.max(beta[j].abs() - bound);
            beta[j] = beta[j].clamp(-bound, bound);
        }
    }
    ConeSolution {
        lambda,
        beta,
        status,
        solver_status: name,
        iterations: sol.iterations,
        cone_excess: if scale > 0.0 { excess / scale } else { excess },
    }
}
