//! The contact-problem solver shared by the formulations that solve the
//! velocity–impulse LCP of physics.md 3.1 (event-driven, Moreau–Jean): one
//! place for the solve with fallbacks, the last resort, the counters, the
//! LCP dumps and the Coulomb check.
//!
//! Every LCP goes through [`crate::lcp::solve()`] (lexicographic Lemke, another
//! pivot rule with another covering vector, a perturbed matrix), whose
//! residual is recomputed on the original data. When all attempts fail, the
//! documented last resort is the frictionless LCP of the same contacts
//! (counted as `lcp_last_resort_frictionless`); if that fails too, no impulse
//! is applied (counted as `lcp_unresolved`). The returned `z` is never NaN.
//!
//! Counters written into the formulation's [`Counters`]: `lcp_solves`,
//! `lcp_unknowns_total`, `lcp_size_max`, `lcp_dump_failures`,
//! `coulomb_violations` (an accepted impulse with `|β| > μ λ (1 + 1e-9)`
//! beyond the rounding allowance of the accepted residual, see
//! [`ContactSolver::check_coulomb`]),
//! and by [`ContactSolver::report`]: the Lemke pivots and fallbacks
//! (`lemke_pivots`, `lemke_max_pivots`, `lcp_solved_first_attempt`,
//! `lcp_solved_by_fallback`, `lcp_fallback_alternative_rule`,
//! `lcp_fallback_perturbed`, `lcp_failed`, `lcp_max_accepted_residual`) and
//! `max_coulomb_ratio` (largest `|β| / (μ λ)` over accepted impulses).

use crate::contact::problem::ContactLcp;
use crate::lcp::{solve, LcpDump, LcpSolution, SolveCounters, SolveOptions};
use crate::run::{ContactLog, Counters, ImpulseRecord};
use std::path::PathBuf;

/// Relative slack of the Coulomb check `|β| ≤ μ λ (1 + 1e-9)`: an accepted
/// LCP solution has residual ≤ 1e-10 relative to `‖q‖`.
pub const COULOMB_SLACK: f64 = 1e-9;

/// Lemke with fallbacks, last resort, dumps and the Coulomb check.
#[derive(Debug, Clone)]
pub struct ContactSolver {
    opts: SolveOptions,
    dump: Option<PathBuf>,
    dump_seq: u64,
    lcp_counters: SolveCounters,
    max_coulomb_ratio: f64,
    log: ContactLog,
}

impl ContactSolver {
    /// A solver with the default [`SolveOptions`]; with `dump`, every LCP
    /// solved is written there as `<seq>.json` (`000000.json`, …).
    pub fn new(dump: Option<PathBuf>) -> ContactSolver {
        ContactSolver {
            opts: SolveOptions::default(),
            dump,
            dump_seq: 0,
            lcp_counters: SolveCounters::default(),
            max_coulomb_ratio: 0.0,
            log: ContactLog::recording(),
        }
    }

    /// Largest `|β| / (μ λ)` over every accepted contact impulse so far (0
    /// without friction).
    pub fn max_coulomb_ratio(&self) -> f64 {
        self.max_coulomb_ratio
    }

    /// The log of accepted frictional impulses (with the contact events the
    /// formulation adds to it).
    pub fn log_mut(&mut self) -> &mut ContactLog {
        &mut self.log
    }

    /// Hands over the log and starts a new one.
    pub fn take_log(&mut self) -> ContactLog {
        std::mem::replace(&mut self.log, ContactLog::recording())
    }

    /// Solves one contact LCP with the fallbacks and the last resort; returns
    /// `z` (never NaN, length `lcp.lcp.n`) and records counters and dumps. `t`
    /// is the simulation time written into the dump, s.
    pub fn solve(&mut self, lcp: &ContactLcp, t: f64, counters: &mut Counters) -> Vec<f64> {
        let sol = solve(&lcp.lcp, &self.opts);
        self.record_solve(lcp, &sol, t, counters);
        if sol.status.is_solved() {
            return sol.z;
        }
        if lcp.friction {
            counters.add("lcp_last_resort_frictionless", 1);
            let fl = lcp.frictionless();
            let sol2 = solve(&fl.lcp, &self.opts);
            self.record_solve(&fl, &sol2, t, counters);
            if sol2.status.is_solved() {
                let mut z = vec![0.0; lcp.lcp.n];
                z[..lcp.m].copy_from_slice(&sol2.z);
                return z;
            }
        }
        counters.add("lcp_unresolved", 1);
        vec![0.0; lcp.lcp.n]
    }

    fn record_solve(
        &mut self,
        lcp: &ContactLcp,
        sol: &LcpSolution,
        t: f64,
        counters: &mut Counters,
    ) {
        self.lcp_counters.record(sol);
        counters.add("lcp_solves", 1);
        counters.add("lcp_unknowns_total", lcp.lcp.n as u64);
        counters.max_value("lcp_size_max", lcp.lcp.n as f64);
        if let Some(dir) = &self.dump {
            let path = dir.join(format!("{:06}.json", self.dump_seq));
            self.dump_seq += 1;
            if LcpDump::from_solution(&lcp.lcp, sol, t, lcp.m)
                .write(&path)
                .is_err()
            {
                counters.add("lcp_dump_failures", 1);
            }
        }
        if sol.status.is_solved() && lcp.friction {
            // Rounding allowance per contact: the impulse that the accepted
            // residual (tolerance × ‖q‖, in velocity units) corresponds to.
            let n = lcp.lcp.n;
            let qn = lcp.lcp.q.iter().map(|v| v * v).sum::<f64>().sqrt();
            let slack: Vec<f64> = (0..lcp.m)
                .map(|j| {
                    // Physical Delassus diagonal (the LCP is scaled by g).
                    let d = lcp.lcp.m[j * n + j] * lcp.scale;
                    if d > 0.0 {
                        self.opts.tolerance * qn / d
                    } else {
                        0.0
                    }
                })
                .collect();
            let beta = lcp.tangential(&sol.z);
            self.check_coulomb(t, &lcp.normal(&sol.z), &beta, lcp.mu, &slack, counters);
        }
    }

    /// Coulomb on accepted impulses `λ`, `β` (N·s) with friction coefficient
    /// `mu`: keeps the largest `|β| / (μ λ)` and counts `coulomb_violations`,
    /// i.e. `|β| > μ λ (1 + COULOMB_SLACK) + slack`. `slack[j]` (N·s, 0 if
    /// missing) is the rounding allowance of contact `j`: a tangential
    /// impulse below it is rounding (e.g. 1e-21 N·s beside `λ = 0`) and is
    /// left out of the ratio. Every impulse goes into the log
    /// ([`ImpulseRecord`], at time `t`, s), whose ratio is the one used here.
    pub fn check_coulomb(
        &mut self,
        t: f64,
        lambda: &[f64],
        beta: &[f64],
        mu: f64,
        slack: &[f64],
        counters: &mut Counters,
    ) {
        for (j, (l, b)) in lambda.iter().zip(beta).enumerate() {
            let bound = mu * l;
            let eps = slack.get(j).copied().unwrap_or(0.0);
            let rec = ImpulseRecord {
                t,
                normal: *l,
                tangent: *b,
                mu,
                slack: eps,
            };
            self.log.push_impulse(rec);
            if b.abs() > eps {
                self.max_coulomb_ratio = self.max_coulomb_ratio.max(rec.coulomb_ratio());
                if b.abs() > bound * (1.0 + COULOMB_SLACK) + eps {
                    counters.add("coulomb_violations", 1);
                }
            }
        }
    }

    /// Adds the Lemke counters and `max_coulomb_ratio` to `c`.
    pub fn report(&self, c: &mut Counters) {
        let l = &self.lcp_counters;
        c.add("lemke_pivots", l.total_pivots);
        c.add("lemke_max_pivots", l.max_pivots);
        c.add("lcp_solved_first_attempt", l.solved);
        c.add("lcp_solved_by_fallback", l.solved_by_fallback);
        c.add("lcp_fallback_alternative_rule", l.by_alternative_rule);
        c.add("lcp_fallback_perturbed", l.by_perturbed);
        c.add("lcp_failed", l.failed);
        c.set_value("lcp_max_accepted_residual", l.max_accepted_residual);
        c.set_value("max_coulomb_ratio", self.max_coulomb_ratio);
    }
}

/// Normal relative velocity of a contact (positive: separating), m/s.
pub fn normal_velocity(
    scn: &crate::model::Scenario,
    bodies: &[crate::state::BodyState],
    c: &crate::contact::Contact,
) -> f64 {
    let n = scn.floes.len();
    let vel = |i: usize| -> crate::geometry::Vec2 {
        if i >= n {
            return crate::geometry::Vec2::zeros();
        }
        let b = &bodies[i];
        b.velocity + crate::geometry::perp(&(c.geom.point - b.position)) * b.angular_velocity
    };
    (vel(c.b) - vel(c.a)).dot(&c.geom.normal)
}
