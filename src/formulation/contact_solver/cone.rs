//! The cone program of the contact solver (docs/physics.md §3.4): the
//! Anitescu–Tasora relaxation by clarabel, counted, with the LCP chain as
//! fallback (the module doc of [`super`]).

use super::counters::*;
use super::warm::Use;
use super::{ContactSolver, LastAnswer};
use crate::contact::cone::{solve_cone, ConeStatus};
use crate::contact::problem::ContactLcp;

impl ContactSolver {
    /// One problem by the cone program, with the LCP chain as fallback.
    pub(super) fn solve_cone(&mut self, lcp: &ContactLcp, t: f64) -> Vec<f64> {
        let p = lcp.normal_tangent();
        let sol = solve_cone(&p, &self.cone_opts);
        let c = &mut self.counters;
        c.add(&CONE_SOLVES, 1);
        c.add(&CONE_ITERATIONS, u64::from(sol.iterations));
        c.max(&CONE_MAX_ITERATIONS, f64::from(sol.iterations));
        c.add(&CONE_UNKNOWNS_TOTAL, p.dim() as u64);
        match sol.status {
            ConeStatus::Solved => {}
            ConeStatus::AlmostSolved => c.add(&CONE_ALMOST_SOLVED, 1),
            ConeStatus::RescuedByPolish => c.add(&CONE_RESCUED_BY_POLISH, 1),
            ConeStatus::Failed => {
                c.add(&CONE_FAILED, 1);
                c.add(&CONE_FALLBACK_LCP, 1);
                let z = self.solve_lcp_for(lcp, t, Use::Sustained);
                if let LastAnswer::Lcp { met, .. } = &mut self.last {
                    // The cone program missed; the fallback's LCP residual stands.
                    *met = false;
                }
                return z;
            }
        }
        self.last = LastAnswer::Cone {
            met: sol.status == ConeStatus::Solved,
        };
        c.max(&CONE_MAX_PROJECTION_REL, sol.cone_excess);
        if sol.polished {
            c.add(&CONE_POLISHED, 1);
        }
        let mut flat = sol.lambda.clone();
        if p.friction {
            flat.extend_from_slice(&sol.beta);
            self.check_coulomb(t, &sol.lambda, &sol.beta, p.mu, &[]);
        }
        // The artefact: normal speed (with the Newton offset) of the
        // contacts that push, u_N⁺ + c = μ |u_T⁺| while sliding.
        let u = p.velocities(&flat);
        let lam_max = sol.lambda.iter().fold(0.0f64, |s, l| s.max(*l));
        for (l, uj) in sol.lambda.iter().zip(&u) {
            if *l > 1e-9 * lam_max {
                self.counters.max(&CONE_MAX_PUSHING_NORMAL_SPEED, *uj);
            }
        }
        lcp.z_from_impulses(&sol.lambda, &sol.beta)
    }
}
