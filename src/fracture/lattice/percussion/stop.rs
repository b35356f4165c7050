//! The pieces of a percussion and its stopping rule (docs/physics.md §7.3;
//! the rule: the module doc of [`super`]): the connected components of the
//! unbroken springs as rigid [`Fragment`]s, whether the contact is over,
//! and the run to the chain's stop ([`Percussion::run`]).

use super::{Fragment, Outcome, Percussion};
use crate::fracture::chain::{Settling, Stop};
use crate::geometry::perp;

impl Percussion<'_> {
    /// The connected components of the unbroken springs, each a label;
    /// returns the labels and their number.
    pub fn components(&self) -> (Vec<usize>, usize) {
        let n = self.len();
        let mut parent: Vec<usize> = (0..n).collect();
        fn root(p: &mut [usize], mut i: usize) -> usize {
            while p[i] != i {
                p[i] = p[p[i]];
                i = p[i];
            }
            i
        }
        for (s, l) in self.lattice.springs.iter().zip(&self.links) {
            if l.bonded {
                let (a, b) = (root(&mut parent, s.nodes[0]), root(&mut parent, s.nodes[1]));
                if a != b {
                    parent[a.max(b)] = a.min(b);
                }
            }
        }
        let mut label = vec![usize::MAX; n];
        let mut count = 0;
        let mut out = vec![0; n];
        for (i, o) in out.iter_mut().enumerate() {
            let r = root(&mut parent, i);
            if label[r] == usize::MAX {
                label[r] = count;
                count += 1;
            }
            *o = label[r];
        }
        (out, count)
    }

    /// The pieces now, in the order of their first node.
    pub fn fragments(&self) -> Vec<Fragment> {
        let (label, count) = self.components();
        let m = &self.lattice.mass;
        let mut nodes: Vec<Vec<usize>> = vec![Vec::new(); count];
        for (i, &c) in label.iter().enumerate() {
            nodes[c].push(i);
        }
        nodes
            .into_iter()
            .map(|list| Fragment::of_nodes(list, &self.x, &self.v, m))
            .collect()
    }

    /// Whether the contact is over (module doc): no node touches the
    /// striker and it is no faster along the normal than any piece within
    /// one lattice spacing of it, at that piece's node nearest it.
    fn contact_over(&self, pieces: &[Fragment]) -> bool {
        if self.touching() {
            return false;
        }
        let reach = self.lattice.spec.spacing;
        self.strikers.iter().enumerate().all(|(k, s)| {
            let n = s.impact.normal;
            pieces.iter().all(|p| {
                let near = p
                    .nodes
                    .iter()
                    .copied()
                    .min_by(|&a, &b| self.gap(k, a).0.total_cmp(&self.gap(k, b).0));
                near.is_none_or(|i| {
                    let r = self.x[i] - p.centre;
                    let u = n.dot(&(p.velocity + perp(&r) * p.angular_velocity));
                    self.gap(k, i).0 > reach || s.velocity <= u
                })
            })
        })
    }

    /// Runs to the stopping rule (module doc).
    pub fn run(&mut self) -> Outcome {
        let initial = self.energies().total();
        let momentum = self.momentum();
        let u0: Vec<f64> = self.strikers.iter().map(|s| s.velocity).collect();
        let undamped = self.links.iter().all(|l| l.c == 0.0);
        let mut settling = Settling::new();
        let mut max_drift: f64 = 0.0;
        let options = self.options;
        let reason = loop {
            if crate::stop::poll(self.steps) {
                break Stop::Interrupted;
            }
            self.step();
            let e = self.energies();
            if undamped {
                max_drift = max_drift.max((e.total() - initial - self.work).abs());
            }
            let closed = self.touching();
            let pieces = if closed { Vec::new() } else { self.fragments() };
            let over = !closed && self.contact_over(&pieces);
            let internal = || {
                let rigid: f64 = pieces.iter().map(Fragment::rigid_energy).sum();
                e.kinetic + e.elastic + e.torsion - rigid - self.striker_energy()
            };
            if let Some(stop) = settling.stop(
                self.t,
                over,
                internal,
                self.impact_energy,
                self.transit,
                &options,
            ) {
                break stop;
            }
        };
        let fragments = self.fragments();
        let rigid: f64 = fragments.iter().map(Fragment::rigid_energy).sum();
        let hulls: f64 = fragments.iter().map(|f| f.area).sum();
        Outcome {
            reason,
            t: self.t,
            contact_end: settling.contact_end,
            dt: self.dt,
            steps: self.steps,
            initial_energy: initial,
            work: self.work,
            impact_energy: self.impact_energy,
            energies: self.energies(),
            energy_drift: max_drift,
            broken: self.broken.clone(),
            striker_velocity: [u0[0], self.strikers[0].velocity],
            striker_velocities: u0
                .iter()
                .zip(&self.strikers)
                .map(|(&a, s)| [a, s.velocity])
                .collect(),
            impulse: self.impulse,
            impulse_moment: self.impulse_moment,
            initial_momentum: momentum,
            fracture_energy: initial + self.work - rigid - self.striker_energy(),
            hull_area_error: (hulls - self.lattice.area) / self.lattice.area,
            fragments,
        }
    }
}
