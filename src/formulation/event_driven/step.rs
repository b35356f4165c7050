//! One step of the scheme (docs/physics.md §4.3): the safe point of the
//! topology stage, impacts, the trial step with sustained contacts, cut
//! at the first located event.

use super::*;

impl EventDriven {
    /// One step of the scheme's own grid from `sys` (impacts at its start,
    /// then the smooth step with sustained contacts, cut at the first event),
    /// never past `end` (s, the end of the run); keeps its record in
    /// [`EventDriven::last`] for the states reported inside it.
    pub(super) fn step(
        &mut self,
        scn: &mut Scenario,
        sys: &mut System,
        end: f64,
        cx: &mut Context,
    ) -> Result<(), FormulationError> {
        // A safe point: fractures decided by the stress criterion at the
        // end of the last step; this instant starts again with the new floe
        // set.
        if let Some(old) = cx.change_floes(scn, sys) {
            return self.floes_changed(scn, sys, &old);
        }
        self.step_loads.clear();
        let n = scn.floes.len();
        let t = sys.t;
        // Flights that have returned are over.
        self.flights
            .retain(|f| f.until - t > 1e-12 * f.until.abs().max(1.0));
        // 1. Closed contacts at this instant.
        let contacts = cx
            .clock
            .time(Stage::Detection, || self.detect(scn, &sys.bodies));
        // A flight whose pair is no longer closed, or is back at its
        // starting gap, is over.
        self.flights.retain(|f| {
            let gap = contacts
                .iter()
                .filter(|c| pair_of(c) == f.pair)
                .map(|c| c.geom.gap)
                .fold(f64::INFINITY, f64::min);
            gap.is_finite() && gap > f.gap
        });
        // 2. Impacts.
        let mut rounds = 0;
        let mut any = false;
        loop {
            let solve = cx.clock.start(Stage::Solve);
            let hit = self.impacts_at(scn, sys, &contacts, None, cx);
            cx.clock.stop(Stage::Solve, solve);
            if !hit {
                break;
            }
            any = true;
            rounds += 1;
            if cx.topology.pending() {
                break;
            }
            if rounds >= MAX_IMPACT_ROUNDS {
                self.counters.add(&IMPACT_ROUNDS_CAPPED, 1);
                break;
            }
        }
        if any {
            self.counters.add(&IMPACT_INSTANTS, 1);
        }
        // A safe point: fractures at this instant (docs/physics.md §9.5);
        // the floes break after the impact that broke them, and the instant
        // starts again with the new floe set (its contacts detected anew).
        if let Some(old) = cx.change_floes(scn, sys) {
            return self.floes_changed(scn, sys, &old);
        }
        // 3. Trial step with sustained contact forces, bounded by the
        // scheme alone (never by the output times).
        let hints = self.integ.hints().to_vec();
        let mut bound = self.integ.step_bound(scn, sys, end);
        if !contacts.is_empty() {
            bound = bound.min(self.horizon);
        }
        // A crushing phase crushes at most the penetration tolerance per
        // step: the step resolves the phase, whose overlap is cut at the
        // next safe point (docs/physics.md §10.2).
        if scn.contact.crushing.is_some() {
            for c in &contacts {
                let u = normal_velocity(scn, &sys.bodies, c);
                if u < 0.0 {
                    bound = bound.min(self.pen_tol / -u);
                    // A pair not yet touching (no crushing force) starts
                    // its phase when it touches: the step ends there.
                    let touch = c.geom.gap / -u;
                    if touch > MIN_CUT_FRACTION * bound {
                        bound = bound.min(touch);
                    }
                }
            }
        }
        // A closed contact still approaching, slower than the impact
        // threshold, is stopped by the sustained force over the step and
        // closes |u| h / 2: beyond a tenth of the tolerance, it is stopped at
        // once instead.
        let solve = cx.clock.start(Stage::Solve);
        self.impacts_at(scn, sys, &contacts, Some(bound), cx);
        cx.clock.stop(Stage::Solve, solve);
        let to_end = bound >= end - t;
        let mut h = bound;
        let p0 = world_polygons(scn, &sys.bodies);
        let mut rejections = 0;
        let mut cuts = 0;
        // Stick adjustments of this step (estimate, then linear correction),
        // allowed while no other cut has shortened it.
        let mut stick_moves = 0;
        // The shortest length at which a pair was found to stick: a
        // correction never lengthens the step back to it (it would find
        // the same stick and cut again: a cycle of re-solves).
        let mut stuck_at = f64::INFINITY;
        let mut other_cut = false;
        loop {
            let sustained = self.sustained_wrenches(scn, sys, &contacts, h, bound, cx)?;
            if let Some((shorter, why)) = sustained.cut {
                if shorter < (1.0 - MIN_CUT_FRACTION) * h && cuts < MAX_CUTS {
                    self.counters.add(why.counter(), 1);
                    cuts += 1;
                    other_cut = true;
                    h = shorter;
                    continue;
                }
            }
            if !other_cut && rejections == 0 && stick_moves < MAX_STICK_MOVES {
                let moved = match (sustained.stick, sustained.slide_stop) {
                    (Some(s), _) if s < (1.0 - MIN_CUT_FRACTION) * h => {
                        stuck_at = stuck_at.min(h);
                        Some(s)
                    }
                    (None, Some(s))
                        if stick_moves > 0
                            && s > (1.0 + MIN_CUT_FRACTION) * h
                            && s.min(bound) < (1.0 - MIN_CUT_FRACTION) * stuck_at =>
                    {
                        Some(s.min(bound))
                    }
                    _ => None,
                };
                if let Some(s) = moved {
                    self.counters.add(&STEPS_CUT_FOR_STICK, 1);
                    stick_moves += 1;
                    h = s;
                    continue;
                }
            }
            let wrenches = sustained.wrenches;
            let mut trial = cx.clock.time(Stage::Integration, || {
                self.integrate(scn, sys, h, &wrenches)
            })?;
            if to_end && h == bound {
                trial.t = end;
            }
            let p1 = world_polygons(scn, &trial.bodies);
            // 4. Event location.
            let event = {
                let t0 = cx.clock.start(Stage::Detection);
                let r = self.locate(scn, sys, &trial, h, &wrenches, &p0, &p1);
                cx.clock.stop(Stage::Detection, t0);
                r?
            };
            let located = matches!(event, Some((s, _)) if s < h);
            let mut next = match event {
                Some((s, (i, j))) if s < h => {
                    self.counters.add(&EVENTS_LOCATED, 1);
                    let pair = (i.min(j), i.max(j));
                    if contacts.iter().any(|c| pair_of(c) == pair) {
                        // The pair was already closed at the step start:
                        // another vertex of a sustained contact closes.
                        self.counters.add(&EVENTS_OF_PAIRS_IN_CONTACT, 1);
                    }
                    cx.clock.time(Stage::Integration, || {
                        self.integrate(scn, sys, s, &wrenches)
                    })?
                }
                _ => trial,
            };
            // 5. Penetration check.
            let p_next = if located {
                world_polygons(scn, &next.bodies)
            } else {
                p1
            };
            // The depth of a pair is its minimum translation distance
            // ([`signed_distance`], the measure of the contact detection and
            // of `floebench check`), not its deepest vertex: two pieces of a
            // split whose cut edges cross, scissored, overlap with no vertex
            // inside the other (docs/physics.md §4.3, step 5).
            let depths: Vec<((usize, usize), f64)> = cx.clock.time(Stage::Detection, || {
                self.swept_pairs(scn, &p_next, &p_next)
                    .iter()
                    .map(|&(i, j)| {
                        let d = Self::pair_signed_distance(scn, i, j, &p_next[i], &p_next[j]);
                        ((i, j), -d)
                    })
                    .collect()
            });
            let depth = depths.iter().map(|d| d.1).fold(0.0, f64::max);
            // A flight whose pair penetrates was misjudged: over.
            let before = self.flights.len();
            self.flights.retain(|f| {
                !depths
                    .iter()
                    .any(|&(p, d)| (p.0.min(p.1), p.0.max(p.1)) == f.pair && d > 0.0)
            });
            if self.flights.len() < before && rejections < MAX_REJECTIONS {
                rejections += 1;
                self.counters.add(&STEPS_REJECTED_PENETRATION, 1);
                continue;
            }
            if depth > self.pen_tol && rejections < MAX_REJECTIONS {
                rejections += 1;
                self.counters.add(&STEPS_REJECTED_PENETRATION, 1);
                h *= 0.5;
                continue;
            }
            if depth > self.pen_tol {
                self.counters.add(&PENETRATIONS_BEYOND_TOLERANCE, 1);
            }
            self.max_penetration = self.max_penetration.max(depth);
            self.counters
                .add(&FLIGHTS_WITHIN_DISTANCE, sustained.flights.len() as u64);
            self.flights.extend(sustained.flights);
            // The impulses delivered over the step [t, next.t]: the
            // sustained wrenches (impulses over h) for the part of h taken.
            let taken = ((next.t - t) / h).clamp(0.0, 1.0);
            let (crushing, work) = &sustained.crushing;
            let reads = cx.topology.reads();
            let crushes = scn.contact.crushing.is_some();
            if reads.sustained || (crushes && reads.percussions) {
                let step: Vec<Load> = sustained
                    .loads
                    .iter()
                    .map(|l| Load {
                        impulse: l.impulse * taken,
                        ..*l
                    })
                    .collect();
                // With crushing there are no impacts: the criteria read the
                // (bounded) impulses of each step as percussions over it, as
                // Moreau–Jean's, with the crushing work as their budget
                // (docs/physics.md §10.2).
                if crushes && reads.percussions && !step.is_empty() {
                    cx.topology
                        .percussion(scn, sys, &step, t, next.t, work * taken);
                }
                if reads.sustained {
                    // The stress criterion reads them with the slow
                    // approaches stopped (docs/physics.md §9.3, §9.5); the
                    // floes break at the next step's start, on the lines
                    // chosen here, carried with them.
                    let mut loads = std::mem::take(&mut self.step_loads);
                    loads.extend(step);
                    cx.topology.sustained(scn, sys, &loads, t, next.t);
                }
            }
            // The pairs that crush: their work over the part of the step
            // taken moves from `dissipated` (where the integration booked
            // the contact work) to `crushing`, and the stage cuts their
            // overlap at the next step's start (docs/physics.md §10.2,
            // §10.4).
            if !crushing.is_empty() {
                next.ledger.dissipated -= work * taken;
                next.ledger.crushing += work * taken;
                cx.crushed(scn, sys, crushing);
            }
            self.last = Some(StepRecord {
                start: std::mem::replace(sys, next),
                wrenches,
                hints,
            });
            self.counters.add(&STEPS, 1);
            break;
        }
        if sys.bodies.len() != n {
            return Err(FormulationError::Other("state size changed".into()));
        }
        Ok(())
    }
}
