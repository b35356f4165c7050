//! Robust LCP driver: a fixed sequence of Lemke attempts, each judged by its
//! residual on the original data.
//!
//! Attempts, in order, stopping at the first accepted one:
//!
//! 0. [`Strategy::Harris`], on problems of at least
//!    [`SolveOptions::harris_from`] unknowns only (none by default): Lemke with
//!    [`PivotRule::Harris`], whose ratio test passes by the tiny blocking
//!    entries on which the lexicographic path of a degenerate contact LCP
//!    loses feasibility. It has no anti-cycling guarantee, which attempt 1
//!    keeps.
//! 1. [`Strategy::Lexicographic`]: Lemke with [`PivotRule::Lexicographic`].
//! 2. [`Strategy::AlternativeRule`]: Lemke with
//!    [`SolveOptions::alternative_rule`] (default
//!    [`PivotRule::MinRatioLargestPivot`], which favours numerically large
//!    pivots where the lexicographic rule may pick small ones) and the
//!    covering vector [`SolveOptions::alternative_covering`] (default
//!    [`Covering::Diagonal`](super::Covering::Diagonal)); skipped if
//!    `alternative_rule` is `None`. For a matrix that is not
//!    copositive-plus, a secondary ray depends on the
//!    covering vector, so a different `d` can succeed where `d = e` fails.
//! 3. [`Strategy::Perturbed`]: Lemke (lexicographic) on `M + εI` for each
//!    `ε = ε_rel · max|M_ij|` with `ε_rel` from
//!    [`SolveOptions::perturbations`] (default `1e-12, 1e-9, 1e-6`). For a
//!    positive semidefinite or copositive `M` this makes the matrix strictly
//!    copositive/P-like and removes secondary rays and degeneracy.
//!
//! Attempts 1 and 3 use [`SolveOptions::covering`] (default all ones).
//! After **every** attempt, whatever Lemke reported, its `z` is projected
//! onto `z >= 0`, its [`residual`](super::residual()) on the original `(M, q)` is computed
//! (compensated `M z + q`) and, if it is not 0 and polishing is on, it is
//! polished, each step kept only if it lowers the residual (except, on the
//! small problems of at most [`SMALL_N`] unknowns, a candidate of a run
//! that reported [`Termination::Solved`] whose residual is already at most
//! [`SolveOptions::unpolished_below`], default `1e-13`, which is kept as it
//! is: there the refinement of a candidate already accepted costs about a
//! third of the solve): when Lemke
//! solved, by up to three steps of iterative refinement of the final basis
//! (`x_B += B⁻¹ (q − B x_B)` with the residual of the **original** M and q,
//! and the tableau's `B⁻¹`: O(n²) a step, valid when `M_αα` is singular, and
//! turning a solution of `M + εI` into one of `M`); then, if the residual
//! is still above the tolerance or Lemke did not solve, by **principal
//! pivoting** from the support `α` of `z` ([`super::pivoting`]): the basis
//! system `M_αα z_α = −q_α` is solved on the original data starting from
//! `z`, and while the basic solution is infeasible its infeasible indices
//! switch sides, for at most [`SolveOptions::polish_solves`] basis solves.
//! The first solve is the classical re-solve on the support; the switches
//! complete a Lemke path that stopped next to a solution. On the contact
//! LCPs that is the common failure: two points of facing edges have nearly
//! equal tangential columns, the path pivots on entries of 1e-9 to 1e-8
//! (exact rational arithmetic on the dumps shows the same pivots, and
//! entries down to 1e-16 further on), rounding amplified by them breaks
//! exact ties, `z0` reaches the rounding level without leaving and the
//! path ends on a secondary ray one exchange away from a solution. The
//! attempt is accepted iff the final residual is `<= tolerance`. A perturbed
//! attempt is thus accepted only on the merit of its residual for the
//! original problem.
//!
//! If no attempt is accepted the status is [`SolveStatus::Failed`] and `z` is
//! the finite candidate with the lowest original residual ("best
//! available"), or all zeros if no attempt produced a finite one (non-finite
//! input). `z` is never NaN. The caller owns the last resort: the contact
//! layer is expected to apply one (e.g. drop friction and re-solve the
//! frictionless LCP, or apply no impulse) and to count it.
//!
//! With finite data and `q >= 0`, `z = 0` is returned before any set-up
//! (residual exactly 0, one accepted attempt of 0 pivots). [`solve_into`]
//! and [`solve_warm_into`] write into a caller's [`LcpSolution`], reusing
//! its buffers: with a reused [`Workspace`] a solve then allocates nothing.

use super::arith::{w_into, ResidualScale, SUPPORT_MAX_N};
use super::lemke::{with_thread_workspace, Scratch, Workspace};
use super::lemke_options::{LemkeOptions, PivotRule, Termination};
use super::scaling::{max_abs, max_abs_finite};
use super::solution::{Attempt, BasisGuess, LcpSolution, SolveStatus, Strategy, WarmStart};
use super::solve_options::{SolveOptions, SMALL_N};
use super::sparse::Columns;
use super::Lcp;

/// Solves `lcp` with the attempt sequence described in the module doc.
///
/// Never panics and never returns a non-finite `z`. If the LCP's fields are
/// inconsistent or `opts.tolerance` is not a finite non-negative number, no
/// attempt is made and the result is [`SolveStatus::Failed`] with `z = 0`
/// (length `lcp.q.len()`). With non-finite data only the first attempt is
/// made (every strategy would see the same data). Uses this thread's
/// [`Workspace`]; see [`solve_with`].
pub fn solve(lcp: &Lcp, opts: &SolveOptions) -> LcpSolution {
    with_thread_workspace(|ws| solve_with(ws, lcp, opts))
}

/// [`solve`] given the compressed columns of `lcp.m` (what
/// [`Columns::scan`] of it builds, e.g. by [`Columns::fill_from_candidates`]
/// from a known pattern): the driver then does not read all of `M` to
/// build them. The same solution as [`solve`].
pub(crate) fn solve_with_columns(lcp: &Lcp, cols: &Columns, opts: &SolveOptions) -> LcpSolution {
    with_thread_workspace(|ws| {
        let mut out = LcpSolution::empty();
        solve_plan(ws, lcp, opts, &mut out, None, Some(cols));
        out
    })
}

/// The attempts of the plan, in order: `(strategy, rule, ε_rel)`; with
/// `warm`, the warm Lemke path first; then, on a problem of `n` unknowns,
/// `n ≥` [`SolveOptions::harris_from`], the Harris attempt.
fn plan(
    opts: &SolveOptions,
    warm: bool,
    n: usize,
) -> impl Iterator<Item = (Strategy, PivotRule, f64)> + '_ {
    warm.then_some((Strategy::WarmLemke, PivotRule::Lexicographic, 0.0))
        .into_iter()
        .chain((n >= opts.harris_from).then_some((Strategy::Harris, PivotRule::Harris, 0.0)))
        .chain(std::iter::once((
            Strategy::Lexicographic,
            PivotRule::Lexicographic,
            0.0,
        )))
        .chain(
            opts.alternative_rule
                .map(|rule| (Strategy::AlternativeRule, rule, 0.0)),
        )
        .chain(
            opts.perturbations
                .iter()
                .filter(|e| e.is_finite() && **e > 0.0)
                .map(|&e| (Strategy::Perturbed, PivotRule::Lexicographic, e)),
        )
}

/// [`solve`] with an explicit work space: once `ws` has grown to the problem
/// size, a solve allocates only its result (`z`, `w`, the attempt list) when
/// the first attempt is accepted. [`solve_into`] reuses those too.
pub fn solve_with(ws: &mut Workspace, lcp: &Lcp, opts: &SolveOptions) -> LcpSolution {
    let mut out = LcpSolution::empty();
    solve_into(ws, lcp, opts, &mut out);
    out
}

/// [`solve_with`] writing into `out`, whose buffers (`z`, `w`, the attempt
/// list) are reused: once `ws` and `out` have grown to the problem size, a
/// solve allocates nothing. Every field of `out` is overwritten; the result
/// is the one [`solve_with`] returns.
///
/// Shortcut: with finite data and `q >= 0`, `z = 0` solves the LCP (then
/// `w = q`, and the residual is exactly 0): it is returned at once,
/// recorded as an accepted lexicographic attempt of 0 pivots, as Lemke's
/// method would report it (it stops before its first pivot).
pub fn solve_into(ws: &mut Workspace, lcp: &Lcp, opts: &SolveOptions, out: &mut LcpSolution) {
    solve_plan(ws, lcp, opts, out, None, None);
}

/// [`solve_into`], with the warm Lemke path from the guessed basis `start`
/// as first attempt when given (the caller checked its length and that the
/// data are finite).
fn solve_plan(
    ws: &mut Workspace,
    lcp: &Lcp,
    opts: &SolveOptions,
    out: &mut LcpSolution,
    start: Option<&[bool]>,
    cols: Option<&Columns>,
) {
    let (m, q) = (&lcp.m[..], &lcp.q[..]);
    let n = q.len();
    out.attempts.clear();
    out.warm = None;
    out.pivots = 0;
    if lcp.check().is_err() || !(opts.tolerance.is_finite() && opts.tolerance >= 0.0) {
        set_vec(&mut out.z, n, |_| 0.0);
        set_vec(&mut out.w, n, |i| q[i]);
        out.residual = f64::INFINITY;
        out.accepted_by = None;
        out.status = SolveStatus::Failed;
        return;
    }
    let mut sc = ws.scratch.take().unwrap_or_default();
    sc.sparse.reset();
    // One pass over the data: the maxima the set-up scales by, finiteness
    // and the sign of q; for a large M, the same pass builds its compressed
    // columns, which the factorised basis and the residual then share.
    // The caller's columns (the assembly, which knows the pattern) spare
    // that pass.
    let (mmax, mfinite) = if n > SUPPORT_MAX_N || n >= opts.revised_from {
        match cols {
            Some(c) => sc.sparse.adopt(c),
            None => sc.sparse.scan(m, n),
        }
    } else {
        max_abs_finite(m)
    };
    let (qmax, qfinite) = max_abs_finite(q);
    let finite = mfinite && qfinite;
    if finite && q.iter().all(|&x| x >= 0.0) {
        ws.scratch = Some(sc);
        set_vec(&mut out.z, n, |_| 0.0);
        set_vec(&mut out.w, n, |i| q[i]);
        out.residual = 0.0;
        out.attempts.push(Attempt {
            strategy: Strategy::Lexicographic,
            rule: PivotRule::Lexicographic,
            epsilon_rel: 0.0,
            epsilon: 0.0,
            termination: Termination::Solved,
            pivots: 0,
            residual: 0.0,
            polished: false,
            basis_solves: 0,
            accepted: true,
            revised: false,
        });
        out.accepted_by = Some(Strategy::Lexicographic);
        out.status = SolveStatus::Solved;
        return;
    }
    let scale = ResidualScale::with_max(q, qmax, qfinite);
    let unpolished_below = if n <= SMALL_N {
        opts.unpolished_below
    } else {
        0.0
    };
    for v in [&mut sc.z, &mut sc.w, &mut sc.best_z, &mut sc.best_w] {
        v.clear();
        v.resize(n, 0.0);
    }
    // max|M_ij|, needed only by a perturbed attempt.
    let mut mscale: Option<f64> = None;
    let attempts = &mut out.attempts;
    let mut pivots = 0usize;
    let mut best_r = f64::INFINITY;
    let mut have_best = false;
    for (strategy, rule, eps_rel) in plan(opts, start.is_some(), n) {
        let covering = if strategy == Strategy::AlternativeRule {
            &opts.alternative_covering
        } else {
            &opts.covering
        };
        let warm = match start {
            Some(s) if strategy == Strategy::WarmLemke => Some(s),
            _ => None,
        };
        let max_pivots = if warm.is_some() {
            let cap = (opts.warm_lemke_pivots * (n as f64 + 1.0)).ceil();
            // A NaN or negative factor gives the smallest cap, 1.
            Some(if cap >= 1.0 { cap as usize } else { 1 })
        } else {
            opts.max_pivots
        };
        let lopts = LemkeOptions {
            rule,
            covering: if warm.is_some() {
                None
            } else {
                covering.vector(m, n)
            },
            pivot_tol: opts.pivot_tol,
            tie_tol: opts.tie_tol,
            lex_tol: opts.lex_tol,
            max_pivots,
            clamp_tol: opts.clamp_tol,
            prefer_z0: true,
            z0_tol: opts.z0_tol,
            revised_from: opts.revised_from,
        };
        let epsilon = if eps_rel > 0.0 {
            let s = *mscale.get_or_insert_with(|| {
                let s = max_abs(m);
                if s > 0.0 && s.is_finite() {
                    s
                } else {
                    1.0
                }
            });
            eps_rel * s
        } else {
            0.0
        };
        let run = if epsilon > 0.0 {
            sc.m_shift.clear();
            sc.m_shift.extend_from_slice(m);
            for i in 0..n {
                sc.m_shift[i * n + i] += epsilon;
            }
            ws.run(&sc.m_shift, q, &lopts)
        } else if let Some(s) = warm {
            ws.run_warm(m, q, &lopts, s)
        } else if finite {
            ws.run_scanned(m, q, &lopts, (mmax, qmax), sc.sparse.columns())
        } else {
            ws.run(m, q, &lopts)
        };
        let termination = if run.tableau {
            ws.read_z(&mut sc.z, run.termination, run.detail, opts.clamp_tol)
                .0
        } else {
            sc.z.iter_mut().for_each(|x| *x = 0.0);
            run.termination
        };
        pivots = pivots.saturating_add(run.pivots);
        // Evaluate on the original data: project, w, residual, polish.
        for x in sc.z.iter_mut() {
            *x = x.max(0.0);
        }
        sc.sparse.w_into(m, q, &sc.z, &mut sc.w, finite);
        let mut resid = scale.residual(&sc.z, &sc.w);
        // A solved path already within `unpolished_below` is kept as it is.
        let settled = run.tableau
            && termination == Termination::Solved
            && resid <= opts.tolerance.min(unpolished_below);
        let mut polished = false;
        let mut basis_solves = 0;
        let interrupted = termination == Termination::Interrupted;
        if opts.polish && resid > 0.0 && finite && !settled && !interrupted {
            let refined = run.tableau && termination == Termination::Solved;
            if refined {
                polished |= refine(ws, &mut sc, (m, q), &scale, &mut resid);
            }
            if (!refined || resid > opts.tolerance) && opts.polish_solves > 0 {
                let pv = &mut sc.pivoting;
                pv.alpha.clear();
                pv.alpha.extend(sc.z.iter().map(|&v| v > 0.0));
                pv.z.clear();
                pv.z.extend_from_slice(&sc.z);
                let out = pv.run(m, q, opts.polish_solves, opts.tolerance, (false, false));
                basis_solves = out.solves;
                if out.residual < resid {
                    sc.z.copy_from_slice(&pv.z);
                    sc.w.copy_from_slice(&pv.w);
                    resid = out.residual;
                    polished = true;
                }
            }
        }
        let accepted = resid <= opts.tolerance;
        attempts.push(Attempt {
            strategy,
            rule,
            epsilon_rel: eps_rel,
            epsilon,
            termination,
            pivots: run.pivots,
            residual: resid,
            polished,
            basis_solves,
            accepted,
            revised: run.tableau && ws.last_run_revised(),
        });
        if !have_best || resid < best_r {
            std::mem::swap(&mut sc.best_z, &mut sc.z);
            std::mem::swap(&mut sc.best_w, &mut sc.w);
            best_r = resid;
            have_best = true;
        }
        if accepted || !finite || interrupted || termination == Termination::InvalidInput {
            break;
        }
    }

    let accepted_by = attempts.iter().find(|a| a.accepted).map(|a| a.strategy);
    // Solved: the warm Lemke path or the first cold attempt was accepted.
    let first_cold = attempts
        .iter()
        .find(|a| a.strategy != Strategy::WarmLemke)
        .map(|a| a.strategy);
    out.status = match accepted_by {
        Some(Strategy::WarmLemke) => SolveStatus::Solved,
        Some(a) if Some(a) == first_cold => SolveStatus::Solved,
        Some(_) => SolveStatus::SolvedByFallback,
        None if attempts
            .last()
            .is_some_and(|a| a.termination == Termination::Interrupted) =>
        {
            SolveStatus::Interrupted
        }
        None => SolveStatus::Failed,
    };
    out.accepted_by = accepted_by;
    out.pivots = pivots;
    if have_best && best_r.is_finite() {
        set_vec(&mut out.z, n, |i| sc.best_z[i]);
        set_vec(&mut out.w, n, |i| sc.best_w[i]);
        out.residual = best_r;
    } else {
        set_vec(&mut out.z, n, |_| 0.0);
        out.w.resize(n, 0.0);
        w_into(m, q, &out.z, &mut out.w, finite);
        out.residual = scale.residual(&out.z, &out.w);
    }
    ws.scratch = Some(sc);
}

/// Sets `v` to `(f(0), …, f(n − 1))`, reusing its allocation.
fn set_vec(v: &mut Vec<f64>, n: usize, f: impl Fn(usize) -> f64) {
    v.clear();
    v.extend((0..n).map(f));
}

/// [`solve`] preceded by a **warm start**: block principal pivoting
/// ([`super::pivoting`]) from the guessed basis, at most
/// [`SolveOptions::warm_solves`] basis solves on the original data. Its
/// candidate is accepted on the same test as every attempt (residual on the
/// original data `<= tolerance`); then no Lemke attempt is made and the
/// status is [`SolveStatus::Solved`] with [`Strategy::WarmStart`].
/// Otherwise, with [`SolveOptions::warm_lemke`], Lemke's path runs from
/// the guessed basis ([`Strategy::WarmLemke`]: the covering column
/// `d = B 1` of the guessed basis `B`, at most
/// [`SolveOptions::warm_lemke_pivots`] pivots per unknown; docs/physics.md
/// §3.3), its candidate judged and polished like every attempt's; then, if
/// it is not accepted, the attempts of [`solve`] follow as if cold (the
/// record of the principal pivoting is kept in [`LcpSolution::warm`]). A
/// guess of the wrong size, a non-finite problem, or `warm_solves = 0`
/// without `warm_lemke`, goes straight to [`solve`] (`warm_solves = 0`
/// with `warm_lemke`: the warm Lemke path alone, then the cold attempts).
///
/// For an LCP with several solutions (friction) the warm start may accept a
/// solution other than the one Lemke would reach; each is a solution to the
/// same tolerance. Uses this thread's [`Workspace`].
pub fn solve_warm(lcp: &Lcp, opts: &SolveOptions, guess: &BasisGuess) -> LcpSolution {
    with_thread_workspace(|ws| solve_warm_with(ws, lcp, opts, guess))
}

/// [`solve_warm`] with an explicit work space.
pub fn solve_warm_with(
    ws: &mut Workspace,
    lcp: &Lcp,
    opts: &SolveOptions,
    guess: &BasisGuess,
) -> LcpSolution {
    let mut out = LcpSolution::empty();
    solve_warm_into(ws, lcp, opts, guess, &mut out);
    out
}

/// [`solve_warm_with`] writing into `out`, whose buffers are reused (see
/// [`solve_into`]).
pub fn solve_warm_into(
    ws: &mut Workspace,
    lcp: &Lcp,
    opts: &SolveOptions,
    guess: &BasisGuess,
    out: &mut LcpSolution,
) {
    let n = lcp.q.len();
    let usable = lcp.check().is_ok()
        && opts.tolerance.is_finite()
        && opts.tolerance >= 0.0
        && (opts.warm_solves > 0 || opts.warm_lemke)
        && guess.basic.len() == n
        && guess.z.len() == n
        && lcp.is_finite();
    if !usable {
        solve_into(ws, lcp, opts, out);
        return;
    }
    let start = opts.warm_lemke.then_some(&guess.basic[..]);
    if opts.warm_solves == 0 {
        solve_plan(ws, lcp, opts, out, start, None);
        return;
    }
    let pv = &mut ws.scratch.get_or_insert_with(Box::default).pivoting;
    pv.alpha.clear();
    pv.alpha.extend_from_slice(&guess.basic);
    pv.z.clear();
    pv.z.extend(guess.z.iter().map(|v| if v.is_finite() { *v } else { 0.0 }));
    // Large problems solve their bases sparse, from the size at which
    // Lemke's attempts use the factorised basis.
    let sparse = n >= opts.revised_from;
    let res = pv.run(
        &lcp.m,
        &lcp.q,
        opts.warm_solves,
        opts.tolerance,
        (true, sparse),
    );
    let warm = WarmStart {
        basis_solves: res.solves,
        residual: res.residual,
        accepted: res.residual <= opts.tolerance,
    };
    if warm.accepted {
        set_vec(&mut out.z, n, |i| pv.z[i]);
        set_vec(&mut out.w, n, |i| pv.w[i]);
        out.residual = res.residual;
        out.pivots = 0;
        out.attempts.clear();
        out.warm = Some(warm);
        out.accepted_by = Some(Strategy::WarmStart);
        out.status = SolveStatus::Solved;
        return;
    }
    solve_plan(ws, lcp, opts, out, start, None);
    out.warm = Some(warm);
}

/// Maximum number of refinement steps of a basic solution.
const REFINE_STEPS: usize = 3;

/// Iterative refinement of the candidate `sc.z` (with `sc.w = M z + q` and
/// residual `*resid`) on the basis left in `ws`; keeps each step that lowers
/// the residual. Returns whether `z` changed.
fn refine(
    ws: &Workspace,
    sc: &mut Scratch,
    (m, q): (&[f64], &[f64]),
    scale: &ResidualScale,
    resid: &mut f64,
) -> bool {
    let mut changed = false;
    ws.basic_values(&mut sc.x);
    sc.z2.clear();
    sc.z2.extend_from_slice(&sc.z);
    sc.w2.resize(q.len(), 0.0);
    for _ in 0..REFINE_STEPS {
        ws.refine_step(&mut sc.x, &sc.w, &mut sc.rho, &mut sc.z2);
        sc.sparse.w_into(m, q, &sc.z2, &mut sc.w2, true);
        let r2 = scale.residual(&sc.z2, &sc.w2);
        if r2.is_nan() || r2 >= *resid {
            break;
        }
        sc.z.copy_from_slice(&sc.z2);
        std::mem::swap(&mut sc.w, &mut sc.w2);
        *resid = r2;
        changed = true;
        if r2 == 0.0 {
            break;
        }
    }
    changed
}
