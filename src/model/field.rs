//! The seeded random floe field of `[[field]]` tables.
//!
//! Random sequential addition of polygons jams near an area fraction of 0.55,
//! below the concentrations of real pack ice, so the field is built from a
//! tessellation instead:
//!
//! 1. `count` seed points are thrown in the region with a minimum spacing
//!    (Poisson-disk dart throwing on a grid), so cells are rounded;
//! 2. the Voronoi cell of each seed is clipped to the region, by half-planes
//!    of the neighbouring seeds found on a grid (a cell is final when twice
//!    its radius is inside the searched disk: the security-radius criterion);
//! 3. each cell gets a number of vertices drawn in `sides`: extra vertices
//!    are removed (smallest ear first), missing ones added by cutting the
//!    sharpest corner; both keep the polygon convex and inside its cell;
//! 4. with `roughness = ρ > 0`, the middle of every edge is moved towards
//!    the polygon's centroid `c` by `ρ` times its distance to it (the midpoint
//!    `m` becomes `m + ρ (c − m)`), a notch that doubles the vertices and
//!    makes the floe non-convex; `ρ = 0` (the default) skips this step and
//!    gives the convex floes bit for bit. The notched polygon is star-shaped
//!    about `c` (every vertex on its own ray from `c`, in angular order), so
//!    it is simple, and it lies inside the convex polygon it was cut from;
//! 5. each polygon is shrunk about its centroid by a common factor `s`,
//!    clamped per floe so its circumradius stays in `radius`, with `s` found
//!    by bisection so the total area is `concentration × region area`.
//!
//! A shrunk polygon lies inside its cell (a notched one inside its shrunk
//! convex polygon), and cells do not overlap, so no two floes overlap. Only `+ − × / sqrt` are used (no trigonometry), so the
//! same seed gives the same field on every machine. The cost is linear in
//! `count` (grids everywhere, no all-pairs loop), and every loop has a
//! bounded number of rounds: a region and count that the case limits admit
//! ([`super::limits`]) but the generator cannot tessellate give a
//! [`FieldError`], never a panic or a hang.

use super::case::FieldSpec;
use super::{limits, Floe, FloeOrigin};
use crate::geometry::{area_properties, cross, radius_about, Vec2};
use crate::rng::SplitMix64;

/// Why a field cannot be generated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FieldError {
    /// The radius range forbids the target concentration.
    #[error("cannot place {count} floes at concentration {target}: {reason}")]
    Infeasible {
        /// Requested floe count.
        count: usize,
        /// Requested concentration.
        target: f64,
        /// Which constraint is in the way, with the numbers.
        reason: String,
    },
}

/// Generates the floes of one `[[field]]` table (validated beforehand).
pub fn generate_field(spec: &FieldSpec, field_index: usize) -> Result<Vec<Floe>, FieldError> {
    let lo = Vec2::new(spec.region[0][0], spec.region[0][1]);
    let hi = Vec2::new(spec.region[1][0], spec.region[1][1]);
    let mut rng = SplitMix64::new(spec.seed);
    let infeasible = |reason: String| FieldError::Infeasible {
        count: spec.count,
        target: spec.concentration,
        reason,
    };
    let degenerate = || infeasible("a tessellation cell degenerated".into());
    // The case loader refuses larger counts first; a direct caller too.
    if spec.count as f64 > limits::FLOES.max {
        return Err(infeasible(format!(
            "more floes than the limit of {}",
            limits::show(limits::FLOES.max)
        )));
    }
    let seeds = throw_seeds(&mut rng, lo, hi, spec.count).ok_or_else(|| {
        infeasible(format!(
            "the region cannot hold {} seed points apart (too small or too thin for its count)",
            spec.count
        ))
    })?;
    let cells = voronoi_cells(&seeds, lo, hi).ok_or_else(degenerate)?;

    // Shapes with the drawn number of sides.
    let mut shapes = Vec::with_capacity(cells.len());
    for cell in cells {
        let target = rng.int_range(spec.sides[0], spec.sides[1]);
        if cell.len() < 3 {
            return Err(degenerate());
        }
        let poly = adjust_sides(cell, target);
        let poly = if spec.roughness > 0.0 {
            notched(&poly, spec.roughness)
        } else {
            poly
        };
        let props = area_properties(&poly);
        if poly.len() < 3 || props.area.is_nan() || props.area <= 0.0 {
            return Err(degenerate());
        }
        let r = radius_about(&poly, &props.centroid);
        shapes.push((poly, props.area, props.centroid, r));
    }

    let (rmin, rmax) = (spec.radius[0], spec.radius[1]);
    if let Some(small) = shapes.iter().map(|s| s.3).reduce(f64::min) {
        if small < rmin {
            return Err(infeasible(format!(
                "the region leaves cells of circumradius {small:.3} m, below radius min {rmin} m; use fewer floes or a smaller radius min"
            )));
        }
    }
    let region_area = (hi.x - lo.x) * (hi.y - lo.y);
    let target_area = spec.concentration * region_area;
    let scale_of = |s: f64, r: f64| -> f64 { s.clamp(rmin / r, rmax / r).min(1.0) };
    let total = |s: f64| -> f64 {
        shapes
            .iter()
            .map(|(_, a, _, r)| a * scale_of(s, *r).powi(2))
            .sum()
    };
    let most = total(1.0);
    if most < target_area {
        return Err(infeasible(format!(
            "at most {:.3} is reachable with radius max {rmax} m and {} sides at most",
            most / region_area,
            spec.sides[1]
        )));
    }
    let least = total(0.0);
    if least > target_area {
        return Err(infeasible(format!(
            "floes of radius min {rmin} m already cover {:.3}; use fewer floes or a smaller radius min",
            least / region_area
        )));
    }
    let (mut a, mut b) = (0.0, 1.0);
    for _ in 0..100 {
        let m = 0.5 * (a + b);
        if total(m) < target_area {
            a = m;
        } else {
            b = m;
        }
    }
    let s = 0.5 * (a + b);

    let velocity = Vec2::new(spec.velocity[0], spec.velocity[1]);
    let mut floes = Vec::with_capacity(shapes.len());
    for (index, (poly, _, c, r)) in shapes.into_iter().enumerate() {
        let k = scale_of(s, r);
        let world: Vec<Vec2> = poly.iter().map(|p| c + (p - c) * k).collect();
        let thickness = rng.range(spec.thickness[0], spec.thickness[1]);
        floes.push(Floe::from_world_polygon(
            &world,
            thickness,
            spec.density,
            velocity,
            0.0,
            FloeOrigin::Field {
                field: field_index,
                index,
            },
        ));
    }
    Ok(floes)
}

/// A uniform grid of point indices over a box.
struct Grid {
    lo: Vec2,
    cell: f64,
    nx: usize,
    ny: usize,
    bins: Vec<Vec<usize>>,
}

impl Grid {
    fn new(lo: Vec2, hi: Vec2, cell: f64) -> Grid {
        let nx = (((hi.x - lo.x) / cell).ceil() as usize).clamp(1, 4096);
        let ny = (((hi.y - lo.y) / cell).ceil() as usize).clamp(1, 4096);
        let cell = ((hi.x - lo.x) / nx as f64).max((hi.y - lo.y) / ny as f64);
        Grid {
            lo,
            cell,
            nx,
            ny,
            bins: vec![Vec::new(); nx * ny],
        }
    }

    fn coords(&self, p: &Vec2) -> (usize, usize) {
        let ix = ((p.x - self.lo.x) / self.cell).floor().max(0.0) as usize;
        let iy = ((p.y - self.lo.y) / self.cell).floor().max(0.0) as usize;
        (ix.min(self.nx - 1), iy.min(self.ny - 1))
    }

    fn insert(&mut self, p: &Vec2, id: usize) {
        let (ix, iy) = self.coords(p);
        self.bins[iy * self.nx + ix].push(id);
    }

    /// Calls `f` on every id in the bins touching the disk of radius `r` at `p`.
    fn near(&self, p: &Vec2, r: f64, mut f: impl FnMut(usize)) {
        let (x0, y0) = self.coords(&(p - Vec2::repeat(r)));
        let (x1, y1) = self.coords(&(p + Vec2::repeat(r)));
        for iy in y0..=y1 {
            for ix in x0..=x1 {
                for &id in &self.bins[iy * self.nx + ix] {
                    f(id);
                }
            }
        }
    }
}

/// Misses in a row before the spacing of the darts is relaxed by 10 %.
const MISSES_BEFORE_RELAXING: usize = 200;
/// Relaxations of the spacing before the darts give up: the bundled fields
/// (and 100,000 floes) need at most one; 20 leave seeds at least 0.12 of
/// the first spacing apart, so a grid bin never holds more than about 150
/// seeds and the cost stays linear. Darts are then at most
/// `(MISSES_BEFORE_RELAXING + 1) × (count + MAX_RELAXATIONS)`.
const MAX_RELAXATIONS: usize = 20;

/// `count` points in the box with a minimum spacing, by dart throwing; the
/// spacing is relaxed by 10 % whenever darts keep missing. `None` when it
/// has been relaxed [`MAX_RELAXATIONS`] times (a region whose points cannot
/// be told apart) or is not a positive number (a region too small for its
/// count).
fn throw_seeds(rng: &mut SplitMix64, lo: Vec2, hi: Vec2, count: usize) -> Option<Vec<Vec2>> {
    let area = (hi.x - lo.x) * (hi.y - lo.y);
    let mut spacing = 0.75 * (area / count as f64).sqrt();
    if !(spacing > 0.0 && spacing.is_finite()) {
        return None;
    }
    let mut grid = Grid::new(lo, hi, spacing);
    let mut pts: Vec<Vec2> = Vec::with_capacity(count);
    let mut misses = 0usize;
    let mut relaxations = 0usize;
    while pts.len() < count {
        let p = Vec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y));
        let mut ok = true;
        grid.near(&p, spacing, |id| {
            if (pts[id] - p).norm_squared() < spacing * spacing {
                ok = false;
            }
        });
        if ok {
            grid.insert(&p, pts.len());
            pts.push(p);
            misses = 0;
        } else {
            misses += 1;
            if misses > MISSES_BEFORE_RELAXING {
                relaxations += 1;
                if relaxations > MAX_RELAXATIONS {
                    return None;
                }
                spacing *= 0.9;
                misses = 0;
            }
        }
    }
    Some(pts)
}

/// Clips the convex polygon `poly` to the half-plane `n · (x − m) ≤ 0`.
fn clip(poly: &[Vec2], m: &Vec2, n: &Vec2, out: &mut Vec<Vec2>) {
    out.clear();
    let k = poly.len();
    for i in 0..k {
        let a = poly[i];
        let b = poly[(i + 1) % k];
        let da = n.dot(&(a - m));
        let db = n.dot(&(b - m));
        if da <= 0.0 {
            out.push(a);
        }
        if (da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0) {
            let t = da / (da - db);
            out.push(a + (b - a) * t);
        }
    }
}

/// Times the searched disk of a cell may grow (by 1.5 each): from three
/// spacings to past the region's diagonal takes at most `log1.5(sqrt(count)
/// × aspect)` rounds, far fewer than this.
const MAX_SEARCH_GROWTH: usize = 200;

/// The Voronoi cells of `seeds`, clipped to the box; `None` when a cell's
/// search does not close (a degenerate region).
fn voronoi_cells(seeds: &[Vec2], lo: Vec2, hi: Vec2) -> Option<Vec<Vec<Vec2>>> {
    let area = (hi.x - lo.x) * (hi.y - lo.y);
    let spacing = (area / seeds.len() as f64).sqrt();
    if !(spacing > 0.0 && spacing.is_finite()) {
        return None;
    }
    let mut grid = Grid::new(lo, hi, spacing);
    for (i, p) in seeds.iter().enumerate() {
        grid.insert(p, i);
    }
    let box_poly = [lo, Vec2::new(hi.x, lo.y), hi, Vec2::new(lo.x, hi.y)];
    let diag = (hi - lo).norm();
    let mut near: Vec<(f64, usize)> = Vec::new();
    let mut buf = Vec::new();
    let mut cells = Vec::with_capacity(seeds.len());
    for (i, p) in seeds.iter().enumerate() {
        let mut r = 3.0 * spacing;
        let mut closed = false;
        for _ in 0..MAX_SEARCH_GROWTH {
            near.clear();
            grid.near(p, r, |j| {
                if j != i {
                    let d2 = (seeds[j] - p).norm_squared();
                    if d2 <= r * r {
                        near.push((d2, j));
                    }
                }
            });
            near.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let mut cell: Vec<Vec2> = box_poly.to_vec();
            for &(_, j) in &near {
                let n = seeds[j] - p;
                let m = (seeds[j] + p) * 0.5;
                clip(&cell, &m, &n, &mut buf);
                std::mem::swap(&mut cell, &mut buf);
            }
            let reach = cell.iter().map(|v| (v - p).norm()).fold(0.0, f64::max);
            if 2.0 * reach <= r || r > diag {
                cells.push(cell);
                closed = true;
                break;
            }
            r *= 1.5;
        }
        if !closed {
            return None;
        }
    }
    Some(cells)
}

/// The convex polygon `poly` with the middle of every edge moved towards
/// its centroid by `roughness` (dimensionless, in `(0, 0.5]`) times its
/// distance to it: `2n` vertices, star-shaped about the centroid, simple and
/// counter-clockwise (step 4 of the module documentation).
fn notched(poly: &[Vec2], roughness: f64) -> Vec<Vec2> {
    let c = area_properties(poly).centroid;
    let n = poly.len();
    let mut out = Vec::with_capacity(2 * n);
    for i in 0..n {
        let (p, q) = (poly[i], poly[(i + 1) % n]);
        let m = (p + q) * 0.5;
        out.push(p);
        out.push(m + (c - m) * roughness);
    }
    out
}

/// Twice the area of the ear at vertex `i`.
fn ear(poly: &[Vec2], i: usize) -> f64 {
    let n = poly.len();
    let a = poly[(i + n - 1) % n];
    let c = poly[(i + 1) % n];
    cross(&(poly[i] - a), &(c - poly[i]))
}

/// Brings a convex cell to `target` vertices, staying inside it (a cell of
/// fewer than 3 vertices is returned as it is: the caller refuses it).
fn adjust_sides(mut poly: Vec<Vec2>, target: usize) -> Vec<Vec2> {
    if poly.len() < 3 {
        return poly;
    }
    // Remove near-collinear vertices first (tiny Voronoi edges).
    let area = area_properties(&poly).area;
    loop {
        if poly.len() <= 3 {
            break;
        }
        let (i, e) = (0..poly.len())
            .map(|i| (i, ear(&poly, i)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((0, f64::INFINITY));
        if e < 1e-6 * area || poly.len() > target {
            poly.remove(i);
        } else {
            break;
        }
    }
    while poly.len() < target {
        // Cut the sharpest corner: smallest cos of the interior angle is the
        // widest; the sharpest has the largest dot of the outgoing edges.
        let n = poly.len();
        let sharpest = (0..n)
            .map(|i| {
                let a = (poly[(i + n - 1) % n] - poly[i]).normalize();
                let c = (poly[(i + 1) % n] - poly[i]).normalize();
                (i, a.dot(&c))
            })
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|x| x.0)
            .unwrap_or(0);
        let v = poly[sharpest];
        let a = poly[(sharpest + n - 1) % n];
        let c = poly[(sharpest + 1) % n];
        let p1 = v + (a - v) * 0.25;
        let p2 = v + (c - v) * 0.25;
        poly[sharpest] = p1;
        poly.insert(sharpest + 1, p2);
    }
    poly
}
