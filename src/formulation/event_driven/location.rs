//! Event location (docs/physics.md §4.3, step 4): the swept motion of each
//! pair over a trial step, the first contact or return of a flight, found
//! by clipping and root finding on the Hermite motion of the floes.

use super::*;

/// The earlier of two cuts.
pub(super) fn earlier(a: Option<(f64, Cut)>, s: f64, why: Cut) -> Option<(f64, Cut)> {
    match a {
        Some((t, _)) if t <= s => a,
        _ => Some((s, why)),
    }
}

/// Margin on the relative travel of two bodies over a step in the transit
/// prefilter (drag makes the forces vary a little over a step).
pub(super) const TRANSIT_MARGIN: f64 = 1.25;
/// Pieces of the path of a vertex relative to another body in the transit
/// test ([`transit`]): the relative path is curved when the bodies turn.
pub(super) const TRANSIT_PIECES: usize = 4;

/// The pose `(G, θ)` of a floe at the fraction `σ` of a step of length `h`
/// from `b0` to `b1`: cubic Hermite interpolation of both from their values
/// and rates at the ends (exact for a motion under constant forces without
/// rotation, and second order in `h` otherwise).
pub(super) fn hermite_pose(b0: &BodyState, b1: &BodyState, h: f64, sigma: f64) -> (Vec2, f64) {
    let s2 = sigma * sigma;
    let s3 = s2 * sigma;
    let (h00, h10, h01, h11) = (
        2.0 * s3 - 3.0 * s2 + 1.0,
        s3 - 2.0 * s2 + sigma,
        -2.0 * s3 + 3.0 * s2,
        s3 - s2,
    );
    (
        b0.position * h00 + b0.velocity * (h10 * h) + b1.position * h01 + b1.velocity * (h11 * h),
        b0.angle * h00
            + b0.angular_velocity * (h10 * h)
            + b1.angle * h01
            + b1.angular_velocity * (h11 * h),
    )
}

/// The motion of body `owner` relative to body `other` over the step of
/// length `h` from `sys` to `end`, at the [`TRANSIT_PIECES`]` + 1` fractions
/// `σ = k / TRANSIT_PIECES` of the step: the rigid maps `x ↦ R(α) x + d`
/// (as `(cos α, sin α, d)`) taking a point of `owner` (its shape for a floe,
/// its world polygon for an obstacle) into the frame of `other`, both poses
/// interpolated by [`hermite_pose`].
pub(super) fn relative_motion(
    scn: &Scenario,
    sys: &System,
    end: &System,
    h: f64,
    owner: usize,
    other: usize,
) -> Vec<(f64, f64, Vec2)> {
    let pose = |body: usize, sigma: f64| -> (Vec2, f64) {
        match scn.body(body) {
            Body::Floe(i) => hermite_pose(&sys.bodies[i], &end.bodies[i], h, sigma),
            Body::Obstacle(_) => (Vec2::zeros(), 0.0),
        }
    };
    (0..=TRANSIT_PIECES)
        .map(|k| {
            let sigma = k as f64 / TRANSIT_PIECES as f64;
            let ((gv, av), (go, ao)) = (pose(owner, sigma), pose(other, sigma));
            let alpha = av - ao;
            (alpha.cos(), alpha.sin(), rotate(&(gv - go), -ao))
        })
        .collect()
}

/// Whether the point `x` of a body (in the body's own coordinates, see
/// [`relative_motion`]) passes within `grow` (m: the impact gap `g_i`,
/// [`IMPACT_GAP_FRACTION`] of `δ`) of the polygon `local` of another body
/// during the step: its path in that body's frame, given by `motion`, is
/// followed in straight pieces, each clipped against the polygon grown by
/// `grow`. Returns the middle of the first passage as a fraction of the
/// step, if there is one.
///
/// A non-convex body is the union of its convex parts (`part_polys`, from
/// [`part_polygons`] of `local`): the passage is against the
/// nearest-in-time part; `part_polys` is empty for a convex body, whose
/// outline is its one part.
pub(super) fn transit(
    motion: &[(f64, f64, Vec2)],
    x: &Vec2,
    local: &[Vec2],
    part_polys: &[Vec<Vec2>],
    grow: f64,
) -> Option<f64> {
    let map = |&(c, s, d): &(f64, f64, Vec2)| Vec2::new(c * x.x - s * x.y, s * x.x + c * x.y) + d;
    let pieces = motion.len().saturating_sub(1).max(1) as f64;
    let mut q0 = map(&motion[0]);
    for (piece, m) in motion.iter().enumerate().skip(1) {
        let q1 = map(m);
        let hit = if part_polys.is_empty() {
            clip(&q0, &q1, local, grow)
        } else {
            part_polys
                .iter()
                .filter_map(|p| clip(&q0, &q1, p, grow))
                .reduce(f64::min)
        };
        if let Some(u) = hit {
            return Some((piece as f64 - 1.0 + u) / pieces);
        }
        q0 = q1;
    }
    None
}

/// The convex parts (index lists `parts`) of the outline `poly` as
/// polygons; empty (no allocation) for a convex body, which is its one part.
pub(super) fn part_polygons(poly: &[Vec2], parts: &[Vec<usize>]) -> Vec<Vec<Vec2>> {
    if parts.len() <= 1 {
        return Vec::new();
    }
    parts
        .iter()
        .map(|ids| ids.iter().map(|&k| poly[k]).collect())
        .collect()
}

/// Signed distance (m) from the point `v` to body `body` of `scn` at its
/// world outline `poly`: the convex formula
/// ([`point_polygon_signed_distance`]) for a convex body, the simple-polygon
/// one ([`point_outline_signed_distance`]) for a non-convex body.
pub(super) fn body_distance(scn: &Scenario, body: usize, v: &Vec2, poly: &[Vec2]) -> f64 {
    if body_parts(scn, body).len() <= 1 {
        point_polygon_signed_distance(v, poly)
    } else {
        point_outline_signed_distance(v, poly)
    }
}

/// Cyrus–Beck clipping of the segment `q0 → q1` against the convex
/// counter-clockwise polygon `poly` grown by `grow` (m): the middle of the
/// part inside, as a fraction of the segment, if there is one.
pub(super) fn clip(q0: &Vec2, q1: &Vec2, poly: &[Vec2], grow: f64) -> Option<f64> {
    let dq = q1 - q0;
    let (mut u_in, mut u_out) = (0.0f64, 1.0f64);
    let n = poly.len();
    for e in 0..n {
        let a = poly[e];
        let edge = poly[(e + 1) % n] - a;
        let len = edge.norm();
        if len == 0.0 {
            continue;
        }
        let normal = Vec2::new(edge.y, -edge.x) / len;
        let num = (q0 - a).dot(&normal) - grow;
        let den = dq.dot(&normal);
        if den == 0.0 {
            if num > 0.0 {
                return None;
            }
        } else if den < 0.0 {
            u_in = u_in.max(-num / den);
        } else {
            u_out = u_out.min(-num / den);
        }
        if u_in > u_out {
            return None;
        }
    }
    Some(0.5 * (u_in + u_out))
}

/// The contact horizon `τ_c = (2 ε Δt_max / a_f)^(1/3)`, s, the longest
/// step with closed contacts. A step holds the contact force constant while
/// the environment forces change; the drag changes them on the time scale
/// `Δt_max` (docs/physics.md §4.2), by about `a_f h / Δt_max` over a step
/// `h` (`a_f` the forcing: the drag of the strongest wind and current on the
/// lightest floe at rest, as an acceleration), which drifts a contact by
/// about `a_f h³ / (2 Δt_max)`: at most the penetration tolerance `ε` within
/// `τ_c`. Without water drag or without forcing the forces on a contact do
/// not change between the kinks of the forcing series (where steps stop
/// anyway) and the horizon is infinite.
pub fn contact_horizon(scn: &Scenario, pen_tol: f64, drag_bound: f64) -> f64 {
    let env = &scn.environment;
    let traction = env.air.drag_factor() * env.air.velocity.max_speed().powi(2)
        + env.water.drag_factor() * env.water.velocity.max_speed().powi(2);
    let forcing = scn
        .floes
        .iter()
        .map(|f| traction / f.surface_density())
        .fold(0.0, f64::max);
    if forcing > 0.0 && drag_bound.is_finite() {
        (2.0 * pen_tol * drag_bound / forcing).cbrt()
    } else {
        f64::INFINITY
    }
}

/// Whether the pair `(min, max)` is isolated among `contacts`: no other
/// pair touches either of its floes (obstacles may touch other floes), so
/// that only the environment pulls its contact back.
pub(super) fn isolated(scn: &Scenario, contacts: &[Contact], pair: (usize, usize)) -> bool {
    let floe = |b: usize| matches!(scn.body(b), Body::Floe(_));
    contacts.iter().all(|d| {
        let p = pair_of(d);
        p == pair
            || !([p.0, p.1]
                .iter()
                .any(|&b| floe(b) && (b == pair.0 || b == pair.1)))
    })
}

/// The pair of a contact, smaller index first.
pub(super) fn pair_of(c: &Contact) -> (usize, usize) {
    (c.a.min(c.b), c.a.max(c.b))
}

impl EventDriven {
    /// Integrates every floe from `sys` over `s` with `wrenches`.
    pub(super) fn integrate(
        &mut self,
        scn: &Scenario,
        sys: &System,
        s: f64,
        wrenches: &[Wrench],
    ) -> Result<System, FormulationError> {
        Ok(self
            .integ
            .advance_system(scn, sys, sys.t + s, wrenches, None)?)
    }

    /// Candidate pairs over a step: swept boxes of the start and end states.
    pub(super) fn swept_pairs(
        &mut self,
        scn: &Scenario,
        p0: &[Vec<Vec2>],
        p1: &[Vec<Vec2>],
    ) -> Vec<(usize, usize)> {
        let boxes: Vec<Aabb> = p0
            .iter()
            .zip(p1)
            .enumerate()
            .map(|(i, (a, b))| {
                let (lo0, hi0) = aabb(a);
                let (lo1, hi1) = aabb(b);
                Aabb {
                    min: lo0.inf(&lo1),
                    max: hi0.sup(&hi1),
                    fixed: matches!(scn.body(i), Body::Obstacle(_)),
                }
            })
            .collect();
        let mut pairs = Vec::new();
        self.sweep_bp.pairs(&boxes, self.distance, &mut pairs);
        pairs
    }

    /// The signed distance (m) between bodies `i` and `j` at their world
    /// outlines `a` and `b`: the minimum translation distance of two convex
    /// polygons ([`signed_distance`]), and for a non-convex body the smallest
    /// over the pairs of their convex parts (a penetration is then the
    /// deepest overlap of two parts).
    pub(super) fn pair_signed_distance(
        scn: &Scenario,
        i: usize,
        j: usize,
        a: &[Vec2],
        b: &[Vec2],
    ) -> f64 {
        let (pa, pb) = (
            part_polygons(a, body_parts(scn, i)),
            part_polygons(b, body_parts(scn, j)),
        );
        if pa.is_empty() && pb.is_empty() {
            return signed_distance(a, b);
        }
        let whole = |poly: &[Vec2]| vec![poly.to_vec()];
        let pa = if pa.is_empty() { whole(a) } else { pa };
        let pb = if pb.is_empty() { whole(b) } else { pb };
        let mut d = f64::INFINITY;
        for qa in &pa {
            for qb in &pb {
                d = d.min(signed_distance(qa, qb));
            }
        }
        d
    }

    /// Finds the first event in `(0, h]`: a vertex that was open and closes.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn locate(
        &mut self,
        scn: &Scenario,
        sys: &System,
        end: &System,
        h: f64,
        wrenches: &[Wrench],
        p0: &[Vec<Vec2>],
        p1: &[Vec<Vec2>],
    ) -> Result<Option<Event>, FormulationError> {
        let delta = self.distance;
        let target = IMPACT_GAP_FRACTION * delta;
        let mut first: Option<Event> = None;
        for (i, j) in self.swept_pairs(scn, p0, p1) {
            // Vertices open at the start and closing at the end: (owner,
            // index); failing those, vertices open at both ends whose path
            // relative to the other body passes within g_i of it (a transit
            // inside the step), with the middle of that passage.
            let mut cand: Vec<(usize, usize)> = Vec::new();
            let mut transits: Vec<((usize, usize), f64)> = Vec::new();
            // A vertex travels at most `reach` relative to the other body
            // over the step (the largest point speeds at the ends, which
            // bound them between under constant forces, with a margin): it
            // can pass within g_i of it only if d0 + d1 ≤ reach + 2 g_i.
            let speed = |b: usize| match scn.body(b) {
                Body::Floe(f) => {
                    let r = scn.floes[f].radius;
                    let at = |s: &BodyState| s.velocity.norm() + s.angular_velocity.abs() * r;
                    at(&sys.bodies[f]).max(at(&end.bodies[f]))
                }
                Body::Obstacle(_) => 0.0,
            };
            let reach = TRANSIT_MARGIN * (speed(i) + speed(j)) * h + 2.0 * target;
            for (owner, other) in [(i, j), (j, i)] {
                let mut motion = None;
                let local: &[Vec2] = match scn.body(other) {
                    Body::Floe(o) => &scn.floes[o].shape,
                    Body::Obstacle(_) => &p0[other],
                };
                let part_polys = part_polygons(local, body_parts(scn, other));
                for (k, (v0, v1)) in p0[owner].iter().zip(&p1[owner]).enumerate() {
                    let d0 = body_distance(scn, other, v0, &p0[other]);
                    if d0 <= delta {
                        continue;
                    }
                    let d1 = body_distance(scn, other, v1, &p1[other]);
                    if d1 < target {
                        cand.push((owner, k));
                        continue;
                    }
                    if d0 + d1 > reach {
                        continue;
                    }
                    let motion = motion
                        .get_or_insert_with(|| relative_motion(scn, sys, end, h, owner, other));
                    let x = match scn.body(owner) {
                        Body::Floe(f) => scn.floes[f].shape[k],
                        Body::Obstacle(_) => *v0,
                    };
                    if let Some(mid) = transit(motion, &x, local, &part_polys, target) {
                        transits.push(((owner, k), mid * h));
                    }
                }
            }
            let hi_limit = first.map_or(h, |f| f.0).min(h);
            let probes: Vec<f64> = if cand.is_empty() {
                cand = transits.iter().map(|t| t.0).collect();
                let mut p: Vec<f64> = transits
                    .iter()
                    .map(|t| t.1)
                    .filter(|&s| s < hi_limit)
                    .collect();
                p.sort_by(f64::total_cmp);
                p
            } else {
                vec![hi_limit]
            };
            if probes.is_empty() {
                continue;
            }
            // φ(s) = min over candidates of d(s) − g_i.
            let phi = |s: f64, me: &mut Self| -> Result<f64, FormulationError> {
                let mut poly = |idx: usize| -> Result<Vec<Vec2>, FormulationError> {
                    if let Body::Obstacle(_) = scn.body(idx) {
                        return Ok(p0[idx].clone());
                    }
                    let mut b = sys.bodies[idx];
                    let mut scratch = Ledger::default();
                    me.integ.advance_with(
                        scn,
                        idx,
                        &mut b,
                        &mut scratch,
                        sys.t,
                        sys.t + s,
                        &wrenches[idx],
                    )?;
                    let mut p = Vec::new();
                    scn.floes[idx].world_polygon(&b.position, b.angle, &mut p);
                    Ok(p)
                };
                let (pi, pj) = (poly(i)?, poly(j)?);
                let mut m = f64::INFINITY;
                for &(owner, k) in &cand {
                    let (own, oth, other) = if owner == i {
                        (&pi, &pj, j)
                    } else {
                        (&pj, &pi, i)
                    };
                    m = m.min(body_distance(scn, other, &own[k], oth));
                }
                Ok(m - target)
            };
            // Only search below the earliest event found so far, up to the
            // first probe where a candidate is closed.
            let mut closed_at = None;
            for &probe in &probes {
                let f = phi(probe, self)?;
                if f <= 0.0 {
                    closed_at = Some((probe, f));
                    break;
                }
            }
            let Some((hi_start, f_start)) = closed_at else {
                continue; // this pair closes after an earlier event, or not at all
            };
            let (mut lo, mut hi) = (0.0, hi_start);
            let mut f_hi = f_start;
            let mut f_lo = phi(lo, self)?;
            let mut side = 0i8;
            let mut s = hi;
            for _ in 0..200 {
                self.counters.add(&ROOT_ITERATIONS, 1);
                s = if f_lo - f_hi != 0.0 {
                    (lo * f_hi - hi * f_lo) / (f_hi - f_lo)
                } else {
                    0.5 * (lo + hi)
                };
                if !(s > lo && s < hi) {
                    s = 0.5 * (lo + hi);
                }
                let f = phi(s, self)?;
                if f.abs() <= ROOT_TOLERANCE * delta {
                    break;
                }
                if f > 0.0 {
                    lo = s;
                    f_lo = f;
                    if side == 1 {
                        f_hi *= 0.5;
                    }
                    side = 1;
                } else {
                    hi = s;
                    f_hi = f;
                    if side == -1 {
                        f_lo *= 0.5;
                    }
                    side = -1;
                }
                if hi - lo <= 1e-15 * (sys.t + h).abs().max(1e-300) {
                    s = hi;
                    break;
                }
            }
            if first.is_none_or(|f| s < f.0) {
                first = Some((s, (i, j)));
            }
        }
        Ok(first)
    }
}
