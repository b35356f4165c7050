//! One rapier step (docs/physics.md §8): the environment forces held over
//! the step, the engine's pipeline, the energy balance of the contacts and
//! the report of the step's impulses to the topology stage.

use super::*;

impl RapierReference {
    /// One rapier step of length `h` from `sys` at `sys.t`.
    pub(super) fn step(
        &mut self,
        scn: &Scenario,
        sys: &mut System,
        h: f64,
        cx: &mut Context,
    ) -> Result<(), FormulationError> {
        let t = sys.t;
        // Environment forces from the start state, by the shared force law.
        cx.clock.time(Stage::Integration, || {
            for (i, b) in sys.bodies.iter().enumerate() {
                let f = self.model.forces(&scn.environment, i, t, b);
                self.forces[i] = f;
                if let Some(rb) = self.bodies.get_mut(self.handles[i]) {
                    convert::set_wrench(rb, &f.force(), f.torque());
                }
            }
        });
        self.counters
            .add(&FORCE_EVALUATIONS, sys.bodies.len() as u64);

        self.params.dt = h;
        // rapier's own stage timers run only in the steps the clock times
        // (they read the clock a dozen times per step).
        let timed = cx.clock.start_split();
        if timed.is_timed() {
            self.pipeline.counters.enable();
        }
        self.pipeline.step(
            rapier2d_f64::math::Vector::ZERO,
            &self.params,
            &mut self.islands,
            &mut self.broad_phase,
            &mut self.narrow_phase,
            &mut self.bodies,
            &mut self.colliders,
            &mut self.impulse_joints,
            &mut self.multibody_joints,
            &mut self.soft_bodies,
            &mut self.ccd,
            &(),
            &(),
        );
        if timed.is_timed() {
            let split = self.stage_split();
            cx.clock.stop_split(timed, split);
            self.pipeline.counters.disable();
        } else {
            cx.clock.stop_split(timed, [0.0; 3]);
        }
        self.counters.add(&STEPS, 1);

        // Read back; work of each force along the actual displacement.
        let n = self.settings.iterations as f64;
        for (i, b) in sys.bodies.iter_mut().enumerate() {
            let Some(rb) = self.bodies.get(self.handles[i]) else {
                continue;
            };
            let (g, a, v, w) = convert::read_body(rb);
            let mut da = a - self.rapier_angle[i];
            if da > std::f64::consts::PI {
                da -= 2.0 * std::f64::consts::PI;
            } else if da < -std::f64::consts::PI {
                da += 2.0 * std::f64::consts::PI;
            }
            self.rapier_angle[i] = a;
            let next = BodyState {
                position: g,
                angle: b.angle + da,
                velocity: v,
                angular_velocity: w,
            };
            if !next.is_finite() {
                return Err(FormulationError::Other(format!(
                    "rapier: floe {i}: non-finite state at t = {} s",
                    t + h
                )));
            }
            let dg = g - b.position;
            let f = &self.forces[i];
            let (wa, ww, wc) = f.works(&dg, da);
            sys.ledger.work_air += wa;
            sys.ledger.work_water += ww;
            sys.ledger.work_coriolis += wc;
            let floe = &scn.floes[i];
            let kinetic = |b: &BodyState| {
                0.5 * floe.mass * b.velocity.norm_squared()
                    + 0.5 * floe.inertia * b.angular_velocity * b.angular_velocity
            };
            let defect =
                h * h * (f.force().norm_squared() / floe.mass + f.torque().powi(2) / floe.inertia)
                    / (2.0 * n);
            self.balance[i] = (kinetic(b) + wa + ww + wc, kinetic(&next), defect);
            *b = next;
        }
        sys.t = t + h;
        self.synced.clone_from(&sys.bodies);

        // Contacts of this step: which floes they touched, pairs, penetration.
        self.scan_contacts(t);
        let mut d = 0.0;
        let (mut before, mut after, mut floes) = (0.0, 0.0, 0usize);
        for (&(e0w, e1, defect), &touched) in self.balance.iter().zip(&self.touched) {
            if touched {
                d += e0w - e1;
                before += e0w;
                after += e1;
                floes += 1;
            } else {
                self.integration_defect += defect;
            }
        }
        sys.ledger.dissipated += d;
        if cx.topology.reads().percussions {
            // The step's impulses, delivered over the step [t, t + h]
            // (docs/physics.md §9.3); the floes break between steps.
            let loads = self.loads(scn);
            cx.topology.percussion(scn, sys, &loads, t, t + h, d);
        }
        if floes > 0 && self.step_points > 0 {
            self.log.push_event(ContactEvent {
                t,
                contacts: self.step_points,
                energy_before: before,
                energy_after: after,
            });
        }
        if d < 0.0 {
            self.energy_gained -= d;
        }
        Ok(())
    }

    /// Splits the CPU time of one rapier step between the stages, in the
    /// proportions of rapier's own (wall-clock) stage timers.
    /// The fractions of the last step spent in detection, solve and the
    /// rest (integration), from rapier's own stage timers.
    pub(super) fn stage_split(&self) -> [f64; 3] {
        let c = &self.pipeline.counters;
        let total = c.step_time.time().as_secs_f64();
        let detection = c.stages.collision_detection_time.time().as_secs_f64();
        let solve = c.stages.solver_time.time().as_secs_f64()
            + c.stages.island_construction_time.time().as_secs_f64()
            + c.stages
                .island_constraints_collection_time
                .time()
                .as_secs_f64();
        if total > 0.0 && detection + solve <= total {
            [detection, solve, total - detection - solve]
        } else {
            [0.0, 1.0, 0.0]
        }
    }

    /// After a step: the floes that received a contact impulse, the pairs
    /// with contacts seen by the solver, and the deepest penetration (at the
    /// start of the step, where rapier's narrow phase computed the manifolds).
    pub(super) fn scan_contacts(&mut self, t: f64) {
        self.touched.iter_mut().for_each(|t| *t = false);
        let mut pairs = 0u64;
        let mut deepest = 0.0f64;
        self.step_points = 0;
        for pair in self.narrow_phase.contact_pairs() {
            for m in pair.manifolds() {
                for p in &m.points {
                    deepest = deepest.max(-p.dist);
                    // Impulses of the step (summed over its substeps).
                    if p.data.impulse != 0.0 || p.data.tangent_impulse[0] != 0.0 {
                        self.step_points += 1;
                        self.log.push_impulse(ImpulseRecord {
                            t,
                            normal: p.data.impulse,
                            tangent: p.data.tangent_impulse[0],
                            mu: m.data.friction,
                            slack: 0.0,
                        });
                    }
                }
            }
            if !pair.has_any_active_contact() {
                continue;
            }
            pairs += 1;
            for c in [pair.collider1, pair.collider2] {
                let floe = self.colliders.get(c).map_or(OBSTACLE, |c| c.user_data);
                if let Some(t) = usize::try_from(floe)
                    .ok()
                    .and_then(|i| self.touched.get_mut(i))
                {
                    *t = true;
                }
            }
        }
        self.counters.add(&CONTACT_PAIR_STEPS, pairs);
        self.max_pairs = self.max_pairs.max(pairs);
        self.max_penetration = self.max_penetration.max(deepest);
    }
}
