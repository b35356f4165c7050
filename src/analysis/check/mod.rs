//! `floebench check`: the physical checks of physics.md section 6, measured
//! on a recorded run, with the expected values computed from the case's own
//! parameters (masses, `e`, `μ`, wind acceleration, gaps), never stored.
//!
//! [`check_run`] decides from the case's *structure* which checks apply
//! (no case names are used):
//!
//! | check | applies when | measured | tolerance |
//! | --- | --- | --- | --- |
//! | `run_completed` | always | 1 if the run reached its duration | – |
//! | `momentum` | no forcing (no air or water drag, `f = 0`), no obstacle | `max_t ‖P(t) − P(0)‖ / Σ M‖Ġ(0)‖` | [`MOMENTUM_TOLERANCE`] |
//! | `impact_energy` | the formulation records contact events | largest kinetic energy gained by one contact event / energy exchanged | [`IMPACT_ENERGY_TOLERANCE`] |
//! | `energy_conserved` | `e = 1`, `μ = 0`, no forcing | `max_t \|E(t) − E(0)\| / E(0)` | [`ENERGY_CONSERVED_TOLERANCE`] |
//! | `coulomb` | the formulation records contact impulses | `max \|β\| / (μ λ)` over every impulse | `1 +` [`COULOMB_SLACK`] |
//! | `penetration` | an obstacle or two floes | deepest overlap at the output times (minimum translation distance) and the formulation's own `max_penetration_m` | the event-driven tolerance of the case |
//! | `symmetry` | the initial configuration is a mirror image of itself about an axis, forcing parallel to it, `f = 0` | `max_t,i ‖G_P(i) − S G_i‖ + r_i \|θ_P(i) + θ_i\|` | [`SYMMETRY_TOLERANCE`] × extent |
//! | `head_on_v1`, `head_on_v2` | two floes, no forcing, no obstacle, no spin, velocities along the line of centres and approaching, symmetric about it | final velocities along the line | [`HEAD_ON_TOLERANCE`] × approach speed |
//! | `bouncing_first_impact`, `bouncing_rest` | one floe at rest at a gap `d > 0` from an obstacle, constant wind, no water drag, `f = 0`, symmetric about the wind line | first contact event; rest time | one output interval (+ rest threshold) |
//! | `sliding_distance`, `sliding_stop` | one floe touching an obstacle face, wind into it, velocity across the wind, `μ > 0`, no water drag, `f = 0` | distance along `v0`; stop time | [`SLIDING_DISTANCE_TOLERANCE`]; one output interval |
//! | `cradle_outcome` (and `cradle_physical` when touching) | ≥ 3 equal floes in a row along the first one's velocity, the others at rest, `e = 1`, no forcing, no obstacle, symmetric | final velocities | [`CRADLE_TOLERANCE`] × `v0` |
//! | `cannon_velocities` | two floes in a row at the same velocity toward an obstacle, no forcing, symmetric; the front one rebounds before they meet and leaves the wall for good | final velocities | [`CRADLE_TOLERANCE`] × `v0` |
//! | `free_drift_velocity` | no obstacle, constant wind and current, water drag, duration ≥ 20 drag time constants | final velocity of each floe | [`FREE_DRIFT_TOLERANCE`] |
//! | `energy_ledger` | always | `max_t \|residual\| / exchanged` | [`LEDGER_TOLERANCE`] |
//!
//! Whether a formulation *claims* a check is decided by one table,
//! each formulation's registry entry ([`formulation::Entry::not_claimed`]): every check is claimed by every formulation unless
//! listed there, with the reason. A failing claimed check makes
//! `floebench check` exit non-zero; a failing unclaimed one is printed as
//! `fail (known)`, a finding.
//!
//! Which formulations run ([`crate::run::batch::default_formulations`]):
//! every formulation of [`crate::formulation::REGISTRY`], except
//! `free-drift` on a case where contacts can happen. A case is
//! *contact-free* ([`Scenario::contact_free`]) when it has no obstacle and every floe
//! starts at rest (only the environment moves them; the drift cases keep
//! their floes apart, which the `penetration` check verifies).

use crate::contact::{signed_distance, Aabb, BroadPhase};
use crate::formulation;
use crate::formulation::contact_solver::COULOMB_SLACK;
use crate::formulation::event_driven::{
    floe_length_scale, EventDrivenSettings, DEFAULT_PENETRATION_FRACTION,
};
use crate::geometry::{cross, Vec2};
use crate::model::{Scenario, VelocitySeries};
use crate::record::counters::common::MAX_PENETRATION;
use crate::run::{EndReason, RunResult, TrajectoryRow};
use serde::Serialize;

/// The result of one check on one run.
#[derive(Debug, Clone, Serialize)]
pub struct CheckOutcome {
    /// Case name.
    pub case: String,
    /// Formulation name.
    pub formulation: String,
    /// Short id of the check, e.g. `head_on_v1`.
    pub check: String,
    /// What is checked, in words.
    pub description: String,
    /// The measured value, in `unit`.
    pub measured: f64,
    /// The exact value where there is one, in `unit`.
    pub expected: Option<f64>,
    /// The tolerance on `|measured − expected|` (or the bound on `measured`
    /// when there is no expected value), in `unit`.
    pub tolerance: f64,
    /// Unit of `measured`, `expected`, `tolerance` (`1`: dimensionless).
    pub unit: String,
    /// Whether the run passes.
    pub pass: bool,
    /// Whether the formulation claims to pass ([`not_claimed`]).
    pub claimed: bool,
    /// The reason when not claimed, or a detail of the measurement.
    pub note: String,
}

/// Momentum conserved to this fraction of `Σ M ‖Ġ(0)‖`: impulses are applied
/// in equal and opposite pairs, so only rounding (1e-16 per impact) changes
/// the total; 1e-10 leaves room for thousands of impacts, and a missing
/// reaction (a one-sided impulse) changes it by order one.
pub const MOMENTUM_TOLERANCE: f64 = 1e-10;

/// Largest kinetic energy one contact event may create, as a fraction of the
/// energy exchanged in the run: the group energies round at 1e-16 and an LCP
/// solution is accepted at a residual of 1e-10 of the velocities (2e-10 of
/// the energy); an impact law that creates energy does so at the scale of
/// the impact's energy.
pub const IMPACT_ENERGY_TOLERANCE: f64 = 1e-9;

/// Kinetic energy conserved to this fraction of `E(0)` for `e = 1`, `μ = 0`
/// without forcing: the same rounding and LCP-residual argument as
/// [`IMPACT_ENERGY_TOLERANCE`], over hundreds of impacts.
pub const ENERGY_CONSERVED_TOLERANCE: f64 = 1e-9;

/// Trajectories stay mirror images to this fraction of the configuration's
/// extent: the initial data are mirror images to rounding (1e-16), each floe
/// is integrated at a relative tolerance of 1e-10 per step, summed over up to
/// 1e4 steps; a broken symmetry (a one-sided impulse, a spurious spin)
/// shows at the scale of the motion.
pub const SYMMETRY_TOLERANCE: f64 = 1e-6;

/// Head-on velocities to this fraction of the approach speed: an LCP
/// solution is accepted at a residual of 1e-10 of the velocities.
pub const HEAD_ON_TOLERANCE: f64 = 1e-9;

/// Cradle and cannon velocities to this fraction of `v0` (the same reason as
/// [`HEAD_ON_TOLERANCE`]).
pub const CRADLE_TOLERANCE: f64 = 1e-9;

/// The sliding distance to this fraction of `v0² / (2 μ a)`: a consistent
/// scheme at the bundled steps errs by `O(h²)` (`μ a h² / 8`, 1e-5 m at 1 s)
/// or `O(v0 h / n)` with substeps (0.6 mm of 17 m); a friction law off by
/// 1 % moves the stop by 1 %.
pub const SLIDING_DISTANCE_TOLERANCE: f64 = 1e-4;

/// A floe is at rest once its speed stays below this fraction of the
/// reference speed (`v1` bouncing, `v0` sliding): decelerating uniformly it
/// is that slow only in the last 1e-3 of its stopping time.
pub const REST_SPEED_FRACTION: f64 = 1e-3;

/// The free-drift velocity to this fraction of the steady speed: the
/// integrators run at 1e-10 and after 20 drag time constants the transient
/// is `e^-20` = 2e-9 of the initial gap.
pub const FREE_DRIFT_TOLERANCE: f64 = 1e-6;

/// Drag time constants a run must last for the free-drift check to apply.
pub const FREE_DRIFT_TIME_CONSTANTS: f64 = 20.0;

/// The energy-ledger residual to this fraction of the energy exchanged: the
/// integrators run at 1e-10 relative; an energy term missing from the
/// ledger (unbooked dissipation, work of a force) is a sizeable fraction of
/// the exchanges.
pub const LEDGER_TOLERANCE: f64 = 1e-6;

/// Relative rounding allowance when matching the initial geometry of a case
/// (mirror images, touching floes, collinear centres).
const GEOMETRY_MATCH: f64 = 1e-9;

/// The reason formulation `formulation` does not claim `check` on `case`
/// (its registry entry's [`formulation::NotClaimed`] list), or `None` when
/// it claims it; an unknown formulation claims nothing.
pub fn not_claimed(formulation: &str, check: &str, case: &str) -> Option<&'static str> {
    match formulation::entry(formulation) {
        Ok(e) => e.not_claimed(check, case),
        Err(_) => Some("not a formulation of the registry"),
    }
}

// ---------------------------------------------------------------------------
// Structure of a case.

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

fn world_polygon(scn: &Scenario, i: usize, g: &Vec2, theta: f64) -> Vec<Vec2> {
    let mut p = Vec::new();
    scn.floes[i].world_polygon(g, theta, &mut p);
    p
}

fn initial_polygon(scn: &Scenario, i: usize) -> Vec<Vec2> {
    world_polygon(scn, i, &scn.floes[i].position, 0.0)
}

/// Extent of the floes about `c`: the largest distance of a floe vertex, m.
fn extent(scn: &Scenario, c: &Vec2) -> f64 {
    scn.floes
        .iter()
        .map(|f| (f.position - c).norm() + f.radius)
        .fold(0.0, f64::max)
}

/// Whether the polygons have the same vertices to `tol` (m), in any order.
fn same_vertices(a: &[Vec2], b: &[Vec2], tol: f64) -> bool {
    a.len() == b.len() && a.iter().all(|p| b.iter().any(|q| (p - q).norm() <= tol))
}

fn series_parallel(v: &VelocitySeries, d: &Vec2) -> bool {
    let ok = |u: &Vec2| cross(d, u).abs() <= 1e-12 * u.norm();
    match v {
        VelocitySeries::Constant(u) => ok(u),
        VelocitySeries::Series(points) => points.iter().all(|p| ok(&p.1)),
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

/// The wind acceleration `a = ρ_a C_a |U_a|² / (ρ_i h)` of floe `i` at t = 0
/// (physics.md section 2: constant wind as gravity), m/s².
pub fn wind_acceleration(scn: &Scenario, i: usize) -> f64 {
    let air = &scn.environment.air;
    let u = air.velocity.at(0.0).norm();
    air.drag_factor() * u * u / scn.floes[i].surface_density()
}

/// The steady free-drift velocity of floe `i` under constant wind and
/// current (physics.md section 2): the root of
/// `τ_a + ρ_w C_w |U_w − u|(U_w − u) − ρ_i h f k ∧ u = 0` by Newton's method,
/// m/s; `None` without water drag, with varying forcing, or if Newton fails.
pub fn steady_drift_velocity(scn: &Scenario, i: usize) -> Option<Vec2> {
    let env = &scn.environment;
    let (VelocitySeries::Constant(ua), VelocitySeries::Constant(uw)) =
        (&env.air.velocity, &env.water.velocity)
    else {
        return None;
    };
    let (ka, kw) = (env.air.drag_factor(), env.water.drag_factor());
    if kw <= 0.0 {
        return None;
    }
    let rho_h = scn.floes[i].surface_density();
    let f = env.coriolis;
    let tau_a = ua * (ka * ua.norm());
    let g = |u: Vec2| -> Vec2 {
        let r = uw - u;
        tau_a + r * (kw * r.norm()) - Vec2::new(-u.y, u.x) * (rho_h * f)
    };
    let mut u = uw + ua * (ka / kw).sqrt();
    let scale = tau_a
        .norm()
        .max(kw * uw.norm().powi(2))
        .max(f64::MIN_POSITIVE);
    for _ in 0..100 {
        let g0 = g(u);
        if g0.norm() <= 1e-13 * scale {
            return Some(u);
        }
        let h = 1e-7 * u.norm().max(1e-3);
        let jx = (g(u + Vec2::new(h, 0.0)) - g0) / h;
        let jy = (g(u + Vec2::new(0.0, h)) - g0) / h;
        let det = jx.x * jy.y - jy.x * jx.y;
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        u -= Vec2::new(jy.y * g0.x - jy.x * g0.y, -jx.y * g0.x + jx.x * g0.y) / det;
    }
    (g(u).norm() <= 1e-10 * scale).then_some(u)
}

/// The first output time from which floe `floe` moves slower than `speed`
/// (m/s) at every later output; `None` if it still moves at the end.
pub fn rest_time(rows: &[TrajectoryRow], floe: usize, speed: f64) -> Option<f64> {
    let mine = || rows.iter().filter(|r| r.floe == floe);
    let last_move = mine()
        .filter(|r| r.vx.hypot(r.vy) > speed)
        .map(|r| r.t)
        .reduce(f64::max);
    match last_move {
        None => mine().map(|r| r.t).next(),
        Some(tm) => mine().map(|r| r.t).find(|&t| t > tm),
    }
}

/// The deepest overlap (m, ≥ 0) between two floes or a floe and an obstacle
/// at the output times of `rows`: the minimum translation distance
/// ([`signed_distance`]) of every overlapping pair.
pub fn sampled_penetration(scn: &Scenario, rows: &[TrajectoryRow]) -> f64 {
    let n = scn.floes.len();
    if n == 0 {
        return 0.0;
    }
    let mut bp = BroadPhase::new();
    let mut pairs = Vec::new();
    let mut deepest = 0.0f64;
    for sample in rows.chunks(n) {
        let mut polys: Vec<Vec<Vec2>> = sample
            .iter()
            .map(|r| world_polygon(scn, r.floe, &Vec2::new(r.x, r.y), r.theta))
            .collect();
        polys.extend(scn.obstacles.iter().map(|o| o.polygon.clone()));
        let boxes: Vec<Aabb> = polys
            .iter()
            .enumerate()
            .map(|(i, p)| Aabb::of_polygon(p, i >= n))
            .collect();
        bp.pairs(&boxes, 0.0, &mut pairs);
        for &(i, j) in &pairs {
            deepest = deepest.max(-signed_distance(&polys[i], &polys[j]));
        }
    }
    deepest
}

/// The final velocity of floe `i`, m/s.
fn final_velocity(run: &RunResult, i: usize) -> Vec2 {
    run.final_state
        .bodies
        .get(i)
        .map_or(Vec2::zeros(), |b| b.velocity)
}

// ---------------------------------------------------------------------------
// The checks.

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
    ) {
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
        });
    }
}

/// The checks of every run of `scn`, run by run ([`check_run`]).
pub fn check_runs(scn: &Scenario, runs: &[RunResult]) -> Vec<CheckOutcome> {
    runs.iter().flat_map(|r| check_run(scn, r)).collect()
}

/// Every check that applies to `scn`, measured on `run` (see the module
/// doc); `claimed` and `note` from [`not_claimed`].
pub fn check_run(scn: &Scenario, run: &RunResult) -> Vec<CheckOutcome> {
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
            other => format!("{other:?} at t = {} s", run.summary.t_reached),
        },
    );
    momentum(&mut r);
    impact_energy(&mut r);
    energy_conserved(&mut r);
    coulomb(&mut r);
    penetration(&mut r);
    symmetry(&mut r);
    head_on(&mut r);
    bouncing(&mut r);
    sliding(&mut r);
    cradle(&mut r);
    cannon(&mut r);
    free_drift(&mut r);
    ledger(&mut r);
    for o in &mut r.out {
        if let Some(reason) = not_claimed(&o.formulation, &o.check, &o.case) {
            o.claimed = false;
            o.note = if o.note.is_empty() {
                reason.to_string()
            } else {
                format!("{reason} [{}]", o.note)
            };
        }
    }
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
    let n = scn.floes.len();
    let worst = r
        .run
        .trajectory
        .chunks(n)
        .map(|rows| {
            let p = rows.iter().fold(Vec2::zeros(), |s, row| {
                s + Vec2::new(row.vx, row.vy) * scn.floes[row.floe].mass
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
    );
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
        format!(
            "largest gain {gain:.3e} J over {} events / {scale:.3e} J exchanged",
            log.event_count()
        ),
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
    );
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
    let sampled = sampled_penetration(scn, &r.run.trajectory);
    let own = r
        .run
        .summary
        .counters
        .value(&MAX_PENETRATION)
        .ok()
        .flatten();
    let tol = EventDrivenSettings::of(scn)
        .map_or(DEFAULT_PENETRATION_FRACTION * floe_length_scale(scn), |s| {
            s.penetration_tolerance(scn)
        });
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
    );
}

/// `(v1', v2')` of a central impact (physics.md section 6).
pub fn head_on_velocities(m1: f64, v1: f64, m2: f64, v2: f64, e: f64) -> (f64, f64) {
    let p = m1 * v1 + m2 * v2;
    (
        (p - m2 * e * (v1 - v2)) / (m1 + m2),
        (p + m1 * e * (v1 - v2)) / (m1 + m2),
    )
}

/// Whether the configuration is symmetric about the line through `c` along
/// `d` with every floe its own image (impacts along it are central).
fn self_symmetric(scn: &Scenario, c: Vec2, d: Vec2) -> bool {
    mirror_pairing(scn, &Axis { c, d }).is_some_and(|p| p.iter().enumerate().all(|(i, &j)| i == j))
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
    );
    r.push(
        "head_on_v2",
        "floe 1 after a central impact: (m1 v1 + m2 v2 + m1 e (v1 - v2))/(m1 + m2)",
        b.dot(&d),
        Some(w2),
        tol,
        "m/s",
        note,
    );
}

/// The direction of the constant wind if the case is "constant wind as
/// gravity" (physics.md section 2): one floe, an obstacle, constant wind,
/// no water drag, no Coriolis.
fn wind_as_gravity(scn: &Scenario) -> Option<Vec2> {
    let env = &scn.environment;
    let VelocitySeries::Constant(ua) = &env.air.velocity else {
        return None;
    };
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

fn bouncing(r: &mut Rows) {
    let scn = r.scn;
    let Some(d) = wind_as_gravity(scn) else {
        return;
    };
    let f = &scn.floes[0];
    if f.velocity.norm() != 0.0 || f.angular_velocity != 0.0 || !self_symmetric(scn, f.position, d)
    {
        return;
    }
    let Some((gap, _)) = translation_gap(scn, 0, &d) else {
        return;
    };
    if gap <= GEOMETRY_MATCH * f.radius {
        return;
    }
    let e = scn.contact.restitution;
    let a = wind_acceleration(scn, 0);
    let t1 = (2.0 * gap / a).sqrt();
    let v1 = a * t1;
    let dt = scn.output_interval;
    let first = r.run.contacts.events.first().map(|ev| ev.t);
    if r.run.contacts.records_events {
        r.push(
            "bouncing_first_impact",
            "first impact at t1 = sqrt(2 d / a)",
            first.unwrap_or(f64::NAN),
            Some(t1),
            dt,
            "s",
            format!("d = {gap:.6} m, a = {a:.6e} m/s^2; tolerance: one output interval"),
        );
    }
    if e < 1.0 {
        let t_inf = t1 * (1.0 + e) / (1.0 - e);
        let v_rest = REST_SPEED_FRACTION * v1;
        // Decelerating at a, the floe is below v_rest during the last
        // 2 v_rest / (a (1 - e)) of the accumulation: the threshold's own shift.
        let tol = dt + 2.0 * v_rest / (a * (1.0 - e));
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
        );
    }
}

fn sliding(r: &mut Rows) {
    let scn = r.scn;
    let Some(d) = wind_as_gravity(scn) else {
        return;
    };
    let f = &scn.floes[0];
    let mu = scn.contact.friction;
    let v0 = f.velocity.norm();
    if mu <= 0.0 || v0 == 0.0 || f.angular_velocity != 0.0 || f.velocity.dot(&d).abs() > 1e-12 * v0
    {
        return;
    }
    let Some((gap, rays)) = translation_gap(scn, 0, &d) else {
        return;
    };
    if gap > GEOMETRY_MATCH * f.radius || rays < 2 {
        return;
    }
    let a = wind_acceleration(scn, 0);
    let t_stop = v0 / (mu * a);
    let dist = v0 * v0 / (2.0 * mu * a);
    if scn.duration < t_stop + scn.output_interval {
        return;
    }
    let dir = f.velocity / v0;
    let end = r
        .run
        .final_state
        .bodies
        .first()
        .map_or(f.position, |b| b.position);
    r.push(
        "sliding_distance",
        "slides v0^2 / (2 mu a) along the wall",
        (end - f.position).dot(&dir),
        Some(dist),
        SLIDING_DISTANCE_TOLERANCE * dist,
        "m",
        format!("v0 = {v0} m/s, mu = {mu}, a = {a:.6e} m/s^2"),
    );
    let v_rest = REST_SPEED_FRACTION * v0;
    r.push(
        "sliding_stop",
        "stops after v0 / (mu a)",
        rest_time(&r.run.trajectory, 0, v_rest).unwrap_or(f64::NAN),
        Some(t_stop),
        scn.output_interval + REST_SPEED_FRACTION * t_stop,
        "s",
        format!(
            "rest: speed below {v_rest:.3e} m/s from then on; tolerance: one output interval + the threshold's shift"
        ),
    );
}

/// Floes in a row along the unit direction `d` from floe 0: the floe
/// indices sorted along `d`, if every centre lies on the line through floe
/// 0's centre (to rounding) and the configuration is symmetric about it.
fn in_a_row(scn: &Scenario, d: Vec2) -> Option<Vec<usize>> {
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
        );
    } else {
        let err = error(&lcp);
        r.push(
            "cradle_outcome",
            "touching: the simultaneous LCP answer ((2-n)/n, 2/n, ..., 2/n) v0 (physics.md section 6)",
            err,
            Some(0.0),
            CRADLE_TOLERANCE,
            "1",
            format!(
                "max |v - v_lcp| / v0; got ({}), LCP ({}) m/s",
                finals.join(", "),
                show(&lcp)
            ),
        );
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
        );
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
    );
}

fn free_drift(r: &mut Rows) {
    let scn = r.scn;
    if !scn.obstacles.is_empty() {
        return;
    }
    let kw = scn.environment.water.drag_factor();
    for i in 0..scn.floes.len() {
        let Some(u) = steady_drift_velocity(scn, i) else {
            return;
        };
        let uw = scn.environment.water.velocity.at(0.0);
        let rel = (u - uw).norm();
        // Linearised drag time constant ρ_i h / (2 ρ_w C_w |u − U_w|).
        let tau = scn.floes[i].surface_density() / (2.0 * kw * rel.max(f64::MIN_POSITIVE));
        if scn.duration < FREE_DRIFT_TIME_CONSTANTS * tau || u.norm() == 0.0 {
            continue;
        }
        let v = final_velocity(r.run, i);
        r.push(
            "free_drift_velocity",
            "reaches the steady free-drift velocity (physics.md section 2)",
            (v - u).norm() / u.norm(),
            Some(0.0),
            FREE_DRIFT_TOLERANCE,
            "1",
            format!(
                "floe {i}: |v - u| / |u|; u = ({:.9}, {:.9}) m/s, got ({:.9}, {:.9}); drag time {tau:.1} s",
                u.x, u.y, v.x, v.y
            ),
        );
    }
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

// ---------------------------------------------------------------------------
// Outcomes.

/// Number of checks that fail although the formulation claims them.
pub fn claimed_failures(rows: &[CheckOutcome]) -> usize {
    rows.iter().filter(|o| o.claimed && !o.pass).count()
}

/// `pass`, `FAIL` (claimed) or `fail (known)` (not claimed).
pub fn verdict(o: &CheckOutcome) -> &'static str {
    match (o.pass, o.claimed) {
        (true, _) => "pass",
        (false, true) => "FAIL",
        (false, false) => "fail (known)",
    }
}
