//! Impacts (docs/physics.md §3.2, §4.3 step 2): Poisson's law on the
//! compression LCP of each group of approaching contacts, the slow
//! approaches stopped, and the separation test of closed contacts. With
//! `[fracture] impact = "lattice"`, a group whose approaching contacts
//! join one pair of bodies is first offered to the topology stage, which
//! resolves it in the pair's lattices (docs/physics.md §9.10); a group of
//! several pairs keeps Poisson's law (the stage counts it).

use super::*;

impl EventDriven {
    /// Resolves the impacts of every group with an approaching closed contact
    /// (a pair in a flight within δ is open). Returns whether any impact
    /// happened.
    ///
    /// With `slow = Some(h)`, the approaches slower than the impact threshold
    /// instead (faster than the rounding floor), those that the sustained
    /// force of a step `h` would let close more than a tenth of the
    /// penetration tolerance (`|u| h / 2`): they are stopped at once,
    /// plastically (`e = 0`; counted apart, not as impacts).
    pub(super) fn impacts_at(
        &mut self,
        scn: &Scenario,
        sys: &mut System,
        contacts: &[Contact],
        slow: Option<f64>,
        cx: &mut Context<'_>,
    ) -> bool {
        // With crushing, a rigid impact would need an unbounded force:
        // every approach is a crushing phase, resolved by the sustained
        // contacts at their bounded force (docs/physics.md §10.2).
        if scn.contact.crushing.is_some() {
            return false;
        }
        let n = scn.floes.len();
        let approaching: Vec<bool> = contacts
            .iter()
            .map(|c| {
                // A pair in a flight within δ is open until it returns.
                if self.flights.iter().any(|f| f.pair == pair_of(c)) {
                    return false;
                }
                let u = normal_velocity(scn, &sys.bodies, c);
                match slow {
                    None => u < -self.impact_speed,
                    Some(h) => u < -APPROACH_TOLERANCE && -u * h > 0.2 * self.pen_tol,
                }
            })
            .collect();
        if !approaching.iter().any(|&a| a) {
            return false;
        }
        let centres = sys.centres();
        let w: Vec<Gen> = sys.velocities();
        let zeros = vec![0.0; contacts.len()];
        let e = if slow.is_some() {
            0.0
        } else {
            scn.contact.restitution
        };
        for g in groups(contacts, n) {
            if !g.contacts.iter().any(|&k| approaching[k]) {
                continue;
            }
            let before = sys.group_kinetic_energy(scn, &g.floes);
            // An impact of one pair may be resolved by the topology stage
            // (`impact = "lattice"`, docs/physics.md §9.10).
            let lattice = if slow.is_none() && cx.topology.reads().impacts {
                let impacting: Vec<&Contact> = g
                    .contacts
                    .iter()
                    .filter(|&&k| approaching[k])
                    .map(|&k| &contacts[k])
                    .collect();
                ImpactQuery::of(scn, &impacting, |i| sys.bodies[i])
                    .and_then(|q| cx.impact(scn, sys, &q).map(|a| (q, a)))
            } else {
                None
            };
            let rigid = match &lattice {
                Some((q, answer)) => {
                    for (i, v, w) in answer.floes(scn, q) {
                        sys.bodies[i].velocity = v;
                        sys.bodies[i].angular_velocity = w;
                    }
                    None
                }
                None => {
                    // The compression LCP of Poisson's law, whatever the
                    // solver of the sustained contacts.
                    let data = GroupData {
                        scn,
                        centres: &centres,
                        contacts,
                        group: &g,
                        w_free: &w,
                        offsets: &zeros,
                        bounds: &[],
                    };
                    let ans = self.solver.solve_impact(&data, sys.t);
                    let dv = &ans.dv;
                    let w_minus: Vec<BodyState> = g.floes.iter().map(|&i| sys.bodies[i]).collect();
                    let apply = |bodies: &mut [BodyState], k: f64| {
                        for (l, &i) in g.floes.iter().enumerate() {
                            let b = &mut bodies[i];
                            b.velocity = w_minus[l].velocity + Vec2::new(dv[l][0], dv[l][1]) * k;
                            b.angular_velocity = w_minus[l].angular_velocity + dv[l][2] * k;
                        }
                    };
                    apply(&mut sys.bodies, 1.0 + e);
                    Some(ans)
                }
            };
            // The group's velocities changed: its flights end here.
            self.flights
                .retain(|f| !g.floes.contains(&f.pair.0) && !g.floes.contains(&f.pair.1));
            let after = sys.group_kinetic_energy(scn, &g.floes);
            if after > before * (1.0 + 1e-12) + 1e-300 {
                self.counters.add(&IMPACT_ENERGY_INCREASES, 1);
            }
            match &lattice {
                Some((_, answer)) => answer.book(&mut sys.ledger, before, after),
                None => sys.ledger.dissipated += before - after,
            }
            if let Some(ans) = rigid {
                if cx.topology.reads().percussions && slow.is_none() {
                    // The impulses applied: (1 + e) times the compression's.
                    let k = 1.0 + e;
                    let normal: Vec<f64> = ans.normal.iter().map(|v| v * k).collect();
                    let tangential: Vec<f64> = ans.tangential.iter().map(|v| v * k).collect();
                    let group: Vec<&Contact> = g.contacts.iter().map(|&k| &contacts[k]).collect();
                    let loads = loads_of(scn, &group, &normal, &tangential);
                    cx.topology
                        .percussion(scn, sys, &loads, sys.t, sys.t, before - after);
                } else if slow.is_some() && cx.topology.reads().sustained {
                    // A slow approach stopped is part of the sustained
                    // contact: the stress criterion reads it with the step's
                    // impulses.
                    let group: Vec<&Contact> = g.contacts.iter().map(|&k| &contacts[k]).collect();
                    self.step_loads
                        .extend(loads_of(scn, &group, &ans.normal, &ans.tangential));
                }
            }
            self.solver.direct.log_mut().push_event(ContactEvent {
                t: sys.t,
                contacts: g.contacts.len(),
                energy_before: before,
                energy_after: after,
            });
            if slow.is_some() {
                self.counters.add(&SLOW_APPROACHES_STOPPED, 1);
                continue;
            }
            self.counters.add(&IMPACTS, 1);
            if self.impacts.len() < MAX_IMPACT_RECORDS {
                self.impacts.push(ImpactRecord {
                    t: sys.t,
                    floes: g.floes.clone(),
                    contacts: g.contacts.len(),
                    energy: (before, after),
                });
            }
        }
        true
    }

    /// The normal relative acceleration of contact `c` from the environment
    /// forces at `sys` (m/s², negative: pulled back into contact), the
    /// centripetal terms included.
    pub(super) fn normal_acceleration(&mut self, scn: &Scenario, sys: &System, c: &Contact) -> f64 {
        let model = self.integ.model();
        let acc = |i: usize| -> Vec2 {
            let Body::Floe(i) = scn.body(i) else {
                return Vec2::zeros();
            };
            let b = &sys.bodies[i];
            let a = model.acceleration(i, &model.forces(&scn.environment, i, sys.t, b));
            let r = c.geom.point - b.position;
            Vec2::new(a[0], a[1]) + perp(&r) * a[2] - r * b.angular_velocity.powi(2)
        };
        (acc(c.b) - acc(c.a)).dot(&c.geom.normal)
    }

    /// What happens to a closed contact `c` that separates at `u` (m/s,
    /// `> 0`), with restitution `e`, under a constant normal acceleration
    /// `a_N < 0` (docs/physics.md §4.3, step 3): its flight rises by
    /// `H = u²/(2|a_N|)`; its bounces (flights `2u eᵏ/|a_N|`) accumulate after
    /// `T = 2u/(|a_N|(1 − e))`. When `e < 1`, the mean motion over `T` (the
    /// normal velocity decaying linearly to rest, which lifts the contact by
    /// `u T/2 = u²/(|a_N|(1 − e))`) stays within the contact distance, and
    /// `T` is within the drag time scale (the forces are constant enough for
    /// the closed form), the contact accumulates. Otherwise a flight that
    /// stays within the contact distance, faster than the impact threshold,
    /// is followed to its return; anything else is left to the apex rule.
    /// Only for an isolated pair ([`isolated`]): in a pile the neighbours'
    /// contact forces, not the environment, pull a contact back, and the
    /// closed forms do not hold (with them, the mean motion pushed piles of
    /// `field_200_coast` apart against the wind: contacts did 6.8e9 J of
    /// positive work in 6000 s).
    pub(super) fn separation(
        &mut self,
        scn: &Scenario,
        sys: &System,
        c: &Contact,
        u: f64,
    ) -> Separation {
        if u <= self.impact_speed {
            // Not a bounce: its return would not be an impact.
            return Separation::Other;
        }
        let a_n = self.normal_acceleration(scn, sys, c);
        if a_n.is_nan() || a_n >= 0.0 {
            return Separation::Other;
        }
        let pull = -a_n;
        let e = scn.contact.restitution;
        let gap = c.geom.gap;
        if e < 1.0 {
            let remaining = 2.0 * u / (pull * (1.0 - e));
            if gap + 0.5 * u * remaining <= self.distance && remaining <= self.integ.drag_bound() {
                return Separation::Accumulating { remaining };
            }
        }
        if gap + u * u / (2.0 * pull) <= self.distance {
            return Separation::FlightWithin {
                flight: 2.0 * u / pull,
            };
        }
        Separation::Other
    }
}
