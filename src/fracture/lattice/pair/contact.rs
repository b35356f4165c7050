//! The contacts of a two-lattice impact (docs/physics.md §9.9, the
//! module doc of [`super`]): the start at first touch, the nodes of one
//! outline inside the other's, their compression-only links, forces,
//! dashpot power and elastic energy.

use super::{Body, Pair};
use crate::fracture::chain::Link;
use crate::geometry::{cross, outline_nearest, Vec2};

/// Moves of the second body along the normal that [`Pair::separate`] may
/// make before it gives up: each removes the deepest overlap, so a convex
/// pair needs one or two (the nearest segment changes as it moves).
const SEPARATION_PASSES: usize = 16;

/// The gap [`Pair::close`] leaves, as a fraction of the largest node
/// coordinate (m/m): ten thousand times the rounding of a coordinate
/// (2.2e-16 relative), far below any length of the impact (1e-9 m for
/// coordinates of 1 km, closed in a microsecond at 1 mm/s).
const CLOSE_MARGIN: f64 = 1e-12;

/// One contact of the step: node `node` of body `from` behind segment
/// `a b` of body `to`'s outline.
#[derive(Debug, Clone, Copy)]
pub(super) struct Touch {
    from: usize,
    node: usize,
    a: usize,
    b: usize,
    t: f64,
    gap: f64,
    normal: Vec2,
}

/// The distance `t ≥ 0` (m) at which the ray `p + t d` meets the segment
/// `a b`, or `None` (parallel, or passing by).
fn ray_meets(p: &Vec2, d: &Vec2, a: &Vec2, b: &Vec2) -> Option<f64> {
    let e = b - a;
    let denominator = cross(d, &e);
    if denominator == 0.0 {
        return None;
    }
    let r = a - p;
    let t = cross(&r, &e) / denominator;
    let u = cross(&r, d) / denominator;
    (t >= 0.0 && (0.0..=1.0).contains(&u)).then_some(t)
}

impl Pair<'_> {
    /// Moves the second body along `−n` until the outlines first touch,
    /// when no outline node of one body is inside the other yet (module
    /// doc, **Start**: the gap a rigid scheme's contact leaves, up to its
    /// tolerance, closed); returns the distance, m, 0 when they touch
    /// already or no node would meet the other outline along `n`.
    pub(super) fn close(&mut self, n: Vec2) -> f64 {
        self.find_touches();
        if self.bodies.len() < 2 || !self.touches.is_empty() {
            return 0.0;
        }
        let mut distance = f64::INFINITY;
        for from in 0..2 {
            // The second body moves along −n: its nodes meet the first's
            // outline along −n, the first's nodes meet its outline along n.
            let d = if from == 0 { n } else { -n };
            let (src, dst) = (&self.bodies[from], &self.bodies[1 - from]);
            let nb = dst.outline.len();
            let outline = &dst.p.x[..nb];
            for &i in &src.outline {
                let p = src.p.x[i];
                for a in 0..nb {
                    if let Some(t) = ray_meets(&p, &d, &outline[a], &outline[(a + 1) % nb]) {
                        distance = distance.min(t);
                    }
                }
            }
        }
        if !distance.is_finite() {
            return 0.0;
        }
        // Stop a hair short of the touch: a node placed on the other
        // outline to rounding may test inside it, and moving back out along
        // `n` a segment oblique to `n` converges slowly (measured: 103
        // impacts of the 200-floe field refused at 1e-12 m of overlap).
        let scale = self
            .bodies
            .iter()
            .flat_map(|b| b.outline.iter().map(|&i| b.p.x[i].amax()))
            .fold(0.0, f64::max);
        let distance = distance - CLOSE_MARGIN * scale;
        if distance <= 0.0 {
            return 0.0;
        }
        let b = &mut self.bodies[1];
        b.p.x.iter_mut().for_each(|x| *x -= n * distance);
        b.start -= n * distance;
        distance
    }

    /// Moves the second body along `n` until no outline node of one body
    /// is inside the other (module doc, **Start**); returns the distance, m.
    /// Fails when [`SEPARATION_PASSES`] moves are not enough.
    pub(super) fn separate(&mut self, n: Vec2) -> Result<f64, String> {
        let mut moved = 0.0;
        for _ in 0..SEPARATION_PASSES {
            self.find_touches();
            let depth = self.touches.iter().map(|c| -c.gap).fold(0.0, f64::max);
            if depth == 0.0 {
                return Ok(moved);
            }
            // A hair more than the depth, so that the deepest node is out.
            let d = depth * (1.0 + 1e-9);
            let b = &mut self.bodies[1];
            b.p.x.iter_mut().for_each(|x| *x += n * d);
            b.start += n * d;
            moved += d;
        }
        Err(format!(
            "the lattices still overlap after moving them {moved} m apart along the normal"
        ))
    }

    /// Finds the contacts at the current positions (module doc).
    pub(super) fn find_touches(&mut self) {
        self.touches.clear();
        if self.bodies.len() < 2 {
            return;
        }
        for from in 0..2 {
            let (src, dst) = (&self.bodies[from], &self.bodies[1 - from]);
            let nb = dst.outline.len();
            let outline = &dst.p.x[..nb];
            let (lo, hi) = bounds(outline);
            for &i in &src.outline {
                let p = src.p.x[i];
                if p.x < lo.x || p.x > hi.x || p.y < lo.y || p.y > hi.y {
                    continue;
                }
                let (gap, a, t) = outline_nearest(&p, outline);
                if gap < 0.0 {
                    let b = (a + 1) % nb;
                    // p − q as the nearest point's search computed it: its
                    // norm is exactly −gap.
                    let r = (p - outline[a]) - (outline[b] - outline[a]) * t;
                    self.touches.push(Touch {
                        from,
                        node: i,
                        a,
                        b,
                        t,
                        gap,
                        normal: r / gap,
                    });
                }
            }
        }
    }

    /// The contact's link and gap rate, m/s.
    pub(super) fn link_of(&self, c: &Touch) -> (Link, f64) {
        let (src, dst) = (&self.bodies[c.from], &self.bodies[1 - c.from]);
        let (m, mo) = (&src.p.lattice.mass, &dst.p.lattice.mass);
        let link = src.contact_link(m[c.node], mo[c.a] + mo[c.b]);
        let v = &dst.p.v;
        let rate = c
            .normal
            .dot(&(src.p.v[c.node] - v[c.a] * (1.0 - c.t) - v[c.b] * c.t));
        (link, rate)
    }

    /// Finds the contacts and adds their forces to the bodies' forces.
    pub(super) fn contact_forces(&mut self) {
        self.find_touches();
        for k in 0..self.touches.len() {
            let c = self.touches[k];
            let (link, rate) = self.link_of(&c);
            let f = link.force(c.gap, rate);
            if f == 0.0 {
                continue;
            }
            let push = -c.normal * f;
            self.bodies[c.from].p.force[c.node] += push;
            let dst = &mut self.bodies[1 - c.from].p.force;
            dst[c.a] -= push * (1.0 - c.t);
            dst[c.b] -= push * c.t;
        }
    }

    /// The power taken out by every dashpot now, W.
    pub(super) fn dashpot_power(&self) -> f64 {
        let contacts: f64 = self
            .touches
            .iter()
            .map(|c| {
                let (link, rate) = self.link_of(c);
                link.dissipation(c.gap, rate)
            })
            .sum();
        contacts + self.bodies.iter().map(|b| b.p.dashpot_power()).sum::<f64>()
    }

    /// The elastic energy of the contacts between the bodies, J.
    pub(super) fn contact_energy(&self) -> f64 {
        self.touches
            .iter()
            .map(|c| self.link_of(c).0.energy(c.gap))
            .sum()
    }
}

impl Body<'_> {
    /// The contact link of an outline node of mass `m` (kg) with a
    /// partner of mass `mo` (kg): the striker's law (module doc).
    pub(super) fn contact_link(&self, m: f64, mo: f64) -> Link {
        let mu = m * mo / (m + mo);
        Link {
            k: self.link_k,
            c: self.damping * (self.link_k * mu).sqrt(),
            rest: 0.0,
            bonded: false,
            critical: f64::INFINITY,
        }
    }
}

/// The bounding box of the points `x`, m.
fn bounds(x: &[Vec2]) -> (Vec2, Vec2) {
    x.iter().fold(
        (Vec2::repeat(f64::INFINITY), Vec2::repeat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    )
}
