//! Building a [`Percussion`]: its constructors ([`Percussion::new`],
//! [`Percussion::with_strikers`] and the two-body impact's placed one),
//! which check the impacts and set up the nodes, the springs' links and
//! the strikers with their contact links, the step and the first forces
//! (docs/physics.md §7.3).

use super::state::mean_stiffness;
use super::striker::{impact_energy_bound, Impact, RigidMotion, Striker};
use super::Percussion;
use crate::fracture::chain::{ChainOptions, Cohesive, Link};
use crate::fracture::lattice::Lattice;
use crate::geometry::{cross, perp, rotate, Vec2};

impl<'a> Percussion<'a> {
    /// A percussion of `lattice` (its floe moving rigidly at `motion`)
    /// struck by `impact`, with the chain's `options`. Fails on an invalid
    /// option or impact.
    pub fn new(
        lattice: &'a Lattice,
        motion: RigidMotion,
        impact: Impact,
        options: ChainOptions,
    ) -> Result<Percussion<'a>, String> {
        Percussion::with_strikers(lattice, motion, &[impact], options)
    }

    /// A percussion of `lattice` (its floe moving rigidly at `motion`)
    /// struck at once by every impact of `impacts` (at least one), each a
    /// striker of its own (docs/physics.md §9.8), with the chain's
    /// `options`. Fails on an invalid option or impact.
    pub fn with_strikers(
        lattice: &'a Lattice,
        motion: RigidMotion,
        impacts: &[Impact],
        options: ChainOptions,
    ) -> Result<Percussion<'a>, String> {
        options.validate()?;
        if impacts.is_empty() {
            return Err("a percussion needs at least one impact".into());
        }
        Percussion::build(lattice, motion, impacts, options, None)
    }

    /// A percussion of `lattice` placed in the world at centre offset `at`
    /// (m) and angle `angle` (rad) (each node at `at + R(angle) x`), moving
    /// rigidly at `motion` about its placed centre of mass, struck by
    /// `impacts` (none: a body whose contacts are another lattice's, the
    /// two-body impact of docs/physics.md §9.9), with the chain's
    /// `options`, all in world coordinates. Fails on an invalid option or
    /// impact.
    pub(in crate::fracture::lattice) fn placed(
        lattice: &'a Lattice,
        motion: RigidMotion,
        impacts: &[Impact],
        options: ChainOptions,
        at: Vec2,
        angle: f64,
    ) -> Result<Percussion<'a>, String> {
        options.validate()?;
        Percussion::build(lattice, motion, impacts, options, Some((at, angle)))
    }

    /// [`Self::with_strikers`] with the nodes placed by `frame` (the offset
    /// and angle of [`Self::placed`]; `None` the lattice's own frame).
    fn build(
        lattice: &'a Lattice,
        motion: RigidMotion,
        impacts: &[Impact],
        options: ChainOptions,
        frame: Option<(Vec2, f64)>,
    ) -> Result<Percussion<'a>, String> {
        for impact in impacts {
            let n = impact.normal.norm();
            if (n - 1.0).abs().is_nan() || (n - 1.0).abs() >= 1e-9 {
                return Err(format!("the impact normal must be a unit vector, got {n}"));
            }
            if impact.mass.is_nan() || impact.mass <= 0.0 {
                return Err(format!(
                    "the striker's mass must be positive, got {}",
                    impact.mass
                ));
            }
            if !(impact.speed.is_finite() && impact.point.iter().all(|c| c.is_finite())) {
                return Err("the impact speed and point must be finite".into());
            }
        }
        let spec = lattice.spec;
        let m = &lattice.mass;
        let total: f64 = m.iter().sum();
        let x: Vec<Vec2> = match frame {
            None => lattice.nodes.clone(),
            Some((at, angle)) => lattice
                .nodes
                .iter()
                .map(|p| at + rotate(p, angle))
                .collect(),
        };
        let g = x.iter().zip(m).map(|(x, &mi)| x * mi).sum::<Vec2>() / total;
        let v: Vec<Vec2> = x
            .iter()
            .map(|p| motion.velocity + perp(&(p - g)) * motion.angular_velocity)
            .collect();
        // Each spring's facet: a third of each adjacent triangle's area.
        let mut share = vec![0.0; lattice.springs.len()];
        for (t, row) in lattice.triangles.iter().zip(&lattice.triangle_springs) {
            let (a, b, c) = (
                lattice.nodes[t[0]],
                lattice.nodes[t[1]],
                lattice.nodes[t[2]],
            );
            let area = 0.5 * cross(&(b - a), &(c - a));
            for &(k, _) in row {
                share[k] += area / 3.0;
            }
        }
        let (links, cohesive): (Vec<Link>, Vec<Option<Cohesive>>) = lattice
            .springs
            .iter()
            .zip(&share)
            .map(|(s, &a)| {
                let [i, j] = s.nodes;
                let mij = 2.0 * m[i] * m[j] / (m[i] + m[j]);
                let width = 2.0 * a / s.length;
                let section = spec.thickness * width;
                let link = Link {
                    k: s.stiffness,
                    c: options.damping * (s.stiffness * mij).sqrt(),
                    rest: s.length,
                    bonded: true,
                    critical: options.bond.critical(s.stiffness, s.length, section),
                };
                (link, options.bond.cohesive(s.stiffness, section))
            })
            .unzip();
        let mean_k = mean_stiffness(lattice);
        let contacts_of = |impact: &Impact| -> Vec<(usize, Link)> {
            (0..x.len())
                .filter(|&i| lattice.on_boundary[i])
                .map(|i| {
                    let mu = if impact.mass.is_finite() {
                        m[i] * impact.mass / (m[i] + impact.mass)
                    } else {
                        m[i]
                    };
                    (
                        i,
                        Link {
                            k: mean_k,
                            c: options.damping * (mean_k * mu).sqrt(),
                            rest: 0.0,
                            bonded: false,
                            critical: f64::INFINITY,
                        },
                    )
                })
                .collect()
        };
        let strikers: Vec<Striker> = impacts
            .iter()
            .map(|impact| {
                let contacts = contacts_of(impact);
                let position = contacts
                    .iter()
                    .map(|&(i, _)| impact.normal.dot(&(x[i] - impact.point)))
                    .fold(f64::INFINITY, f64::min);
                let at_point =
                    motion.velocity + perp(&(impact.point - g)) * motion.angular_velocity;
                Striker {
                    impact: *impact,
                    contacts,
                    position,
                    velocity: impact.normal.dot(&at_point) + impact.speed,
                    force: 0.0,
                }
            })
            .collect();
        let impact_energy = match impacts {
            [impact] => {
                let mu = if impact.mass.is_finite() {
                    impact.mass * total / (impact.mass + total)
                } else {
                    total
                };
                0.5 * mu * impact.speed * impact.speed
            }
            _ => {
                let inertia: f64 = x
                    .iter()
                    .zip(m)
                    .map(|(p, &mi)| mi * (p - g).norm_squared())
                    .sum();
                let velocity: Vec<f64> = strikers.iter().map(|s| s.velocity).collect();
                impact_energy_bound(total, inertia, motion, impacts, &velocity)
            }
        };
        let radius = x.iter().map(|p| (p - g).norm()).fold(0.0, f64::max);
        let wave = (spec.young / (spec.density * (1.0 - spec.poisson * spec.poisson))).sqrt();
        let mut sides = vec![[usize::MAX; 2]; lattice.springs.len()];
        for (t, row) in lattice.triangle_springs.iter().enumerate() {
            for &(k, _) in row {
                let side = if sides[k][0] == usize::MAX { 0 } else { 1 };
                sides[k][side] = t;
            }
        }
        let mut p = Percussion {
            lattice,
            force: vec![Vec2::zeros(); x.len()],
            x,
            v,
            links,
            cohesive,
            intact: vec![true; lattice.triangles.len()],
            sides,
            strikers,
            contact_moment: 0.0,
            impulse: Vec2::zeros(),
            impulse_moment: 0.0,
            work: 0.0,
            t: 0.0,
            dt: 0.0,
            steps: 0,
            broken: Vec::new(),
            transit: 2.0 * radius / wave,
            impact_energy,
            options,
        };
        p.dt = options.safety * p.stable_step();
        p.forces();
        Ok(p)
    }
}
