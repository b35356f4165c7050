//! The lattice model in the formulations (`[fracture] model = "lattice"`,
//! docs/physics.md §9.8): the equivalent rigid impact of a contact solve's
//! pair load, the trigger bound, the percussion of the struck floe's
//! lattice ([`super::lattice::percussion`]) and the rigid pieces it leaves.
//!
//! **Equivalent impact.** A solve put the impulse `P` on a floe at the
//! pair's centre of pressure `x`. Its normal `n` is `P/|P|` (pointing into
//! the floe; the contact normal for a frictionless pair, inside the friction
//! cone otherwise) and `P_n = |P|` (an upper bound of the normal impulse).
//! With `μ` the pair's effective mass along `n` at `x` (each floe's
//! `(1/m + (r × n)²/I)^{-1}`, `∞` for an obstacle, combined in series) and
//! `e` the restitution, the rigid law `P_n = (1 + e) μ u_N` gives the
//! approach speed `u_N`. The other body is the striker, of its own effective
//! mass along `n` at `x` (`∞` for an obstacle). The struck floe's lattice is
//! at rest in its body frame (its rigid motion, spin included, is the
//! formulation's, not the lattice's).
//!
//! Several pairs loading a floe in one solve are one percussion with a
//! striker each ([`equivalent_impacts`]: their approach speeds from the
//! floe's Delassus operator, all pairs active at once).
//!
//! **Trigger bound.** The percussion starts with the floe at rest and the
//! striker approaching at `u_N`; no energy is ever in the lattice's
//! deformation, dashpots and broken bonds beyond `½ μ_G u_N²`, `μ_G = m* M /
//! (m* + M)` (`M` for an obstacle): §9.8 proves it.
//! With several strikers the bound is the least energy over the inertial
//! frames that stop every infinite striker
//! ([`super::lattice::percussion::impact_energy_bound`]). A bond breaks only when
//! it holds its breaking energy `½ κ δ_c²` (a cohesive bond: when it has
//! taken `G h w`, elastic and softening), so an impact whose bound is below
//! the floe's weakest bond cannot break it and is skipped (`trigger =
//! "bound"`).
//!
//! **Pieces.** The lattice's connected components at the end of the
//! percussion, measured at the nodes' rest positions (the crack pattern on
//! the floe as it was) with their final velocities; a component of one
//! node, of fewer than three hull vertices or of area below `min_area` is
//! merged into the piece whose hull is nearest its centre. The rigid pieces
//! are the Voronoi cells of the components' centres of mass in the parent's
//! outline ([`pieces`]): convex and a partition of the parent, where the
//! convex hulls of jagged components overlap.
//!
//! References: D. Balasoiu (2020), PhD thesis, Université Grenoble Alpes
//! (the percussion by an effective mass).

use super::chain::{BondRule, ChainOptions};
use super::lattice::percussion::{strain_of_toughness, Fragment, Impact, Percussion, RigidMotion};
use super::lattice::{Lattice, LatticeSpec, Mesh};
use super::split::{self, Piece};
use super::PairLoad;
use crate::geometry::{area_properties, cross, perp, point_polygon_signed_distance, rotate, Vec2};
pub use crate::model::fracture::lattice_spacing;
use crate::model::fracture::{cohesive_onset_strain, FractureSettings, LatticeMesh, LatticeRule};
use crate::model::{Body, Floe, Scenario};
use crate::state::{BodyState, System};

/// The lattice of `floe` in the case's `[fracture]` table: its spacing
/// ([`lattice_spacing`]), its thickness and density, `young` and
/// `seed`. The one place a [`LatticeSpec`] of a run is made.
pub fn lattice_spec(s: &FractureSettings, floe: &Floe) -> LatticeSpec {
    LatticeSpec {
        spacing: lattice_spacing(s, floe.area, &floe.shape),
        thickness: floe.thickness,
        density: floe.density,
        young: s.young,
        poisson: s.poisson,
        seed: s.seed,
        mesh: match s.mesh {
            LatticeMesh::Random => Mesh::Random,
            LatticeMesh::Triangular => Mesh::triangular_variant(0.0, s.seed),
        },
    }
}

/// The largest centrifugal strain of a spinning floe over its bonds'
/// nominal breaking strain that the lattice model neglects (docs/physics.md
/// §9.8): the lattice starts unstressed in the floe's body frame, so a
/// floe's own spin must not pre-stretch its bonds by more than 1 % of what
/// breaks them (the critical speed then moves by about 1 % or less, far
/// below the 15–20 % scatter of the lattice's disorder, §7.3).
pub const SPIN_PRESTRESS_LIMIT: f64 = 0.01;

/// The centrifugal pre-strain of a floe spinning at `omega` (rad/s) over its
/// bonds' nominal breaking strain, for a floe of density `density`
/// (kg/m³), circumradius `radius` (m) about its centre of mass and lattice
/// spacing `spacing` (m) (docs/physics.md §9.8): the peak stress of a
/// spinning disc of radius `R`, `(3 + ν)/8 ρ ω² R²` (plane stress, at its
/// centre), over `E`, against the rule's strain `ε_c` (`critical_strain`,
/// `√(4 G/(3 E s))` for a toughness, the equilateral lattice's, or the
/// cohesive rule's onset of softening `σ_t (1 − ν)/E`). The
/// disc of radius `R` holds the floe.
pub fn spin_prestress(
    s: &FractureSettings,
    density: f64,
    radius: f64,
    omega: f64,
    spacing: f64,
) -> f64 {
    let critical = match s.rule {
        LatticeRule::Strain => s.critical_strain,
        LatticeRule::Toughness => strain_of_toughness(s.toughness, s.young, spacing),
        LatticeRule::Cohesive => cohesive_onset_strain(s.strength, s.young, s.poisson),
    };
    (3.0 + s.poisson) / 8.0 * density * (omega * radius).powi(2) / (s.young * critical)
}

/// The percussion options of the case: its dashpot ratio and bond rule.
pub fn chain_options(s: &FractureSettings) -> ChainOptions {
    ChainOptions {
        damping: s.damping,
        bond: match s.rule {
            LatticeRule::Toughness => BondRule::Toughness(s.toughness),
            LatticeRule::Strain => BondRule::Strain(s.critical_strain),
            LatticeRule::Cohesive => BondRule::Cohesive {
                toughness: s.toughness,
                strength: s.strength,
            },
        },
        ..ChainOptions::default()
    }
}

/// The effective mass (kg) of body `body` along the unit `n` at the world
/// point `x`: `(1/m + (r × n)²/I)^{-1}`, `∞` for an obstacle.
pub fn effective_mass(scn: &Scenario, sys: &System, body: usize, x: &Vec2, n: &Vec2) -> f64 {
    match scn.body(body) {
        Body::Floe(i) => {
            let f = &scn.floes[i];
            let rn = cross(&(x - sys.bodies[i].position), n);
            1.0 / (1.0 / f.mass + rn * rn / f.inertia)
        }
        _ => f64::INFINITY,
    }
}

/// The equivalent rigid impact of pair `pair` on floe `floe` (module doc),
/// in the floe's body frame, with the reduced mass `μ` (kg) of the rigid
/// law; `None` without an impulse.
pub fn equivalent_impact(
    scn: &Scenario,
    sys: &System,
    floe: usize,
    pair: &PairLoad,
) -> Option<(Impact, f64)> {
    let pn = pair.impulse.norm();
    if !(pn.is_finite() && pn > 0.0) {
        return None;
    }
    let n = pair.impulse / pn;
    let own = effective_mass(scn, sys, floe, &pair.point, &n);
    let striker = effective_mass(scn, sys, pair.other, &pair.point, &n);
    let mu = 1.0 / (1.0 / own + 1.0 / striker);
    let speed = pn / ((1.0 + scn.contact.restitution) * mu);
    let b = &sys.bodies[floe];
    Some((
        Impact {
            point: rotate(&(pair.point - b.position), -b.angle),
            normal: rotate(&n, -b.angle),
            mass: striker,
            speed,
        },
        mu,
    ))
}

/// The equivalent rigid impacts of all the pairs `pairs` loading floe
/// `floe` in one solve, in the floe's body frame (docs/physics.md §9.8):
/// the approach speeds `u` that, with every pair active at once, give the
/// solve's impulses under the rigid law, `(1 + e) u = G P`, `G` the
/// Delassus operator of the floe and its strikers along the pairs' normals
/// (`G_kl = n_k · n_l / M + (r_k × n_k)(r_l × n_l)/I + δ_kl / m*_k`, each
/// striker on its own, of its effective mass `m*_k`, `∞` for an obstacle).
/// One pair gives [`equivalent_impact`]'s. When two or more obstacles load
/// the floe their speeds are replaced by those of one common frame `W`
/// fitted to them by least squares (`u_k = n_k · W`): the obstacles are one
/// fixed world, and rigid walls approaching the floe at speeds no common
/// frame has would crush it without limit. Pairs without an impulse are
/// left out; `None` if none is left.
pub fn equivalent_impacts(
    scn: &Scenario,
    sys: &System,
    floe: usize,
    pairs: &[PairLoad],
) -> Option<Vec<Impact>> {
    let pairs: Vec<&PairLoad> = pairs
        .iter()
        .filter(|p| {
            let n = p.impulse.norm();
            n.is_finite() && n > 0.0
        })
        .collect();
    if let [one] = pairs[..] {
        return equivalent_impact(scn, sys, floe, one).map(|(i, _)| vec![i]);
    }
    if pairs.is_empty() {
        return None;
    }
    let f = &scn.floes[floe];
    let b = &sys.bodies[floe];
    let e = 1.0 + scn.contact.restitution;
    let normal: Vec<Vec2> = pairs.iter().map(|p| p.impulse / p.impulse.norm()).collect();
    let arm: Vec<f64> = pairs
        .iter()
        .zip(&normal)
        .map(|(p, n)| cross(&(p.point - b.position), n))
        .collect();
    let striker: Vec<f64> = pairs
        .iter()
        .zip(&normal)
        .map(|(p, n)| effective_mass(scn, sys, p.other, &p.point, n))
        .collect();
    let mut speed: Vec<f64> = (0..pairs.len())
        .map(|k| {
            let own: f64 = (0..pairs.len())
                .map(|l| {
                    pairs[l].impulse.norm()
                        * (normal[k].dot(&normal[l]) / f.mass + arm[k] * arm[l] / f.inertia)
                })
                .sum();
            (own + pairs[k].impulse.norm() / striker[k]) / e
        })
        .collect();
    let walls: Vec<usize> = (0..pairs.len())
        .filter(|&k| striker[k].is_infinite())
        .collect();
    if walls.len() >= 2 {
        let mut a = nalgebra::Matrix2::zeros();
        let mut rhs = Vec2::zeros();
        for &k in &walls {
            a += normal[k] * normal[k].transpose();
            rhs += normal[k] * speed[k];
        }
        let w = match a
            .try_inverse()
            .filter(|_| a.determinant() > 1e-9 * a.trace().powi(2))
        {
            Some(inv) => inv * rhs,
            // Parallel walls: W along their common line.
            None => {
                let n0 = normal[walls[0]];
                n0 * (walls
                    .iter()
                    .map(|&k| speed[k] * normal[k].dot(&n0))
                    .sum::<f64>()
                    / walls.len() as f64)
            }
        };
        for &k in &walls {
            speed[k] = normal[k].dot(&w);
        }
    }
    let impacts: Vec<Impact> = (0..pairs.len())
        .map(|k| Impact {
            point: rotate(&(pairs[k].point - b.position), -b.angle),
            normal: rotate(&normal[k], -b.angle),
            mass: striker[k],
            speed: speed[k],
        })
        .collect();
    impacts
        .iter()
        .all(|i| i.speed.is_finite())
        .then_some(impacts)
}

/// What a percussion made of a floe, in its body frame: the pieces (at
/// least two; rest positions, final velocities of the lattice run) and the
/// lattice's totals.
#[derive(Debug, Clone, PartialEq)]
pub struct LatticeSplit {
    /// The pieces.
    pub pieces: Vec<Fragment>,
    /// The energy the lattice did not return to the rigid motion of the
    /// pieces and the striker, J ([`super::lattice::percussion::Outcome::fracture_energy`]).
    pub loss: f64,
    /// Bonds broken.
    pub broken: usize,
    /// The springs that broke, in the order they broke (the crack,
    /// [`super::crack`]).
    pub bonds: Vec<usize>,
    /// The impacts that broke it (one striker each, [`strike_all`]).
    pub impacts: Vec<Impact>,
}

/// The outcome of one triggered impact: the impact energy bound (J), the
/// weakest bond's breaking energy (J), and the pieces when the floe broke.
#[derive(Debug, Clone, PartialEq)]
pub struct Strike {
    /// `½ μ_G u_N²`, J.
    pub bound: f64,
    /// The floe's weakest bond, `½ κ δ_c²`, J.
    pub weakest: f64,
    /// Whether the percussion ran (`trigger = "always"`, or the bound
    /// reached the weakest bond).
    pub ran: bool,
    /// Bonds the percussion broke (0 if it did not run).
    pub broken: usize,
    /// The split, when at least two pieces were left.
    pub split: Option<LatticeSplit>,
}

/// Runs the percussion of `impact` in `lattice` (trigger `always` runs it
/// whatever the bound) and gathers its pieces; `area_density` is `ρ h`
/// (kg/m²) and `min_area` (m²) the smallest piece. Fails when the
/// percussion refuses the impact.
pub fn strike(
    lattice: &Lattice,
    impact: Impact,
    options: ChainOptions,
    always: bool,
    min_area: f64,
    area_density: f64,
) -> Result<Strike, String> {
    strike_all(lattice, &[impact], options, always, min_area, area_density)
}

/// As [`strike`], for several impacts at once: one percussion with a
/// striker per impact ([`Percussion::with_strikers`]), its bound the
/// several strikers' ([`super::lattice::percussion::impact_energy_bound`]).
pub fn strike_all(
    lattice: &Lattice,
    impacts: &[Impact],
    options: ChainOptions,
    always: bool,
    min_area: f64,
    area_density: f64,
) -> Result<Strike, String> {
    let mut p = Percussion::with_strikers(lattice, RigidMotion::default(), impacts, options)?;
    let bound = p.impact_energy;
    let weakest = p.weakest_bond_energy();
    if !always && bound < weakest {
        return Ok(Strike {
            bound,
            weakest,
            ran: false,
            broken: 0,
            split: None,
        });
    }
    let o = p.run();
    let split = LatticeSplit {
        pieces: o
            .fragments
            .into_iter()
            .map(|f| Fragment::of_nodes(f.nodes, &lattice.nodes, &p.v, &lattice.mass))
            .collect(),
        loss: o.fracture_energy,
        broken: o.broken.len(),
        bonds: o.broken.iter().map(|b| b.spring).collect(),
        impacts: impacts.to_vec(),
    };
    Ok(Strike {
        bound,
        weakest,
        ran: true,
        broken: o.broken.len(),
        split: merged(split, lattice, &p.v, min_area, area_density),
    })
}

/// `split` with its components (`pieces`: every connected component of a
/// lattice run's unbroken springs, at rest positions, of node velocities
/// `v` in the lattice's frame) made floes: the small ones merged
/// ([`merge_small`]); `None` when fewer than two are left.
pub fn merged(
    mut split: LatticeSplit,
    lattice: &Lattice,
    v: &[Vec2],
    min_area: f64,
    area_density: f64,
) -> Option<LatticeSplit> {
    split.pieces = merge_small(
        std::mem::take(&mut split.pieces),
        &lattice.nodes,
        v,
        &lattice.mass,
        min_area,
        area_density,
    );
    (split.pieces.len() >= 2).then_some(split)
}

/// Merges every component too small to be a floe (one node, fewer than 3
/// hull vertices, or an area `mass / (ρ h)` below `min_area`) into the
/// large one whose hull is nearest its centre; the sums over nodes keep
/// total mass and momenta. Returns the large ones (none if there is none).
pub fn merge_small(
    fragments: Vec<Fragment>,
    x: &[Vec2],
    v: &[Vec2],
    m: &[f64],
    min_area: f64,
    area_density: f64,
) -> Vec<Fragment> {
    let small =
        |f: &Fragment| f.nodes.len() < 2 || f.hull.len() < 3 || f.mass / area_density < min_area;
    let (small, mut large): (Vec<Fragment>, Vec<Fragment>) = fragments.into_iter().partition(small);
    if large.is_empty() || small.is_empty() {
        return large;
    }
    let mut extra: Vec<Vec<usize>> = vec![Vec::new(); large.len()];
    for s in &small {
        let nearest = (0..large.len())
            .min_by(|&a, &b| {
                point_polygon_signed_distance(&s.centre, &large[a].hull)
                    .total_cmp(&point_polygon_signed_distance(&s.centre, &large[b].hull))
            })
            .unwrap_or(0);
        extra[nearest].extend(&s.nodes);
    }
    for (f, add) in large.iter_mut().zip(extra) {
        if !add.is_empty() {
            let mut nodes = std::mem::take(&mut f.nodes);
            nodes.extend(add);
            nodes.sort_unstable();
            *f = Fragment::of_nodes(nodes, x, v, m);
        }
    }
    large
}

/// The convex cell of seed `j` among `seeds` in the convex outline
/// `outline` (all in one frame): the outline clipped by the bisector of `j`
/// and every other seed, on `j`'s side (a Voronoi cell). `None` when it is
/// empty.
fn voronoi_cell(outline: &[Vec2], seeds: &[Vec2], j: usize) -> Option<Vec<Vec2>> {
    let mut poly = outline.to_vec();
    for (k, c) in seeds.iter().enumerate() {
        if k == j {
            continue;
        }
        let mid = (seeds[j] + c) * 0.5;
        let dir = perp(&(c - seeds[j]));
        // `j` is on the left of `dir` (cross(dir, s_j − mid) > 0).
        match split::cut(&poly, &mid, &dir) {
            Some(cut) => poly = cut.left,
            None => {
                let g = area_properties(&poly).centroid;
                if cross(&dir, &(g - mid)) < 0.0 {
                    return None;
                }
            }
        }
    }
    Some(poly)
}

/// The rigid pieces of `parent` (state `b`, after the formulation's
/// impact) from `split` (module doc, docs/physics.md §9.8). Outlines: the
/// Voronoi cells of the components' centres of mass in the parent's
/// outline, so the pieces are convex, do not overlap and partition the
/// parent (area and mass exactly). Velocities: the parent's rigid velocity
/// at each piece's centre plus the component's deviation `δ_j` from the
/// lattice's overall rigid motion, less their mass-weighted mean over the
/// pieces; spins: the parent's `Ω` plus the component's spin deviation
/// `(L_j − I_j Ω_L)/I_j`, less the constant that makes the angular
/// momentum about the parent's centre of mass the parent's. Linear and
/// angular momentum are then the parent's to rounding. `None` if a cell is
/// empty.
pub fn pieces(parent: &Floe, b: &BodyState, split: &LatticeSplit) -> Option<Vec<Piece>> {
    let mass: f64 = split.pieces.iter().map(|f| f.mass).sum();
    let g = split.pieces.iter().map(|f| f.centre * f.mass).sum::<Vec2>() / mass;
    let momentum: Vec2 = split.pieces.iter().map(|f| f.momentum).sum();
    let (mut angular, mut inertia) = (0.0, 0.0);
    for f in &split.pieces {
        let r = f.centre - g;
        angular += f.angular_momentum + cross(&r, &f.momentum);
        inertia += f.inertia + f.mass * r.norm_squared();
    }
    let (v_l, omega_l) = (momentum / mass, angular / inertia);
    // Cells in the parent's centre frame (world axes, origin at its centre
    // of mass), seeded by the components' centres.
    let mut outline = Vec::with_capacity(parent.shape.len());
    parent.world_polygon(&Vec2::zeros(), b.angle, &mut outline);
    let seeds: Vec<Vec2> = split
        .pieces
        .iter()
        .map(|f| rotate(&f.centre, b.angle))
        .collect();
    let mut floes = Vec::with_capacity(seeds.len());
    for j in 0..seeds.len() {
        let cell = voronoi_cell(&outline, &seeds, j)?;
        let f = Floe::from_world_polygon(
            &cell,
            parent.thickness,
            parent.density,
            Vec2::zeros(),
            0.0,
            parent.origin,
        );
        if f.area.is_nan() || f.area <= 0.0 {
            return None;
        }
        floes.push(f);
    }
    let total: f64 = floes.iter().map(|f| f.mass).sum();
    let deviation: Vec<Vec2> = split
        .pieces
        .iter()
        .map(|f| {
            rotate(
                &(f.momentum / f.mass - (v_l + perp(&(f.centre - g)) * omega_l)),
                b.angle,
            )
        })
        .collect();
    let mean = floes
        .iter()
        .zip(&deviation)
        .map(|(f, d)| d * f.mass)
        .sum::<Vec2>()
        / total;
    let velocity: Vec<Vec2> = floes
        .iter()
        .zip(&deviation)
        .map(|(f, d)| b.velocity + perp(&f.position) * b.angular_velocity + d - mean)
        .collect();
    let spin: Vec<f64> = split
        .pieces
        .iter()
        .map(|f| {
            if f.inertia > 0.0 {
                (f.angular_momentum - f.inertia * omega_l) / f.inertia
            } else {
                0.0
            }
        })
        .collect();
    // Angular momentum about the parent's centre of mass: the parent's
    // `I Ω` once the spins are shifted by `c`.
    let (mut l, mut polar) = (0.0, 0.0);
    for ((f, v), s) in floes.iter().zip(&velocity).zip(&spin) {
        l += f.inertia * (b.angular_velocity + s) + f.mass * cross(&f.position, v);
        polar += f.inertia;
    }
    let c = (l - parent.inertia * b.angular_velocity) / polar;
    let mut out = Vec::with_capacity(floes.len());
    for ((mut f, v), s) in floes.into_iter().zip(velocity).zip(spin) {
        let omega = b.angular_velocity + s - c;
        f.velocity = v;
        f.angular_velocity = omega;
        f.parent = Some(parent.id);
        f.position = b.position + f.position;
        out.push(Piece {
            state: BodyState {
                position: f.position,
                angle: 0.0,
                velocity: v,
                angular_velocity: omega,
            },
            floe: f,
        });
    }
    Some(out)
}
