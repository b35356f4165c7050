//! The model: what a case file describes, checked and ready to simulate.
//!
//! A [`Scenario`] is immutable during a run. It holds the floes (rigid simple
//! polygons, convex or not, with exact mass properties), the fixed obstacles, the environment
//! (wind, current, Coriolis), the contact law and the settings of the
//! integrator and of each formulation. Loading and validation of case files
//! live in [`case`], the documented bounds of every number in [`limits`]; the
//! seeded random floe field in [`field`]; the gridded forcing read from CF
//! NetCDF files in [`netcdf`]; Siconos' 2D frictional contact problem files
//! in [`fc2d`]. The model imports only the foundations
//! ([`crate::geometry`], [`crate::rng`], [`crate::fsio`]).

pub mod case;
pub mod fc2d;
pub mod field;
pub mod forcing;
pub mod fracture;
pub mod limits;
pub mod netcdf;
pub mod settings;
pub mod source;

use crate::geometry::{area_properties, radius_about, Vec2};
use serde::Serialize;
use std::collections::BTreeMap;

pub use case::{load_case_with, parse_case_with, CaseError};
pub use forcing::{OutsideLog, VelocityField, VelocitySeries};
pub use fracture::{FloeHistory, FractureSettings};
pub use settings::{SettingsReader, SettingsTable, TableSpec};
pub use source::{CaseSource, CaseWarning};

/// Default ice density, kg/m³.
pub const DEFAULT_ICE_DENSITY: f64 = 917.0;

/// A rigid floe: a simple polygon (convex or not) with uniform thickness and
/// density.
#[derive(Debug, Clone, Serialize)]
pub struct Floe {
    /// Outline relative to the centre of mass at angle 0, counter-clockwise, m.
    pub shape: Vec<Vec2>,
    /// The convex parts of the outline, held rigidly together: each a
    /// counter-clockwise list of indices into `shape`
    /// ([`crate::geometry::decompose::convex_parts`]); one part `0..n` for a
    /// convex floe. Computed once, in the body frame.
    pub parts: Vec<Vec<usize>>,
    /// Centre of mass at t = 0, m.
    pub position: Vec2,
    /// Velocity of the centre of mass at t = 0, m/s.
    pub velocity: Vec2,
    /// Angular velocity at t = 0, rad/s.
    pub angular_velocity: f64,
    /// Orientation at t = 0, rad: the angle the outline `shape` is turned
    /// by. 0 for a floe of a case file and for a piece of a fracture (whose
    /// outline is its world outline at birth); an earlier run's angle for a
    /// run started from it ([`crate::state::restart`]), so that a restarted
    /// run's angles go on from the earlier run's and a restart of a restart
    /// finds its floes turned as they were.
    pub angle: f64,
    /// Thickness `h`, m.
    pub thickness: f64,
    /// Density `ρ_i`, kg/m³.
    pub density: f64,
    /// Area `|ω|`, m².
    pub area: f64,
    /// Mass `M = ρ_i h |ω|`, kg.
    pub mass: f64,
    /// Polar moment of inertia about the centre of mass, kg·m².
    pub inertia: f64,
    /// Polar second moment of area about the centre of mass, `∫|x − G|²`, m⁴.
    pub area_moment: f64,
    /// Largest distance from the centre of mass to a vertex, m.
    pub radius: f64,
    /// Where the floe comes from in the case file (for messages; a piece
    /// keeps its first ancestor's).
    pub origin: FloeOrigin,
    /// Stable id: the index in the case (listed floes first, then each
    /// field's) for the initial floes; the next free id for each piece of a
    /// fracture (docs/physics.md §9). It is the `floe` column of
    /// `trajectory.csv`.
    pub id: usize,
    /// The floe this one is a piece of (`None` for the initial floes).
    pub parent: Option<usize>,
    /// When the floe began, s (0 for the initial floes, the fracture's time
    /// for a piece).
    pub t_birth: f64,
    /// The orientation of its body frame at birth, rad: the angle its
    /// first ancestor had turned by then (0 for the initial floes), so that
    /// `theta_birth + θ(t)` is its orientation against its first ancestor's
    /// at t = 0.
    pub theta_birth: f64,
}

/// Where a floe was declared.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum FloeOrigin {
    /// The n-th `[[floe]]` table (from 0).
    Listed(usize),
    /// Floe `index` (from 0) of the `field`-th `[[field]]` table.
    Field {
        /// Which `[[field]]` table, from 0.
        field: usize,
        /// Which floe of that field, from 0.
        index: usize,
    },
}

impl FloeOrigin {
    /// `[[floe]] #k` or `[[field]] #f floe i`, as messages name a floe.
    pub fn label(&self) -> String {
        match self {
            FloeOrigin::Listed(k) => format!("[[floe]] #{k}"),
            FloeOrigin::Field { field, index } => format!("[[field]] #{field} floe {index}"),
        }
    }
}

impl Floe {
    /// Builds a floe from its world outline at t = 0 (validated simple, CCW,
    /// by [`crate::geometry::check_simple_ccw`]).
    pub fn from_world_polygon(
        polygon: &[Vec2],
        thickness: f64,
        density: f64,
        velocity: Vec2,
        angular_velocity: f64,
        origin: FloeOrigin,
    ) -> Floe {
        let props = area_properties(polygon);
        let shape: Vec<Vec2> = polygon.iter().map(|p| p - props.centroid).collect();
        let surface_density = density * thickness;
        Floe {
            radius: radius_about(&shape, &Vec2::zeros()),
            parts: parts_of(polygon),
            shape,
            position: props.centroid,
            velocity,
            angular_velocity,
            angle: 0.0,
            thickness,
            density,
            area: props.area,
            mass: surface_density * props.area,
            inertia: surface_density * props.polar_moment,
            area_moment: props.polar_moment,
            origin,
            id: 0,
            parent: None,
            t_birth: 0.0,
            theta_birth: 0.0,
        }
    }

    /// Whether the floe is a single convex part.
    pub fn is_convex(&self) -> bool {
        self.parts.len() == 1
    }

    /// The outline in world coordinates for a centre `g` and angle `theta`.
    pub fn world_polygon(&self, g: &Vec2, theta: f64, out: &mut Vec<Vec2>) {
        crate::geometry::place(&self.shape, g, theta, out);
    }

    /// Kinetic energy `½ M |v|² + ½ I ω²` at velocity `v` (m/s) and angular
    /// velocity `omega` (rad/s), J: the one formula of the project.
    pub fn kinetic_energy(&self, v: &Vec2, omega: f64) -> f64 {
        0.5 * self.mass * v.norm_squared() + 0.5 * self.inertia * omega * omega
    }

    /// Mass per unit area `ρ_i h`, kg/m².
    pub fn surface_density(&self) -> f64 {
        self.density * self.thickness
    }

    /// The equal-area diameter `2·sqrt(A/π)`, m: the diameter of the disc
    /// of the floe's area.
    pub fn diameter(&self) -> f64 {
        2.0 * (self.area / std::f64::consts::PI).sqrt()
    }
}

/// The convex parts of a validated outline
/// ([`crate::geometry::decompose::convex_parts`]). The case validation
/// refuses an outline that cannot be split, so the fallback (the outline as
/// one part) is never taken on a loaded case.
pub fn parts_of(polygon: &[Vec2]) -> Vec<Vec<usize>> {
    crate::geometry::decompose::convex_parts(polygon)
        .unwrap_or_else(|| vec![(0..polygon.len()).collect()])
}

/// A fixed obstacle (coast, island, wall): infinite mass, never moves.
#[derive(Debug, Clone, Serialize)]
pub struct Obstacle {
    /// Outline in world coordinates, counter-clockwise, m.
    pub polygon: Vec<Vec2>,
    /// Its convex parts, as for [`Floe::parts`].
    pub parts: Vec<Vec<usize>>,
}

impl Obstacle {
    /// An obstacle of the validated simple counter-clockwise outline
    /// `polygon` (m), split into its convex parts.
    pub fn new(polygon: Vec<Vec2>) -> Obstacle {
        Obstacle {
            parts: parts_of(&polygon),
            polygon,
        }
    }

    /// Whether the obstacle is a single convex part.
    pub fn is_convex(&self) -> bool {
        self.parts.len() == 1
    }
}

/// A fluid (air or water) acting on the floes by quadratic drag.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Fluid {
    /// Density, kg/m³ (default 0: no drag).
    pub density: f64,
    /// Dimensionless drag coefficient (default 0).
    pub drag: f64,
    /// Fluid velocity `u(x, y, t)`, m/s ([`forcing`]).
    pub velocity: VelocityField,
}

impl Fluid {
    /// A fluid that exerts no force.
    pub fn none() -> Fluid {
        Fluid {
            density: 0.0,
            drag: 0.0,
            velocity: VelocityField::constant(Vec2::zeros()),
        }
    }

    /// `ρ C`, kg/m³: the drag factor of `τ = ρ C |U| U`.
    pub fn drag_factor(&self) -> f64 {
        self.density * self.drag
    }
}

/// The environment of docs/physics.md §2.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Environment {
    /// Coriolis parameter `f`, s⁻¹ (default 0).
    pub coriolis: f64,
    /// Air: drag on the surface from the absolute wind `U_a`.
    pub air: Fluid,
    /// Water: drag from the relative velocity `U_w − Ṗ` at each point.
    pub water: Fluid,
    /// The first point outside a field's extent that the fields of this
    /// environment were evaluated at: a run's log, not case data (not
    /// serialised, always equal); the runner takes it after each output
    /// interval (docs/physics.md §2.4).
    #[serde(skip)]
    pub outside: OutsideLog,
}

impl Default for Environment {
    fn default() -> Self {
        Environment {
            coriolis: 0.0,
            air: Fluid::none(),
            water: Fluid::none(),
            outside: OutsideLog::default(),
        }
    }
}

/// The contact law shared by every pair.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ContactLaw {
    /// Restitution coefficient `e` in [0, 1].
    pub restitution: f64,
    /// Friction coefficient `μ` ≥ 0.
    pub friction: f64,
    /// Contact distance, m; 0 lets each formulation choose its own.
    pub distance: f64,
    /// The ice's crushing law (`[contact] crushing`); `None` (the default):
    /// rigid contacts that carry any force (docs/physics.md §10).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub crushing: Option<Crushing>,
}

/// The compressive failure of ice at a contact (`[contact] crushing`,
/// docs/physics.md §10): the normal force a contact carries is bounded by
/// `p(A)·A`, `A = h × w` (m²) the crushed face's area, `h` the thinner
/// floe's thickness and `w` the contact's width (m). Coasts do not crush;
/// the ice crushes against them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case", tag = "law")]
pub enum Crushing {
    /// A constant crushing pressure `σ_c` (Pa): `F_max = σ_c h w`.
    Strength {
        /// `σ_c`, Pa (sea ice: 0.5–5 MPa).
        strength: f64,
    },
    /// The pressure–area law `p = P0 A^ex` (Hopkins 1992; ISO 19906):
    /// `F_max = P0 A^(1+ex)`.
    PressureArea {
        /// `P0`, Pa at `A` = 1 m².
        p0: f64,
        /// `ex` in [−1, 0].
        exponent: f64,
    },
}

impl Crushing {
    /// The largest normal force (N) of a crushed face of thickness `h` (m)
    /// and width `w` (m); 0 for a face without area (a corner), except for
    /// `ex = −1`, whose force `P0` does not depend on the area.
    pub fn max_force(&self, h: f64, w: f64) -> f64 {
        let area = (h * w).max(0.0);
        match *self {
            Crushing::Strength { strength } => strength * area,
            Crushing::PressureArea { p0, exponent } => p0 * area.powf(1.0 + exponent),
        }
    }

    /// The pressure (Pa) on a face of area `area` (m²).
    pub fn pressure(&self, area: f64) -> f64 {
        match *self {
            Crushing::Strength { strength } => strength,
            Crushing::PressureArea { p0, exponent } => p0 * area.powf(exponent),
        }
    }
}

/// Which smooth integrator advances the floes between impacts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum IntegratorKind {
    /// Adaptive Dormand–Prince 5(4): exact for constant forces; the default.
    Dopri5,
    /// Explicit Euler as in Rabatel's report, step bounded by the drag stability limit.
    Euler,
}

impl std::str::FromStr for IntegratorKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "dopri5" => Ok(IntegratorKind::Dopri5),
            "euler" => Ok(IntegratorKind::Euler),
            other => Err(format!(
                "unknown integrator `{other}`; expected `dopri5` or `euler`"
            )),
        }
    }
}

/// Settings of the smooth integrator (`[integrator]` table, optional).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct IntegratorSettings {
    /// Method (default `dopri5`).
    pub method: IntegratorKind,
    /// Relative tolerance of the adaptive method (default 1e-10).
    pub tolerance: f64,
    /// Largest step, s. Default: none for `dopri5`; for `euler` the drag
    /// stability bound of docs/physics.md §4.2 (and the output interval).
    pub max_step: Option<f64>,
}

impl Default for IntegratorSettings {
    fn default() -> Self {
        IntegratorSettings {
            method: IntegratorKind::Dopri5,
            tolerance: 1e-10,
            max_step: None,
        }
    }
}

/// What a body id names: bodies are numbered floes first (in the
/// scenario's order), then obstacles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Body {
    /// Floe `k` (`scn.floes[k]`).
    Floe(usize),
    /// Obstacle `k` (`scn.obstacles[k]`): fixed, infinite mass.
    Obstacle(usize),
}

/// A validated scenario: everything a formulation needs, immutable during a run.
#[derive(Debug, Clone, Serialize)]
pub struct Scenario {
    /// Case name, `[a-z0-9_]+`.
    pub name: String,
    /// One-line description.
    pub description: String,
    /// Simulated time, s.
    pub duration: f64,
    /// Trajectory sampling interval, s.
    pub output_interval: f64,
    /// Wind, current, Coriolis.
    pub environment: Environment,
    /// Restitution, friction, contact distance.
    pub contact: ContactLaw,
    /// The floes: the listed ones first, then each field's in order.
    pub floes: Vec<Floe>,
    /// Fixed obstacles.
    pub obstacles: Vec<Obstacle>,
    /// The smooth integrator.
    pub integrator: IntegratorSettings,
    /// The `[formulation.<name>]` tables as written (validated by their
    /// owners at load), by name.
    pub formulation_settings: BTreeMap<String, SettingsTable>,
    /// Where the initial state comes from when it is not the case file's:
    /// the state of an earlier run (`floebench run --from`, see
    /// [`crate::state::restart`]).
    pub restart: Option<Restart>,
    /// The `[fracture]` table (absent: no fracture, docs/physics.md §9).
    pub fracture: FractureSettings,
    /// The floes that ended and the fractures so far. Empty for a case as
    /// loaded; during a run the floe set `floes` changes only by a fracture
    /// ([`crate::fracture::apply_split`]), which records here what it did.
    pub history: FloeHistory,
    /// The case file, the lines of its keys and floes, and the warnings
    /// found while loading it (empty for a scenario not read from a file;
    /// not case data: not serialised).
    #[serde(skip)]
    pub source: CaseSource,
}

/// The earlier run a scenario starts from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Restart {
    /// The trajectory file read.
    pub file: std::path::PathBuf,
    /// The output time of that file whose state is the initial state, s
    /// (the new run's time starts again at 0).
    pub t: f64,
}

impl Scenario {
    /// What body id `i` names (floes first, then obstacles).
    pub fn body(&self, i: usize) -> Body {
        let n = self.floes.len();
        if i < n {
            Body::Floe(i)
        } else {
            Body::Obstacle(i - n)
        }
    }

    /// The `[formulation.<name>]` table of the case (empty when the case
    /// does not write it).
    pub fn settings_table(&self, name: &str) -> SettingsTable {
        self.formulation_settings
            .get(name)
            .cloned()
            .unwrap_or_else(|| SettingsTable::empty(name))
    }

    /// Whether contacts cannot happen by construction: no obstacle and every
    /// floe at rest at t = 0 (only the environment moves them); the
    /// formulations that ignore contacts (`free-drift`) run only there.
    pub fn contact_free(&self) -> bool {
        self.obstacles.is_empty()
            && self
                .floes
                .iter()
                .all(|f| f.velocity.norm() == 0.0 && f.angular_velocity == 0.0)
    }

    /// The drag stability bound of explicit Euler for floe `i`, s
    /// (docs/physics.md §4.2, origin report eq. 3.6):
    /// `Δt_max = ρ_i h / (2 |U_a| sqrt(ρ_a C_a ρ_w C_w))` with the largest wind
    /// speed of the run (over the field's extent and time,
    /// [`VelocityField::max_speed`]). Without wind, the water-drag bound
    /// `ρ_i h / (2 ρ_w C_w V)` with `V` the largest current speed plus the
    /// floe's initial speed (edge and spin included); infinite without drag.
    pub fn euler_stability_bound(&self, i: usize) -> f64 {
        let floe = &self.floes[i];
        let env = &self.environment;
        let rho_h = floe.surface_density();
        let kw = env.water.drag_factor();
        if kw <= 0.0 {
            return f64::INFINITY;
        }
        let ka = env.air.drag_factor();
        let ua = env.air.velocity.max_speed();
        let v_air = if ka > 0.0 { ua * (ka / kw).sqrt() } else { 0.0 };
        let v_rest = env.water.velocity.max_speed()
            + floe.velocity.norm()
            + floe.angular_velocity.abs() * floe.radius;
        if !v_air.is_finite() {
            // ρ_a C_a / (ρ_w C_w) overflows (a negligible water drag): the
            // wind's bound in the form that does not, and the other one.
            let wind = rho_h / (2.0 * ua * ka.sqrt() * kw.sqrt());
            return wind.min(rho_h / (2.0 * kw * v_rest));
        }
        let v = v_air.max(v_rest);
        if v <= 0.0 {
            return f64::INFINITY;
        }
        rho_h / (2.0 * kw * v)
    }

    /// The median equal-area floe diameter `d_med`, m ([`Floe::diameter`];
    /// the mean of the two middle ones for an even count; 0 without
    /// floes): the one length scale of the report, the unit of every
    /// divergence between runs and of the chaos probe's perturbation
    /// (docs/output-format.md). The median, not the mean, so that one floe
    /// of another size (a floe written in the wrong units) does not set the
    /// scale of all the others.
    pub fn median_floe_diameter(&self) -> f64 {
        let mut d: Vec<f64> = self.floes.iter().map(Floe::diameter).collect();
        d.sort_by(f64::total_cmp);
        let n = d.len();
        match n {
            0 => 0.0,
            _ if n % 2 == 1 => d[n / 2],
            _ => 0.5 * (d[n / 2 - 1] + d[n / 2]),
        }
    }

    /// The smallest floe radius, m (infinite without floes).
    pub fn min_floe_radius(&self) -> f64 {
        self.floes
            .iter()
            .map(|f| f.radius)
            .fold(f64::INFINITY, f64::min)
    }

    /// The date of t = 0 (`YYYY-MM-DD hh:mm:ss`, UTC) when a gridded
    /// forcing gives one (the wind's first), for the time axis of
    /// `trajectory.nc`.
    pub fn start_date(&self) -> Option<String> {
        [&self.environment.air, &self.environment.water]
            .iter()
            .find_map(|f| match &f.velocity {
                VelocityField::Grid(g) => g.data.epoch,
                _ => None,
            })
            .map(netcdf::cf::format_date)
    }

    /// Times in (0, duration) where the wind or the current has a kink in
    /// time (series points, scale points, grid records), s.
    pub fn forcing_breakpoints(&self) -> Vec<f64> {
        let mut ts: Vec<f64> = self
            .environment
            .air
            .velocity
            .breakpoints()
            .into_iter()
            .chain(self.environment.water.velocity.breakpoints())
            .filter(|&t| t > 0.0 && t < self.duration)
            .collect();
        ts.sort_by(f64::total_cmp);
        ts.dedup();
        ts
    }
}
