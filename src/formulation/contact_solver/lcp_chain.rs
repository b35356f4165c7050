//! The LCP chain of the contact solver (docs/physics.md §3.1, §3.3; the
//! module doc of [`super`]): Lemke with its fallbacks, warm-started or from
//! a predicted basis, timed and profiled by size; the frictionless last
//! resort; the record and dump of every solve; the Coulomb check of every
//! accepted impulse.

use super::counters::*;
use super::warm::{support_changes, Use};
use super::{ContactSolver, LastAnswer};
use crate::contact::problem::ContactLcp;
use crate::lcp::predict::{basis_mismatch, solve_predicted, Blocks, Prediction};
use crate::lcp::solve::solve_with_columns;
use crate::lcp::SolveStatus;
use crate::lcp::Strategy;
use crate::lcp::{solve, solve_warm, BasisGuess, LcpDump, LcpSolution};
use crate::record::profile::bucket_of;
use crate::record::ImpulseRecord;
pub use crate::record::COULOMB_SLACK;

impl ContactSolver {
    /// Lemke with its fallbacks on `lcp`, warm-started from `guess` if
    /// given, timed and profiled by size.
    pub(super) fn lemke(&mut self, lcp: &ContactLcp, guess: Option<&BasisGuess>) -> LcpSolution {
        let k = bucket_of(lcp.lcp().n);
        let started = self.timer.begin(k);
        let blocks = match (guess, self.predict_from) {
            // A bounded LCP (crushing) is solved cold: its bound rows are
            // no block of the predictor's, nor of the warm start's history.
            (None, Some(from)) if lcp.lcp().n >= from && !lcp.bounded() => {
                Blocks::new(lcp.lcp().n, lcp.blocks())
            }
            _ => None,
        };
        let (sol, prediction) = match (guess, &blocks) {
            (Some(g), _) => (solve_warm(lcp.lcp(), &self.opts, g), None),
            (None, Some(b)) => solve_predicted(lcp.lcp(), &self.opts, b, &self.predict),
            (None, None) => match lcp.columns() {
                Some(cols) => (solve_with_columns(lcp.lcp(), cols, &self.opts), None),
                None => (solve(lcp.lcp(), &self.opts), None),
            },
        };
        let seconds = self.timer.end(k, started);
        if let Some(p) = &prediction {
            self.count_prediction(lcp, p, &sol);
        }
        if let Some(b) = self.profile.buckets.get_mut(k) {
            b.solves += 1;
            b.pivots += sol.pivots as u64;
            b.unknowns += lcp.lcp().n as u64;
            if guess.is_none() && prediction.is_none() && sol.status.is_solved() {
                b.min_pivots += crate::lcp::min_cold_pivots(crate::lcp::support(&sol.z)) as u64;
                b.bounded_pivots += sol.pivots as u64;
            }
            if let Some(g) = guess {
                b.warm_tried += 1;
                if sol.accepted_by == Some(Strategy::WarmStart) {
                    b.warm_hits += 1;
                }
                if let Some(a) = sol.warm_lemke_attempt() {
                    b.warm_lemke_pivots += a.pivots as u64;
                    if a.accepted {
                        b.warm_lemke_hits += 1;
                    }
                }
                if sol.status.is_solved() {
                    let changes = support_changes(&g.basic, &sol.z);
                    b.warm_support_changes += changes;
                    self.counters.add(&LCP_WARM_SUPPORT_CHANGES, changes);
                }
            }
            match sol.status {
                SolveStatus::Solved => b.first_attempt += 1,
                SolveStatus::SolvedByFallback => b.fallback += 1,
                SolveStatus::Failed => b.failed += 1,
                SolveStatus::Interrupted => {}
            }
            b.seconds += seconds.unwrap_or(0.0);
        }
        sol
    }

    /// The exact finish of an iterative answer (`polish`,
    /// docs/physics.md §3.5): `lcp` solved from `guess`, the iterative
    /// answer's active set and impulses (basis solves from it, then the
    /// cold chain), recorded like every LCP. Returns `z` when an attempt
    /// solved it, `None` (counted) when none did.
    pub fn polish(&mut self, lcp: &ContactLcp, guess: &BasisGuess, t: f64) -> Option<Vec<f64>> {
        self.counters.declare(POLISH_COUNTERS);
        self.counters.add(&POLISH_SOLVES, 1);
        let sol = self.lemke(lcp, Some(guess));
        if sol.status == SolveStatus::Interrupted {
            self.counters.add(&SOLVES_INTERRUPTED, 1);
            return None;
        }
        self.record_solve(lcp, &sol, t);
        if sol.accepted_by == Some(Strategy::WarmStart) {
            self.counters.add(&POLISH_ACTIVE_SET_EXACT, 1);
        }
        if sol.status.is_solved() {
            Some(sol.z)
        } else {
            self.counters.add(&POLISH_FAILED, 1);
            None
        }
    }

    /// Counts a contact solve cut short by a stop request
    /// ([`SOLVES_INTERRUPTED`]; an iterative one, whose solver has no
    /// counters of its own).
    pub fn count_interrupted(&mut self) {
        self.counters.add(&SOLVES_INTERRUPTED, 1);
    }

    /// Counts one solve from a predicted basis `p` with outcome `sol`.
    pub(super) fn count_prediction(&mut self, lcp: &ContactLcp, p: &Prediction, sol: &LcpSolution) {
        let c = &mut self.counters;
        c.add(&LCP_PREDICT_SOLVES, 1);
        c.add(&LCP_PREDICT_SWEEPS, p.sweeps as u64);
        if let Some(a) = sol.warm_lemke_attempt() {
            c.add(&LCP_PREDICT_PIVOTS, a.pivots as u64);
            c.add(
                if a.accepted {
                    &LCP_PREDICT_HITS
                } else {
                    &LCP_PREDICT_MISSES
                },
                1,
            );
        }
        if sol.status.is_solved() {
            let qn = lcp.lcp().q.iter().map(|v| v * v).sum::<f64>().sqrt();
            let tie = self.opts.tolerance * qn;
            let (wrong, _) = basis_mismatch(&p.guess.basic, &sol.z, &sol.w, tie);
            c.add(&LCP_PREDICT_WRONG, wrong as u64);
        }
    }

    /// [`ContactSolver::solve_lcp`] with the warm-start history of `usage`.
    pub(super) fn solve_lcp_for(&mut self, lcp: &ContactLcp, t: f64, usage: Use) -> Vec<f64> {
        let cache = self
            .warm
            .as_mut()
            .filter(|_| !lcp.bounded())
            .map(|c| &mut c[usage as usize]);
        let guess = cache.and_then(|c| {
            c.at(t);
            c.guess(lcp)
        });
        let sol = self.lemke(lcp, guess.as_ref());
        if sol.status == SolveStatus::Interrupted {
            // No record, no fallback: the run ends at its last output
            // before this step (crate::stop); the answer is finite.
            self.counters.add(&SOLVES_INTERRUPTED, 1);
            return vec![0.0; lcp.lcp().n];
        }
        self.record_solve(lcp, &sol, t);
        let warm_solved = matches!(
            sol.accepted_by,
            Some(Strategy::WarmStart | Strategy::WarmLemke)
        );
        if self.warm_check && warm_solved {
            self.check_warm(lcp, &sol, usage);
        }
        self.last = LastAnswer::Lcp {
            residual: sol.residual,
            met: sol.status.is_solved(),
        };
        if sol.status.is_solved() {
            if let Some(c) = self.warm.as_mut().filter(|_| !lcp.bounded()) {
                c[usage as usize].store(lcp, &sol.z);
            }
            return sol.z;
        }
        if lcp.friction {
            self.counters.add(&LCP_LAST_RESORT_FRICTIONLESS, 1);
            let fl = lcp.frictionless();
            let sol2 = self.lemke(&fl, None);
            self.record_solve(&fl, &sol2, t);
            if sol2.status.is_solved() {
                self.last = LastAnswer::Lcp {
                    residual: sol2.residual,
                    met: false,
                };
                let mut z = vec![0.0; lcp.lcp().n];
                z[..lcp.m].copy_from_slice(&sol2.z[..lcp.m]);
                return z;
            }
        }
        self.counters.add(&LCP_UNRESOLVED, 1);
        vec![0.0; lcp.lcp().n]
    }

    pub(super) fn record_solve(&mut self, lcp: &ContactLcp, sol: &LcpSolution, t: f64) {
        self.lcp_counters.record(sol);
        self.counters.add(&LCP_SOLVES, 1);
        self.counters.add(&LCP_UNKNOWNS_TOTAL, lcp.lcp().n as u64);
        self.counters.max(&LCP_SIZE_MAX, lcp.lcp().n as f64);
        if let Some(dir) = &self.dump {
            let path = dir.join(format!("{:06}.json", self.dump_seq));
            self.dump_seq += 1;
            if LcpDump::from_solution(lcp.lcp(), sol, t, lcp.m, lcp.merged_groups())
                .write(&path)
                .is_err()
            {
                self.counters.add(&LCP_DUMP_FAILURES, 1);
            }
        }
        if sol.status.is_solved() && lcp.friction {
            // Rounding allowance per contact: the impulse that the accepted
            // residual (tolerance × ‖q‖, in velocity units) corresponds to.
            let n = lcp.lcp().n;
            let qn = lcp.lcp().q.iter().map(|v| v * v).sum::<f64>().sqrt();
            let slack: Vec<f64> = (0..lcp.m)
                .map(|j| {
                    // Physical Delassus diagonal (the LCP is scaled by g).
                    let d = lcp.lcp().m[j * n + j] * lcp.scale;
                    if d > 0.0 {
                        self.opts.tolerance * qn / d
                    } else {
                        0.0
                    }
                })
                .collect();
            let beta = lcp.tangential(&sol.z);
            self.check_coulomb(t, &lcp.normal(&sol.z), &beta, lcp.mu, &slack);
        }
    }

    /// Coulomb on accepted impulses `λ`, `β` (N·s) with friction coefficient
    /// `mu`: keeps the largest `|β| / (μ λ)` and counts
    /// [`COULOMB_VIOLATIONS`], i.e. `|β| > μ λ (1 + COULOMB_SLACK) + slack`
    /// ([`ImpulseRecord::outside_cone`]).
    /// `slack[j]` (N·s, 0 if missing) is the rounding allowance of contact
    /// `j`: a tangential impulse below it is rounding (e.g. 1e-21 N·s beside
    /// `λ = 0`) and is left out of the ratio. Every impulse goes into the log
    /// ([`ImpulseRecord`], at time `t`, s), whose ratio is the one used here.
    pub fn check_coulomb(&mut self, t: f64, lambda: &[f64], beta: &[f64], mu: f64, slack: &[f64]) {
        for (j, (l, b)) in lambda.iter().zip(beta).enumerate() {
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
                if rec.outside_cone() {
                    self.counters.add(&COULOMB_VIOLATIONS, 1);
                }
            }
        }
    }
}
