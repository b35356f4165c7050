//! The 2D percussion of a floe (docs/physics.md §7.3): the floe's lattice
//! ([`super::Lattice`]) integrated from a rigid impact, the striker an
//! effective mass in unilateral contact with it, bonds breaking, and the
//! connected components of the broken lattice becoming rigid pieces.
//!
//! **Scheme.** The lattice's springs are geometrically exact central
//! springs (force `κ (|x_j − x_i| − L₀)` along the current direction, so a
//! rigid rotation loads nothing) in parallel with dashpots
//! `c = β √(κ m_ij)` (`m_ij = 2 m_i m_j / (m_i + m_j)`, `β` the chain's
//! damping ratio, 0.5 by default, [`ChainOptions`]), and, when the lattice
//! has them (Poisson ratio below 1/3), its torsion springs with their
//! geometrically exact forces ([`Lattice::torsion_forces`]), undamped. The
//! striker is a rigid
//! half-plane of effective mass `m*` (kg, `∞` for an obstacle) moving along
//! the impact normal `n` (pointing into the floe); it pushes each outline
//! node through a compression-only penalty link (the chain's unilateral
//! link, rest length 0) of the lattice's mean spring stiffness `κ̄` and its
//! dashpot `β √(κ̄ m_i*)` (`m_i*` the reduced mass of the node and the
//! striker): a penalty, not an exact contact. A half-plane is what a coast
//! is, and a face of another floe near the contact point. Several strikers
//! can act at once ([`Percussion::with_strikers`], a floe squeezed between
//! two bodies), each its own half-plane, mass and contact links; the
//! impact energy bound is then [`impact_energy_bound`] (docs/physics.md §9.8).
//!
//! A bond breaks, for good, when its elongation passes `δ_c`
//! ([`crate::fracture::chain::BondRule::critical`]): with a toughness `G` the energy `½ κ δ²` it
//! holds reaches `G h w`, `w = 2 A_e / L₀` the width of its share of the
//! triangles (`A_e` a third of each adjacent triangle's area): the facet it
//! opens (`s/√3`, the Voronoi facet, in an equilateral lattice of spacing
//! `s`). A broken bond becomes a compression-only link, and the triangles on
//! its sides lose their torsion springs, whose energy is booked with the
//! bond's.
//!
//! **Integrator.** The chain's velocity Verlet ([`super::super::chain`]) at
//! the damped stable step `s (2/ω)(√(1+ζ²) − ζ)`, `ω` the block-Gershgorin
//! bound on the highest frequency of `M^{-½} K M^{-½}` (springs and every
//! possible contact), `ω² ≤ max_i Σ_j κ_ij (1/m_i + 1/√(m_i m_j))` plus
//! the torsion springs' `Σ c |∇_i θ| Σ_j |∇_j θ| / √(m_i m_j)` over the
//! corners of node `i` (their blocks `c ∇_i θ ∇_j θᵀ`), and `ζ`
//! the same bound on the dashpots over `2ω`; safety `s` (0.9 by default).
//! The geometric stiffness of a stretched spring, `O(strain)`, is left out
//! of the bound.
//!
//! **Stopping rule** (the chain's, [`super::super::chain::Stop`]): the
//! contact is over when no outline node touches the striker and the striker
//! is no faster along `n` than the rigid motion of any piece within one
//! lattice spacing of it, at its node nearest the striker (a piece further
//! away, spinning, can have a node moving towards the striker for ever); the waves have settled when the internal energy (kinetic
//! and elastic, less the pieces' and the striker's rigid kinetic energy) is
//! under `settle` times the impact energy `½ μ u_N²` (`μ` the reduced mass
//! of `m*` and the floe), or `settle_transits` transit times (the floe's
//! diameter over the P-wave speed `√(E / (ρ (1 − ν²)))`, ν the lattice's) have passed since
//! the contact ended; in any case after `limit_transits` transit times.
//!
//! References: D. Balasoiu (2020), PhD thesis, Université Grenoble Alpes
//! (the percussion by an effective mass); T. Belytschko, W. K. Liu and
//! B. Moran (2000), *Nonlinear finite elements for continua and
//! structures*, §6.3 (the stable step with damping); A. M. Andrew (1979),
//! *Information Processing Letters* 9(5) (the convex hull).
//!
//! [`critical_ram_speed`] finds, by bisection, the least speed at which a
//! floe rammed into a coast ([`ram`]) breaks.

use super::{corner_angle, Lattice};
use crate::fracture::chain::{
    damped_stable_step, drift, kick, ChainOptions, Energies, Link, Settling, Stop,
};
use crate::geometry::{area_properties, convex_hull, cross, perp, Vec2};

/// The rigid impact that starts a percussion, in the lattice's frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impact {
    /// The contact point, m.
    pub point: Vec2,
    /// The unit normal, pointing into the struck floe (the striker pushes
    /// along it).
    pub normal: Vec2,
    /// The striker's effective mass along the normal, kg (`f64::INFINITY`
    /// for an obstacle or a coast).
    pub mass: f64,
    /// The relative normal speed of approach, m/s (> 0).
    pub speed: f64,
}

/// The floe's rigid motion at the impact: velocity of its centre of mass
/// (m/s) and angular velocity (rad/s).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RigidMotion {
    /// Velocity of the centre of mass, m/s.
    pub velocity: Vec2,
    /// Angular velocity, rad/s.
    pub angular_velocity: f64,
}

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
        let mass: f64 = list.iter().map(|&i| m[i]).sum();
        let centre = list.iter().map(|&i| x[i] * m[i]).sum::<Vec2>() / mass;
        let momentum: Vec2 = list.iter().map(|&i| v[i] * m[i]).sum();
        let velocity = momentum / mass;
        let (mut l, mut inertia) = (0.0, 0.0);
        for &i in &list {
            let r = x[i] - centre;
            l += m[i] * cross(&r, &(v[i] - velocity));
            inertia += m[i] * r.norm_squared();
        }
        let points: Vec<Vec2> = list.iter().map(|&i| x[i]).collect();
        let hull = convex_hull(&points);
        let area = if hull.len() >= 3 {
            area_properties(&hull).area
        } else {
            0.0
        };
        Fragment {
            nodes: list,
            mass,
            centre,
            momentum,
            angular_momentum: l,
            inertia,
            velocity,
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

/// A percussion under way: the lattice's state and the striker's.
#[derive(Debug, Clone)]
pub struct Percussion<'a> {
    lattice: &'a Lattice,
    /// Node positions, m.
    pub x: Vec<Vec2>,
    /// Node velocities, m/s.
    pub v: Vec<Vec2>,
    links: Vec<Link>,
    /// Whether each triangle keeps its torsion springs (until one of its
    /// edges breaks).
    intact: Vec<bool>,
    /// The triangles on each side of each spring (`usize::MAX` for none).
    sides: Vec<[usize; 2]>,
    /// The strikers (one per impact), each with its contact links.
    strikers: Vec<Striker>,
    force: Vec<Vec2>,
    contact_moment: f64,
    /// Impulse (N·s) the strikers gave the floe so far.
    pub impulse: Vec2,
    /// Moment of that impulse about the frame's origin, N·m·s.
    pub impulse_moment: f64,
    /// Work (J) done on the floe by the strikers of infinite mass (which
    /// keep their velocity; 0 for a striker at rest and for a finite mass,
    /// whose kinetic energy is counted instead).
    pub work: f64,
    /// Time since the impact, s.
    pub t: f64,
    /// The step, s.
    pub dt: f64,
    /// Steps taken.
    pub steps: u64,
    /// The springs broken so far.
    pub broken: Vec<BrokenSpring>,
    /// Transit time of a P wave across the floe, s.
    pub transit: f64,
    /// The impact energy bound `B` (`½ μ u_N²` for one striker,
    /// [`impact_energy_bound`] for several), J.
    pub impact_energy: f64,
    options: ChainOptions,
}

/// One striker of a percussion: a rigid half-plane along its impact's
/// normal, in unilateral contact with every outline node.
#[derive(Debug, Clone)]
struct Striker {
    impact: Impact,
    /// The outline nodes and their contact links with this striker.
    contacts: Vec<(usize, Link)>,
    /// Its position along the normal (its face is the line
    /// `n · (x − point) = position`), m.
    position: f64,
    /// Its velocity along the normal, m/s.
    velocity: f64,
    /// The force of its contacts (along `−n` on the nodes), N.
    force: f64,
}

impl Striker {
    /// Its kinetic energy along the normal (0 for an infinite mass), J.
    fn energy(&self) -> f64 {
        if self.impact.mass.is_finite() {
            0.5 * self.impact.mass * self.velocity * self.velocity
        } else {
            0.0
        }
    }
}

/// The bound `B` (J) on the energy a percussion of a floe (mass `mass`, kg;
/// polar inertia `inertia` about its centre of mass, kg·m²; rigid motion
/// `motion`) by several strikers can put into its deformation, dashpots
/// and broken bonds (docs/physics.md §9.8): each striker `k` moves along
/// its normal `n_k` at `s_k` (`velocity[k]`, m/s, in the lattice's frame).
/// In an inertial frame moving at `W` in which every infinite striker is
/// at rest along its normal (`n_k · W = s_k`), no striker does work (a
/// half-plane pushes along its normal only), so the energy there,
/// `½ M |V − W|² + ½ I ω² + Σ_finite ½ m_k (s_k − n_k · W)²` at the start,
/// bounds `V + D + F` for ever. `B` is its least value over the admissible
/// `W`; `∞` when the infinite strikers admit no common frame (rigid walls
/// closing on the floe crush it without limit). One finite striker and a
/// floe at rest give `½ μ_G u²`, `μ_G = m M/(m + M)`; one infinite, `½ M u²`.
pub fn impact_energy_bound(
    mass: f64,
    inertia: f64,
    motion: RigidMotion,
    impacts: &[Impact],
    velocity: &[f64],
) -> f64 {
    let v = motion.velocity;
    let energy = |w: &Vec2| {
        let mut e = 0.5 * mass * (v - w).norm_squared()
            + 0.5 * inertia * motion.angular_velocity * motion.angular_velocity;
        for (i, s) in impacts.iter().zip(velocity) {
            if i.mass.is_finite() {
                let d = s - i.normal.dot(w);
                e += 0.5 * i.mass * d * d;
            }
        }
        e
    };
    let walls: Vec<(Vec2, f64)> = impacts
        .iter()
        .zip(velocity)
        .filter(|(i, _)| i.mass.is_infinite())
        .map(|(i, &s)| (i.normal, s))
        .collect();
    // The quadratic's matrix M 1 + Σ m n nᵀ and right-hand side M V + Σ m s n.
    let (mut a, mut b) = (nalgebra::Matrix2::identity() * mass, v * mass);
    for (i, &s) in impacts.iter().zip(velocity) {
        if i.mass.is_finite() {
            a += i.normal * i.normal.transpose() * i.mass;
            b += i.normal * (i.mass * s);
        }
    }
    let w = match walls.first() {
        None => match a.try_inverse() {
            Some(inv) => inv * b,
            None => return f64::INFINITY,
        },
        Some(&(n0, s0)) => {
            let other = walls.iter().find(|(n, _)| cross(&n0, n).abs() > 1e-9);
            match other {
                // Two walls that are not parallel fix W.
                Some(&(n1, s1)) => {
                    let det = cross(&n0, &n1);
                    Vec2::new(s0 * n1.y - s1 * n0.y, n0.x * s1 - n1.x * s0) / det
                }
                // Parallel walls fix W along n0; the rest minimises.
                None => {
                    let t = perp(&n0);
                    let base = n0 * s0;
                    let along = (t.transpose() * a * t)[0];
                    let rhs = t.dot(&(b - a * base));
                    base + t * (rhs / along)
                }
            }
        }
    };
    let scale = walls.iter().map(|(_, s)| s.abs()).fold(0.0, f64::max);
    if walls
        .iter()
        .any(|(n, s)| (n.dot(&w) - s).abs() > 1e-9 * scale.max(f64::MIN_POSITIVE))
    {
        return f64::INFINITY;
    }
    energy(&w)
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
        let g = lattice
            .nodes
            .iter()
            .zip(m)
            .map(|(x, &mi)| x * mi)
            .sum::<Vec2>()
            / total;
        let x = lattice.nodes.clone();
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
        let links: Vec<Link> = lattice
            .springs
            .iter()
            .zip(&share)
            .map(|(s, &a)| {
                let [i, j] = s.nodes;
                let mij = 2.0 * m[i] * m[j] / (m[i] + m[j]);
                let width = 2.0 * a / s.length;
                Link {
                    k: s.stiffness,
                    c: options.damping * (s.stiffness * mij).sqrt(),
                    rest: s.length,
                    bonded: true,
                    critical: options
                        .bond
                        .critical(s.stiffness, s.length, spec.thickness * width),
                }
            })
            .collect();
        let mean_k =
            lattice.springs.iter().map(|s| s.stiffness).sum::<f64>() / lattice.springs.len() as f64;
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

    /// The stable step of the scheme, s (module doc).
    pub fn stable_step(&self) -> f64 {
        let m = &self.lattice.mass;
        let n = m.len();
        let rows = n + self.strikers.len();
        let (mut ks, mut cs) = (vec![0.0; rows], vec![0.0; rows]);
        let mut add = |i: usize, j: usize, mi: f64, mj: f64, l: &Link| {
            let w = 1.0 / mi + 1.0 / (mi * mj).sqrt();
            ks[i] += l.k * w;
            cs[i] += l.c * w;
            let w = 1.0 / mj + 1.0 / (mi * mj).sqrt();
            ks[j] += l.k * w;
            cs[j] += l.c * w;
        };
        for (s, l) in self.lattice.springs.iter().zip(&self.links) {
            let [i, j] = s.nodes;
            add(i, j, m[i], m[j], l);
        }
        // Striker k is unknown n + k (infinite mass: its row is empty).
        for (k, st) in self.strikers.iter().enumerate() {
            for (i, l) in &st.contacts {
                add(*i, n + k, m[*i], st.impact.mass, l);
            }
        }
        // A torsion spring's linearised stiffness is c ∇θ ∇θᵀ: its (i, j)
        // block has norm c |∇_i θ| |∇_j θ|.
        for c in &self.lattice.corners {
            for (&i, gi) in c.nodes.iter().zip(&c.grad) {
                let row: f64 = c
                    .nodes
                    .iter()
                    .zip(&c.grad)
                    .map(|(&j, gj)| gj.norm() / (m[i] * m[j]).sqrt())
                    .sum();
                ks[i] += c.stiffness * gi.norm() * row;
            }
        }
        let omega = ks.iter().fold(0.0, |a: f64, &b| a.max(b)).sqrt();
        let gamma = cs.iter().fold(0.0, |a: f64, &b| a.max(b));
        damped_stable_step(omega, gamma / (2.0 * omega))
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether the lattice has no node (never, once built).
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Elongation (m), its rate (m/s) and direction of spring `k`.
    fn spring_state(&self, k: usize) -> (f64, f64, Vec2) {
        let [i, j] = self.lattice.springs[k].nodes;
        let d = self.x[j] - self.x[i];
        let l = d.norm();
        let dir = d / l;
        (
            l - self.links[k].rest,
            dir.dot(&(self.v[j] - self.v[i])),
            dir,
        )
    }

    /// Gap (m) and its rate (m/s) between striker `k` and node `i`.
    fn gap(&self, k: usize, i: usize) -> (f64, f64) {
        let s = &self.strikers[k];
        let n = s.impact.normal;
        (
            n.dot(&(self.x[i] - s.impact.point)) - s.position,
            n.dot(&self.v[i]) - s.velocity,
        )
    }

    /// Whether an outline node touches a striker.
    fn touching(&self) -> bool {
        self.strikers
            .iter()
            .enumerate()
            .any(|(k, s)| s.contacts.iter().any(|&(i, _)| self.gap(k, i).0 < 0.0))
    }

    /// The node forces and the striker's at the current state, N.
    fn forces(&mut self) {
        self.force.iter_mut().for_each(|f| *f = Vec2::zeros());
        for k in 0..self.links.len() {
            let (d, dv, dir) = self.spring_state(k);
            let f = self.links[k].force(d, dv);
            let [i, j] = self.lattice.springs[k].nodes;
            self.force[i] += dir * f;
            self.force[j] -= dir * f;
        }
        let intact = &self.intact;
        self.lattice
            .torsion_forces(&self.x, |t| intact[t], &mut self.force);
        self.contact_moment = 0.0;
        for k in 0..self.strikers.len() {
            let mut total = 0.0;
            let normal = self.strikers[k].impact.normal;
            for c in 0..self.strikers[k].contacts.len() {
                let (i, link) = self.strikers[k].contacts[c];
                let (g, dg) = self.gap(k, i);
                let f = link.force(g, dg);
                if f != 0.0 {
                    let push = -normal * f;
                    self.force[i] += push;
                    total += f;
                    self.contact_moment += cross(&self.x[i], &push);
                }
            }
            self.strikers[k].force = total;
        }
    }

    /// The impulse of the contact forces of the last [`Self::forces`]
    /// over `h` seconds, added to the running totals.
    fn book_contact(&mut self, h: f64) {
        for s in &self.strikers {
            self.impulse -= s.impact.normal * (s.force * h);
        }
        self.impulse_moment += self.contact_moment * h;
        for s in &self.strikers {
            if s.impact.mass.is_infinite() {
                self.work -= s.velocity * s.force * h;
            }
        }
    }

    /// Breaks every bond stretched past its critical elongation; the
    /// triangles on its sides lose their torsion springs, whose energy goes
    /// with the bond's.
    fn break_bonds(&mut self) {
        for k in 0..self.links.len() {
            let (d, _, _) = self.spring_state(k);
            let l = &mut self.links[k];
            if l.bonded && d > l.critical {
                l.bonded = false;
                let mut energy = 0.5 * l.k * d * d;
                for t in self.sides[k] {
                    if t != usize::MAX && self.intact[t] {
                        energy += self.triangle_torsion_energy(t);
                        self.intact[t] = false;
                    }
                }
                self.broken.push(BrokenSpring {
                    spring: k,
                    t: self.t,
                    energy,
                });
            }
        }
    }

    /// The energy of triangle `t`'s torsion springs now, J.
    fn triangle_torsion_energy(&self, t: usize) -> f64 {
        self.lattice
            .corners
            .iter()
            .skip(3 * t)
            .take(3)
            .map(|c| {
                let [o, a, b] = c.nodes;
                let d = corner_angle(&self.x[o], &self.x[a], &self.x[b]).0 - c.angle;
                0.5 * c.stiffness * d * d
            })
            .sum()
    }

    /// Half a kick of the strikers.
    fn kick_striker(&mut self, h: f64) {
        for s in &mut self.strikers {
            if s.impact.mass.is_finite() {
                s.velocity += h * s.force / s.impact.mass;
            }
        }
    }

    /// One velocity Verlet step.
    pub fn step(&mut self) {
        let h = 0.5 * self.dt;
        self.book_contact(h);
        kick(&mut self.v, &self.force, &self.lattice.mass, h);
        self.kick_striker(h);
        drift(&mut self.x, &self.v, self.dt);
        for s in &mut self.strikers {
            s.position += self.dt * s.velocity;
        }
        self.t += self.dt;
        self.steps += 1;
        self.break_bonds();
        self.forces();
        self.book_contact(h);
        kick(&mut self.v, &self.force, &self.lattice.mass, h);
        self.kick_striker(h);
    }

    /// The energies now (the strikers' kinetic energy when their mass is
    /// finite).
    pub fn energies(&self) -> Energies {
        let striker = self.striker_energy();
        let springs: f64 = (0..self.links.len())
            .map(|k| self.links[k].energy(self.spring_state(k).0))
            .sum();
        let contacts: f64 = self
            .strikers
            .iter()
            .enumerate()
            .map(|(k, s)| {
                s.contacts
                    .iter()
                    .map(|&(i, l)| l.energy(self.gap(k, i).0))
                    .sum::<f64>()
            })
            .sum();
        let torsion: f64 = (0..self.intact.len())
            .filter(|&t| self.intact[t])
            .map(|t| self.triangle_torsion_energy(t))
            .sum();
        Energies {
            torsion,
            kinetic: striker
                + self
                    .lattice
                    .mass
                    .iter()
                    .zip(&self.v)
                    .map(|(m, v)| 0.5 * m * v.norm_squared())
                    .sum::<f64>(),
            elastic: springs + contacts,
            fracture: self.broken.iter().map(|b| b.energy).sum(),
        }
    }

    /// Linear momentum (kg·m/s) and angular momentum about the frame's
    /// origin (kg·m²/s) of the nodes.
    pub fn momentum(&self) -> (Vec2, f64) {
        let m = &self.lattice.mass;
        (
            (0..self.len()).map(|i| self.v[i] * m[i]).sum(),
            (0..self.len())
                .map(|i| m[i] * cross(&self.x[i], &self.v[i]))
                .sum(),
        )
    }

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

    /// The strikers' kinetic energy along their normals, J.
    fn striker_energy(&self) -> f64 {
        self.strikers.iter().map(Striker::energy).sum()
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

    /// The smallest energy that breaks a bond, `½ κ δ_c²` over the springs,
    /// J (`∞` for unbreakable bonds): the trigger bound's threshold
    /// (docs/physics.md §9.8).
    pub fn weakest_bond_energy(&self) -> f64 {
        self.links
            .iter()
            .map(|l| 0.5 * l.k * l.critical * l.critical)
            .fold(f64::INFINITY, f64::min)
    }

    /// Whether spring `k` still holds.
    pub fn bonded(&self, k: usize) -> bool {
        self.links[k].bonded
    }

    /// The lattice.
    pub fn lattice(&self) -> &Lattice {
        self.lattice
    }
}

/// The rule a bond breaks by, for a lattice of `spacing` (m) and Young's
/// modulus `young` (Pa): the critical strain `√(4 G / (3 E s))` a toughness
/// `G` amounts to in an equilateral lattice (docs/physics.md §7.3).
pub fn strain_of_toughness(toughness: f64, young: f64, spacing: f64) -> f64 {
    (4.0 * toughness / (3.0 * young * spacing)).sqrt()
}

/// The percussion of `lattice`'s floe rammed at `speed` (m/s) along
/// `normal` (unit, into the floe) into a fixed coast touching it at
/// `point` (m): the floe moves rigidly at `−speed · normal`, the striker is
/// an obstacle at rest ([`Impact::mass`] infinite).
pub fn ram(
    lattice: &Lattice,
    point: Vec2,
    normal: Vec2,
    speed: f64,
    options: ChainOptions,
) -> Result<Outcome, String> {
    let motion = RigidMotion {
        velocity: -normal * speed,
        angular_velocity: 0.0,
    };
    let impact = Impact {
        point,
        normal,
        mass: f64::INFINITY,
        speed,
    };
    Ok(Percussion::new(lattice, motion, impact, options)?.run())
}

/// What counts as a break in [`critical_ram_speed`] (docs/physics.md §7.3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Break {
    /// At least two pieces of this many nodes or more (a piece of fewer is
    /// debris). A fixed node count is a piece whose size shrinks with the
    /// spacing.
    Pieces(usize),
    /// At least two pieces each holding this fraction (in `(0, 0.5]`) of
    /// the floe's mass or more: a piece of a fixed physical size.
    MassFraction(f64),
    /// Any bond broken: the onset of damage, where the lattice's largest
    /// bond strain reaches the critical one.
    FirstBond,
}

impl Break {
    /// Whether the percussion `outcome` of a floe of mass `total` (kg) is a
    /// break.
    pub fn holds(&self, outcome: &Outcome, total: f64) -> bool {
        match *self {
            Break::Pieces(n) => {
                outcome
                    .fragments
                    .iter()
                    .filter(|f| f.nodes.len() >= n)
                    .count()
                    >= 2
            }
            Break::MassFraction(q) => {
                outcome
                    .fragments
                    .iter()
                    .filter(|f| f.mass >= q * total)
                    .count()
                    >= 2
            }
            Break::FirstBond => !outcome.broken.is_empty(),
        }
    }
}

/// The critical ramming speed of [`ram`], m/s: the least speed at which
/// the floe ends in at least two pieces of `min_nodes` nodes or more (a
/// piece of fewer is debris), found by doubling from 1 m/s until it
/// breaks (an error past `max_speed`), then bisection to `rel_tol` of the
/// speed (docs/physics.md §7.3). Bisection assumes that a floe that breaks
/// at a speed breaks at every higher one; returned is the upper end of the
/// last bracket (a speed that breaks it). [`critical_ram_speed_by`] with
/// [`Break::Pieces`].
pub fn critical_ram_speed(
    lattice: &Lattice,
    point: Vec2,
    normal: Vec2,
    options: ChainOptions,
    min_nodes: usize,
    rel_tol: f64,
    max_speed: f64,
) -> Result<f64, String> {
    critical_ram_speed_by(
        lattice,
        point,
        normal,
        options,
        Break::Pieces(min_nodes),
        rel_tol,
        max_speed,
    )
}

/// [`critical_ram_speed`] with what counts as a break given by `criterion`
/// (a criterion met at 1 m/s is bisected from `[0, 1]`).
pub fn critical_ram_speed_by(
    lattice: &Lattice,
    point: Vec2,
    normal: Vec2,
    options: ChainOptions,
    criterion: Break,
    rel_tol: f64,
    max_speed: f64,
) -> Result<f64, String> {
    if !(rel_tol > 0.0 && rel_tol < 1.0) {
        return Err(format!("the tolerance must be in (0, 1), got {rel_tol}"));
    }
    if let Break::MassFraction(q) = criterion {
        if !(q > 0.0 && q <= 0.5) {
            return Err(format!("the mass fraction must be in (0, 0.5], got {q}"));
        }
    }
    let total: f64 = lattice.mass.iter().sum();
    let breaks = |v: f64| -> Result<bool, String> {
        Ok(criterion.holds(&ram(lattice, point, normal, v, options)?, total))
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    while !breaks(hi)? {
        lo = hi;
        hi *= 2.0;
        if hi > max_speed {
            return Err(format!("the floe does not break up to {max_speed} m/s"));
        }
    }
    while hi - lo > rel_tol * hi {
        let mid = 0.5 * (lo + hi);
        if breaks(mid)? {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Ok(hi)
}

/// The mean and the sample standard deviation (m/s) of critical speeds
/// over seeds or mesh variants (the standard deviation 0 for one speed).
pub fn mean_and_deviation(speeds: &[f64]) -> (f64, f64) {
    let n = speeds.len() as f64;
    let mean = speeds.iter().sum::<f64>() / n;
    let var = speeds.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (mean, var.sqrt())
}
