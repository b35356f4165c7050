//! The documented limits of case files (docs/case-format.md, "Limits"):
//! every number a case may hold is bounded, each bound chosen from the
//! physics of floes or from what one machine can hold, with its reason.
//!
//! A [`Limit`] is one bound with its unit and reason; the case loader
//! ([`super::case`]) and the readers of the `[formulation.<name>]` tables
//! ([`super::settings::SettingsReader`]) check every value against its
//! limit and report a refusal as one line naming the file, the line and the
//! key. The counts that decide what a run allocates (floes, outputs, steps)
//! and the memory a run needs ([`run_memory_bytes`]) are checked before
//! anything is generated or allocated. The limits of the `[fracture]`
//! table, and the material bounds they rest on, are in [`fracture`].

pub mod fracture;
mod tables;

pub use tables::*;

/// One bound on a number: `min ≤ v ≤ max` (or `min < v` when `min_open`),
/// or on a magnitude `|v| ≤ max` (a vector's length, or a signed number).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limit {
    /// The key as written in its table (`thickness`).
    pub key: &'static str,
    /// Where the key is written (`[[floe]]`, `[[field]]`), for the docs.
    pub tables: &'static str,
    /// The smallest value allowed (ignored for a magnitude).
    pub min: f64,
    /// Whether `min` itself is refused (`min < v`).
    pub min_open: bool,
    /// The largest value (or magnitude) allowed.
    pub max: f64,
    /// Whether the bound is on `|v|` (then `min` is not used).
    pub magnitude: bool,
    /// Whether the value is an integer (messages then say nothing of finiteness).
    pub integer: bool,
    /// The unit, as written in messages (`m`, `kg/m^3`; empty: none).
    pub unit: &'static str,
    /// Why the bound is there (one short clause).
    pub why: &'static str,
}

impl Limit {
    /// A number in `[min, max]`.
    pub const fn range(
        key: &'static str,
        tables: &'static str,
        min: f64,
        max: f64,
        unit: &'static str,
        why: &'static str,
    ) -> Limit {
        Limit {
            key,
            tables,
            min,
            min_open: false,
            max,
            magnitude: false,
            integer: false,
            unit,
            why,
        }
    }

    /// A number or a vector of length at most `max`.
    pub const fn magnitude(
        key: &'static str,
        tables: &'static str,
        max: f64,
        unit: &'static str,
        why: &'static str,
    ) -> Limit {
        Limit {
            min: -max,
            magnitude: true,
            ..Limit::range(key, tables, 0.0, max, unit, why)
        }
    }

    /// The same bound with `min` itself refused: `(min, max]`.
    pub const fn exclusive_min(self) -> Limit {
        Limit {
            min_open: true,
            ..self
        }
    }

    /// The same bound on an integer.
    pub const fn integers(self) -> Limit {
        Limit {
            integer: true,
            ..self
        }
    }

    /// Whether `v` is allowed (a NaN never is).
    pub fn admits(&self, v: f64) -> bool {
        if self.magnitude {
            return v.abs() <= self.max;
        }
        let low = if self.min_open {
            v > self.min
        } else {
            v >= self.min
        };
        low && v <= self.max
    }

    /// `v` if allowed, else the one-line refusal naming `name` (the key as
    /// the message shows it, e.g. `[[floe]] #0: thickness`).
    pub fn check(&self, name: &str, v: f64) -> Result<f64, String> {
        self.check_shown(name, v, &show(v))
    }

    /// An integer `v` if allowed (shown exactly, however large).
    pub fn check_integer(&self, name: &str, v: i128) -> Result<i128, String> {
        self.check_shown(name, v as f64, &v.to_string()).map(|_| v)
    }

    /// A vector whose length is bounded (`|[x, y]| ≤ max`): each component
    /// must be finite and the length within the limit.
    pub fn check_vector(&self, name: &str, v: [f64; 2]) -> Result<[f64; 2], String> {
        if !(v[0].is_finite() && v[1].is_finite()) {
            return Err(format!("{name} must be finite"));
        }
        let len = v[0].hypot(v[1]);
        if len <= self.max {
            Ok(v)
        } else {
            let u = unit(self.unit);
            Err(format!(
                "{name} = [{}, {}]{u} has a length of {}{u}, above the limit of {}{u}: {}",
                show(v[0]),
                show(v[1]),
                show(len),
                show(self.max),
                self.why
            ))
        }
    }

    /// The refusal of `v`, written as `shown`, or `Ok(v)`.
    fn check_shown(&self, name: &str, v: f64, shown: &str) -> Result<f64, String> {
        if self.admits(v) {
            return Ok(v);
        }
        let u = unit(self.unit);
        // An integer's unit follows the bound only: `count = 0 must be >= 1`.
        let value_unit = if self.integer { "" } else { u.as_str() };
        if self.magnitude {
            if !v.is_finite() {
                return Err(format!("{name} = {shown}{value_unit} must be finite"));
            }
            let (what, side) = if v < 0.0 {
                ("below", -self.max)
            } else {
                ("above", self.max)
            };
            return Err(format!(
                "{name} = {shown}{value_unit} is {what} the limit of {}{u}: {}",
                show(side),
                self.why
            ));
        }
        if !v.is_finite() || !(v > self.min || (!self.min_open && v == self.min)) {
            let finite = if self.integer { "" } else { "finite and " };
            let op = if self.min_open { ">" } else { ">=" };
            let min_unit = if self.min == 0.0 || self.integer {
                ""
            } else {
                u.as_str()
            };
            return Err(format!(
                "{name} = {shown}{value_unit} must be {finite}{op} {}{min_unit}",
                show(self.min)
            ));
        }
        Err(format!(
            "{name} = {shown}{value_unit} is above the limit of {}{u}: {}",
            show(self.max),
            self.why
        ))
    }

    /// The bound as the docs' table writes it (`(0, 1000]`, `magnitude ≤ 100`).
    pub fn interval(&self) -> String {
        if self.magnitude {
            format!("magnitude ≤ {}", show(self.max))
        } else {
            let open = if self.min_open { "(" } else { "[" };
            format!("{open}{}, {}]", show(self.min), show(self.max))
        }
    }
}

/// The row of the "Limits" table of docs/case-format.md that documents
/// `limit` (a test holds the docs to it).
pub fn doc_row(limit: &Limit) -> String {
    let unit = if limit.unit.is_empty() {
        "–"
    } else {
        limit.unit
    };
    format!(
        "| `{}` | {} | {} | {unit} | {} |",
        limit.key,
        limit.tables,
        limit.interval(),
        limit.why
    )
}

/// A unit as it follows a number in messages (` m`, or nothing).
fn unit(u: &str) -> String {
    if u.is_empty() {
        String::new()
    } else {
        format!(" {u}")
    }
}

/// A number as a user would write it: plain from 1e-3 up to 1e6,
/// scientific outside (`5e-324`, `1e7`, `1e300`), exact in both (shortest
/// round-trip digits).
pub fn show(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || !a.is_finite() || (1e-3..1e6).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Every limit of the case file itself (the formulations declare theirs in
/// their [`super::settings::TableSpec`]).
pub const CASE_LIMITS: &[Limit] = &[
    DURATION,
    OUTPUT_INTERVAL,
    OUTPUTS,
    STEPS,
    STEP,
    CORIOLIS,
    FLUID_DENSITY,
    DRAG,
    FLUID_SPEED,
    SERIES_TIME,
    VELOCITY_GRADIENT,
    FIELD_SCALE,
    VORTEX_RADIUS,
    GRID_VALUES,
    RESTITUTION,
    FRICTION,
    CONTACT_DISTANCE,
    CRUSHING_STRENGTH,
    CRUSHING_P0,
    CRUSHING_EXPONENT,
    COORDINATE,
    VERTICES,
    RADIUS,
    THICKNESS,
    DENSITY,
    SPEED,
    ANGULAR_VELOCITY,
    FLOES,
    CONCENTRATION,
    ROUGHNESS,
    TOLERANCE,
    FILE_BYTES,
    RUN_BYTES,
    fracture::TOUGHNESS,
    fracture::MIN_AREA,
    fracture::WINDOW,
    fracture::MOHR_Q,
    fracture::MOHR_SIGMA_C,
    fracture::MOHR_SIGMA_11,
    fracture::HIBLER_P_STAR,
    fracture::HIBLER_C,
    fracture::CONCENTRATION,
    fracture::YOUNG,
    fracture::DAMPING,
    fracture::POISSON,
    fracture::SPACING,
    fracture::CRITICAL_STRAIN,
    fracture::STRENGTH,
    fracture::SEED,
];

/// Bytes a run keeps per output time and floe: the trajectory row (64 B)
/// and its line of `trajectory.csv` (8 numbers, about 190 B).
pub const BYTES_PER_ROW: f64 = 256.0;
/// Bytes a run keeps per output time besides the floes: the output time,
/// the energy sample (56 B) and its line of `energy.csv`.
pub const BYTES_PER_OUTPUT: f64 = 256.0;
/// Bytes per floe while a field is generated and a run holds its state
/// (seed, cell, polygons of up to 64 vertices, grids, contact structures).
pub const BYTES_PER_FLOE: f64 = 8192.0;

/// The number of intervals of `interval` (s) in `duration` (s), rounded
/// up: the outputs of a run, or the steps of a fixed step; `+∞` when it
/// overflows; at least 1.
pub fn output_count(duration: f64, interval: f64) -> f64 {
    (duration / interval).ceil().max(1.0)
}

/// An estimate of the memory a run of `floes` floes with `outputs` outputs
/// needs, bytes (the field generator's included): what the runner records
/// and writes grows as outputs × floes, the rest as floes.
pub fn run_memory_bytes(floes: f64, outputs: f64) -> f64 {
    (outputs + 1.0) * (BYTES_PER_ROW * floes + BYTES_PER_OUTPUT) + BYTES_PER_FLOE * floes
}

/// CPU seconds per floe per simulated second of the rough run-time
/// estimate [`rough_cpu_seconds`]: the rate of the default formulation
/// (event-driven) on a 100-floe channel driven by the wind (5e-5; the
/// 16-floe `cases/narrow_channel.toml` runs at 8e-6). A rough figure: it
/// is known before running only to within one or two orders of magnitude
/// (a jammed pack costs more per floe, free drift less), enough to tell
/// a run of minutes from one of days.
pub const ROUGH_CPU_PER_FLOE_SECOND: f64 = 5e-5;

/// The CPU time above which loading a case warns ([`rough_cpu_seconds`]),
/// s: one day.
pub const CPU_WARNING_SECONDS: f64 = 86_400.0;

/// A rough estimate of the CPU time of one run of `floes` floes over
/// `duration` (s) before it runs, s: `floes × duration ×`
/// [`ROUGH_CPU_PER_FLOE_SECOND`]. The run's own estimate (the progress
/// bar's, from its measured rate) is known only once it runs.
pub fn rough_cpu_seconds(floes: f64, duration: f64) -> f64 {
    floes * duration * ROUGH_CPU_PER_FLOE_SECOND
}

/// The refusal of an interval `h` (s: a step, or the output interval) that
/// gives more than `limit` (steps, outputs) over `duration` (s); `name` is
/// the key as messages show it.
pub fn check_count(limit: &Limit, name: &str, h: f64, duration: f64) -> Result<(), String> {
    let n = output_count(duration, h);
    if limit.admits(n) {
        Ok(())
    } else {
        let count = if n.is_finite() {
            show(n)
        } else {
            format!("more than {}", show(f64::MAX))
        };
        Err(format!(
            "{name} = {} s gives {count} {} over the duration of {} s, above the limit of {} {}: {}",
            show(h),
            limit.unit,
            show(duration),
            show(limit.max),
            limit.unit,
            limit.why
        ))
    }
}

/// A number of bytes for messages (`5.3 GB`).
pub fn show_bytes(b: f64) -> String {
    if b >= 1e9 {
        format!("{:.1} GB", b / 1e9)
    } else {
        format!("{:.0} MB", b / 1e6)
    }
}

#[cfg(test)]
mod tests;
