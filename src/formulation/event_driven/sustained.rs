//! Sustained contacts (docs/physics.md §4.3, step 3): constant contact
//! wrenches over a trial step from the velocity–impulse problem, and the
//! stick rule's estimates of when sliding contacts stop.

use super::*;

impl EventDriven {
    /// Constant contact wrenches over a trial step of length `h` for the
    /// closed contacts (sustained contact), from the velocity–impulse LCP;
    /// or where the step must be cut (docs/physics.md §4.3, step 3).
    /// The stick rule's estimates are returned apart
    /// (`EventDriven::stick_times`).
    pub(super) fn sustained_wrenches(
        &mut self,
        scn: &Scenario,
        sys: &System,
        contacts: &[Contact],
        h: f64,
        nominal: f64,
        cx: &mut Context,
    ) -> Result<Sustained, FormulationError> {
        let n = scn.floes.len();
        let t = sys.t;
        let mut out = Sustained {
            wrenches: vec![Wrench::default(); n],
            cut: None,
            flights: Vec::new(),
            stick: None,
            slide_stop: None,
            loads: Vec::new(),
            crushing: (Vec::new(), 0.0),
        };
        if contacts.is_empty() {
            return Ok(out);
        }
        // The separation velocity asked of each contact at the end of the
        // step (m/s): −g/H for a penetration (relaxed Signorini over the
        // nominal step H, not the halved or cut one: a speed −g/h grows
        // without bound as h shrinks, and puts kinetic energy in), the decay
        // of an accumulation, else 0; `None`: open (in a flight within δ).
        let mut target: Vec<Option<f64>> = Vec::with_capacity(contacts.len());
        let mut apex_rule = vec![false; contacts.len()];
        for (k, c) in contacts.iter().enumerate() {
            let pair = pair_of(c);
            if let Some(f) = self.flights.iter().find(|f| f.pair == pair) {
                out.cut = earlier(out.cut, f.until - t, Cut::Return);
                target.push(None);
                continue;
            }
            // A crushing pair's overlap is crushed ice, cut at the next
            // safe point, not a penetration to undo.
            let mut ask = if c.geom.gap < 0.0 && scn.contact.crushing.is_none() {
                -c.geom.gap / nominal.max(h)
            } else {
                0.0
            };
            let u = normal_velocity(scn, &sys.bodies, c);
            if u > APPROACH_TOLERANCE {
                let separation = if isolated(scn, contacts, pair) {
                    self.separation(scn, sys, c, u)
                } else {
                    Separation::Other
                };
                match separation {
                    Separation::Accumulating { remaining } => {
                        // The normal velocity decays linearly to rest at the
                        // accumulation time.
                        self.counters.add(&ACCUMULATING_CONTACTS, 1);
                        // Cut at the accumulation time unless the decay
                        // stretched over the step stays within δ (a lift
                        // u h/2) and adds less than the penetration
                        // tolerance after it (u (h − T)/2).
                        if c.geom.gap + 0.5 * u * h > self.distance
                            || u * (h - remaining) > 2.0 * self.pen_tol
                        {
                            out.cut = earlier(out.cut, remaining, Cut::Accumulation);
                        }
                        ask = ask.max(u * (1.0 - h / remaining).max(0.0));
                    }
                    Separation::FlightWithin { flight } => {
                        let gap = contacts
                            .iter()
                            .filter(|d| pair_of(d) == pair)
                            .map(|d| d.geom.gap)
                            .fold(f64::INFINITY, f64::min);
                        out.flights.push(Flight {
                            pair,
                            until: t + flight,
                            gap,
                        });
                        out.cut = earlier(out.cut, flight, Cut::Return);
                        target.push(None);
                        continue;
                    }
                    Separation::Other => apex_rule[k] = true,
                }
            }
            target.push(Some(ask));
        }
        // A flight makes its whole pair open.
        for (k, c) in contacts.iter().enumerate() {
            if out.flights.iter().any(|f| f.pair == pair_of(c)) {
                target[k] = None;
            }
        }
        let kept: Vec<usize> = (0..contacts.len())
            .filter(|&k| target[k].is_some())
            .collect();
        let closed: Vec<Contact> = kept.iter().map(|&k| contacts[k]).collect();
        let gs = groups(&closed, n);
        // Free velocities after h of the floes in contact.
        let mut w_free: Vec<Gen> = vec![[0.0; 3]; n];
        let integ = &mut self.integ;
        cx.clock
            .time(Stage::Integration, || -> Result<(), FormulationError> {
                for g in &gs {
                    for &i in &g.floes {
                        let mut b = sys.bodies[i];
                        let mut scratch = Ledger::default();
                        integ.advance(scn, i, &mut b, &mut scratch, t, t + h)?;
                        w_free[i] = [b.velocity.x, b.velocity.y, b.angular_velocity];
                    }
                }
                Ok(())
            })?;
        // The apex rule: a closed contact that separates now but whose free
        // flight returns within h and rises above the contact distance: cut
        // the step at the apex (estimated with a constant normal
        // acceleration) so that the return is located as an event; a
        // micro-bounce that stays within δ (slower than the impact
        // threshold) is absorbed by the sustained LCP (counted).
        let free_bodies: Vec<BodyState> = sys
            .bodies
            .iter()
            .zip(&w_free)
            .map(|(b, w)| BodyState {
                velocity: Vec2::new(w[0], w[1]),
                angular_velocity: w[2],
                ..*b
            })
            .collect();
        for (&k, c) in kept.iter().zip(&closed) {
            if !apex_rule[k] {
                continue;
            }
            let u0 = normal_velocity(scn, &sys.bodies, c);
            let u1 = normal_velocity(scn, &free_bodies, c);
            if u1 < 0.0 {
                let apex = h * u0 / (u0 - u1);
                if c.geom.gap + 0.5 * u0 * apex > self.distance {
                    out.cut = earlier(out.cut, apex, Cut::Apex);
                } else {
                    self.counters.add(&MICRO_BOUNCES_ABSORBED, 1);
                }
            }
        }
        if out.cut.is_some_and(|(s, _)| s < h) {
            return Ok(out);
        }
        let centres = sys.centres();
        let offsets: Vec<f64> = kept.iter().map(|&k| -target[k].unwrap_or(0.0)).collect();
        if closed.iter().any(|c| c.geom.gap < 0.0) {
            self.counters.add(&POSITION_CORRECTIONS, 1);
        }
        let mu = scn.contact.friction;
        // Per closed contact: λ, β, tangential compliance; and the floes'
        // velocities at the end of the step.
        let mut lambda = vec![0.0; closed.len()];
        let mut beta = vec![0.0; closed.len()];
        let mut g_t = vec![0.0; closed.len()];
        let mut end_bodies = free_bodies;
        // The crushing bounds of the step's impulses (docs/physics.md §10).
        let bounds = crate::contact::crush::normal_bounds(scn, &closed, h);
        let solve_start = cx.clock.start(Stage::Solve);
        for g in &gs {
            let data = GroupData {
                scn,
                centres: &centres,
                contacts: &closed,
                group: g,
                w_free: &w_free,
                offsets: &offsets,
                bounds: &bounds,
            };
            let ans = self.solver.solve(&data, t, h);
            let (l, b) = (&ans.normal, &ans.tangential);
            for (j, &k) in g.contacts.iter().enumerate() {
                lambda[k] = l[j];
                beta[k] = b[j];
                g_t[k] = ans.compliance[j];
            }
            // The loads of the stress criterion, and of a crushing phase's
            // percussions (docs/physics.md §10.2).
            let crushing_loads = !bounds.is_empty() && cx.topology.reads().percussions;
            if cx.topology.reads().sustained || crushing_loads {
                // The group's impulses over h: loads of the stress criterion
                // (docs/physics.md §9.3, §9.5).
                let group: Vec<&Contact> = g.contacts.iter().map(|&k| &closed[k]).collect();
                out.loads.extend(loads_of(scn, &group, l, b));
            }
            let (p, dv) = (&ans.impulses, &ans.dv);
            for (l, &i) in g.floes.iter().enumerate() {
                out.wrenches[i] = Wrench {
                    force: Vec2::new(p[l][0], p[l][1]) / h,
                    torque: p[l][2] / h,
                };
                end_bodies[i].velocity += Vec2::new(dv[l][0], dv[l][1]);
                end_bodies[i].angular_velocity += dv[l][2];
            }
            self.counters.add(&SUSTAINED_SOLVES, 1);
        }
        cx.clock.stop(Stage::Solve, solve_start);
        if !bounds.is_empty() {
            out.crushing = crushing_work(scn, sys, &closed, (&lambda, &bounds), &end_bodies);
            // A crushing phase that ends within the step: its pair stopped
            // approaching with an impulse below the bound, which the bounded
            // force delivers in the fraction λ/b of the step; the step is
            // cut there, so that the phase ends at its time.
            for (k, c) in closed.iter().enumerate() {
                let (l, b) = (lambda[k], bounds[k]);
                if b.is_finite()
                    && l > 0.0
                    && l < b * (1.0 - crate::contact::crush::AT_BOUND)
                    && normal_velocity(scn, &sys.bodies, c) < -APPROACH_TOLERANCE
                {
                    out.cut = earlier(out.cut, h * l / b, Cut::CrushStop);
                }
            }
        }
        if mu > 0.0 {
            (out.stick, out.slide_stop) =
                self.stick_times(scn, sys, &closed, &lambda, &beta, &g_t, &end_bodies, h);
        }
        Ok(out)
    }

    /// The stick rule of a trial step of length `h` (docs/physics.md §4.3,
    /// step 3), for the isolated pairs ([`isolated`]) of `closed` that slide
    /// at the start (slip `u₀`) by more than the contact distance over the
    /// step (in a pile the neighbours share the load, so the pair's own
    /// compliance does not give its stop, and each cut re-solves the whole
    /// group: on `narrow_channel` 192 of 275 steps were cut so; a shorter slip
    /// is below the scheme's resolution and not worth a cut: the constant
    /// friction force smears it over the step; with the penetration
    /// tolerance instead, `narrow_channel` took three times as many stick
    /// cuts for the same result). Returns:
    ///
    /// - the earliest stop of a pair that has stuck by the end (its summed
    ///   friction impulse `B`, along the slip, inside the cone `μΛ` of its
    ///   summed normal impulse): had it slid throughout, its slip at the end
    ///   would be `−G_T (μΛ + B)` (`G_T` the mean tangential compliance of
    ///   its points), so its slip, linear in time under constant forces,
    ///   stopped at `s* = h u₀ / (u₀ + G_T (μΛ + B))`;
    /// - the earliest stop of a pair still sliding at the end with a
    ///   smaller slip `u₁` (same direction), extrapolated linearly:
    ///   `h u₀ / (u₀ − u₁)` (after a cut at `s*`, this corrects `G_T`, which
    ///   overestimates the compliance of a face whose two points share the
    ///   load so that the floe does not turn).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn stick_times(
        &self,
        scn: &Scenario,
        sys: &System,
        closed: &[Contact],
        lambda: &[f64],
        beta: &[f64],
        g_t: &[f64],
        end_bodies: &[BodyState],
        h: f64,
    ) -> (Option<f64>, Option<f64>) {
        let mu = scn.contact.friction;
        // Per pair: slip at the start and at the end (vectors), Λ, B
        // (vector), Σ G_T, points.
        struct PairSlip {
            pair: (usize, usize),
            start: Vec2,
            end: Vec2,
            lambda: f64,
            beta: Vec2,
            compliance: f64,
            points: f64,
        }
        let mut pairs: Vec<PairSlip> = Vec::new();
        for (k, c) in closed.iter().enumerate() {
            let b = c.geom.tangent * beta[k];
            match pairs.iter_mut().find(|p| p.pair == pair_of(c)) {
                Some(p) => {
                    p.lambda += lambda[k];
                    p.beta += b;
                    p.compliance += g_t[k];
                    p.points += 1.0;
                }
                None => pairs.push(PairSlip {
                    pair: pair_of(c),
                    start: c.geom.tangent * tangential_velocity(scn, &sys.bodies, c),
                    end: c.geom.tangent * tangential_velocity(scn, end_bodies, c),
                    lambda: lambda[k],
                    beta: b,
                    compliance: g_t[k],
                    points: 1.0,
                }),
            }
        }
        let (mut stuck, mut sliding) = (None::<f64>, None::<f64>);
        let min = |a: Option<f64>, b: f64| Some(a.map_or(b, |a: f64| a.min(b)));
        for p in pairs {
            let u0 = p.start.norm();
            // Only an isolated pair: in a pile the neighbours share the
            // load and the pair's own compliance does not give its stop,
            // and every cut re-solves the whole group.
            if !(u0 * h > self.distance && p.lambda > 0.0 && isolated(scn, closed, p.pair)) {
                continue;
            }
            let dir = p.start / u0;
            if p.beta.norm() < (1.0 - STICK_SLACK) * mu * p.lambda {
                let reversal = (p.compliance / p.points) * (mu * p.lambda + p.beta.dot(&dir));
                if reversal > 0.0 {
                    stuck = min(stuck, h * u0 / (u0 + reversal));
                }
            } else {
                let u1 = p.end.dot(&dir);
                if u1 > 0.0 && u1 < u0 {
                    sliding = min(sliding, h * u0 / (u0 - u1));
                }
            }
        }
        (stuck, sliding)
    }
}

/// The contacts of `closed` that crush over the step
/// ([`crate::contact::crush::crushing`]; `lambda`, `bounds`: N·s per
/// contact), as body pairs, and
/// the work (J) of their forces over the step: `−λ_j ū_N,j`, `ū_N` the
/// mean of the relative normal velocities at the step's start (`sys`) and
/// end (`end`), exact for the constant wrenches of the step when the
/// environment forces do not change the velocities (their change is
/// second order in the step); it is a share of the contact work the
/// integration books, moved from `dissipated` to `crushing`
/// (docs/physics.md §10.2).
fn crushing_work(
    scn: &Scenario,
    sys: &System,
    closed: &[Contact],
    (lambda, bounds): (&[f64], &[f64]),
    end: &[BodyState],
) -> (Vec<(usize, usize)>, f64) {
    let mut pairs = Vec::new();
    let mut work = 0.0;
    for (k, c) in closed.iter().enumerate() {
        let after = normal_velocity(scn, end, c);
        if !crate::contact::crush::crushing(bounds[k], after) {
            continue;
        }
        let u = 0.5 * (normal_velocity(scn, &sys.bodies, c) + after);
        work -= lambda[k] * u;
        if !pairs.contains(&(c.a, c.b)) {
            pairs.push((c.a, c.b));
        }
    }
    (pairs, work)
}
