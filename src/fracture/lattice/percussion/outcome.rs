//! What a percussion gives (docs/physics.md §7.3): the broken springs, the
//! pieces as rigid bodies ([`Fragment`]) and the [`Outcome`] of a run.

use crate::fracture::chain::{Energies, Stop};
use crate::geometry::{area_properties, convex_hull, cross, Vec2};

/// A spring that broke.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BrokenSpring {
    /// The spring (index in the lattice).
    pub spring: usize,
    /// When, s.
    pub t: f64,
    /// The energy it held, J.
    pub energy: f64,
}

/// A piece: a connected component of the lattice's unbroken springs, as a
/// rigid body.
#[derive(Debug, Clone, PartialEq)]
pub struct Fragment {
    /// Its nodes.
    pub nodes: Vec<usize>,
    /// Mass, kg.
    pub mass: f64,
    /// Centre of mass, m.
    pub centre: Vec2,
    /// Linear momentum, kg·m/s.
    pub momentum: Vec2,
    /// Angular momentum about its centre of mass, kg·m²/s.
    pub angular_momentum: f64,
    /// Polar inertia of its nodes about its centre of mass, kg·m².
    pub inertia: f64,
    /// Velocity of the centre of mass (momentum / mass), m/s.
    pub velocity: Vec2,
    /// Angular velocity (angular momentum / inertia; 0 for one node), rad/s.
    pub angular_velocity: f64,
    /// The convex hull of its nodes (counter-clockwise; fewer than 3
    /// vertices for one or two nodes), m.
    pub hull: Vec<Vec2>,
    /// The hull's area, m².
    pub area: f64,
}

impl Fragment {
    /// The rigid body of the nodes `list` at positions `x` (m) with
    /// velocities `v` (m/s) and masses `m` (kg): its mass, centre of mass,
    /// momenta, inertia and the convex hull of the positions.
    pub fn of_nodes(list: Vec<usize>, x: &[Vec2], v: &[Vec2], m: &[f64]) -> Fragment {
        let nm = NodeMotion::of(&list, x, v, m);
        let (l, inertia) = (nm.angular_momentum, nm.inertia);
        let points: Vec<Vec2> = list.iter().map(|&i| x[i]).collect();
        let hull = convex_hull(&points);
        let area = if hull.len() >= 3 {
            area_properties(&hull).area
        } else {
            0.0
        };
        Fragment {
            nodes: list,
            mass: nm.mass,
            centre: nm.centre,
            momentum: nm.momentum,
            angular_momentum: l,
            inertia,
            velocity: nm.velocity,
            angular_velocity: if inertia > 0.0 { l / inertia } else { 0.0 },
            hull,
            area,
        }
    }

    /// The kinetic energy of its rigid motion, `½ |P|²/M + ½ L²/I`, J.
    pub fn rigid_energy(&self) -> f64 {
        let spin = if self.inertia > 0.0 {
            0.5 * self.angular_momentum * self.angular_momentum / self.inertia
        } else {
            0.0
        };
        0.5 * self.momentum.norm_squared() / self.mass + spin
    }
}

/// The rigid motion of a set of nodes: its mass, centre of mass and
/// momenta (the sums behind [`Fragment`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(in crate::fracture::lattice) struct NodeMotion {
    /// Mass, kg.
    pub mass: f64,
    /// Centre of mass, m.
    pub centre: Vec2,
    /// Linear momentum, kg·m/s.
    pub momentum: Vec2,
    /// Velocity of the centre of mass, m/s.
    pub velocity: Vec2,
    /// Angular momentum about the centre of mass, kg·m²/s.
    pub angular_momentum: f64,
    /// Polar inertia of the nodes about the centre of mass, kg·m².
    pub inertia: f64,
}

impl NodeMotion {
    /// The nodes `list` at positions `x` (m) with velocities `v` (m/s)
    /// and masses `m` (kg).
    pub(in crate::fracture::lattice) fn of(
        list: &[usize],
        x: &[Vec2],
        v: &[Vec2],
        m: &[f64],
    ) -> NodeMotion {
        let mass: f64 = list.iter().map(|&i| m[i]).sum();
        let centre = list.iter().map(|&i| x[i] * m[i]).sum::<Vec2>() / mass;
        let momentum: Vec2 = list.iter().map(|&i| v[i] * m[i]).sum();
        let velocity = momentum / mass;
        let (mut l, mut inertia) = (0.0, 0.0);
        for &i in list {
            let r = x[i] - centre;
            l += m[i] * cross(&r, &(v[i] - velocity));
            inertia += m[i] * r.norm_squared();
        }
        NodeMotion {
            mass,
            centre,
            momentum,
            velocity,
            angular_momentum: l,
            inertia,
        }
    }
}

/// What a percussion gives.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// Why it stopped.
    pub reason: Stop,
    /// When, s after the impact.
    pub t: f64,
    /// When the contact ended, s.
    pub contact_end: f64,
    /// The step, s.
    pub dt: f64,
    /// Steps taken.
    pub steps: u64,
    /// Kinetic energy of the floe and a finite striker at the impact, J.
    pub initial_energy: f64,
    /// Work done by a striker of infinite mass, J (0 if it is at rest).
    pub work: f64,
    /// The impact energy `½ μ u_N²`, J.
    pub impact_energy: f64,
    /// Energies at the end (the striker's kinetic energy included when its
    /// mass is finite).
    pub energies: Energies,
    /// Without dashpots, the largest `|E(t) − E(0) − W(t)|` of kinetic +
    /// elastic + fracture energy `E` over the run, `W` the striker's work,
    /// J (0 with dashpots).
    pub energy_drift: f64,
    /// The pieces.
    pub fragments: Vec<Fragment>,
    /// The broken springs, in order.
    pub broken: Vec<BrokenSpring>,
    /// The (first) striker's velocity along the normal at the impact and
    /// at the end, m/s.
    pub striker_velocity: [f64; 2],
    /// Every striker's velocity along its normal at the impact and at the
    /// end, m/s, in the order of the impacts.
    pub striker_velocities: Vec<[f64; 2]>,
    /// The impulse the striker gave the floe, N·s.
    pub impulse: Vec2,
    /// Its moment about the frame's origin, N·m·s.
    pub impulse_moment: f64,
    /// The floe's linear momentum (kg·m/s) and angular momentum about the
    /// frame's origin (kg·m²/s) at the impact.
    pub initial_momentum: (Vec2, f64),
    /// The energy not in the rigid motion of the pieces and the striker:
    /// initial kinetic energy plus the striker's work, less their kinetic
    /// energy at the end, J (the dashpots', the broken bonds' and what
    /// still rings).
    pub fracture_energy: f64,
    /// `(Σ hull areas − lattice area) / lattice area` (-): the convex hulls
    /// against the exact partition of the outline.
    pub hull_area_error: f64,
}

impl Outcome {
    /// Total linear momentum of the pieces, kg·m/s.
    pub fn momentum(&self) -> Vec2 {
        self.fragments.iter().map(|f| f.momentum).sum()
    }

    /// Total angular momentum of the pieces about the frame's origin,
    /// kg·m²/s.
    pub fn angular_momentum(&self) -> f64 {
        self.fragments
            .iter()
            .map(|f| f.angular_momentum + cross(&f.centre, &f.momentum))
            .sum()
    }
}
