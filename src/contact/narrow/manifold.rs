//! Contact points of two convex polygons (the module doc of [`super`],
//! "Contact points"): [`contacts`] and its variants from the pair's
//! separation, the reference/incident edge clipping in `manifold`.

use super::minkowski::{next, outward_normal, pair, separation_in};
use super::{ContactGeom, Feature, NarrowOptions, PartOf, Parts, Separation, Side};
use crate::geometry::{cross, perp, Vec2};

/// Appends to `out` the contact points of polygons `a` and `b` if their
/// signed distance is at most `distance` (m, a contact distance `≥ 0`), with
/// the default [`NarrowOptions`].
///
/// One point for a vertex–edge or vertex–vertex configuration, two for
/// facing parallel edges whose projections overlap (the ends of the
/// overlap). Only points with `gap ≤ distance` are kept. Normals point from
/// A to B.
pub fn contacts(a: &[Vec2], b: &[Vec2], distance: f64, out: &mut Vec<ContactGeom>) {
    contacts_with(a, b, distance, &NarrowOptions::default(), out);
}

/// [`contacts`] with explicit tolerances.
pub fn contacts_with(
    a: &[Vec2],
    b: &[Vec2],
    distance: f64,
    options: &NarrowOptions,
    out: &mut Vec<ContactGeom>,
) {
    for_each_contact(a, b, distance, options, |g| out.push(g));
}

/// Calls `emit` on each contact point of the pair (see [`contacts`]).
pub(crate) fn for_each_contact(
    a: &[Vec2],
    b: &[Vec2],
    distance: f64,
    options: &NarrowOptions,
    emit: impl FnMut(ContactGeom),
) {
    for_each_part_contact(a, b, &Parts::default(), distance, options, emit);
}

/// [`for_each_contact`] for two convex parts of compound bodies (see
/// [`separation_in`]): internal edges are neither reference nor incident
/// edges. Features are indices into the parts.
pub(crate) fn for_each_part_contact(
    a: &[Vec2],
    b: &[Vec2],
    parts: &Parts,
    distance: f64,
    options: &NarrowOptions,
    mut emit: impl FnMut(ContactGeom),
) {
    let Some(sep) = separation_in(a, b, parts) else {
        return;
    };
    let within = sep.distance <= distance; // false for NaN
    if !within {
        return;
    }
    match (sep.feature.a, sep.feature.b) {
        (Feature::Edge(r), Feature::Vertex(q)) => {
            let inc = parts.b.as_ref();
            manifold(a, r, b, q, inc, Side::A, &sep, distance, options, &mut emit)
        }
        (Feature::Vertex(q), Feature::Edge(r)) => {
            let inc = parts.a.as_ref();
            manifold(b, r, a, q, inc, Side::B, &sep, distance, options, &mut emit)
        }
        (Feature::Vertex(i), Feature::Vertex(j)) => emit(ContactGeom {
            point: 0.5 * (a[i] + b[j]),
            normal: sep.normal,
            tangent: perp(&sep.normal),
            gap: sep.distance,
            feature: sep.feature,
        }),
        // Never produced by `separation`.
        (Feature::Edge(_), Feature::Edge(_)) => {}
    }
}

/// Where a clipped end of the incident edge comes from.
#[derive(Clone, Copy)]
enum ClipEnd {
    /// An unclipped vertex of the incident polygon.
    Incident(usize),
    /// The slab plane through this vertex of the reference polygon.
    Reference(usize),
}

/// Contact points for the reference edge `r` of `refp` (on side `ref_side`)
/// against the vertex `q` of `inc` (a part of a compound body when
/// `inc_part` is given: its internal edges are not incident edges), given
/// the pair's separation.
#[allow(clippy::too_many_arguments)]
fn manifold(
    refp: &[Vec2],
    r: usize,
    inc: &[Vec2],
    q: usize,
    inc_part: Option<&PartOf>,
    ref_side: Side,
    sep: &Separation,
    distance: f64,
    options: &NarrowOptions,
    emit: &mut impl FnMut(ContactGeom),
) {
    let normal = sep.normal;
    let tangent = perp(&normal);
    let n_ref = match ref_side {
        Side::A => normal,
        Side::B => -normal,
    };
    let r_next = next(r, refp.len());
    let (r0, r1) = (refp[r], refp[r_next]);
    let make = |p: Vec2, gap: f64, own: Feature, other: Feature| ContactGeom {
        point: p - 0.5 * gap * n_ref,
        normal,
        tangent,
        gap,
        feature: pair(ref_side, own, other),
    };
    let single = make(inc[q], sep.distance, Feature::Edge(r), Feature::Vertex(q));

    // Incident edge: the edge at `q` whose normal is most opposed to n_ref.
    let m = inc.len();
    let prev = if q == 0 { m - 1 } else { q - 1 };
    let mut incident: Option<(usize, f64, Vec2)> = None; // (edge, n·n_ref, normal)
    for k in [prev, q] {
        if inc_part.is_some_and(|p| p.internal(k)) {
            continue;
        }
        if let Some(nk) = outward_normal(&inc[k], &inc[next(k, m)]) {
            let c = nk.dot(&n_ref);
            if incident.is_none_or(|(_, best, _)| c < best) {
                incident = Some((k, c, nk));
            }
        }
    }
    let parallel = incident.filter(|&(_, c, nk)| {
        c < 0.0 && cross(&nk, &n_ref).abs() <= options.parallel_tolerance.sin()
    });
    let Some((k, _, _)) = parallel else {
        emit(single);
        return;
    };

    // Clip the incident edge p(λ) = p0 + λ (p1 − p0) to the slab of the
    // reference edge, 0 ≤ u·(p − r0) ≤ len.
    let k_next = next(k, m);
    let (p0, p1) = (inc[k], inc[k_next]);
    let u_raw = r1 - r0;
    let len = u_raw.norm();
    let u = u_raw / len; // len > 0: the reference edge has a normal
    let s0 = u.dot(&(p0 - r0));
    let ds = u.dot(&(p1 - r0)) - s0;
    let oblique = ds.abs() > 0.0; // false for NaN
    if !oblique {
        emit(single);
        return;
    }
    let at_r0 = -s0 / ds;
    let at_r1 = (len - s0) / ds;
    let ((lmin, fmin), (lmax, fmax)) = if at_r0 <= at_r1 {
        ((at_r0, r), (at_r1, r_next))
    } else {
        ((at_r1, r_next), (at_r0, r))
    };
    let (lo, end_lo) = if lmin > 0.0 {
        (lmin, ClipEnd::Reference(fmin))
    } else {
        (0.0, ClipEnd::Incident(k))
    };
    let (hi, end_hi) = if lmax < 1.0 {
        (lmax, ClipEnd::Reference(fmax))
    } else {
        (1.0, ClipEnd::Incident(k_next))
    };
    let nonempty = lo <= hi; // false for NaN
    if !nonempty {
        emit(single);
        return;
    }
    let point_at = |lambda: f64, end: ClipEnd| {
        let (p, own, other) = match end {
            ClipEnd::Incident(v) => (inc[v], Feature::Edge(r), Feature::Vertex(v)),
            ClipEnd::Reference(v) => (
                p0 + lambda * (p1 - p0),
                Feature::Vertex(v),
                Feature::Edge(k),
            ),
        };
        make(p, n_ref.dot(&(p - r0)), own, other)
    };
    let c_lo = point_at(lo, end_lo);
    let c_hi = point_at(hi, end_hi);
    let overlap = (hi - lo) * (p1 - p0).norm();
    let keep_lo = c_lo.gap <= distance;
    let keep_hi = c_hi.gap <= distance;
    let two_points = overlap > options.merge_fraction * len; // false for NaN
    if !two_points {
        let deeper = if c_hi.gap < c_lo.gap { c_hi } else { c_lo };
        emit(if deeper.gap <= distance {
            deeper
        } else {
            single
        });
    } else if keep_lo || keep_hi {
        if keep_lo {
            emit(c_lo);
        }
        if keep_hi {
            emit(c_hi);
        }
    } else {
        emit(single);
    }
}
