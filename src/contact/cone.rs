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
//! **Active-set polish.** An interior point stops at a tolerance, and on
//! degenerate contacts (a resting contact with `u = 0` and `λ = 0`, common
//! after a plastic impact) it leaves impulses of the order of the square
//! root of the tolerance: measured 3e-8 m/s of spurious separation per step
//! on the head-on impact with `e = 0`. As Lemke's driver polishes on its
//! support, the solution is therefore polished on the active set it
//! indicates: each contact is classified as open (`λ` negligible: `p = 0`),
//! sticking (`u = 0`), sliding (`β = s μ λ`, `u_N + μ s u_T = 0` with `s`
//! the sign of `β`), or, without friction, closed (`u_N = 0`); the linear
//! system of those equations is solved (LU with partial pivoting, the one
//! of [`crate::lcp`]), and the polished point is kept only if it is
//! consistent: `λ ≥ 0`, `|β| ≤ μ λ` on sticking contacts, `u_N ≥ μ |u_T|`
//! on open ones and friction opposing the sliding, to 1e-9 of the problem's
//! scale (counted in [`ConeSolution::polished`]). A singular but consistent
//! system (two sticking points of facing edges share their tangential
//! column) is solved with a diagonal shift of 1e-12 (the scaled matrix has
//! a unit diagonal) and checked the same way.
//!
//! When every free relative velocity is at rounding level (below 1e-13 of
//! the largest term that makes it), the answer `p = 0` is returned without
//! calling clarabel.
//!
//! The solution is projected back onto `K_μ` (`λ ← max(λ, 0)`, `|β| ≤ μλ`),
//! a change within the solver tolerance whose size is reported
//! ([`ConeSolution::cone_excess`]). A status other than `Solved` or
//! `AlmostSolved` whose last iterate does not polish into a consistent
//! point, or a non-finite solution, is a failure: the caller counts it and
//! falls back (the Moreau–Jean formulation falls back to the
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
    /// Clarabel stopped without a solution (iteration cap, slow progress)
    /// but its last iterate polished into a consistent KKT point; accepted,
    /// counted.
    RescuedByPolish,
    /// Anything else (infeasible, iteration cap or numerical error without a
    /// consistent polish, setup error, non-finite solution): the caller falls
    /// back.
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
    /// impulse scale `max_j |b_j| / G_jj` (removed by the projection).
    pub cone_excess: f64,
    /// Whether the active-set polish replaced the interior point.
    pub polished: bool,
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
            polished: false,
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
            polished: false,
        };
    }
    let friction = p.friction && p.mu > 0.0;
    // Free relative velocities at rounding level: p = 0 (a resting contact
    // without load; an interior point would leave impulses of the order of
    // the square root of its tolerance there).
    if p.b.iter().all(|v| v.abs() <= ROUNDING * p.v_scale) {
        return ConeSolution {
            lambda: vec![0.0; m],
            beta: vec![0.0; m],
            status: ConeStatus::Solved,
            solver_status: "zero free velocity".into(),
            iterations: 0,
            cone_excess: 0.0,
            polished: true,
        };
    }
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
    // Constraints, column by column: (row, value) entries.
    let mut entries: Vec<Vec<(usize, f64)>> = vec![Vec::new(); nv];
    let (mut rows, mut bc, mut cones) = if friction {
        // Rows (2j, 2j+1) = (μ λ_j, β_j) ∈ SOC(2).
        for (c, e) in entries.iter_mut().enumerate() {
            if c < m {
                e.push((2 * c, -p.mu));
            } else {
                e.push((2 * (c - m) + 1, -1.0));
            }
        }
        let cones: Vec<SupportedConeT<f64>> = (0..m)
            .map(|_| SupportedConeT::SecondOrderConeT(2))
            .collect();
        (2 * m, vec![0.0; 2 * m], cones)
    } else {
        for (c, e) in entries.iter_mut().enumerate() {
            e.push((c, -1.0));
        }
        (m, vec![0.0; m], vec![SupportedConeT::NonnegativeConeT(m)])
    };
    // The crushing bounds `λ_j ≤ b_j` (docs/physics.md §10): rows
    // `d_j x_j + s = b_j`, `s ≥ 0`.
    let bounded: Vec<usize> = (0..m)
        .filter(|&j| p.bounds.get(j).is_some_and(|b| b.is_finite()))
        .collect();
    for &j in &bounded {
        entries[j].push((rows, d[j]));
        bc.push(p.bounds[j].max(0.0));
        rows += 1;
    }
    if !bounded.is_empty() {
        cones.push(SupportedConeT::NonnegativeConeT(bounded.len()));
    }
    let mut colptr = Vec::with_capacity(nv + 1);
    let (mut rowval, mut nzval) = (Vec::new(), Vec::new());
    colptr.push(0);
    for e in &entries {
        for &(r, v) in e {
            rowval.push(r);
            nzval.push(v);
        }
        colptr.push(rowval.len());
    }
    let a = CscMatrix::new(rows, nv, colptr, rowval, nzval);
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
    let mut status = match sol.status {
        SolverStatus::Solved => ConeStatus::Solved,
        SolverStatus::AlmostSolved => ConeStatus::AlmostSolved,
        _ => ConeStatus::Failed,
    };
    let name = format!("{:?}", sol.status);
    if sol.x.iter().any(|v| !v.is_finite()) {
        let mut f = ConeSolution::failed(m, name);
        f.iterations = sol.iterations;
        return f;
    }
    // Dense scaled Delassus matrix for the polish.
    let mut gs = vec![0.0; nv * nv];
    for r in 0..nv {
        for c in 0..nv {
            gs[r * nv + c] = d[r] * p.g[r * dim + c] * d[c];
        }
    }
    // The polish knows no bound: a bounded problem keeps clarabel's point.
    let polished = match bounded.is_empty() {
        true => polish(&gs, &q, &sol.x, m, p.mu, friction),
        false => None,
    };
    if status == ConeStatus::Failed {
        // An interior point stopped early (iteration cap, slow progress) is
        // kept only if it polishes into a consistent KKT point.
        if polished.is_none() {
            let mut f = ConeSolution::failed(m, name);
            f.iterations = sol.iterations;
            return f;
        }
        status = ConeStatus::RescuedByPolish;
    }
    let x = polished.as_deref().unwrap_or(&sol.x);
    let mut lambda: Vec<f64> = (0..m).map(|j| d[j] * x[j]).collect();
    let mut beta: Vec<f64> = if friction {
        (0..m).map(|j| d[m + j] * x[m + j]).collect()
    } else {
        vec![0.0; m]
    };
    // Project onto K_μ, measuring how far outside the raw point was.
    let scale = (0..m)
        .map(|j| p.b[j].abs() / p.g[j * dim + j])
        .fold(0.0f64, |s, v| if v.is_finite() { s.max(v) } else { s });
    let mut excess = 0.0f64;
    for j in 0..m {
        if lambda[j] < 0.0 {
            excess = excess.max(-lambda[j]);
            lambda[j] = 0.0;
        }
        if let Some(&b) = p.bounds.get(j).filter(|b| lambda[j] > **b) {
            excess = excess.max(lambda[j] - b);
            lambda[j] = b;
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
        polished: polished.is_some(),
    }
}

/// Free relative velocities below this fraction of their terms' scale are
/// rounding.
const ROUNDING: f64 = 1e-13;

/// Diagonal shift of a singular polish system (its diagonal is of order 1).
const SINGULAR_SHIFT: f64 = 1e-12;

/// The active-set polish of the module doc, on the scaled problem
/// `û = G x + q` (`G` unit-diagonal, `nv × nv` row-major; `x` the interior
/// point: `λ̂_1..λ̂_m`, then `β̂_1..β̂_m` with friction). Returns the polished
/// point if consistent.
fn polish(g: &[f64], q: &[f64], x: &[f64], m: usize, mu: f64, friction: bool) -> Option<Vec<f64>> {
    #[derive(Clone, Copy, PartialEq)]
    enum Class {
        Open,
        Closed,
        Stick,
        Slide(f64),
    }
    let nv = q.len();
    let scale = q.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    if scale == 0.0 {
        // No free relative velocity: p = 0 is the solution.
        return Some(vec![0.0; nv]);
    }
    if !scale.is_finite() {
        return None;
    }
    // λ̂ is of order q̂ (unit diagonal): below 1e-5 of it, a contact is open.
    let zero = 1e-5 * scale;
    let class: Vec<Class> = (0..m)
        .map(|j| {
            if x[j] <= zero {
                Class::Open
            } else if !friction {
                Class::Closed
            } else if x[m + j].abs() < mu * x[j] * (1.0 - 1e-6) {
                Class::Stick
            } else {
                Class::Slide(x[m + j].signum())
            }
        })
        .collect();
    // Unknowns (variable index, and for a sliding λ the β it carries) and
    // equations (a combination of rows of û).
    let mut vars: Vec<(usize, Option<(usize, f64)>)> = Vec::new();
    let mut eqs: Vec<Vec<(usize, f64)>> = Vec::new();
    for (j, c) in class.iter().enumerate() {
        match *c {
            Class::Open => {}
            Class::Closed => {
                vars.push((j, None));
                eqs.push(vec![(j, 1.0)]);
            }
            Class::Stick => {
                vars.push((j, None));
                vars.push((m + j, None));
                eqs.push(vec![(j, 1.0)]);
                eqs.push(vec![(m + j, 1.0)]);
            }
            Class::Slide(s) => {
                vars.push((j, Some((m + j, s * mu))));
                eqs.push(vec![(j, 1.0), (m + j, mu * s)]);
            }
        }
    }
    let k = vars.len();
    let mut xn = vec![0.0; nv];
    if k > 0 {
        let mut a = vec![0.0; k * k];
        let mut rhs = vec![0.0; k];
        for (r, eq) in eqs.iter().enumerate() {
            for &(row, w) in eq {
                rhs[r] -= w * q[row];
                for (c, &(var, carried)) in vars.iter().enumerate() {
                    a[r * k + c] += w * g[row * nv + var];
                    if let Some((bvar, f)) = carried {
                        a[r * k + c] += w * f * g[row * nv + bvar];
                    }
                }
            }
        }
        // Facing edges give sticking contacts whose tangential columns are
        // equal (the split of the friction impulse is indeterminate): the
        // system is then singular but consistent, and a tiny diagonal shift
        // picks one of its solutions (checked below like any other).
        let lu = crate::lcp::polish::Lu::factor(a.clone(), k).or_else(|| {
            let mut shifted = a.clone();
            for i in 0..k {
                shifted[i * k + i] += SINGULAR_SHIFT;
            }
            crate::lcp::polish::Lu::factor(shifted, k)
        })?;
        let mut y = lu.solve(&rhs);
        // One step of iterative refinement.
        let res: Vec<f64> = (0..k)
            .map(|r| rhs[r] - (0..k).map(|c| a[r * k + c] * y[c]).sum::<f64>())
            .collect();
        for (yi, di) in y.iter_mut().zip(lu.solve(&res)) {
            *yi += di;
        }
        for (&(var, carried), &v) in vars.iter().zip(&y) {
            xn[var] = v;
            if let Some((bvar, f)) = carried {
                xn[bvar] = f * v;
            }
        }
    }
    if xn.iter().any(|v| !v.is_finite()) {
        return None;
    }
    // Consistency, to 1e-9 of the scale.
    let tol = 1e-9 * scale;
    let u: Vec<f64> = (0..nv)
        .map(|r| q[r] + (0..nv).map(|c| g[r * nv + c] * xn[c]).sum::<f64>())
        .collect();
    for (j, c) in class.iter().enumerate() {
        let (ut, bt) = if friction {
            (u[m + j], xn[m + j])
        } else {
            (0.0, 0.0)
        };
        let ok = match *c {
            Class::Open => u[j] >= mu * ut.abs() - tol,
            Class::Closed => xn[j] >= -tol,
            Class::Stick => xn[j] >= -tol && bt.abs() <= mu * xn[j] + tol,
            // Friction opposes the sliding: u_T has the sign of −β.
            Class::Slide(s) => xn[j] >= -tol && s * ut <= tol,
        };
        if !ok {
            return None;
        }
    }
    Some(xn)
}
