//! The limits of the case file, table by table: one [`Limit`] per key,
//! re-exported by [`super`] (which gathers them in `CASE_LIMITS`).

#[cfg(doc)]
use super::run_memory_bytes;
use super::Limit;

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

/// `[contact] crushing = { strength }`, Pa.
pub const CRUSHING_STRENGTH: Limit = Limit::range(
    "crushing.strength",
    "[contact]",
    0.0,
    1e9,
    "Pa",
    "sea ice crushes at 0.5-5 MPa (Timco & Weeks 2010); 1 GPa is past any ice",
)
.exclusive_min();

/// `[contact] crushing = { p0, exponent }`: `P0`, Pa at an area of 1 m².
pub const CRUSHING_P0: Limit = Limit::range(
    "crushing.p0",
    "[contact]",
    0.0,
    1e9,
    "Pa",
    "P0 of the pressure-area curves is 1-10 MPa at 1 m^2 (ISO 19906, Hopkins 1992)",
)
.exclusive_min();

/// `[contact] crushing = { p0, exponent }`: the exponent of `p = P0 A^ex`.
pub const CRUSHING_EXPONENT: Limit = Limit::range(
    "crushing.exponent",
    "[contact]",
    -1.0,
    0.0,
    "",
    "pressure falls with area (ex <= 0) but force does not (ex >= -1); measured ex is about -0.5",
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
