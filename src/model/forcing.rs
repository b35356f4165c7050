//! The velocity of a fluid (wind or current) as a function of place and
//! time, `u(x, y, t)`: the one point function of the fluid velocity that
//! the force model, the step bounds and the checks use (docs/physics.md
//! §2.4).
//!
//! A [`VelocityField`] is one of:
//!
//! - uniform in space: a constant or a piecewise-linear time series
//!   ([`VelocitySeries`], the forcing of every case before fields existed;
//!   the force model keeps its closed form for it, so those results are
//!   unchanged bit for bit);
//! - `linear`: `u(p) = u₀ + ∇u (p − p₀)` with a constant velocity gradient
//!   (shear, convergence, rotation), on an extent box;
//! - `vortex`: a Rankine vortex (solid rotation inside the core radius `R`,
//!   azimuthal speed `S R / r` outside) whose centre drifts at a constant
//!   velocity and which drifts the fluid with it;
//! - `grid`: values on a rectilinear grid read from a CF NetCDF file
//!   ([`super::netcdf`]), bilinear in space and linear in time.
//!
//! The analytic fields may be multiplied by a dimensionless time series
//! ([`Scale`]). Each field knows its largest speed over its extent and the
//! duration ([`VelocityField::max_speed`]): the Euler stability bound and
//! the step bounds use it. Bilinear and linear interpolation are convex
//! combinations of the nodes, so for a grid the largest node speed is an
//! exact bound.
//!
//! A field with an extent (linear, grid) refuses points outside it unless
//! the case says `outside = "clamp"` (the value at the nearest point of the
//! extent). The force law cannot fail in the middle of a step, so an
//! outside point is evaluated clamped and noted in the [`OutsideLog`] the
//! caller passes (the environment's own, [`super::Environment::outside`],
//! in the run's copy of the scenario); the runner takes it after each
//! output interval and ends the run with an error naming the file, the
//! variable and the point (docs/physics.md §2.4).

use crate::geometry::Vec2;
use serde::Serialize;
use std::sync::{Arc, OnceLock};

/// A velocity that is constant or piecewise linear in time.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum VelocitySeries {
    /// The same velocity at all times, m/s.
    Constant(Vec2),
    /// Points `(t, u)` with strictly increasing `t` (s), `u` in m/s; linear in
    /// between, held at the first value before the first point and at the
    /// last value after the last point.
    Series(Vec<(f64, Vec2)>),
}

impl VelocitySeries {
    /// The velocity at time `t`, m/s.
    pub fn at(&self, t: f64) -> Vec2 {
        match self {
            VelocitySeries::Constant(u) => *u,
            VelocitySeries::Series(points) => {
                let Some(first) = points.first() else {
                    return Vec2::zeros();
                };
                if t <= first.0 {
                    return first.1;
                }
                // Points are few; a binary search keeps long series fast.
                let k = points.partition_point(|p| p.0 <= t);
                if k >= points.len() {
                    return points[points.len() - 1].1;
                }
                let (t0, u0) = points[k - 1];
                let (t1, u1) = points[k];
                let s = (t - t0) / (t1 - t0);
                u0 + (u1 - u0) * s
            }
        }
    }

    /// The largest speed the series takes, m/s.
    pub fn max_speed(&self) -> f64 {
        match self {
            VelocitySeries::Constant(u) => u.norm(),
            VelocitySeries::Series(points) => points.iter().map(|p| p.1.norm()).fold(0.0, f64::max),
        }
    }

    /// The times (s) where the series has a kink, for integrators to stop at.
    pub fn breakpoints(&self) -> &[(f64, Vec2)] {
        match self {
            VelocitySeries::Constant(_) => &[],
            VelocitySeries::Series(points) => points,
        }
    }
}

/// A dimensionless factor of time that scales an analytic field: points
/// `(t, s)` with strictly increasing `t` (s), linear in between, held at the
/// first value before the first point and at the last after the last.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Scale {
    /// The points `(t s, factor)`.
    pub points: Vec<(f64, f64)>,
}

impl Scale {
    /// The factor at time `t` (s); 1 without points.
    pub fn at(&self, t: f64) -> f64 {
        let p = &self.points;
        let Some(first) = p.first() else {
            return 1.0;
        };
        if t <= first.0 {
            return first.1;
        }
        let k = p.partition_point(|q| q.0 <= t);
        if k >= p.len() {
            return p[p.len() - 1].1;
        }
        let (t0, s0) = p[k - 1];
        let (t1, s1) = p[k];
        s0 + (s1 - s0) * ((t - t0) / (t1 - t0))
    }

    /// The largest `|factor|` (1 without points).
    pub fn max_abs(&self) -> f64 {
        if self.points.is_empty() {
            return 1.0;
        }
        self.points.iter().map(|p| p.1.abs()).fold(0.0, f64::max)
    }
}

/// What a field with an extent does at a point outside it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Outside {
    /// The run ends with an error naming the point (the default).
    Error,
    /// The value at the nearest point of the extent.
    Clamp,
}

/// An axis-aligned box `[xmin, xmax] × [ymin, ymax]`, m.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Extent {
    /// Lower corner, m.
    pub min: Vec2,
    /// Upper corner, m.
    pub max: Vec2,
}

impl Extent {
    /// Whether `p` lies in the closed box.
    pub fn contains(&self, p: &Vec2) -> bool {
        p.x >= self.min.x && p.x <= self.max.x && p.y >= self.min.y && p.y <= self.max.y
    }

    /// The nearest point of the box to `p`.
    pub fn clamp(&self, p: &Vec2) -> Vec2 {
        Vec2::new(
            p.x.clamp(self.min.x, self.max.x),
            p.y.clamp(self.min.y, self.max.y),
        )
    }

    /// The four corners.
    pub fn corners(&self) -> [Vec2; 4] {
        [
            self.min,
            Vec2::new(self.max.x, self.min.y),
            self.max,
            Vec2::new(self.min.x, self.max.y),
        ]
    }
}

/// `u(p) = u₀ + ∇u (p − p₀)` on an extent, optionally scaled in time.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LinearField {
    /// The velocity `u₀` at `at`, m/s.
    pub velocity: Vec2,
    /// The point `p₀`, m.
    pub at: Vec2,
    /// The gradient `[[∂u/∂x, ∂u/∂y], [∂v/∂x, ∂v/∂y]]`, 1/s.
    pub gradient: [[f64; 2]; 2],
    /// Where the field is defined (its largest speed is taken there), m.
    pub extent: Extent,
    /// What happens outside the extent.
    pub outside: Outside,
    /// The time factor.
    pub scale: Scale,
}

impl LinearField {
    /// The unscaled velocity at `p` (no extent rule), m/s.
    fn value(&self, p: &Vec2) -> Vec2 {
        let d = p - self.at;
        let g = &self.gradient;
        self.velocity + Vec2::new(g[0][0] * d.x + g[0][1] * d.y, g[1][0] * d.x + g[1][1] * d.y)
    }
}

/// A Rankine vortex whose centre drifts at a constant velocity, optionally
/// scaled in time: at `r = |p − c(t)|` the velocity is
/// `c' + S (r/R) e_θ` inside the core (`r ≤ R`) and `c' + S (R/r) e_θ`
/// outside, `e_θ` counter-clockwise (a negative `S` turns clockwise), with
/// `c(t) = c₀ + c' t`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VortexField {
    /// The centre at t = 0, m.
    pub center: Vec2,
    /// The core radius `R`, m.
    pub radius: f64,
    /// The peak azimuthal speed `S` (at `r = R`), m/s; positive
    /// counter-clockwise.
    pub speed: f64,
    /// The drift of the centre `c'`, m/s (also added to the fluid velocity).
    pub center_velocity: Vec2,
    /// The time factor (of the whole velocity).
    pub scale: Scale,
}

impl VortexField {
    /// The unscaled velocity at `p` and time `t`, m/s.
    fn value(&self, p: &Vec2, t: f64) -> Vec2 {
        let d = p - (self.center + self.center_velocity * t);
        let r = d.norm();
        let e = Vec2::new(-d.y, d.x); // r e_θ
        let swirl = if r <= self.radius {
            e * (self.speed / self.radius)
        } else {
            e * (self.speed * self.radius / (r * r))
        };
        self.center_velocity + swirl
    }
}

/// Gridded values (m/s) on a rectilinear grid, as read from a file.
#[derive(Debug, Clone, PartialEq)]
pub struct GridData {
    /// Node abscissae, strictly increasing, m.
    pub x: Vec<f64>,
    /// Node ordinates, strictly increasing, m.
    pub y: Vec<f64>,
    /// Times of the records, strictly increasing, s from the run's t = 0
    /// (one record: steady).
    pub t: Vec<f64>,
    /// `u` at `[k][j][i]` = `u[(k * ny + j) * nx + i]` (time k, y j, x i), m/s.
    pub u: Vec<f64>,
    /// `v`, laid out as `u`, m/s.
    pub v: Vec<f64>,
    /// The date of the run's t = 0, s from 1970-01-01 00:00:00 UTC (`None`
    /// for a steady file without a time axis nor a `start`).
    pub epoch: Option<f64>,
}

/// A gridded field: the data and where it came from (for messages).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GridField {
    /// The file, as the case names it (relative to the case file).
    pub file: String,
    /// The variables of the two components.
    pub variables: [String; 2],
    /// What happens outside the grid.
    pub outside: Outside,
    /// The values.
    #[serde(skip)]
    pub data: Arc<GridData>,
    /// Largest node speed, m/s.
    pub max_speed: f64,
    /// Whether every record has the same value at every node: the field
    /// is then uniform in space, and the air drag takes its closed form.
    pub uniform_in_space: bool,
}

/// `a + (b − a) w`: equal to `a` to the bit where `b = a`.
#[inline]
fn lerp(a: Vec2, b: Vec2, w: f64) -> Vec2 {
    a + (b - a) * w
}

/// Index `k` of the cell `[a[k], a[k+1]]` holding `s` (clamped) and the
/// weight of `a[k+1]`.
fn cell(a: &[f64], s: f64) -> (usize, f64) {
    if a.len() < 2 {
        return (0, 0.0);
    }
    let k = a.partition_point(|&q| q <= s).clamp(1, a.len() - 1) - 1;
    let w = ((s - a[k]) / (a[k + 1] - a[k])).clamp(0.0, 1.0);
    (k, w)
}

impl GridField {
    /// The grid's extent, m.
    pub fn extent(&self) -> Extent {
        let d = &self.data;
        Extent {
            min: Vec2::new(d.x[0], d.y[0]),
            max: Vec2::new(d.x[d.x.len() - 1], d.y[d.y.len() - 1]),
        }
    }

    /// Bilinear in space, linear in time (held outside the time axis, which
    /// the case checks covers the run), at a point inside the grid (m) and
    /// time `t` (s), m/s.
    fn value(&self, p: &Vec2, t: f64) -> Vec2 {
        let d = &self.data;
        let (nx, ny) = (d.x.len(), d.y.len());
        let (i, wx) = cell(&d.x, p.x);
        let (j, wy) = cell(&d.y, p.y);
        let (k, wt) = cell(&d.t, t);
        let i1 = (i + 1).min(nx - 1);
        let j1 = (j + 1).min(ny - 1);
        let at = |k: usize| -> Vec2 {
            let node = |jj: usize, ii: usize| {
                let n = (k * ny + jj) * nx + ii;
                Vec2::new(d.u[n], d.v[n])
            };
            // `a + (b − a) w`: exact where the values are equal.
            let bottom = lerp(node(j, i), node(j, i1), wx);
            let top = lerp(node(j1, i), node(j1, i1), wx);
            lerp(bottom, top, wy)
        };
        if d.t.len() < 2 || wt == 0.0 {
            at(k)
        } else {
            lerp(at(k), at(k + 1), wt)
        }
    }
}

/// The velocity of a fluid over the sea plane, m/s.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum VelocityField {
    /// Uniform in space: constant or a time series.
    Uniform(VelocitySeries),
    /// A constant gradient (`field = "linear"`).
    Linear(LinearField),
    /// A drifting Rankine vortex (`field = "vortex"`).
    Vortex(VortexField),
    /// Gridded from a NetCDF file (`field = "netcdf"`).
    Grid(GridField),
}

impl VelocityField {
    /// A uniform constant velocity, m/s.
    pub fn constant(u: Vec2) -> VelocityField {
        VelocityField::Uniform(VelocitySeries::Constant(u))
    }

    /// The velocity at world point `p` (m) and time `t` (s), m/s: the one
    /// point function of the fluid velocity. A point outside the extent of
    /// a field that refuses it is evaluated clamped and noted in `log`.
    #[inline]
    pub fn at(&self, p: &Vec2, t: f64, log: &OutsideLog) -> Vec2 {
        match self {
            VelocityField::Uniform(s) => s.at(t),
            VelocityField::Linear(f) => {
                let q = self.inside(&f.extent, f.outside, p, t, log);
                f.value(&q) * f.scale.at(t)
            }
            VelocityField::Vortex(f) => f.value(p, t) * f.scale.at(t),
            VelocityField::Grid(g) => {
                let q = self.inside(&g.extent(), g.outside, p, t, log);
                g.value(&q, t)
            }
        }
    }

    /// `p`, or its nearest point in `extent` (noting the first outside
    /// point in `log` when the field refuses it).
    fn inside(
        &self,
        extent: &Extent,
        outside: Outside,
        p: &Vec2,
        t: f64,
        log: &OutsideLog,
    ) -> Vec2 {
        if extent.contains(p) {
            return *p;
        }
        if outside == Outside::Error {
            log.note(|| self.outside_message(extent, p, t));
        }
        extent.clamp(p)
    }

    /// The error of a point outside the extent.
    fn outside_message(&self, e: &Extent, p: &Vec2, t: f64) -> String {
        let whose = match self {
            VelocityField::Grid(g) => format!(
                "the grid of {} (variables {}, {})",
                g.file, g.variables[0], g.variables[1]
            ),
            _ => "the extent of the linear field".to_string(),
        };
        format!(
            "the point ({}, {}) m at t = {t} s is outside {whose}: x in [{}, {}] m, y in [{}, {}] m (`outside = \"clamp\"` holds the edge values instead)",
            p.x, p.y, e.min.x, e.max.x, e.min.y, e.max.y
        )
    }

    /// Whether the velocity is the same at every point (the closed form of
    /// the air drag applies: area × traction, no torque).
    pub fn is_uniform(&self) -> bool {
        match self {
            VelocityField::Uniform(_) => true,
            VelocityField::Grid(g) => g.uniform_in_space,
            _ => false,
        }
    }

    /// The time series of a field declared uniform in space (`velocity` or
    /// `series`), if it is one.
    pub fn uniform(&self) -> Option<&VelocitySeries> {
        match self {
            VelocityField::Uniform(s) => Some(s),
            _ => None,
        }
    }

    /// The velocity of a field constant in space and time, m/s, if it is one.
    pub fn constant_value(&self) -> Option<Vec2> {
        match self {
            VelocityField::Uniform(VelocitySeries::Constant(u)) => Some(*u),
            _ => None,
        }
    }

    /// The largest speed of the field over its extent (the whole plane for
    /// a vortex) and all times, m/s.
    pub fn max_speed(&self) -> f64 {
        match self {
            VelocityField::Uniform(s) => s.max_speed(),
            VelocityField::Linear(f) => {
                // |u| is convex and u affine: the largest is at a corner.
                let m = f
                    .extent
                    .corners()
                    .iter()
                    .map(|c| f.value(c).norm())
                    .fold(0.0, f64::max);
                m * f.scale.max_abs()
            }
            VelocityField::Vortex(f) => {
                (f.center_velocity.norm() + f.speed.abs()) * f.scale.max_abs()
            }
            VelocityField::Grid(g) => g.max_speed,
        }
    }

    /// The times (s) where the field has a kink in time (series points,
    /// scale points, grid records), for integrators to stop at.
    pub fn breakpoints(&self) -> Vec<f64> {
        match self {
            VelocityField::Uniform(s) => s.breakpoints().iter().map(|p| p.0).collect(),
            VelocityField::Linear(f) => f.scale.points.iter().map(|p| p.0).collect(),
            VelocityField::Vortex(f) => f.scale.points.iter().map(|p| p.0).collect(),
            VelocityField::Grid(g) => g.data.t.clone(),
        }
    }

    /// Whether the field is zero everywhere at all times.
    pub fn is_zero(&self) -> bool {
        self.max_speed() == 0.0
    }
}

/// The first point outside a field's extent met by the evaluations
/// ([`VelocityField::at`]) given this log, as an error message naming the
/// field (file and variables for a grid) and the point. Each environment
/// carries one ([`super::Environment::outside`]), so a run's copy of the
/// scenario holds its own; the runner takes it before a run and after each
/// output interval. Noting costs nothing while every point is inside (the
/// first message is formatted once, later ones not at all), and it can be
/// noted through a shared reference from any thread.
///
/// A log is not part of the value of what holds it: two logs always
/// compare equal.
#[derive(Debug, Clone, Default)]
pub struct OutsideLog(OnceLock<String>);

impl OutsideLog {
    /// Notes `message()` unless a point is noted already.
    #[cold]
    pub fn note(&self, message: impl FnOnce() -> String) {
        if self.0.get().is_none() {
            let _ = self.0.set(message());
        }
    }

    /// The first point noted since the last [`OutsideLog::take`], if any.
    pub fn first(&self) -> Option<&str> {
        self.0.get().map(String::as_str)
    }

    /// Hands over (and clears) the first point noted since the last call.
    pub fn take(&mut self) -> Option<String> {
        self.0.take()
    }
}

impl PartialEq for OutsideLog {
    fn eq(&self, _: &OutsideLog) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(nt: usize) -> GridField {
        let x = vec![0.0, 10.0, 30.0];
        let y = vec![-5.0, 5.0];
        let t: Vec<f64> = (0..nt).map(|k| 100.0 * k as f64).collect();
        let (mut u, mut v) = (Vec::new(), Vec::new());
        for &tk in &t {
            for &yj in &y {
                for &xi in &x {
                    u.push(1.0 + 0.1 * xi - 0.2 * yj + 0.001 * tk);
                    v.push(-0.5 + 0.05 * xi + 0.3 * yj);
                }
            }
        }
        let data = GridData {
            x,
            y,
            t,
            u,
            v,
            epoch: None,
        };
        GridField {
            file: "g.nc".into(),
            variables: ["u".into(), "v".into()],
            outside: Outside::Error,
            data: Arc::new(data),
            max_speed: 0.0,
            uniform_in_space: false,
        }
    }

    #[test]
    fn bilinear_in_space_and_linear_in_time_reproduce_an_affine_field() {
        let f = VelocityField::Grid(grid(3));
        let mut log = OutsideLog::default();
        for (p, t) in [
            (Vec2::new(3.0, 1.0), 0.0),
            (Vec2::new(29.0, -4.0), 150.0),
            (Vec2::new(0.0, 5.0), 200.0),
        ] {
            let u = f.at(&p, t, &log);
            let ux = 1.0 + 0.1 * p.x - 0.2 * p.y + 0.001 * t;
            let uy = -0.5 + 0.05 * p.x + 0.3 * p.y;
            assert!((u.x - ux).abs() <= 1e-12 * ux.abs().max(1.0));
            assert!((u.y - uy).abs() <= 1e-12 * uy.abs().max(1.0));
        }
        assert!(log.take().is_none());
    }

    #[test]
    fn an_outside_point_is_recorded_with_the_file_and_clamped() {
        let f = VelocityField::Grid(grid(1));
        let mut log = OutsideLog::default();
        let u = f.at(&Vec2::new(40.0, 0.0), 0.0, &log);
        let edge = f.at(&Vec2::new(30.0, 0.0), 0.0, &log);
        assert_eq!(u, edge);
        let m = log.take().expect("recorded");
        assert!(m.contains("g.nc") && m.contains("(40, 0)"), "{m}");
        assert!(log.take().is_none());
    }

    #[test]
    fn the_rankine_vortex_turns_rigidly_in_its_core_and_decays_outside() {
        let f = VortexField {
            center: Vec2::new(0.0, 0.0),
            radius: 100.0,
            speed: 2.0,
            center_velocity: Vec2::new(0.0, 0.0),
            scale: Scale { points: vec![] },
        };
        assert_eq!(f.value(&Vec2::new(50.0, 0.0), 0.0), Vec2::new(0.0, 1.0));
        assert_eq!(f.value(&Vec2::new(100.0, 0.0), 0.0), Vec2::new(0.0, 2.0));
        assert_eq!(f.value(&Vec2::new(0.0, 200.0), 0.0), Vec2::new(-1.0, 0.0));
    }
}
