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

// ---------------------------------------------------------------------------
// The limits of the case file, table by table.

/// `[case] duration`, s.
pub const DURATION: Limit = Limit::range(
    "duration",
    "[case]",
    0.0,
    1e8,
    "s",
    "about three years, longer than any sea-ice season a contact benchmark covers",
)
.exclusive_min();

/// `[case] output_interval`, s.
pub const OUTPUT_INTERVAL: Limit = Limit::range(
    "output_interval",
    "[case]",
    0.0,
    1e8,
    "s",
    "the duration limit: a longer interval keeps only the final state",
)
.exclusive_min();

/// The number of outputs `duration / output_interval`.
pub const OUTPUTS: Limit = Limit::range(
    "duration / output_interval",
    "[case]",
    1.0,
    1e6,
    "outputs",
    "a million samples per floe are more than any figure or metric reads, and each costs memory",
)
.integers();

/// The number of steps `duration / step` of a fixed-step formulation (and
/// `duration / max_step` of the integrator).
pub const STEPS: Limit = Limit::range(
    "duration / step",
    "[formulation.moreau], [formulation.rapier], [integrator] max_step",
    1.0,
    1e9,
    "steps",
    "a billion steps take hours of CPU even for one floe",
)
.integers();

/// A step of a fixed-step formulation or the integrator's largest step, s.
pub const STEP: Limit = Limit::range(
    "step",
    "[formulation.moreau], [formulation.rapier], [integrator] max_step",
    1e-6,
    1e4,
    "s",
    "floes change over milliseconds at the fastest; beyond about three hours a step spans the whole drag response",
);

/// `[environment] coriolis`, s⁻¹.
pub const CORIOLIS: Limit = Limit::magnitude(
    "coriolis",
    "[environment]",
    1.0,
    "s^-1",
    "Earth's largest is 1.46e-4 s^-1; rotating-tank experiments reach about 1 s^-1",
);

/// `density` of `air` and `water`, kg/m³.
pub const FLUID_DENSITY: Limit = Limit::range(
    "density",
    "[environment] air, water",
    0.0,
    1e4,
    "kg/m^3",
    "seawater is 1025 kg/m^3 and air 1.3 kg/m^3",
);

/// `drag` of `air` and `water`.
pub const DRAG: Limit = Limit::range(
    "drag",
    "[environment] air, water",
    0.0,
    1.0,
    "",
    "ice drag coefficients are 1e-3 to 1e-2; 1 is a bluff body's",
);

/// `velocity` of `air` and `water` and the velocities of a `series`, m/s.
pub const FLUID_SPEED: Limit = Limit::magnitude(
    "velocity",
    "[environment] air, water (and series)",
    100.0,
    "m/s",
    "above the strongest sustained winds (about 90 m/s); ocean currents are below 3 m/s",
);

/// The times of a `series`, s.
pub const SERIES_TIME: Limit = Limit::magnitude(
    "series time",
    "[environment] air, water",
    1e8,
    "s",
    "the duration limit: a later point is never reached",
);

/// Each component of a linear field's `gradient`, 1/s.
pub const VELOCITY_GRADIENT: Limit = Limit::magnitude(
    "gradient",
    "[environment] air, water (field = \"linear\")",
    1.0,
    "s^-1",
    "ocean and wind shears at floe scales are below about 1e-3 s^-1; 1 s^-1 is a laboratory flume's",
);

/// The factors of an analytic field's `scale` series.
pub const FIELD_SCALE: Limit = Limit::magnitude(
    "scale factor",
    "[environment] air, water (field = \"linear\", \"vortex\")",
    100.0,
    "",
    "a factor of the written field; the field's largest speed is also held to the fluid speed limit",
);

/// The core radius of a vortex, m.
pub const VORTEX_RADIUS: Limit = Limit::range(
    "radius",
    "[environment] air, water (field = \"vortex\")",
    1e-2,
    1e7,
    "m",
    "the floe radius limits: a core smaller than a centimetre is not resolved by any floe",
);

/// Values (nodes × records) of one component of a gridded field.
pub const GRID_VALUES: Limit = Limit::range(
    "grid values",
    "[environment] air, water (field = \"netcdf\")",
    1.0,
    2e7,
    "",
    "two components of 2e7 values take 320 MB; a regional ERA5 month at 0.25 degrees is about 1e6",
)
.integers();

/// `[contact] restitution`.
pub const RESTITUTION: Limit = Limit::range(
    "restitution",
    "[contact]",
    0.0,
    1.0,
    "",
    "Poisson's coefficient: 0 is plastic, 1 elastic, above 1 an impact would create energy",
);

/// `[contact] friction`.
pub const FRICTION: Limit = Limit::range(
    "friction",
    "[contact]",
    0.0,
    10.0,
    "",
    "ice-ice friction coefficients are 0.1 to 0.8; 10 already sticks at every contact",
);

/// `[contact] distance`, m.
pub const CONTACT_DISTANCE: Limit = Limit::range(
    "distance",
    "[contact]",
    0.0,
    1e3,
    "m",
    "a contact distance is a small fraction of a floe (0 lets the formulation choose)",
);

/// Every coordinate of a polygon and of a field's region, m.
pub const COORDINATE: Limit = Limit::magnitude(
    "polygon, region",
    "[[floe]], [[obstacle]], [[field]]",
    1e7,
    "m",
    "10,000 km: past it a plane is not the Earth; f64 still resolves 2e-9 m there",
);

/// Vertices of a polygon (listed, or a field's `sides`).
pub const VERTICES: Limit = Limit::range(
    "vertices",
    "[[floe]], [[obstacle]] polygon; [[field]] sides",
    3.0,
    64.0,
    "",
    "more sides do not change a floe's contacts but every contact test costs O(sides)",
)
.integers();

/// The circumradius of a polygon about its centroid (a field's `radius`), m.
pub const RADIUS: Limit = Limit::range(
    "radius",
    "[[floe]], [[obstacle]] polygon; [[field]] radius",
    1e-2,
    1e7,
    "m",
    "the contact tolerances are 1e-3 and 1e-4 of the smallest radius: at 1 cm they are still 500 floating-point spacings of a coordinate of 1e7 m",
);

/// Thickness of a floe, m.
pub const THICKNESS: Limit = Limit::range(
    "thickness",
    "[[floe]], [[field]]",
    1e-3,
    1e3,
    "m",
    "new ice is a few centimetres thick, icebergs a few hundred metres",
);

/// Density of a floe, kg/m³.
pub const DENSITY: Limit = Limit::range(
    "density",
    "[[floe]], [[field]]",
    1.0,
    1e4,
    "kg/m^3",
    "sea ice is 900 to 930 kg/m^3; lighter than air or denser than rock, a body is no floe",
);

/// Velocity of a floe, m/s.
pub const SPEED: Limit = Limit::magnitude(
    "velocity",
    "[[floe]], [[field]]",
    100.0,
    "m/s",
    "sea ice drifts below 1 m/s; 100 m/s is faster than any wind that drives it",
);

/// Angular velocity of a floe, rad/s.
pub const ANGULAR_VELOCITY: Limit = Limit::magnitude(
    "angular_velocity",
    "[[floe]]",
    10.0,
    "rad/s",
    "a turn in 0.6 s; floes turn in minutes to hours",
);

/// Floes of one `[[field]]` (`count`), and of the whole case.
pub const FLOES: Limit = Limit::range(
    "count",
    "[[field]]; and every floe of the case",
    1.0,
    1e5,
    "floes",
    "ten times the largest bundled field; its generation takes about a second and every run grows with the floes",
).integers();

/// `[[field]] concentration`.
pub const CONCENTRATION: Limit = Limit::range(
    "concentration",
    "[[field]]",
    0.0,
    0.9,
    "",
    "the tessellation's shrunk cells cannot cover more",
)
.exclusive_min();

/// `[[field]] roughness`: how deep each edge of a generated floe is notched
/// (a fraction of the distance from the floe's centroid to the edge's
/// midpoint). Up to one half: deeper notches leave thin arms that the
/// contact distance and the decomposition into convex parts resolve badly.
pub const ROUGHNESS: Limit = Limit::range(
    "roughness",
    "[[field]]",
    0.0,
    0.5,
    "",
    "deeper notches leave arms thinner than half the floe",
);

/// `[integrator] tolerance`.
pub const TOLERANCE: Limit = Limit::range(
    "tolerance",
    "[integrator]",
    1e-14,
    0.1,
    "",
    "above 10 % is no accuracy; below 1e-14 the error estimate is rounding (f64 epsilon is 2.2e-16)",
);

/// The size of a case file, bytes: read whole and parsed twice.
pub const FILE_BYTES: Limit = Limit::range(
    "file size",
    "the case file",
    0.0,
    6.4e7,
    "bytes",
    "64 MB is some 30,000 listed floes of 64 vertices; larger sets are what [[field]] is for",
)
.integers();

/// The memory a run may need, bytes ([`run_memory_bytes`]).
pub const RUN_BYTES: Limit = Limit::range(
    "estimated memory of a run",
    "the whole case",
    0.0,
    4e9,
    "bytes",
    "4 GB per run: compare runs one per core and keeps each formulation's run of a case",
)
.integers();

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
mod tests {
    use super::*;

    #[test]
    fn messages_name_the_value_the_bound_and_the_reason() {
        let m = THICKNESS.check("[[floe]] #0: thickness", 9e15).unwrap_err();
        assert!(
            m.starts_with("[[floe]] #0: thickness = 9e15 m is above the limit of 1000 m: new ice"),
            "{m}"
        );
        let m = THICKNESS.check("thickness", -1.0).unwrap_err();
        assert_eq!(m, "thickness = -1 m must be finite and >= 0.001 m");
        let m = THICKNESS.check("thickness", 1e-300).unwrap_err();
        assert_eq!(m, "thickness = 1e-300 m must be finite and >= 0.001 m");
        let m = FRICTION.check("friction", f64::NAN).unwrap_err();
        assert_eq!(m, "friction = NaN must be finite and >= 0");
        let m = CORIOLIS.check("coriolis", -3.0).unwrap_err();
        assert!(
            m.starts_with("coriolis = -3 s^-1 is below the limit of -1 s^-1"),
            "{m}"
        );
        let m = FLOES.check_integer("count", i64::MAX as i128).unwrap_err();
        assert!(
            m.starts_with("count = 9223372036854775807 is above the limit of 100000 floes"),
            "{m}"
        );
        let m = FLOES.check_integer("count", 0).unwrap_err();
        assert_eq!(m, "count = 0 must be >= 1");
        let m = DURATION.check("duration", f64::INFINITY).unwrap_err();
        assert_eq!(m, "duration = inf s must be finite and > 0");
        let m = SPEED.check_vector("velocity", [3e8, 0.0]).unwrap_err();
        assert!(
            m.starts_with(
                "velocity = [3e8, 0] m/s has a length of 3e8 m/s, above the limit of 100 m/s"
            ),
            "{m}"
        );
        assert!(CONCENTRATION.check("c", 0.0).is_err() && CONCENTRATION.check("c", 0.9).is_ok());
        assert_eq!(show(5e-324), "5e-324");
        assert_eq!(show(1e300), "1e300");
        assert_eq!(show(0.5), "0.5");
    }

    #[test]
    fn step_counts_are_bounded_through_the_duration() {
        assert!(check_count(&STEPS, "step", 1.0, 1e8).is_ok());
        let m = check_count(&STEPS, "step", 1e-6, 1e8).unwrap_err();
        assert!(m.contains("gives 1e14 steps"), "{m}");
        assert!(check_count(&OUTPUTS, "output_interval", 5e-324, 10.0).is_err());
    }
}
