//! What a case's structure is, read from its initial data alone: whether
//! anything forces the floes, mirror symmetries (axes and the pairing of
//! floes they give), floes in a row, gaps to obstacles, and whether the
//! case is "constant wind as gravity" (docs/physics.md §2). The checks
//! apply by structure, never by case name.

use crate::geometry::{cross, Vec2};
use crate::model::{Scenario, VelocityField, VelocitySeries};

/// Relative rounding allowance when matching the initial geometry of a case
/// (mirror images, touching floes, collinear centres).
pub(super) const GEOMETRY_MATCH: f64 = 1e-9;

/// Whether no environment force acts: no air or water drag and no Coriolis.
pub fn no_forcing(scn: &Scenario) -> bool {
    let env = &scn.environment;
    let air_off = env.air.drag_factor() == 0.0 || env.air.velocity.max_speed() == 0.0;
    air_off && env.water.drag_factor() == 0.0 && env.coriolis == 0.0
}

/// A mirror line through `c` with unit direction `d`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axis {
    /// A point of the line, m.
    pub c: Vec2,
    /// Unit direction.
    pub d: Vec2,
}

impl Axis {
    /// The mirror image of a point.
    pub fn point(&self, p: &Vec2) -> Vec2 {
        self.c + self.vector(&(p - self.c))
    }

    /// The mirror image of a vector.
    pub fn vector(&self, v: &Vec2) -> Vec2 {
        self.d * (2.0 * self.d.dot(v)) - v
    }
}

pub(super) fn world_polygon(scn: &Scenario, i: usize, g: &Vec2, theta: f64) -> Vec<Vec2> {
    let mut p = Vec::new();
    scn.floes[i].world_polygon(g, theta, &mut p);
    p
}

pub(super) fn initial_polygon(scn: &Scenario, i: usize) -> Vec<Vec2> {
    world_polygon(scn, i, &scn.floes[i].position, 0.0)
}

/// Extent of the floes about `c`: the largest distance of a floe vertex, m.
pub(super) fn extent(scn: &Scenario, c: &Vec2) -> f64 {
    scn.floes
        .iter()
        .map(|f| (f.position - c).norm() + f.radius)
        .fold(0.0, f64::max)
}

/// Whether the polygons have the same vertices to `tol` (m), in any order.
fn same_vertices(a: &[Vec2], b: &[Vec2], tol: f64) -> bool {
    a.len() == b.len() && a.iter().all(|p| b.iter().any(|q| (p - q).norm() <= tol))
}

/// Whether a fluid velocity is uniform in space and parallel to `d` at all
/// times (a field varying in space breaks the mirror symmetries the checks
/// look for, so it never qualifies).
fn series_parallel(v: &VelocityField, d: &Vec2) -> bool {
    let ok = |u: &Vec2| cross(d, u).abs() <= 1e-12 * u.norm();
    match v.uniform() {
        Some(VelocitySeries::Constant(u)) => ok(u),
        Some(VelocitySeries::Series(points)) => points.iter().all(|p| ok(&p.1)),
        None => v.is_zero(),
    }
}

/// The pairing of floes by the mirror `axis`, if the initial configuration
/// (outlines, thickness, density, velocities, spins, obstacles) is its own
/// mirror image, the forcing is parallel to the axis and there is no
/// Coriolis force: `pairing[i]` is the floe at the mirror image of floe `i`.
pub fn mirror_pairing(scn: &Scenario, axis: &Axis) -> Option<Vec<usize>> {
    let env = &scn.environment;
    if env.coriolis != 0.0
        || (env.air.drag_factor() > 0.0 && !series_parallel(&env.air.velocity, &axis.d))
        || (env.water.drag_factor() > 0.0 && !series_parallel(&env.water.velocity, &axis.d))
    {
        return None;
    }
    let tol = GEOMETRY_MATCH * extent(scn, &axis.c).max(f64::MIN_POSITIVE);
    let vmax = scn
        .floes
        .iter()
        .map(|f| f.velocity.norm() + f.angular_velocity.abs() * f.radius)
        .fold(0.0, f64::max);
    let vtol = GEOMETRY_MATCH * vmax;
    let polys: Vec<Vec<Vec2>> = (0..scn.floes.len())
        .map(|i| initial_polygon(scn, i))
        .collect();
    let mut pairing = Vec::with_capacity(scn.floes.len());
    for (i, fi) in scn.floes.iter().enumerate() {
        let g = axis.point(&fi.position);
        let mirrored: Vec<Vec2> = polys[i].iter().map(|p| axis.point(p)).collect();
        let v = axis.vector(&fi.velocity);
        let j = scn.floes.iter().enumerate().position(|(j, fj)| {
            (fj.position - g).norm() <= tol
                && fj.thickness == fi.thickness
                && fj.density == fi.density
                && (fj.velocity - v).norm() <= vtol
                && (fj.angular_velocity + fi.angular_velocity).abs() * fi.radius <= vtol
                && same_vertices(&mirrored, &polys[j], tol)
        })?;
        pairing.push(j);
    }
    for o in &scn.obstacles {
        let mirrored: Vec<Vec2> = o.polygon.iter().map(|p| axis.point(p)).collect();
        let size = o
            .polygon
            .iter()
            .map(|p| (p - axis.c).norm())
            .fold(0.0, f64::max);
        let otol = GEOMETRY_MATCH * size.max(f64::MIN_POSITIVE);
        if !scn
            .obstacles
            .iter()
            .any(|q| same_vertices(&mirrored, &q.polygon, otol))
        {
            return None;
        }
    }
    Some(pairing)
}

/// The mass-weighted centroid of the floes at t = 0, m.
fn mass_centroid(scn: &Scenario) -> Vec2 {
    let m: f64 = scn.floes.iter().map(|f| f.mass).sum();
    scn.floes
        .iter()
        .fold(Vec2::zeros(), |s, f| s + f.position * f.mass)
        / m
}

/// Directions of the principal axes of a 2×2 second-moment tensor.
fn principal_directions(sxx: f64, sxy: f64, syy: f64) -> [Vec2; 2] {
    let phi = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    [
        Vec2::new(phi.cos(), phi.sin()),
        Vec2::new(-phi.sin(), phi.cos()),
    ]
}

/// A mirror symmetry of the initial configuration, if any: the axis passes
/// through the floes' mass centroid (a mirror maps it onto itself) along a
/// principal direction of the floes' centroids or vertices (a mirror axis is
/// one), or along x, y or a diagonal (when those tensors are isotropic).
pub fn find_symmetry(scn: &Scenario) -> Option<(Axis, Vec<usize>)> {
    if scn.floes.is_empty() {
        return None;
    }
    let c = mass_centroid(scn);
    let mut dirs: Vec<Vec2> = Vec::new();
    let (mut a, mut b) = ([0.0; 3], [0.0; 3]);
    for (i, f) in scn.floes.iter().enumerate() {
        let r = f.position - c;
        a[0] += f.mass * r.x * r.x;
        a[1] += f.mass * r.x * r.y;
        a[2] += f.mass * r.y * r.y;
        for p in initial_polygon(scn, i) {
            let r = p - c;
            b[0] += r.x * r.x;
            b[1] += r.x * r.y;
            b[2] += r.y * r.y;
        }
    }
    dirs.extend(principal_directions(a[0], a[1], a[2]));
    dirs.extend(principal_directions(b[0], b[1], b[2]));
    for k in 0..4 {
        let phi = k as f64 * std::f64::consts::FRAC_PI_4;
        dirs.push(Vec2::new(phi.cos(), phi.sin()));
    }
    dirs.into_iter().find_map(|d| {
        let axis = Axis { c, d };
        mirror_pairing(scn, &axis).map(|p| (axis, p))
    })
}

/// Whether the configuration is symmetric about the line through `c` along
/// `d` with every floe its own image (impacts along it are central).
pub(super) fn self_symmetric(scn: &Scenario, c: Vec2, d: Vec2) -> bool {
    mirror_pairing(scn, &Axis { c, d }).is_some_and(|p| p.iter().enumerate().all(|(i, &j)| i == j))
}

/// Smallest distance `s ≥ 0` along the ray `p + s d` to the polygon's
/// boundary (`None` if the ray misses it).
fn ray_polygon(p: &Vec2, d: &Vec2, poly: &[Vec2]) -> Option<f64> {
    let n = poly.len();
    let mut best: Option<f64> = None;
    for k in 0..n {
        let a = poly[k];
        let e = poly[(k + 1) % n] - a;
        let den = cross(d, &e);
        if den.abs() <= 1e-14 * e.norm() {
            continue;
        }
        let ap = a - p;
        let s = cross(&ap, &e) / den;
        let t = cross(&ap, d) / den;
        if (-1e-12..=1.0 + 1e-12).contains(&t) {
            let s = s.max(0.0);
            if s >= 0.0 {
                best = Some(best.map_or(s, |b: f64| b.min(s)));
            }
        }
    }
    best
}

/// How far floe `i` can translate along the unit direction `d` from t = 0
/// before it touches an obstacle (m, `None` if never), and how many vertex
/// rays (floe vertices forward, obstacle vertices backward) reach that
/// distance (two or more: a face contact).
pub fn translation_gap(scn: &Scenario, i: usize, d: &Vec2) -> Option<(f64, usize)> {
    let poly = initial_polygon(scn, i);
    let mut hits: Vec<f64> = Vec::new();
    for o in &scn.obstacles {
        hits.extend(poly.iter().filter_map(|p| ray_polygon(p, d, &o.polygon)));
        hits.extend(o.polygon.iter().filter_map(|q| ray_polygon(q, &-d, &poly)));
    }
    let gap = hits.iter().copied().reduce(f64::min)?;
    let tol = GEOMETRY_MATCH * scn.floes[i].radius;
    let count = hits.iter().filter(|&&s| s <= gap + tol).count();
    Some((gap, count))
}

/// The direction of the constant wind if the case is "constant wind as
/// gravity" (docs/physics.md §2.3): one floe, an obstacle, constant wind,
/// no water drag, no Coriolis.
pub(super) fn wind_as_gravity(scn: &Scenario) -> Option<Vec2> {
    let env = &scn.environment;
    let ua = env.air.velocity.constant_value()?;
    if scn.floes.len() != 1
        || scn.obstacles.is_empty()
        || env.air.drag_factor() <= 0.0
        || env.water.drag_factor() != 0.0
        || env.coriolis != 0.0
    {
        return None;
    }
    ua.try_normalize(0.0)
}

/// Floes in a row along the unit direction `d` from floe 0: the floe
/// indices sorted along `d`, if every centre lies on the line through floe
/// 0's centre (to rounding) and the configuration is symmetric about it.
pub(super) fn in_a_row(scn: &Scenario, d: Vec2) -> Option<Vec<usize>> {
    let c = scn.floes[0].position;
    let tol = GEOMETRY_MATCH * extent(scn, &c);
    if scn
        .floes
        .iter()
        .any(|f| cross(&d, &(f.position - c)).abs() > tol)
        || !self_symmetric(scn, c, d)
    {
        return None;
    }
    let mut order: Vec<usize> = (0..scn.floes.len()).collect();
    order.sort_by(|&i, &j| {
        let (si, sj) = (
            (scn.floes[i].position - c).dot(&d),
            (scn.floes[j].position - c).dot(&d),
        );
        si.total_cmp(&sj)
    });
    Some(order)
}
