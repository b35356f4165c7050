//! The checks against exact motions (docs/physics.md §2, §3.2; the table of
//! the module doc of [`crate::analysis::check`]): mirror symmetry, the
//! head-on impact, the bouncing floe, the sliding floe, Newton's cradle,
//! the cannon, free drift and the inertial oscillation.

use super::{penetration_tolerance, Rows};
use crate::analysis::check::exact::head_on_velocities;
use crate::analysis::check::measure::{final_velocity, rest_time};
use crate::analysis::check::setup::{Bouncing, Drift, Inertial, Sliding};
use crate::analysis::check::structure::{
    extent, find_symmetry, in_a_row, initial_polygon, no_forcing, self_symmetric, translation_gap,
    GEOMETRY_MATCH,
};
use crate::analysis::check::{
    CRADLE_TOLERANCE, FREE_DRIFT_TOLERANCE, HEAD_ON_TOLERANCE, INERTIAL_PERIOD_TOLERANCE,
    REST_SPEED_FRACTION, SAINT_VENANT_TOLERANCE, SLENDER, SLIDING_DISTANCE_TOLERANCE,
    SYMMETRY_TOLERANCE,
};
use crate::contact::signed_distance;
use crate::geometry::{cross, perp, Vec2};
use crate::model::Scenario;
use crate::run::{RunResult, TrajectoryRow};

pub(super) fn symmetry(r: &mut Rows) {
    let scn = r.scn;
    // The lattices that resolve impacts (docs/physics.md §9.10) are random
    // meshes, not mirror images of themselves.
    if scn.fracture.lattice_impacts() {
        return;
    }
    let Some((axis, pairing)) = find_symmetry(scn) else {
        return;
    };
    let n = scn.floes.len();
    let mut worst = 0.0f64;
    let mut at = 0.0;
    for rows in r.run.trajectory.chunks(n) {
        for (i, row) in rows.iter().enumerate() {
            let Some(other) = rows.get(pairing[i]) else {
                continue;
            };
            let g = axis.point(&Vec2::new(row.x, row.y));
            let err = (Vec2::new(other.x, other.y) - g).norm()
                + scn.floes[i].radius * (other.theta + row.theta).abs();
            if err > worst {
                worst = err;
                at = row.t;
            }
        }
    }
    let scale = extent(scn, &axis.c);
    r.push(
        "symmetry",
        "trajectories stay mirror images",
        worst,
        Some(0.0),
        SYMMETRY_TOLERANCE * scale,
        "m",
        format!(
            "axis through ({:.4}, {:.4}) along ({:.4}, {:.4}); worst at t = {at} s; extent {scale:.4} m",
            axis.c.x, axis.c.y, axis.d.x, axis.d.y
        ),
    )
    .scale = Some(scale);
}

/// A central impact of two floes (the set-up of `head_on` and
/// `saint_venant`): two floes, no forcing, no obstacle, no spin, velocities
/// along the line of centres and approaching, the configuration symmetric
/// about it; the unit direction from the first to the second and the two
/// velocities along it.
fn central_pair(scn: &Scenario) -> Option<(Vec2, f64, f64)> {
    if scn.floes.len() != 2 || !scn.obstacles.is_empty() || !no_forcing(scn) {
        return None;
    }
    let (f1, f2) = (&scn.floes[0], &scn.floes[1]);
    let d = (f2.position - f1.position).try_normalize(0.0)?;
    let along = |v: &Vec2| cross(&d, v).abs() <= 1e-12 * v.norm();
    let (v1, v2) = (f1.velocity.dot(&d), f2.velocity.dot(&d));
    let central = along(&f1.velocity)
        && along(&f2.velocity)
        && f1.angular_velocity == 0.0
        && f2.angular_velocity == 0.0
        && v1 > v2
        && self_symmetric(scn, f1.position, d);
    central.then_some((d, v1, v2))
}

pub(super) fn head_on(r: &mut Rows) {
    let scn = r.scn;
    // The closed form is the restitution law's, which the lattices
    // replace with impact = "lattice" (docs/physics.md §9.10).
    if scn.fracture.lattice_impacts() {
        return;
    }
    let Some((d, v1, v2)) = central_pair(scn) else {
        return;
    };
    let (f1, f2) = (&scn.floes[0], &scn.floes[1]);
    let e = scn.contact.restitution;
    let (w1, w2) = head_on_velocities(f1.mass, v1, f2.mass, v2, e);
    let tol = HEAD_ON_TOLERANCE * (v1 - v2);
    let (a, b) = (final_velocity(r.run, 0), final_velocity(r.run, 1));
    let note = format!("M1 = {:.6e} kg, M2 = {:.6e} kg, e = {e}", f1.mass, f2.mass);
    r.push(
        "head_on_v1",
        "floe 0 after a central impact: (m1 v1 + m2 v2 - m2 e (v1 - v2))/(m1 + m2)",
        a.dot(&d),
        Some(w1),
        tol,
        "m/s",
        note.clone(),
    )
    .scale = Some(v1 - v2);
    r.push(
        "head_on_v2",
        "floe 1 after a central impact: (m1 v1 + m2 v2 + m1 e (v1 - v2))/(m1 + m2)",
        b.dot(&d),
        Some(w2),
        tol,
        "m/s",
        note,
    )
    .scale = Some(v1 - v2);
}

/// Floe `i`'s length along the unit direction `d` and width across it (m)
/// when it is a rectangle with sides along `d` and across it.
fn bar_along(scn: &Scenario, i: usize, d: Vec2) -> Option<(f64, f64)> {
    let poly = initial_polygon(scn, i);
    if poly.len() != 4 {
        return None;
    }
    let n = perp(&d);
    let span = |axis: &Vec2| {
        let x: Vec<f64> = poly.iter().map(|p| p.dot(axis)).collect();
        let (lo, hi) = x
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        (x, lo, hi)
    };
    let ((xs, x0, x1), (ys, y0, y1)) = (span(&d), span(&n));
    let tol = GEOMETRY_MATCH * scn.floes[i].radius;
    let at_side = |v: f64, lo: f64, hi: f64| (v - lo).abs() <= tol || (v - hi).abs() <= tol;
    let rectangle =
        xs.iter().all(|&x| at_side(x, x0, x1)) && ys.iter().all(|&y| at_side(y, y0, y1));
    rectangle.then_some((x1 - x0, y1 - y0))
}

/// Saint-Venant's bars (docs/physics.md §9.10): two bars of one ice, the
/// same cross-section, slender (each at least [`SLENDER`] widths long),
/// meeting end-on, their impact resolved in their lattices without
/// dashpots. One-dimensional wave theory: they separate at
/// `e = min(L1, L2)/max(L1, L2)` (the shorter bar's wave returns and the
/// contact ends; the longer bar keeps the rest as vibration).
pub(super) fn saint_venant(r: &mut Rows) {
    let scn = r.scn;
    if !scn.fracture.lattice_impacts() || scn.fracture.damping != 0.0 {
        return;
    }
    let Some((d, v1, v2)) = central_pair(scn) else {
        return;
    };
    let (Some((l1, w1)), Some((l2, w2))) = (bar_along(scn, 0, d), bar_along(scn, 1, d)) else {
        return;
    };
    let (f1, f2) = (&scn.floes[0], &scn.floes[1]);
    let same = |a: f64, b: f64| (a - b).abs() <= GEOMETRY_MATCH * a.abs().max(b.abs());
    if !same(w1, w2)
        || !same(f1.thickness, f2.thickness)
        || !same(f1.density, f2.density)
        || l1.min(l2) < SLENDER * w1
    {
        return;
    }
    let expected = l1.min(l2) / l1.max(l2);
    let (a, b) = (final_velocity(r.run, 0), final_velocity(r.run, 1));
    let measured = (b - a).dot(&d) / (v1 - v2);
    r.push(
        "saint_venant",
        "bars end-on, impact in their lattices: e_eff = -u_N(after)/u_N(before) against Saint-Venant's min(L1, L2)/max(L1, L2)",
        measured,
        Some(expected),
        SAINT_VENANT_TOLERANCE * expected,
        "1",
        format!("L1 = {l1:.6} m, L2 = {l2:.6} m, width {w1:.6} m; restitution {} unused", scn.contact.restitution),
    )
    .scale = Some(expected);
}

pub(super) fn bouncing(r: &mut Rows) {
    let scn = r.scn;
    let Some(b) = Bouncing::of(scn) else {
        return;
    };
    let dt = scn.output_interval;
    if r.run.contacts.records_events {
        // Located to the position accuracy contacts are held to: crossing the
        // penetration tolerance at the impact speed takes tol / v1.
        let tol = penetration_tolerance(scn) / b.v1;
        let (measured, how) = first_impact(&b, r.run);
        r.push(
            "bouncing_first_impact",
            "first impact at t1 = sqrt(2 d / a)",
            measured,
            Some(b.t1),
            tol,
            "s",
            format!(
                "{how}; d = {:.6} m, a = {:.6e} m/s^2; tolerance: the penetration tolerance / v1",
                b.gap, b.a
            ),
        )
        .scale = Some(b.t1);
    }
    if let Some(t_inf) = b.rest_time() {
        let v_rest = REST_SPEED_FRACTION * b.v1;
        // Decelerating at a, the floe is below v_rest during the last
        // 2 v_rest / (a (1 - e)) of the accumulation: the threshold's own shift.
        let tol = dt + 2.0 * v_rest / (b.a * (1.0 - b.e));
        let rest = rest_time(&r.run.trajectory, 0, v_rest);
        r.push(
            "bouncing_rest",
            "comes to rest at the accumulation time t1 (1 + e)/(1 - e)",
            rest.unwrap_or(f64::NAN),
            Some(t_inf),
            tol,
            "s",
            format!(
                "rest: speed below {v_rest:.3e} m/s from then on; tolerance: one output interval + the threshold's shift"
            ),
    )
    .scale = Some(t_inf);
    }
}

/// The time the bouncing floe of `b` reaches the obstacle in `run`, and how
/// it was found: from the last output before the formulation's first
/// contact event, the exact free flight (uniform acceleration `a` along the
/// wind, docs/physics.md §2.3) continued to gap 0. NaN without a contact
/// event; the event's own time when the floe had already crossed the
/// obstacle's face at that output (the contact came late).
fn first_impact(b: &Bouncing, run: &RunResult) -> (f64, String) {
    let Some(event) = run.contacts.events.first() else {
        return (f64::NAN, "no contact event".into());
    };
    let Some(row) = run
        .trajectory
        .iter()
        .rev()
        .find(|row| row.floe == 0 && row.t <= event.t)
    else {
        return (event.t, format!("first contact event at {} s", event.t));
    };
    let gap = b.gap_of(Vec2::new(row.x, row.y));
    let v = Vec2::new(row.vx, row.vy).dot(&b.dir);
    if gap < 0.0 {
        return (
            event.t,
            format!(
                "the floe crossed the face before its first contact event at {} s",
                event.t
            ),
        );
    }
    // gap = v s + a s^2 / 2, the positive root in the stable form.
    let s = 2.0 * gap / (v + (v * v + 2.0 * b.a * gap).sqrt());
    (
        row.t + s,
        format!(
            "free flight from the output at {} s (gap {gap:.6e} m) to the face; first contact event at {} s",
            row.t, event.t
        ),
    )
}

pub(super) fn sliding(r: &mut Rows) {
    let scn = r.scn;
    let Some(sl) = Sliding::of(scn) else {
        return;
    };
    let end = r
        .run
        .final_state
        .bodies
        .first()
        .map_or(sl.start, |b| b.position);
    r.push(
        "sliding_distance",
        "slides v0^2 / (2 mu a) along the wall",
        (end - sl.start).dot(&sl.dir),
        Some(sl.distance),
        SLIDING_DISTANCE_TOLERANCE * sl.distance,
        "m",
        format!("v0 = {} m/s, mu = {}, a = {:.6e} m/s^2", sl.v0, sl.mu, sl.a),
    )
    .scale = Some(sl.distance);
    let v_rest = REST_SPEED_FRACTION * sl.v0;
    r.push(
        "sliding_stop",
        "stops after v0 / (mu a)",
        rest_time(&r.run.trajectory, 0, v_rest).unwrap_or(f64::NAN),
        Some(sl.t_stop),
        scn.output_interval + REST_SPEED_FRACTION * sl.t_stop,
        "s",
        format!(
            "rest: speed below {v_rest:.3e} m/s from then on; tolerance: one output interval + the threshold's shift"
        ),
    )
    .scale = Some(sl.t_stop);
}

pub(super) fn cradle(r: &mut Rows) {
    let scn = r.scn;
    let n = scn.floes.len();
    if n < 3 || !scn.obstacles.is_empty() || !no_forcing(scn) || scn.contact.restitution != 1.0 {
        return;
    }
    let f0 = &scn.floes[0];
    let v0 = f0.velocity.norm();
    let Some(d) = f0.velocity.try_normalize(0.0) else {
        return;
    };
    let m = f0.mass;
    if scn.floes.iter().any(|f| (f.mass - m).abs() > 1e-12 * m)
        || scn.floes.iter().any(|f| f.angular_velocity != 0.0)
        || scn.floes[1..].iter().any(|f| f.velocity.norm() != 0.0)
    {
        return;
    }
    let Some(order) = in_a_row(scn, d) else {
        return;
    };
    if order[0] != 0 {
        return;
    }
    let gaps: Vec<f64> = order
        .windows(2)
        .map(|w| signed_distance(&initial_polygon(scn, w[0]), &initial_polygon(scn, w[1])))
        .collect();
    let tol = GEOMETRY_MATCH * f0.radius;
    let touching = gaps.iter().all(|&g| g.abs() <= tol);
    let apart = gaps.iter().all(|&g| g > tol);
    if !touching && !apart {
        return;
    }
    let physical: Vec<f64> = (0..n).map(|k| if k + 1 == n { v0 } else { 0.0 }).collect();
    let nf = n as f64;
    let lcp: Vec<f64> = (0..n)
        .map(|k| {
            if k == 0 {
                (2.0 - nf) / nf * v0
            } else {
                2.0 / nf * v0
            }
        })
        .collect();
    let error = |expected: &[f64]| -> f64 {
        order
            .iter()
            .zip(expected)
            .map(|(&i, &x)| (final_velocity(r.run, i) - d * x).norm() / v0)
            .fold(0.0, f64::max)
    };
    let finals: Vec<String> = order
        .iter()
        .map(|&i| format!("{:.6}", final_velocity(r.run, i).dot(&d)))
        .collect();
    let show = |x: &[f64]| {
        x.iter()
            .map(|v| format!("{v:.6}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    if apart {
        let err = error(&physical);
        r.push(
            "cradle_outcome",
            "with gaps: sequential impacts, the last floe leaves at v0, the others at rest",
            err,
            Some(0.0),
            CRADLE_TOLERANCE,
            "1",
            format!(
                "max |v - v_exact| / v0; got ({}), exact ({}) m/s",
                finals.join(", "),
                show(&physical)
            ),
        )
        .scale = Some(1.0);
    } else {
        let err = error(&lcp);
        r.push(
            "cradle_outcome",
            "touching: the simultaneous LCP answer ((2-n)/n, 2/n, ..., 2/n) v0 (docs/physics.md §6.1)",
            err,
            Some(0.0),
            CRADLE_TOLERANCE,
            "1",
            format!(
                "max |v - v_lcp| / v0; got ({}), LCP ({}) m/s",
                finals.join(", "),
                show(&lcp)
            ),
    )
    .scale = Some(1.0);
        let err = error(&physical);
        r.push(
            "cradle_physical",
            "touching: the physical answer, the last floe leaves at v0",
            err,
            Some(0.0),
            CRADLE_TOLERANCE,
            "1",
            format!(
                "max |v - v_exact| / v0; got ({}), physical ({}) m/s",
                finals.join(", "),
                show(&physical)
            ),
        )
        .scale = Some(1.0);
    }
}

pub(super) fn cannon(r: &mut Rows) {
    let scn = r.scn;
    if scn.floes.len() != 2 || scn.obstacles.is_empty() || !no_forcing(scn) {
        return;
    }
    let (fa, fb) = (&scn.floes[0], &scn.floes[1]);
    let v0 = fa.velocity.norm();
    let Some(d) = fa.velocity.try_normalize(0.0) else {
        return;
    };
    if (fb.velocity - fa.velocity).norm() > GEOMETRY_MATCH * v0
        || fa.angular_velocity != 0.0
        || fb.angular_velocity != 0.0
    {
        return;
    }
    let Some(order) = in_a_row(scn, d) else {
        return;
    };
    let (rear, front) = (order[0], order[1]);
    let Some((wall_gap, _)) = translation_gap(scn, front, &d) else {
        return;
    };
    let between = signed_distance(&initial_polygon(scn, rear), &initial_polygon(scn, front));
    let tol = GEOMETRY_MATCH * fa.radius.min(fb.radius);
    if wall_gap <= tol || between <= tol {
        return;
    }
    let e = scn.contact.restitution;
    let (mr, mf) = (scn.floes[rear].mass, scn.floes[front].mass);
    // The front floe rebounds at -e v0, then meets the rear one head-on.
    let (vr, vf) = head_on_velocities(mr, v0, mf, -e * v0, e);
    if vf > 0.0 || vr > vf {
        return; // it returns to the wall, or they meet again: no closed form
    }
    let err = [(rear, vr), (front, vf)]
        .iter()
        .map(|&(i, x)| (final_velocity(r.run, i) - d * x).norm() / v0)
        .fold(0.0, f64::max);
    r.push(
        "cannon_velocities",
        "front floe rebounds at -e v0 from the wall, then fires the rear one (head-on law)",
        err,
        Some(0.0),
        CRADLE_TOLERANCE,
        "1",
        format!(
            "max |v - v_exact| / v0; exact rear {vr:.6}, front {vf:.6} m/s; got rear {:.6}, front {:.6} m/s",
            final_velocity(r.run, rear).dot(&d),
            final_velocity(r.run, front).dot(&d)
        ),
    )
    .scale = Some(1.0);
}

pub(super) fn free_drift(r: &mut Rows) {
    let Some(drift) = Drift::of(r.scn) else {
        return;
    };
    for &(i, u, tau) in &drift.floes {
        let v = final_velocity(r.run, i);
        r.push(
            "free_drift_velocity",
            "reaches the steady free-drift velocity (docs/physics.md §2.2)",
            (v - u).norm() / u.norm(),
            Some(0.0),
            FREE_DRIFT_TOLERANCE,
            "1",
            format!(
                "floe {i}: |v - u| / |u|; u = ({:.9}, {:.9}) m/s, got ({:.9}, {:.9}); drag time {tau:.1} s",
                u.x, u.y, v.x, v.y
            ),
    )
    .scale = Some(1.0);
    }
}

pub(super) fn inertial(r: &mut Rows) {
    let Some(inr) = Inertial::of(r.scn) else {
        return;
    };
    let measured = inertial_period(&inr, &r.run.trajectory);
    r.push(
        "inertial_period",
        "after the wind stops the velocity turns at -f: period 2 pi / |f| (docs/physics.md §2.2)",
        measured.map_or(f64::NAN, |m| m.0),
        Some(inr.period),
        INERTIAL_PERIOD_TOLERANCE * inr.period,
        "s",
        match measured {
            Some((_, turns, t0, t1)) => format!(
                "2 pi (t1 - t0) / (turned angle), {turns:.3} turns from t0 = {t0} s to t1 = {t1} s, f = {} 1/s",
                inr.f
            ),
            None => "the floe is at rest in the calm: no turning to measure".into(),
        },
    )
    .scale = Some(inr.period);
}

/// The period of the turning of floe 0's velocity over the calm of `inr`:
/// `2π (t1 − t0) / Δφ`, with `Δφ` the angle the velocity turned in the
/// sense of the Coriolis force (clockwise for `f > 0`), unwrapped from one
/// output to the next; negative when it turns the wrong way. Returns the
/// period, the turns, `t0` and `t1`; `None` if the floe does not move.
fn inertial_period(inr: &Inertial, rows: &[TrajectoryRow]) -> Option<(f64, f64, f64, f64)> {
    let calm: Vec<&TrajectoryRow> = rows
        .iter()
        .filter(|row| row.floe == 0 && row.t >= inr.t_calm)
        .collect();
    let (first, last) = (calm.first()?, calm.last()?);
    if calm.iter().any(|row| row.vx.hypot(row.vy) == 0.0) || last.t <= first.t {
        return None;
    }
    let mut turned = 0.0;
    for w in calm.windows(2) {
        let (a, b) = (w[0].vy.atan2(w[0].vx), w[1].vy.atan2(w[1].vx));
        let mut d = b - a;
        d -= std::f64::consts::TAU * (d / std::f64::consts::TAU).round();
        turned += d;
    }
    // Coriolis turns the velocity by −f t: the turned angle in its sense.
    let along = -turned * inr.f.signum();
    let turns = along / std::f64::consts::TAU;
    Some((
        std::f64::consts::TAU * (last.t - first.t) / along,
        turns,
        first.t,
        last.t,
    ))
}
