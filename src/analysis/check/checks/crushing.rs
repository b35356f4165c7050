//! The checks of crushing ice against its closed forms (docs/physics.md
//! §10.3; the table of the module doc of [`crate::analysis::check`]): a
//! floe rammed into a straight coast with a corner (`crush_volume`,
//! `crush_peak_force`, `crush_duration`) or a flat face (`crush_volume`,
//! `crush_force`, `crush_duration`), the ice crushing at a constant
//! strength and all the normal kinetic energy crushed (`e = 0`).
//!
//! Set-up: `[contact] crushing = { strength }`, `e = 0`, one floe without
//! spin moving toward an obstacle, no forcing, the configuration symmetric
//! about the line of motion. A corner: one vertex ray reaches the coast
//! first, the floe's foremost vertex; a face: two or more.
//!
//! Measures on the run: the crushed volume its summary counts
//! (`crushed_volume_m3`); the force as the mean of each output interval,
//! `M |Δv| / Δt` along the motion (the crushed mass, which leaves with the
//! floe's velocity, is neglected: 5e-4 of the floe in the bundled cases);
//! the duration from the first contact (`gap / V`, exact without forcing)
//! to the zero of the velocity along the motion, within the output
//! interval where it stops, at the deceleration of the interval before.

use super::Rows;
use crate::analysis::check::exact::{corner_crush, flat_crush};
use crate::analysis::check::structure::{
    initial_polygon, no_forcing, self_symmetric, translation_gap,
};
use crate::analysis::check::{CRUSH_FORCE_TOLERANCE, CRUSH_VOLUME_TOLERANCE};
use crate::geometry::Vec2;
use crate::model::Crushing;

/// The fraction of the approach speed below which a floe has stopped.
const STOPPED: f64 = 1e-9;

/// The counter of the crushed volume, m³.
const CRUSHED_VOLUME: &str = "crushed_volume_m3";

/// The corner or face of a floe rammed into a coast (module doc).
enum Ram {
    /// A corner of interior angle (rad).
    Corner(f64),
    /// A face of width (m).
    Face(f64),
}

pub(super) fn crushing(r: &mut Rows) {
    let scn = r.scn;
    let Some(Crushing::Strength { strength }) = scn.contact.crushing else {
        return;
    };
    if scn.floes.len() != 1
        || scn.obstacles.is_empty()
        || !no_forcing(scn)
        || scn.contact.restitution != 0.0
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
    let Some((gap, rays)) = translation_gap(scn, 0, &d) else {
        return;
    };
    if !self_symmetric(scn, f.position, d) {
        return;
    }
    let poly = initial_polygon(scn, 0);
    let ram = if rays == 1 {
        match corner_angle(&poly, &d) {
            Some(phi) => Ram::Corner(phi),
            None => return,
        }
    } else {
        Ram::Face(face_width(&poly, &d))
    };
    let (volume, force, duration) = match ram {
        Ram::Corner(phi) => corner_crush(f.mass, v0, strength, f.thickness, phi),
        Ram::Face(w) => flat_crush(f.mass, v0, strength, f.thickness, w),
    };
    let what = match ram {
        Ram::Corner(phi) => format!("a corner of {:.6} rad", phi),
        Ram::Face(w) => format!("a face {w:.6} m wide"),
    };
    let measured = r
        .run
        .summary
        .counters
        .by_name(CRUSHED_VOLUME)
        .ok()
        .flatten()
        .unwrap_or(f64::NAN);
    r.push(
        "crush_volume",
        "the volume of ice crushed by a floe rammed into a coast",
        measured,
        Some(volume),
        CRUSH_VOLUME_TOLERANCE * volume,
        "m^3",
        format!("{what}, V = {v0} m/s, sigma_c = {strength} Pa"),
    )
    .scale = Some(volume);
    let (peak, stop) = force_history(r, d, f.mass, gap / v0);
    let (name, description) = match ram {
        Ram::Corner(_) => (
            "crush_peak_force",
            "the peak crushing force of a corner rammed into a coast",
        ),
        Ram::Face(_) => (
            "crush_force",
            "the constant crushing force of a face against a coast",
        ),
    };
    r.push(
        name,
        description,
        peak,
        Some(force),
        CRUSH_FORCE_TOLERANCE * force,
        "N",
        format!("{what}: mean force of each output interval"),
    )
    .scale = Some(force);
    r.push(
        "crush_duration",
        "the time a floe rammed into a coast takes to stop crushing",
        stop,
        Some(duration),
        CRUSH_FORCE_TOLERANCE * duration,
        "s",
        format!("{what}: from the first contact at t = {} s", gap / v0),
    )
    .scale = Some(duration);
}

/// The interior angle (rad) of the floe's foremost vertex along `d`, if one
/// vertex is foremost.
fn corner_angle(poly: &[Vec2], d: &Vec2) -> Option<f64> {
    let n = poly.len();
    let s: Vec<f64> = poly.iter().map(|p| p.dot(d)).collect();
    let front = (0..n).max_by(|&i, &j| s[i].total_cmp(&s[j]))?;
    let a = poly[(front + n - 1) % n] - poly[front];
    let b = poly[(front + 1) % n] - poly[front];
    let angle = a.angle(&b);
    (angle > 0.0 && angle < std::f64::consts::PI).then_some(angle)
}

/// The width (m) of the floe's foremost face across `d`: the extent across
/// `d` of its vertices within rounding of the foremost.
fn face_width(poly: &[Vec2], d: &Vec2) -> f64 {
    let s: Vec<f64> = poly.iter().map(|p| p.dot(d)).collect();
    let front = s.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let scale = poly.iter().map(|p| p.norm()).fold(0.0, f64::max);
    let across = Vec2::new(-d.y, d.x);
    let c: Vec<f64> = poly
        .iter()
        .zip(&s)
        .filter(|(_, &si)| front - si <= 1e-9 * scale)
        .map(|(p, _)| p.dot(&across))
        .collect();
    c.iter().copied().fold(f64::NEG_INFINITY, f64::max)
        - c.iter().copied().fold(f64::INFINITY, f64::min)
}

/// The largest mean force of an output interval (N), `m |Δv·d| / Δt`, and
/// the time (s) from `t_contact` to the first zero of the velocity along
/// `d`: in the interval where it stops, the last positive velocity
/// continued at the deceleration of the interval before (a floe stops and
/// stays: the velocity at the interval's end is zero, not the continued
/// line), within the interval; NaN if it never stops.
fn force_history(r: &Rows, d: Vec2, m: f64, t_contact: f64) -> (f64, f64) {
    let rows: Vec<(f64, f64)> = r
        .run
        .trajectory
        .iter()
        .filter(|row| row.floe == r.scn.floes[0].id)
        .map(|row| (row.t, Vec2::new(row.vx, row.vy).dot(&d)))
        .collect();
    let mut peak = 0.0f64;
    for w in rows.windows(2) {
        let ((t0, v0), (t1, v1)) = (w[0], w[1]);
        if t1 > t0 {
            peak = peak.max(m * (v1 - v0).abs() / (t1 - t0));
        }
    }
    // Stopped: slower than a billionth of the approach (a floe at rest
    // against the coast keeps a velocity at the rounding of its last
    // impulse, 1e-77 m/s measured).
    let v0 = rows.first().map_or(0.0, |r| r.1);
    let stopped = STOPPED * v0;
    let stop = rows
        .windows(3)
        .find(|w| w[1].1 > stopped && w[2].1 <= stopped)
        .map_or(f64::NAN, |w| {
            let ((tp, vp), (t0, v0), (t1, _)) = (w[0], w[1], w[2]);
            let rate = (vp - v0) / (t0 - tp);
            let dt = if rate > 0.0 { v0 / rate } else { t1 - t0 };
            t0 + dt.min(t1 - t0) - t_contact
        });
    (peak, stop)
}
