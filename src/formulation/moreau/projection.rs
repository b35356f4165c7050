//! The position projection after a Moreau–Jean step (`[formulation.moreau]
//! projection = true`, docs/physics.md §5.1 step 5; Acary 2012's direct
//! projection of the positions, velocities kept).
//!
//! **Rule.** The contacts detected at `q_k` give, linearised, the gaps at
//! `q_{k+1}`: `g_j + J_jᵀ (q_{k+1} − q_k)` (`J_j` the contact's normal
//! rows at `q_k`). Each connected group with a predicted gap below
//! `−d` (`d` the `projection_depth`) is projected: the frictionless
//! problem `g_j + J_jᵀ Δq + d + J_jᵀ M⁻¹ J μ ≥ 0 ⟂ μ ≥ 0` (the least
//! `M`-norm displacement `M⁻¹ J μ` that brings every contact of the group
//! to a depth of at most `d`) is solved by Gauss–Seidel at the iterative
//! solver's tolerance, and `q_{k+1} += M⁻¹ J μ`. The velocities are not
//! touched, so the kinetic energy and the ledger are not either. The
//! depth `d > 0` keeps a projected contact active at the next step (its
//! gap within the activation test), so that it rests instead of rattling.
//! A solve stopped at `max_iterations` above its tolerance is applied and
//! counted ([`PROJECTIONS_UNCONVERGED`]).

use super::*;
use crate::iterative::{nsgs, IterativeOptions, Method, SparseContacts};

impl Moreau {
    /// Projects the positions of `sys` (at `q_{k+1}`) from `before` (the
    /// floes' `(G, θ)` at `q_k`) over the contacts `detected` at `q_k`
    /// (module doc), with the depth `depth` (m).
    pub(super) fn project(
        &mut self,
        scn: &Scenario,
        sys: &mut System,
        before: &[(Vec2, f64)],
        depth: f64,
    ) {
        let detected = std::mem::take(&mut self.detected);
        if detected.is_empty() {
            return;
        }
        let n = scn.floes.len();
        // The step's displacement, as the "free velocity" of a unit step.
        let moved: Vec<Gen> = sys
            .bodies
            .iter()
            .zip(before)
            .map(|(b, (g, a))| [b.position.x - g.x, b.position.y - g.y, b.angle - a])
            .collect();
        let centres: Vec<Vec2> = before.iter().map(|(g, _)| *g).collect();
        let offsets: Vec<f64> = detected.iter().map(|c| c.geom.gap + depth).collect();
        let options = self
            .solver
            .iterative
            .as_ref()
            .map_or(IterativeOptions::new(Method::Nsgs), |it| it.options);
        for g in groups(&detected, n) {
            let mut prob = SparseContacts::build(scn, &centres, &detected, &g, &moved, &offsets);
            prob.mu = 0.0;
            // The predicted gaps plus the depth: q_N of the problem.
            let deepest = (0..prob.len())
                .map(|j| prob.free(j)[0])
                .fold(f64::INFINITY, f64::min);
            if deepest >= 0.0 {
                continue;
            }
            self.counters.max(&PROJECTION_DEPTH_MAX, depth - deepest);
            let mut p = vec![[0.0; 2]; prob.len()];
            let (outcome, dq) = nsgs::solve(
                &prob,
                &mut p,
                options.tolerance,
                options.max_iterations,
                options.relaxation,
            );
            self.counters.add(&PROJECTIONS, 1);
            self.counters
                .max(&PROJECTION_RESIDUAL_MAX, outcome.residual);
            if !outcome.converged {
                self.counters.add(&PROJECTIONS_UNCONVERGED, 1);
            }
            if dq.iter().flatten().any(|d| !d.is_finite()) {
                continue;
            }
            for (l, &i) in g.floes.iter().enumerate() {
                let b = &mut sys.bodies[i];
                b.position += Vec2::new(dq[l][0], dq[l][1]);
                b.angle += dq[l][2];
            }
        }
    }
}
