//! The checks, one function each: whether it applies (the case's
//! structure), what it measures on the run, the exact answer and the
//! tolerance it is held to (see the table of the module doc of
//! [`super`]).

use super::exact::head_on_velocities;
use super::exact::ram_critical_speed_of;
use super::measure::{final_velocity, rest_time, sampled_penetration};
use super::setup::{Bouncing, Drift, Inertial, Sliding};
use super::structure::{
    extent, find_symmetry, in_a_row, initial_polygon, no_forcing, self_symmetric, translation_gap,
    GEOMETRY_MATCH,
};
use super::{
    CheckOutcome, CRADLE_TOLERANCE, ENERGY_CONSERVED_TOLERANCE, FRACTURE_CONSERVATION_TOLERANCE,
    FREE_DRIFT_TOLERANCE, HEAD_ON_TOLERANCE, IMPACT_ENERGY_TOLERANCE, INERTIAL_PERIOD_TOLERANCE,
    LEDGER_TOLERANCE, MOMENTUM_TOLERANCE, RAM_CRITICAL_SPEED_TOLERANCE, REST_SPEED_FRACTION,
    SLIDING_DISTANCE_TOLERANCE, SYMMETRY_TOLERANCE,
};
use crate::analysis::divergence::row_frames;
use crate::contact::signed_distance;
use crate::formulation::contact_solver::COULOMB_SLACK;
use crate::formulation::event_driven::{
    floe_length_scale, EventDrivenSettings, DEFAULT_PENETRATION_FRACTION,
};
use crate::fracture::split::cut;
use crate::fracture::strike::{lattice_spacing, spin_prestress, SPIN_PRESTRESS_LIMIT};
use crate::geometry::{cross, Vec2};
use crate::model::fracture::FractureModel;
use crate::model::Scenario;
use crate::record::counters::common::MAX_PENETRATION;
use crate::run::{EndReason, RunResult, TrajectoryRow};

struct Rows<'a> {
    scn: &'a Scenario,
    run: &'a RunResult,
    out: Vec<CheckOutcome>,
}

impl Rows<'_> {
    #[allow(clippy::too_many_arguments)]
    fn push(
        &mut self,
        check: &str,
        description: &str,
        measured: f64,
        expected: Option<f64>,
        tolerance: f64,
        unit: &str,
        note: String,
    ) -> &mut CheckOutcome {
        // A check against an exact answer sets `scale` on the row returned.
        let pass = match expected {
            Some(x) => (measured - x).abs() <= tolerance,
            None => measured <= tolerance,
        };
        self.out.push(CheckOutcome {
            case: self.scn.name.clone(),
            formulation: self.run.summary.formulation.clone(),
            check: check.to_string(),
            description: description.to_string(),
            measured,
            expected,
            tolerance,
            unit: unit.to_string(),
            pass,
            claimed: true,
            note,
            scale: None,
        });
        let last = self.out.len() - 1;
        &mut self.out[last]
    }
}

/// Every check that applies to `scn`, measured on `run`, each claimed
/// (the claims are [`super::check_run`]'s).
pub(super) fn all(scn: &Scenario, run: &RunResult) -> Vec<CheckOutcome> {
    let mut r = Rows {
        scn,
        run,
        out: Vec::new(),
    };
    let completed = run.summary.end == EndReason::Completed;
    r.push(
        "run_completed",
        "the run reaches the case's duration",
        if completed { 1.0 } else { 0.0 },
        Some(1.0),
        0.0,
        "1",
        match &run.summary.end {
            EndReason::Completed => String::new(),
            other => format!("{other}; reached t = {} s", run.summary.t_reached),
        },
    );
    momentum(&mut r);
    impact_energy(&mut r);
    energy_conserved(&mut r);
    coulomb(&mut r);
    penetration(&mut r);
    // The checks of final velocities after impacts without forcing follow
    // each initial floe's material through its pieces when floes broke (a
    // split conserves momentum; `final_velocity`, docs/physics.md §9.7).
    head_on(&mut r);
    cradle(&mut r);
    cannon(&mut r);
    // The other checks read from the case's initial floes follow those floes
    // through the run: they apply to a run whose floes did not break.
    if run.fractures.is_empty() {
        symmetry(&mut r);
        bouncing(&mut r);
        sliding(&mut r);
        free_drift(&mut r);
        inertial(&mut r);
    }
    fracture_conservation(&mut r);
    ram_critical_speed(&mut r);
    lattice_spin(&mut r);
    ledger(&mut r);
    r.out
}

fn momentum(r: &mut Rows) {
    let scn = r.scn;
    if !no_forcing(scn) || !scn.obstacles.is_empty() || scn.floes.len() < 2 {
        return;
    }
    let scale: f64 = scn.floes.iter().map(|f| f.mass * f.velocity.norm()).sum();
    if scale == 0.0 {
        return;
    }
    let p0 = scn
        .floes
        .iter()
        .fold(Vec2::zeros(), |s, f| s + f.velocity * f.mass);
    // Each floe alive at an output, with its own mass (the pieces of broken
    // floes included).
    let mass = |id: usize| r.run.floes.get(id).map_or(f64::NAN, |f| f.mass);
    let worst = row_frames(&r.run.trajectory)
        .map(|rows| {
            let p = rows.iter().fold(Vec2::zeros(), |s, row| {
                s + Vec2::new(row.vx, row.vy) * mass(row.floe)
            });
            (p - p0).norm() / scale
        })
        .fold(0.0, f64::max);
    r.push(
        "momentum",
        "total momentum conserved across impacts (no forcing, no obstacle)",
        worst,
        None,
        MOMENTUM_TOLERANCE,
        "1",
        "max_t |P(t) - P(0)| / sum M |v(0)|".into(),
    )
    .scale = Some(1.0);
}

fn impact_energy(r: &mut Rows) {
    let log = &r.run.contacts;
    let Some(gain) = log.max_energy_gain() else {
        return;
    };
    let scale = r.run.summary.energy.exchanged.max(f64::MIN_POSITIVE);
    r.push(
        "impact_energy",
        "no contact event creates kinetic energy (e <= 1)",
        gain.max(0.0) / scale,
        None,
        IMPACT_ENERGY_TOLERANCE,
        "1",
        if gain > 0.0 {
            format!(
                "largest gain {gain:.3e} J over {} events / {scale:.3e} J exchanged",
                log.event_count()
            )
        } else if gain == 0.0 {
            format!(
                "no event gained energy (the largest change is 0 J) over {} events / {scale:.3e} J exchanged",
                log.event_count()
            )
        } else {
            format!(
                "every event lost energy: the smallest loss is {:.3e} J over {} events / {scale:.3e} J exchanged",
                -gain,
                log.event_count()
            )
        },
    );
}

fn energy_conserved(r: &mut Rows) {
    let scn = r.scn;
    if scn.contact.restitution != 1.0 || scn.contact.friction != 0.0 || !no_forcing(scn) {
        return;
    }
    let e0 = r.run.summary.energy.initial_kinetic;
    if e0 <= 0.0 {
        return;
    }
    let worst = r
        .run
        .energy
        .iter()
        .map(|s| (s.kinetic - e0).abs() / e0)
        .fold(0.0, f64::max);
    r.push(
        "energy_conserved",
        "kinetic energy conserved (e = 1, mu = 0, no forcing)",
        worst,
        None,
        ENERGY_CONSERVED_TOLERANCE,
        "1",
        "max_t |E(t) - E(0)| / E(0)".into(),
    )
    .scale = Some(1.0);
}

fn coulomb(r: &mut Rows) {
    let log = &r.run.contacts;
    if log.impulse_count() == 0 {
        return;
    }
    r.push(
        "coulomb",
        "every contact impulse in the Coulomb cone |beta| <= mu lambda",
        log.max_coulomb_ratio(),
        None,
        1.0 + COULOMB_SLACK,
        "|beta|/(mu lambda)",
        format!(
            "{} impulses, {} of the kept {} outside the cone",
            log.impulse_count(),
            log.impulses
                .iter()
                .filter(|i| i.coulomb_ratio() > 1.0 + COULOMB_SLACK)
                .count(),
            log.impulses.len()
        ),
    );
}

fn penetration(r: &mut Rows) {
    let scn = r.scn;
    if scn.floes.len() < 2 && scn.obstacles.is_empty() {
        return;
    }
    let sampled = sampled_penetration(scn, r.run);
    let own = r
        .run
        .summary
        .counters
        .value(&MAX_PENETRATION)
        .ok()
        .flatten();
    let tol = penetration_tolerance(scn);
    r.push(
        "penetration",
        "deepest overlap, at the outputs and as the formulation saw it",
        own.unwrap_or(0.0).max(sampled),
        Some(0.0),
        tol,
        "m",
        format!(
            "outputs {sampled:.3e} m, formulation {}; tolerance: the event-driven one of the case",
            own.map_or("n/a".to_string(), |v| format!("{v:.3e} m"))
        ),
    );
}

fn symmetry(r: &mut Rows) {
    let scn = r.scn;
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

fn head_on(r: &mut Rows) {
    let scn = r.scn;
    if scn.floes.len() != 2 || !scn.obstacles.is_empty() || !no_forcing(scn) {
        return;
    }
    let (f1, f2) = (&scn.floes[0], &scn.floes[1]);
    let Some(d) = (f2.position - f1.position).try_normalize(0.0) else {
        return;
    };
    let along = |v: &Vec2| cross(&d, v).abs() <= 1e-12 * v.norm();
    let (v1, v2) = (f1.velocity.dot(&d), f2.velocity.dot(&d));
    if !along(&f1.velocity)
        || !along(&f2.velocity)
        || f1.angular_velocity != 0.0
        || f2.angular_velocity != 0.0
        || v1 <= v2
        || !self_symmetric(scn, f1.position, d)
    {
        return;
    }
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

fn bouncing(r: &mut Rows) {
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

/// The event-driven penetration tolerance of the case, m (the bound of the
/// `penetration` check).
fn penetration_tolerance(scn: &Scenario) -> f64 {
    EventDrivenSettings::of(scn)
        .map_or(DEFAULT_PENETRATION_FRACTION * floe_length_scale(scn), |s| {
            s.penetration_tolerance(scn)
        })
}

fn sliding(r: &mut Rows) {
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

fn cradle(r: &mut Rows) {
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

fn cannon(r: &mut Rows) {
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

fn free_drift(r: &mut Rows) {
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

fn inertial(r: &mut Rows) {
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

fn fracture_conservation(r: &mut Rows) {
    let fr = &r.run.fractures;
    if fr.is_empty() {
        return;
    }
    let worst = fr.iter().map(|f| f.conservation).fold(0.0, f64::max);
    r.push(
        "fracture_conservation",
        "every split conserves area, mass, momenta and kinetic energy",
        worst,
        Some(0.0),
        FRACTURE_CONSERVATION_TOLERANCE,
        "1",
        format!(
            "{} fractures, {} floes at the end",
            fr.len(),
            r.run.summary.floes_at_end
        ),
    )
    .scale = Some(1.0);
}

fn ram_critical_speed(r: &mut Rows) {
    let scn = r.scn;
    if scn.fracture.model != FractureModel::Energy
        || scn.floes.len() != 1
        || !no_forcing(scn)
        || scn.floes[0].angular_velocity != 0.0
    {
        return;
    }
    let f = &scn.floes[0];
    let v0 = f.velocity.norm();
    if v0 == 0.0 {
        return;
    }
    let d = f.velocity / v0;
    if translation_gap(scn, 0, &d).is_none_or(|(_, rays)| rays < 2)
        || !self_symmetric(scn, f.position, d)
    {
        return;
    }
    let Some(chord) = cut(&initial_polygon(scn, 0), &f.position, &d) else {
        return;
    };
    let vc = ram_critical_speed_of(
        scn.fracture.toughness,
        f.thickness,
        chord.length,
        scn.contact.restitution,
        f.mass,
    );
    if v0 <= vc * (1.0 + RAM_CRITICAL_SPEED_TOLERANCE) {
        return;
    }
    let measured = r
        .run
        .fractures
        .first()
        .map_or(f64::NAN, |fr| v0 * (fr.threshold / fr.measure).sqrt());
    r.push(
        "ram_critical_speed",
        "the critical speed of a floe rammed into a coast (energy criterion)",
        measured,
        Some(vc),
        RAM_CRITICAL_SPEED_TOLERANCE * vc,
        "m/s",
        format!(
            "v0 = {v0} m/s, chord {:.6} m; {} fractures",
            chord.length,
            r.run.fractures.len()
        ),
    )
    .scale = Some(vc);
}

/// `lattice_spin_prestress`: the lattice model starts each percussion
/// unstressed, neglecting the floe's own spin (docs/physics.md §9.8); the
/// largest centrifugal pre-strain, over its bonds' breaking strain, of a
/// floe at its last output before a percussion that broke it (the
/// percussions that broke nothing are not in the run's records). A piece
/// that spins fast but is never struck again is not where the neglect
/// acts, so the floes alive at the outputs are not all taken.
fn lattice_spin(r: &mut Rows) {
    let s = &r.scn.fracture;
    if s.model != FractureModel::Lattice {
        return;
    }
    let (mut worst, mut at) = (0.0, None);
    for fr in &r.run.fractures {
        let Some(f) = r.run.floes.iter().find(|f| f.id == fr.parent) else {
            continue;
        };
        // The parent's spin at its last output at or before the fracture.
        let Some(row) = r
            .run
            .trajectory
            .iter()
            .filter(|row| row.floe == fr.parent && row.t <= fr.t)
            .max_by(|a, b| a.t.total_cmp(&b.t))
        else {
            continue;
        };
        let radius = f
            .polygon
            .iter()
            .map(|p| p[0].hypot(p[1]))
            .fold(0.0, f64::max);
        let density = f.mass / (f.area * f.thickness);
        let ratio = spin_prestress(s, density, radius, row.omega, lattice_spacing(s, f.area));
        if at.is_none() || ratio > worst {
            (worst, at) = (ratio, Some((fr.parent, fr.t)));
        }
    }
    let note = match at {
        Some((floe, t)) => {
            format!("largest for floe {floe} broken at t = {t} s (its spin at the output before)")
        }
        None => "no fracture".to_string(),
    };
    r.push(
        "lattice_spin_prestress",
        "a floe's spin pre-stretches its lattice by little against its bonds' breaking strain when a percussion breaks it",
        worst,
        None,
        SPIN_PRESTRESS_LIMIT,
        "1",
        note,
    );
}

fn ledger(r: &mut Rows) {
    let e = &r.run.summary.energy;
    let scale = e.exchanged.max(f64::MIN_POSITIVE);
    r.push(
        "energy_ledger",
        "energy ledger balances: |E - E0 - W_ext + D| at every output",
        e.max_abs_residual / scale,
        None,
        LEDGER_TOLERANCE,
        "1",
        format!(
            "largest residual {:.3e} J of {:.3e} J exchanged",
            e.max_abs_residual, e.exchanged
        ),
    );
}
