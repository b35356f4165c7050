//! The contact part of a Moreau–Jean step (docs/physics.md §5.1 steps 2
//! and 3): which detected contacts enter the step's problem (closed ones,
//! and with `open_contacts = "gap"` the open ones too), and the solve of
//! every group with Newton's law on the closed contacts and the linearised
//! gap on the open ones.

use super::*;

impl Moreau {
    /// Whether a contact of gap `gap` (m) and normal velocity `u` (m/s) at
    /// the start of a step of `h` is closed: its predicted gap
    /// `g + h γ u_N` within the rounding allowance `ε`.
    fn closed(&self, gap: f64, u: f64, h: f64) -> bool {
        gap + h * self.gamma * u <= self.activation_tolerance
    }

    /// Contacts at `q_k` whose predicted gap `g + h γ u_N` is closed (and,
    /// with `open_contacts = "gap"`, the open ones within the detection
    /// margin too); updates the penetration record from the gaps. A facing edge pair gives the
    /// narrow phase's points within the step's reach, plus each clipped end
    /// of the pair within the contact distance `δ` (the second corner of a
    /// nearly flush pair; docs/physics.md §5.1 step 2).
    pub(super) fn active_contacts(&mut self, scn: &Scenario, sys: &System, h: f64) -> Vec<Contact> {
        let margin = 2.0 * h * self.gamma * sys.max_point_speed(scn);
        let mut contacts = Vec::new();
        detect_contacts(scn, &sys.bodies, margin, &mut self.bp, &mut contacts);
        let mut flush = Vec::new();
        detect_contacts_with(
            scn,
            &sys.bodies,
            self.flush_distance,
            &CLIPPED_EDGE_PAIRS,
            &mut self.bp,
            &mut flush,
        );
        let known: HashSet<ContactKey> = contacts.iter().map(Contact::key).collect();
        contacts.extend(flush.into_iter().filter(|c| !known.contains(&c.key())));
        for c in &contacts {
            self.max_penetration = self.max_penetration.max(-c.geom.gap);
        }
        if self.open_contacts == OpenContacts::Inactive {
            contacts.retain(|c| self.closed(c.geom.gap, normal_velocity(scn, &sys.bodies, c), h));
        }
        contacts
    }

    /// Solves the contact problem of every group of `active` and writes the
    /// new velocities (`w_free` where no contact acts); books the
    /// dissipation and reports the impulses to the topology stage.
    pub(super) fn solve_contacts(
        &mut self,
        scn: &Scenario,
        sys: &mut System,
        h: f64,
        active: &[Contact],
        w_free: &[Gen],
        cx: &mut Context<'_>,
    ) -> Vec<Gen> {
        let mut w_new = w_free.to_vec();
        let n = scn.floes.len();
        let e = scn.contact.restitution;
        let u_minus: Vec<f64> = active
            .iter()
            .map(|c| normal_velocity(scn, &sys.bodies, c))
            .collect();
        // Newton's law on every closed contact (module doc); the
        // linearised gap on the open ones (`open_contacts = "gap"`: the
        // positions' θ-method keeps `g + h ((1 − θ) u⁻ + θ u⁺) ≥ 0`), never
        // slower than the pair's own approach `−u⁻` (its impact is Newton's,
        // at the step that closes it).
        let closed: Vec<bool> = active
            .iter()
            .zip(&u_minus)
            .map(|(c, &u)| self.closed(c.geom.gap, u, h))
            .collect();
        let offsets: Vec<f64> = active
            .iter()
            .zip(&u_minus)
            .zip(&closed)
            .map(|((c, &u), &shut)| match shut {
                true => e * u,
                false => ((c.geom.gap + h * (1.0 - self.theta) * u) / (h * self.theta)).max(-u),
            })
            .collect();
        if self.open_contacts == OpenContacts::Gap {
            let open = closed.iter().filter(|&&shut| !shut).count();
            self.counters.add(&OPEN_CONTACTS, open as u64);
        }
        let centres = sys.centres();
        // The crushing bound of each contact's impulse over the step
        // (docs/physics.md §10; empty: rigid contacts).
        let bounds = crate::contact::crush::normal_bounds(scn, active, h);
        let gs = groups(active, n);
        self.counters.add(&ACTIVE_CONTACTS, active.len() as u64);
        self.counters.max(&ACTIVE_CONTACTS_MAX, active.len() as f64);
        self.counters.add(&CONTACT_GROUPS, gs.len() as u64);
        let mut any = false;
        let (mut e_before, mut e_after) = (0.0, 0.0);
        for g in &gs {
            let data = GroupData {
                scn,
                centres: &centres,
                contacts: active,
                group: g,
                w_free,
                offsets: &offsets,
                bounds: &bounds,
            };
            // An impact of one pair may be resolved in the lattices
            // (`impact = "lattice"`, [`lattice`]).
            let lattice = cx.topology.reads().impacts.then(|| {
                let group = (g, active, &u_minus[..], &closed[..]);
                self.lattice_impact(scn, sys, group, w_free, cx)
            });
            let (rigid, dv) = match lattice.flatten() {
                Some(answer) => (Err(answer), Moreau::lattice_dv(scn, g, &answer, w_free)),
                None => {
                    let GroupAnswer {
                        normal,
                        tangential,
                        dv,
                        ..
                    } = self.solver.solve(&data, sys.t, h);
                    if self.open_contacts == OpenContacts::Gap {
                        let pushing = g
                            .contacts
                            .iter()
                            .zip(&normal)
                            .filter(|&(&k, &l)| !closed[k] && l > 0.0)
                            .count();
                        self.counters.add(&OPEN_CONTACTS_PUSHING, pushing as u64);
                    }
                    (Ok((normal, tangential)), dv)
                }
            };
            let v_scale = g
                .floes
                .iter()
                .flat_map(|&i| w_free[i])
                .fold(0.0f64, |m, v| m.max(v.abs()));
            let negligible = NEGLIGIBLE_VELOCITY_FRACTION * v_scale + 1e-300;
            if dv.iter().flatten().any(|d| d.abs() > negligible) {
                any = true;
            }
            let before = group_energy(scn, w_free, &g.floes);
            for (l, &i) in g.floes.iter().enumerate() {
                for d in 0..3 {
                    w_new[i][d] = w_free[i][d] + dv[l][d];
                }
            }
            let after = group_energy(scn, &w_new, &g.floes);
            if crate::iterative::creates_energy(before, after) {
                self.counters.add(&CONTACT_ENERGY_INCREASES, 1);
                self.counters
                    .max(&CONTACT_ENERGY_INCREASE_MAX, after - before);
            }
            let impulses = match rigid {
                Ok(impulses) => {
                    // The work of the contacts at their crushing bound,
                    // booked apart (docs/physics.md §10).
                    let crushed = match bounds.is_empty() {
                        true => 0.0,
                        false => self.crushing(
                            scn,
                            &centres,
                            (w_free, &w_new),
                            g,
                            active,
                            (&impulses.0, &bounds),
                        ),
                    };
                    sys.ledger.dissipated += before - after - crushed;
                    sys.ledger.crushing += crushed;
                    Some(impulses)
                }
                // The stage queued the impact's cracks itself.
                Err((_, answer)) => {
                    answer.book(&mut sys.ledger, before, after);
                    None
                }
            };
            if let (true, Some((normal, tangential))) = (cx.topology.reads().percussions, impulses)
            {
                // The step's impulses, on the floes at q_k, delivered over
                // the step [t_k, t_k + h] (docs/physics.md §9.3); the floes
                // break between steps (§9.5).
                let group: Vec<&Contact> = g.contacts.iter().map(|&k| &active[k]).collect();
                let loads = loads_of(scn, &group, &normal, &tangential);
                cx.topology
                    .percussion(scn, sys, &loads, sys.t, sys.t + h, before - after);
            }
            if dv.iter().flatten().any(|d| d.abs() > negligible) {
                self.solver.direct.log_mut().push_event(ContactEvent {
                    t: sys.t,
                    contacts: g.contacts.len(),
                    energy_before: before,
                    energy_after: after,
                });
            }
            e_before += before;
            e_after += after;
        }
        if cx.topology.reads().impacts {
            self.keep_active_pairs(active, &closed);
        }
        // The pairs at their crushing bound: the stage cuts their overlap
        // at the next step's start (docs/physics.md §10.4).
        let crushing = std::mem::take(&mut self.crushing_pairs);
        cx.crushed(scn, sys, &crushing);
        if any {
            self.counters.add(&STEPS_WITH_IMPULSES, 1);
            if self.records.len() < MAX_RECORDS {
                self.records.push(ContactStep {
                    t: sys.t,
                    h,
                    contacts: active.len(),
                    approaching: u_minus.iter().filter(|&&u| u < 0.0).count(),
                    energy: (e_before, e_after),
                });
            }
        }
        w_new
    }
}

impl Moreau {
    /// The work of the contacts of group `g` that crush
    /// ([`crate::contact::crush::crushing`]: bounded, and still approaching
    /// after the step's impulses; `impulses`: the group's normal impulses,
    /// N·s, and every contact's bound), J: `−λ_j ū_N,j`, `ū_N` the mean of the
    /// relative normal velocities before (`w.0`, the free velocities) and
    /// after (`w.1`) the step's impulses, so that the group's kinetic
    /// energy change `Σ p_j·ū_j` splits exactly into this and the rest
    /// (docs/physics.md §10). The pairs crushing are kept for the crush
    /// stage.
    fn crushing(
        &mut self,
        scn: &Scenario,
        centres: &[Vec2],
        w: (&[Gen], &[Gen]),
        g: &ContactGroup,
        active: &[Contact],
        (normal, bounds): (&[f64], &[f64]),
    ) -> f64 {
        let mut work = 0.0;
        for (&k, &l) in g.contacts.iter().zip(normal) {
            let c = &active[k];
            let u = |w: &[Gen]| crate::contact::crush::normal_velocity(scn, centres, w, c);
            let after = u(w.1);
            if !crate::contact::crush::crushing(bounds[k], after) {
                continue;
            }
            work -= l * 0.5 * (u(w.0) + after);
            self.crushing_pairs.push((c.a, c.b));
        }
        work
    }
}

fn group_energy(scn: &Scenario, w: &[Gen], floes: &[usize]) -> f64 {
    floes
        .iter()
        .map(|&i| scn.floes[i].kinetic_energy(&Vec2::new(w[i][0], w[i][1]), w[i][2]))
        .sum()
}
