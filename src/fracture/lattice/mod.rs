//! The 2D mass–spring lattice of a floe (docs/physics.md §7.2): a seeded
//! Poisson-disc point set inside the (convex) outline ([`Mesh::Random`], the
//! default) or the nodes of an equilateral triangular lattice clipped to it
//! ([`Mesh::Triangular`], no disorder), in both cases with the outline's
//! vertices and points along its edges, their Delaunay
//! triangulation ([`delaunay`], Bowyer–Watson), lumped node masses whose
//! total mass, centre of mass and polar inertia are the rigid floe's, and
//! central springs of stiffness `k / sin θ` per triangle edge (θ the angle
//! opposite the edge, after Balasoiu 2020) and, when the Poisson ratio asked
//! for is below 1/3, torsion (angular) springs of stiffness `c` at every
//! triangle corner (energy `½ c (θ − θ₀)²`, the corner's angle θ measured
//! from the current positions, so a rigid rotation loads nothing). `k` and
//! `c` are calibrated so that the lattice's isotropic (orientation-averaged)
//! affine response has the floe's Young's modulus and Poisson ratio: central
//! springs give the Lamé coefficients `λ = μ` (the Cauchy relation, ν = 1/3)
//! and torsion springs add to `μ` what they take from `λ`
//! (docs/physics.md §7.2).
//!
//! Static solutions ([`Lattice::solve`]) are linear (small displacements):
//! conjugate gradients on the lattice's stiffness matrix, applied without
//! assembling it, with some degrees of freedom prescribed. Stresses are the
//! virial of each triangle's springs ([`Lattice::triangle_stress`]).
//!
//! References: R. Bridson (2007), Fast Poisson disk sampling in arbitrary
//! dimensions, SIGGRAPH sketches; A. Bowyer (1981) and D. F. Watson (1981),
//! *The Computer Journal* 24(2); D. Balasoiu (2020), PhD thesis, Université
//! Grenoble Alpes.
//!
//! [`percussion`] integrates a lattice struck by a rigid impact;
//! [`rectangle`] strikes a rectangular floe on its left face
//! (`floebench percussion-2d`); [`pair`] resolves both bodies of an impact
//! as lattices (docs/physics.md §9.9).

pub mod bars;
pub mod delaunay;
pub mod pair;
pub mod percussion;
pub mod rectangle;

use super::chain::positive;
use crate::geometry::{area_properties, cross, perp, point_polygon_signed_distance, Vec2};
use crate::model::limits::fracture::{POISSON_MAX, POISSON_MIN};
use crate::rng::SplitMix64;
use nalgebra::{Matrix2, Matrix3, Matrix4, Vector4};
use std::collections::HashMap;

/// What a lattice is made of and how fine it is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LatticeSpec {
    /// Target distance between nodes (the Poisson-disc radius), m.
    pub spacing: f64,
    /// Floe thickness, m.
    pub thickness: f64,
    /// Ice density, kg/m³.
    pub density: f64,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Poisson ratio (-), in `(−1, 1/3]` ([`POISSON_MIN`], [`POISSON_MAX`]).
    /// 1/3 (the default) is central springs alone, no torsion springs;
    /// below it, torsion springs at the triangle corners lower it (ice:
    /// about 0.3).
    pub poisson: f64,
    /// Seed of the Poisson-disc sampling (unused by a triangular mesh).
    pub seed: u64,
    /// How the nodes inside the outline are placed: a seeded Poisson-disc
    /// set ([`Mesh::Random`], the default) or a regular triangular lattice
    /// ([`Mesh::Triangular`]).
    pub mesh: Mesh,
}

/// How the nodes inside a floe's outline are placed (docs/physics.md §7.2).
/// Either way the outline carries its vertices and points at most one
/// spacing apart along each edge, and the nodes inside are at least half a
/// spacing from it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Mesh {
    /// A seeded Poisson-disc set (Bridson 2007): a disordered, isotropic
    /// lattice; its seed is [`LatticeSpec::seed`].
    #[default]
    Random,
    /// The nodes of an equilateral triangular lattice of side the spacing:
    /// elastically isotropic and without disorder (every interior node is
    /// a centre of symmetry, so a uniform strain is an equilibrium inside);
    /// only its boundary cells, where it is clipped to the outline, are
    /// irregular. Its two freedoms are its orientation and its offset.
    Triangular {
        /// The angle of its first lattice direction from the x axis, rad
        /// (it repeats every π/3).
        angle: f64,
        /// The position of one of its nodes relative to the outline's
        /// centroid, in lattice coordinates along its two directions at
        /// `angle` and `angle + π/3` (fractions of the spacing; 0, 0 puts
        /// a node at the centroid).
        offset: [f64; 2],
    },
}

impl Default for LatticeSpec {
    /// Ice at the lattice's usual resolution: spacing 1 m, thickness 1 m,
    /// density 917 kg/m³ (the project's), Young's modulus 8.95 GPa
    /// (Balasoiu's), Poisson ratio 1/3 (central springs alone: no torsion
    /// springs, what the lattice was before they were built), seed 1, the
    /// random mesh.
    fn default() -> Self {
        LatticeSpec {
            spacing: 1.0,
            thickness: 1.0,
            density: 917.0,
            young: 8.95e9,
            poisson: POISSON_MAX,
            seed: 1,
            mesh: Mesh::Random,
        }
    }
}

impl Mesh {
    /// The `k`-th of a sequence of triangular meshes at `angle` (rad) that
    /// differ by their offset, in place of seeds: offset
    /// `frac(k (α₁, α₂))` in lattice coordinates, `α₁ = 0.7548776662`,
    /// `α₂ = 0.5698402910` (the plastic-number sequence of Roberts 2018,
    /// which covers the unit square evenly). `k = 0` is no offset: on a
    /// square whose faces are along the lattice it puts nodes at exactly
    /// half a spacing from a face, where rounding decides whether they are
    /// kept (docs/physics.md §7.2), so variants start at 1.
    pub fn triangular_variant(angle: f64, k: u64) -> Mesh {
        let k = k as f64;
        Mesh::Triangular {
            angle,
            offset: [(k * 0.7548776662).fract(), (k * 0.5698402910).fract()],
        }
    }
}

impl LatticeSpec {
    /// The torsion springs' share of the Lamé coefficients, as the ratio
    /// `Δμ / μ_s` of what they add to `μ` (and take from `λ`) to the
    /// central springs' `μ_s = λ_s`: `(1 − 3ν)/(1 + ν)`, 0 at ν = 1/3
    /// (docs/physics.md §7.2).
    pub fn torsion_ratio(&self) -> f64 {
        (1.0 - 3.0 * self.poisson) / (1.0 + self.poisson)
    }
}

/// A torsion (angular) spring at the corner of a triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Corner {
    /// Its nodes: the corner's vertex `o`, then `a` and `b`, the angle
    /// going counter-clockwise from `a − o` to `b − o`.
    pub nodes: [usize; 3],
    /// Stiffness `c`, J/rad² (N·m per radian of angle change, per radian).
    pub stiffness: f64,
    /// Rest angle `θ₀`, rad.
    pub angle: f64,
    /// The gradient of the angle with respect to the three nodes'
    /// positions at rest (same order as `nodes`), 1/m.
    pub grad: [Vec2; 3],
}

impl Corner {
    /// The linearised change of its angle under displacements `u` (m),
    /// rad.
    pub fn angle_change(&self, u: &[Vec2]) -> f64 {
        self.nodes
            .iter()
            .zip(&self.grad)
            .map(|(&i, g)| g.dot(&u[i]))
            .sum()
    }
}

/// The angle (rad) at `o` from `a − o` to `b − o`, counter-clockwise, in
/// `(−π, π]`, and its gradients with respect to `o`, `a`, `b` (1/m): the
/// direction `φ` of a vector `e` has `∂φ/∂e = k ∧ e / |e|²`.
pub fn corner_angle(o: &Vec2, a: &Vec2, b: &Vec2) -> (f64, [Vec2; 3]) {
    let (ea, eb) = (a - o, b - o);
    let theta = cross(&ea, &eb).atan2(ea.dot(&eb));
    let ga = -perp(&ea) / ea.norm_squared();
    let gb = perp(&eb) / eb.norm_squared();
    (theta, [-(ga + gb), ga, gb])
}

/// A central spring between two nodes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spring {
    /// Its nodes.
    pub nodes: [usize; 2],
    /// Stiffness, N/m (the sum of its triangles' `k / sin θ`).
    pub stiffness: f64,
    /// Rest length, m.
    pub length: f64,
    /// Unit vector from the first node to the second.
    pub dir: Vec2,
}

/// The lattice of one floe.
#[derive(Debug, Clone)]
pub struct Lattice {
    /// Node positions, m (in the outline's frame).
    pub nodes: Vec<Vec2>,
    /// Whether each node lies on the outline.
    pub on_boundary: Vec<bool>,
    /// Node masses, kg.
    pub mass: Vec<f64>,
    /// The Delaunay triangles (counter-clockwise).
    pub triangles: Vec<[usize; 3]>,
    /// The springs, one per triangle edge.
    pub springs: Vec<Spring>,
    /// For each triangle, its three edges: (spring, that triangle's share of
    /// its stiffness `k / sin θ`, N/m).
    pub triangle_springs: Vec<[(usize, f64); 3]>,
    /// The calibrated `k`, N/m.
    pub k: f64,
    /// The torsion springs, three per triangle (those of triangle `t` are
    /// `3t..3t + 3`), or none when the Poisson ratio is 1/3.
    pub corners: Vec<Corner>,
    /// The calibrated torsion stiffness `c` of every corner, J/rad² (0
    /// when there are none).
    pub torsion: f64,
    /// The area covered by the triangles, m².
    pub area: f64,
    /// The spec it was built from.
    pub spec: LatticeSpec,
}

/// A seeded Poisson-disc point set in the convex counter-clockwise polygon
/// `poly` at `spacing` (Bridson 2007): first the outline, its vertices and
/// points at most `spacing` apart along each edge; then, from the
/// centroid, points at least `spacing` from every other and `spacing/2`
/// inside the outline, 30 candidates per active point in the annulus
/// `[spacing, 2 spacing)`. Returns the points and how many of the first
/// are on the outline.
pub fn poisson_disc(poly: &[Vec2], spacing: f64, seed: u64) -> (Vec<Vec2>, usize) {
    let mut pts = outline_points(poly, spacing);
    let nb = pts.len();
    let cell = spacing / std::f64::consts::SQRT_2;
    let key = |p: &Vec2| ((p.x / cell).floor() as i64, (p.y / cell).floor() as i64);
    let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (i, p) in pts.iter().enumerate() {
        grid.entry(key(p)).or_default().push(i);
    }
    let far = |pts: &[Vec2], grid: &HashMap<(i64, i64), Vec<usize>>, p: &Vec2| {
        let (cx, cy) = key(p);
        for dx in -2..=2 {
            for dy in -2..=2 {
                if let Some(list) = grid.get(&(cx + dx, cy + dy)) {
                    if list.iter().any(|&j| (pts[j] - p).norm() < spacing) {
                        return false;
                    }
                }
            }
        }
        true
    };
    let inside = |p: &Vec2| point_polygon_signed_distance(p, poly) <= -0.5 * spacing;
    let mut rng = SplitMix64::new(seed);
    let mut active: Vec<usize> = Vec::new();
    let start = area_properties(poly).centroid;
    if inside(&start) && far(&pts, &grid, &start) {
        grid.entry(key(&start)).or_default().push(pts.len());
        active.push(pts.len());
        pts.push(start);
    }
    while !active.is_empty() {
        let a = rng.int_range(0, active.len() - 1);
        let centre = pts[active[a]];
        let mut found = false;
        for _ in 0..30 {
            let r = spacing * (1.0 + rng.uniform());
            let t = rng.range(0.0, std::f64::consts::TAU);
            let p = centre + Vec2::new(r * t.cos(), r * t.sin());
            if inside(&p) && far(&pts, &grid, &p) {
                grid.entry(key(&p)).or_default().push(pts.len());
                active.push(pts.len());
                pts.push(p);
                found = true;
                break;
            }
        }
        if !found {
            active.swap_remove(a);
        }
    }
    (pts, nb)
}

/// The outline's nodes: the vertices of the polygon `poly` and, along
/// each edge, equally spaced points at most `spacing` apart (both meshes).
fn outline_points(poly: &[Vec2], spacing: f64) -> Vec<Vec2> {
    let mut pts: Vec<Vec2> = Vec::new();
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let m = ((b - a).norm() / spacing).ceil().max(1.0) as usize;
        for j in 0..m {
            pts.push(a + (b - a) * (j as f64 / m as f64));
        }
    }
    pts
}

/// The nodes of a triangular mesh of the convex counter-clockwise polygon
/// `poly` ([`Mesh::Triangular`]): the outline's ([`outline_points`]), then
/// the nodes `o + i a₁ + j a₂` of the equilateral lattice of side
/// `spacing` (`a₁` at `angle`, `a₂` at `angle + π/3`, `o` the centroid
/// plus `offset` in those coordinates) that lie at least `spacing/2`
/// inside the outline, in the order of `j` then `i`. Returns the points and
/// how many of the first are on the outline.
pub fn triangular_points(
    poly: &[Vec2],
    spacing: f64,
    angle: f64,
    offset: [f64; 2],
) -> (Vec<Vec2>, usize) {
    let mut pts = outline_points(poly, spacing);
    let nb = pts.len();
    let a1 = Vec2::new(angle.cos(), angle.sin()) * spacing;
    let third = angle + std::f64::consts::FRAC_PI_3;
    let a2 = Vec2::new(third.cos(), third.sin()) * spacing;
    let origin = area_properties(poly).centroid + a1 * offset[0] + a2 * offset[1];
    // |i a₁ + j a₂|² = s² (i² + i j + j²) ≥ ¾ s² max(|i|, |j|)², so
    // |i|, |j| ≤ 2R/(s√3) cover the disc of radius R about the origin that
    // holds the outline.
    let radius = poly.iter().map(|p| (p - origin).norm()).fold(0.0, f64::max);
    let n = (2.0 * radius / (spacing * 3f64.sqrt())).ceil() as i64 + 1;
    for j in -n..=n {
        for i in -n..=n {
            let p = origin + a1 * i as f64 + a2 * j as f64;
            if point_polygon_signed_distance(&p, poly) <= -0.5 * spacing {
                pts.push(p);
            }
        }
    }
    (pts, nb)
}

/// The angle-sine of the corner `c` of triangle `a b c`.
fn sine_at(a: &Vec2, b: &Vec2, c: &Vec2) -> f64 {
    let (u, v) = (a - c, b - c);
    cross(&u, &v).abs() / (u.norm() * v.norm())
}

impl Lattice {
    /// The lattice of the convex counter-clockwise outline `poly` (m).
    /// Fails when the spec is not positive and finite, the spacing is not
    /// below the outline's size, the triangles do not cover the outline
    /// (area to 1e-9 relative), or the mass correction would make a mass
    /// not positive.
    pub fn build(poly: &[Vec2], spec: LatticeSpec) -> Result<Lattice, String> {
        positive("spacing", spec.spacing)?;
        positive("thickness", spec.thickness)?;
        positive("density", spec.density)?;
        positive("Young's modulus", spec.young)?;
        if !(spec.poisson > POISSON_MIN && spec.poisson <= POISSON_MAX) {
            return Err(format!(
                "the lattice's Poisson ratio must be in (-1, 1/3] (central springs give 1/3, \
                 torsion springs lower it; -1 would need infinitely stiff ones), got {}",
                spec.poisson
            ));
        }
        let props = area_properties(poly);
        if props.area.is_nan() || props.area <= 0.0 {
            return Err("the outline has no area".into());
        }
        if spec.spacing * spec.spacing > props.area {
            return Err(format!(
                "spacing {} m is not below the outline's size (area {} m²)",
                spec.spacing, props.area
            ));
        }
        let (nodes, nb) = match spec.mesh {
            Mesh::Random => poisson_disc(poly, spec.spacing, spec.seed),
            Mesh::Triangular { angle, offset } => {
                if !(angle.is_finite() && offset.iter().all(|o| o.is_finite())) {
                    return Err(format!(
                        "the triangular mesh's angle and offset must be finite, got {angle} and \
                         {offset:?}"
                    ));
                }
                triangular_points(poly, spec.spacing, angle, offset)
            }
        };
        let triangles = delaunay::triangulate(&nodes);
        let tri_area = |t: &[usize; 3]| {
            0.5 * cross(&(nodes[t[1]] - nodes[t[0]]), &(nodes[t[2]] - nodes[t[0]]))
        };
        let area: f64 = triangles.iter().map(tri_area).sum();
        if (area - props.area).abs() > 1e-9 * props.area {
            return Err(format!(
                "the triangulation covers {area} m² of an outline of {} m²",
                props.area
            ));
        }
        // Springs: k / sin θ per triangle edge, with k = 1 N/m for now.
        let mut index: HashMap<(usize, usize), usize> = HashMap::new();
        let mut springs: Vec<Spring> = Vec::new();
        let mut triangle_springs = Vec::with_capacity(triangles.len());
        let mut sum = 0.0; // Σ_T Σ_e l² / sin θ
        for t in &triangles {
            let mut row = [(0, 0.0); 3];
            for e in 0..3 {
                let (i, j, o) = (t[e], t[(e + 1) % 3], t[(e + 2) % 3]);
                let s = sine_at(&nodes[i], &nodes[j], &nodes[o]);
                let d = nodes[j] - nodes[i];
                let l = d.norm();
                let key = (i.min(j), i.max(j));
                let k = *index.entry(key).or_insert_with(|| {
                    springs.push(Spring {
                        nodes: [key.0, key.1],
                        stiffness: 0.0,
                        length: l,
                        dir: (nodes[key.1] - nodes[key.0]) / l,
                    });
                    springs.len() - 1
                });
                springs[k].stiffness += 1.0 / s;
                row[e] = (k, 1.0 / s);
                sum += l * l / s;
            }
            triangle_springs.push(row);
        }
        // The isotropic average of the affine response of the springs:
        // λ_s = μ_s = k Σ / (8 A) (times the thickness: k carries it); the
        // bulk modulus λ + μ = 2 μ_s is theirs alone, E h / (2 (1 − ν)), so
        // k = 2 A E h / ((1 − ν) Σ) (3 A E h / Σ at ν = 1/3).
        let k = 2.0 * area * spec.young * spec.thickness / ((1.0 - spec.poisson) * sum);
        // Torsion springs add Δμ = c Σ sin²θ / (2 A) to μ and take it from
        // λ; Δμ = μ_s (1 − 3ν)/(1 + ν) gives the Poisson ratio ν.
        let mut corners = Vec::new();
        let mut torsion = 0.0;
        let ratio = spec.torsion_ratio();
        if ratio > 0.0 {
            let mut sines = 0.0;
            for t in &triangles {
                for e in 0..3 {
                    let (o, a, b) = (t[e], t[(e + 1) % 3], t[(e + 2) % 3]);
                    let (angle, grad) = corner_angle(&nodes[o], &nodes[a], &nodes[b]);
                    sines += angle.sin().powi(2);
                    corners.push(Corner {
                        nodes: [o, a, b],
                        stiffness: 0.0,
                        angle,
                        grad,
                    });
                }
            }
            let mu_s = k * sum / (8.0 * area);
            torsion = 2.0 * area * ratio * mu_s / sines;
            corners.iter_mut().for_each(|c| c.stiffness = torsion);
        }
        for s in &mut springs {
            s.stiffness *= k;
        }
        for row in &mut triangle_springs {
            for e in row.iter_mut() {
                e.1 *= k;
            }
        }
        let mass = lumped_masses(&nodes, &triangles, poly, spec.density * spec.thickness)?;
        let mut on_boundary = vec![false; nodes.len()];
        on_boundary[..nb].iter_mut().for_each(|b| *b = true);
        Ok(Lattice {
            nodes,
            on_boundary,
            mass,
            triangles,
            springs,
            triangle_springs,
            k,
            corners,
            torsion,
            area,
            spec,
        })
    }

    /// `K u`: the stiffness matrix of the linearised springs applied to
    /// the node displacements `u` (m), in N.
    pub fn apply(&self, u: &[Vec2], out: &mut [Vec2]) {
        out.iter_mut().for_each(|f| *f = Vec2::zeros());
        for s in &self.springs {
            let [i, j] = s.nodes;
            let f = s.dir * (s.stiffness * s.dir.dot(&(u[j] - u[i])));
            out[i] -= f;
            out[j] += f;
        }
        for c in &self.corners {
            let m = c.stiffness * c.angle_change(u);
            for (&i, g) in c.nodes.iter().zip(&c.grad) {
                out[i] += g * m;
            }
        }
    }

    /// The torsion springs' forces (N) at the node positions `x` (m),
    /// geometrically exact (a rigid motion gives none), added to `out`,
    /// those of the triangles `t` with `intact(t)` false left out; returns
    /// their energy `Σ ½ c (θ − θ₀)²`, J.
    pub fn torsion_forces(
        &self,
        x: &[Vec2],
        intact: impl Fn(usize) -> bool,
        out: &mut [Vec2],
    ) -> f64 {
        let mut energy = 0.0;
        for (n, c) in self.corners.iter().enumerate() {
            if !intact(n / 3) {
                continue;
            }
            let [o, a, b] = c.nodes;
            let (theta, grad) = corner_angle(&x[o], &x[a], &x[b]);
            let d = theta - c.angle;
            energy += 0.5 * c.stiffness * d * d;
            for (&i, g) in c.nodes.iter().zip(&grad) {
                out[i] -= g * (c.stiffness * d);
            }
        }
        energy
    }

    /// The virial `Σ_i x_i ⊗ g_i` of corner `c`'s rest gradient, m/m: times
    /// the corner's moment `c δθ` it is its contribution to `A h σ`.
    fn corner_virial(&self, c: &Corner) -> Matrix2<f64> {
        c.nodes
            .iter()
            .zip(&c.grad)
            .map(|(&i, g)| self.nodes[i] * g.transpose())
            .sum()
    }

    /// The tension of each spring under displacements `u`, N.
    pub fn tensions(&self, u: &[Vec2]) -> Vec<f64> {
        self.springs
            .iter()
            .map(|s| s.stiffness * s.dir.dot(&(u[s.nodes[1]] - u[s.nodes[0]])))
            .collect()
    }

    /// The stress of each triangle under displacements `u`, Pa: the virial
    /// `(1/(A_T h)) Σ_e f_e l_e t_e ⊗ t_e` of its share of its three springs,
    /// plus that of its torsion springs, `(1/(A_T h)) Σ_corners c δθ Σ_i x_i ⊗ ∇_i θ`.
    pub fn triangle_stress(&self, u: &[Vec2]) -> Vec<Matrix2<f64>> {
        self.triangles
            .iter()
            .zip(&self.triangle_springs)
            .enumerate()
            .map(|(n, (t, row))| {
                let a = 0.5
                    * cross(
                        &(self.nodes[t[1]] - self.nodes[t[0]]),
                        &(self.nodes[t[2]] - self.nodes[t[0]]),
                    );
                let mut sigma = Matrix2::zeros();
                for &(k, kt) in row {
                    let s = &self.springs[k];
                    let f = kt * s.dir.dot(&(u[s.nodes[1]] - u[s.nodes[0]]));
                    sigma += s.dir * s.dir.transpose() * (f * s.length);
                }
                for c in self.corners.iter().skip(3 * n).take(3) {
                    sigma += self.corner_virial(c) * (c.stiffness * c.angle_change(u));
                }
                sigma / (a * self.spec.thickness)
            })
            .collect()
    }

    /// The mean stress of the whole lattice under `u`, Pa: the virial of
    /// every spring and torsion spring over the lattice's volume.
    pub fn mean_stress(&self, u: &[Vec2]) -> Matrix2<f64> {
        let mut sigma = Matrix2::zeros();
        for (s, f) in self.springs.iter().zip(self.tensions(u)) {
            sigma += s.dir * s.dir.transpose() * (f * s.length);
        }
        for c in &self.corners {
            sigma += self.corner_virial(c) * (c.stiffness * c.angle_change(u));
        }
        sigma / (self.area * self.spec.thickness)
    }

    /// The force (N) that the material on the left of the segment `a → b`
    /// exerts on the material on its right, through the springs that cross
    /// the segment and the torsion springs of the triangles it cuts (in
    /// the share of the triangle's two cut edges that it crosses), under
    /// displacements `u` (small displacements: the crossing is judged at
    /// rest). Across a cut through the whole body this is exact statics,
    /// with no averaging window.
    pub fn force_across(&self, u: &[Vec2], a: &Vec2, b: &Vec2) -> Vec2 {
        let d = b - a;
        let side = |p: &Vec2| cross(&d, &(p - a));
        let mut total = Vec2::zeros();
        for (s, f) in self.springs.iter().zip(self.tensions(u)) {
            let (p, q) = (self.nodes[s.nodes[0]], self.nodes[s.nodes[1]]);
            let (sp, sq) = (side(&p), side(&q));
            if sp * sq >= 0.0 {
                continue;
            }
            let e = q - p;
            let (ta, tb) = (cross(&e, &(a - p)), cross(&e, &(b - p)));
            if ta * tb >= 0.0 {
                continue;
            }
            // The spring pulls its right node towards its left one.
            total += if sp > 0.0 { -s.dir * f } else { s.dir * f };
        }
        // A triangle the line separates has two edges across it; its
        // torsion springs push its nodes on the right with Σ_right f_i,
        // counted in the share of those two crossings inside the segment.
        let crosses = |p: &Vec2, q: &Vec2| {
            let e = q - p;
            side(p) * side(q) < 0.0 && cross(&e, &(a - p)) * cross(&e, &(b - p)) < 0.0
        };
        for (n, t) in self.triangles.iter().enumerate() {
            let Some(corners) = self.corners.get(3 * n..3 * n + 3) else {
                break;
            };
            let p: Vec<Vec2> = t.iter().map(|&i| self.nodes[i]).collect();
            let cut = (0..3).filter(|&e| crosses(&p[e], &p[(e + 1) % 3])).count();
            if cut == 0 {
                continue;
            }
            let mut push = Vec2::zeros();
            for c in corners {
                let m = c.stiffness * c.angle_change(u);
                for (&i, g) in c.nodes.iter().zip(&c.grad) {
                    if side(&self.nodes[i]) < 0.0 {
                        push -= g * m;
                    }
                }
            }
            total += push * (cut as f64 / 2.0);
        }
        total
    }

    /// The static displacements under node forces `force` (N), the nodes
    /// with `fixed[i]` held at `u0[i]` (m), the others starting from
    /// `u0`: conjugate gradients to a residual of `tol` times the norm of
    /// the right-hand side, at most `max_iter` iterations. With no node
    /// fixed the forces must be self-equilibrated (the solution is then
    /// defined up to a rigid motion, which leaves tensions and stresses
    /// unchanged). Returns the displacements, the iterations and the
    /// relative residual.
    pub fn solve(
        &self,
        force: &[Vec2],
        fixed: &[bool],
        u0: &[Vec2],
        tol: f64,
        max_iter: usize,
    ) -> (Vec<Vec2>, usize, f64) {
        let n = self.nodes.len();
        let mask = |v: &mut [Vec2]| {
            for (x, f) in v.iter_mut().zip(fixed) {
                if *f {
                    *x = Vec2::zeros();
                }
            }
        };
        let dot = |a: &[Vec2], b: &[Vec2]| a.iter().zip(b).map(|(x, y)| x.dot(y)).sum::<f64>();
        let mut u = u0.to_vec();
        let mut ku = vec![Vec2::zeros(); n];
        self.apply(&u, &mut ku);
        let mut r: Vec<Vec2> = force.iter().zip(&ku).map(|(f, k)| f - k).collect();
        mask(&mut r);
        let mut rhs: Vec<Vec2> = force.to_vec();
        mask(&mut rhs);
        let scale = dot(&rhs, &rhs).sqrt().max(dot(&r, &r).sqrt());
        if scale == 0.0 {
            return (u, 0, 0.0);
        }
        let mut p = r.clone();
        let mut rr = dot(&r, &r);
        let mut kp = vec![Vec2::zeros(); n];
        let mut it = 0;
        while it < max_iter && rr.sqrt() > tol * scale {
            self.apply(&p, &mut kp);
            mask(&mut kp);
            let pkp = dot(&p, &kp);
            if pkp.is_nan() || pkp <= 0.0 {
                break;
            }
            let alpha = rr / pkp;
            for i in 0..n {
                u[i] += p[i] * alpha;
                r[i] -= kp[i] * alpha;
            }
            let rr_new = dot(&r, &r);
            let beta = rr_new / rr;
            rr = rr_new;
            for i in 0..n {
                p[i] = r[i] + p[i] * beta;
            }
            it += 1;
        }
        (u, it, rr.sqrt() / scale)
    }

    /// The affine displacement field `u = ε x` of strain `eps`.
    pub fn affine(&self, eps: &Matrix2<f64>) -> Vec<Vec2> {
        self.nodes.iter().map(|x| eps * x).collect()
    }

    /// The effective stiffness (Voigt: xx, yy, xy against ε_xx, ε_yy,
    /// γ_xy), Pa, of the three unit strains: every node displaced affinely
    /// (`relaxed = false`), or only the outline's nodes, the inside
    /// relaxed to equilibrium (`relaxed = true`, conjugate gradients to
    /// 1e-10).
    pub fn stiffness(&self, relaxed: bool) -> Matrix3<f64> {
        let strains = [
            Matrix2::new(1.0, 0.0, 0.0, 0.0),
            Matrix2::new(0.0, 0.0, 0.0, 1.0),
            Matrix2::new(0.0, 0.5, 0.5, 0.0),
        ];
        let mut c = Matrix3::zeros();
        for (col, eps) in strains.iter().enumerate() {
            let mut u = self.affine(eps);
            if relaxed {
                let zero = vec![Vec2::zeros(); u.len()];
                u = self.solve(&zero, &self.on_boundary, &u, 1e-10, 100_000).0;
            }
            let s = self.mean_stress(&u);
            c[(0, col)] = s[(0, 0)];
            c[(1, col)] = s[(1, 1)];
            c[(2, col)] = s[(0, 1)];
        }
        c
    }
}

/// Young's moduli along x and y, Poisson ratio ν_xy and shear modulus
/// of a stiffness `c` (Voigt, Pa), from its compliance; `None` if it is
/// singular.
pub fn moduli(c: &Matrix3<f64>) -> Option<(f64, f64, f64, f64)> {
    let s = c.try_inverse()?;
    Some((
        1.0 / s[(0, 0)],
        1.0 / s[(1, 1)],
        -s[(1, 0)] / s[(0, 0)],
        1.0 / s[(2, 2)],
    ))
}

/// Node masses (kg) of a triangulation of `poly` with surface density
/// `sigma` (kg/m²): each triangle's mass in thirds to its vertices, then
/// the smallest relative change `m_i = m⁰_i (1 + b_iᵀ λ)`,
/// `b_i = (1, x_i, y_i, |x_i − G|²)`, that makes the total mass, the
/// centre of mass `G` and the polar inertia about it the rigid floe's (a
/// 4 × 4 solve). The thirds alone overestimate the inertia by
/// `Σ_T m_T (a² + b² + c²)/12` (three point masses at the corners against
/// the triangle's own `m_T (a² + b² + c²)/36`), a relative `O(h²/D²)`.
pub fn lumped_masses(
    nodes: &[Vec2],
    triangles: &[[usize; 3]],
    poly: &[Vec2],
    sigma: f64,
) -> Result<Vec<f64>, String> {
    let props = area_properties(poly);
    let g = props.centroid;
    let mut m0 = vec![0.0; nodes.len()];
    for t in triangles {
        let a = 0.5 * cross(&(nodes[t[1]] - nodes[t[0]]), &(nodes[t[2]] - nodes[t[0]]));
        for &i in t {
            m0[i] += sigma * a / 3.0;
        }
    }
    let b = |i: usize| {
        let d = nodes[i] - g;
        Vector4::new(1.0, d.x, d.y, d.norm_squared())
    };
    let target = Vector4::new(sigma * props.area, 0.0, 0.0, sigma * props.polar_moment);
    let mut lhs = Matrix4::zeros();
    let mut have = Vector4::zeros();
    for (i, &m) in m0.iter().enumerate() {
        let bi = b(i);
        lhs += bi * bi.transpose() * m;
        have += bi * m;
    }
    let lambda = lhs
        .try_inverse()
        .ok_or("the mass correction is singular (too few nodes)")?
        * (target - have);
    let mass: Vec<f64> = (0..nodes.len())
        .map(|i| m0[i] * (1.0 + b(i).dot(&lambda)))
        .collect();
    if mass.iter().any(|m| m.is_nan() || *m <= 0.0) {
        return Err("the mass correction makes a node mass not positive".into());
    }
    Ok(mass)
}
