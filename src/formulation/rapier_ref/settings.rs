//! The rapier reference's settings (`[formulation.rapier]`), resolved
//! against the case, its counters and constants (docs/physics.md §8).

use super::*;

/// `[formulation.rapier]`.
pub const TABLE: TableSpec = TableSpec {
    name: "rapier",
    validate: |t| RapierSettings::from_table(t).map(|_| ()),
    limits: &[
        STEP,
        ITERATIONS,
        NATURAL_FREQUENCY,
        DAMPING_RATIO,
        PREDICTION,
    ],
};

/// The bound of `iterations`.
pub const ITERATIONS: Limit = Limit::range(
    "iterations",
    "[formulation.rapier]",
    1.0,
    1000.0,
    "",
    "rapier's examples use up to a few dozen; 1000 substeps cost 250 times the default",
)
.integers();

/// The bound of `natural_frequency`, Hz.
pub const NATURAL_FREQUENCY: Limit = Limit::range(
    "natural_frequency",
    "[formulation.rapier]",
    1e-6,
    1e6,
    "Hz",
    "a contact spring from one cycle in 12 days to a megahertz, far past what any step resolves",
);

/// The bound of `damping_ratio`.
pub const DAMPING_RATIO: Limit = Limit::range(
    "damping_ratio",
    "[formulation.rapier]",
    1e-3,
    1e3,
    "",
    "from nearly undamped to a thousand times critical",
);

/// The bound of `prediction`, m.
pub const PREDICTION: Limit = Limit::range(
    "prediction",
    "[formulation.rapier]",
    0.0,
    1e3,
    "m",
    "a speculative contact distance is a fraction of a floe; 1 km already pairs most floes of a field",
).exclusive_min();

/// Settings of the rapier reference formulation (`[formulation.rapier]`).
///
/// They decide what "regularised" means for [`crate::formulation::rapier_ref`];
/// the defaults are chosen for floes (metres to kilometres, tonnes to
/// megatonnes, drift below 1 m/s, forcing time scales of minutes to hours),
/// not rapier's game defaults (1/60 s steps, 30 Hz contacts with damping
/// ratio 10, a 2 cm prediction distance): see
/// docs/results/2026-12-04-formulations-notes.md, "The rapier reference".
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RapierSettings {
    /// Time step `h`, s (default 0.1: a floe at 0.5 m/s moves 5 cm per step,
    /// 0.5 % of the smallest bundled floe).
    pub step: f64,
    /// Substeps (rapier's solver iterations) per step, `n` (default 4,
    /// rapier's default).
    pub iterations: usize,
    /// Contact softness: natural frequency of the spring that pushes a
    /// penetration out, Hz (default `n / (4h)`, a quarter of the substep
    /// rate: 10 Hz at the default step and substeps; a stiffer spring is not
    /// resolved by the substeps and only gives energy back to piles).
    pub natural_frequency: Option<f64>,
    /// Damping ratio of that spring (default 1: critically damped, the
    /// penetration is removed without overshoot; ice does not spring back,
    /// restitution is applied separately).
    pub damping_ratio: f64,
    /// Prediction distance, m: pairs closer than this get speculative
    /// contacts (default `h × 1 m/s`: an approach up to 1 m/s, twice the
    /// fastest drift, is stopped at contact instead of penetrating).
    pub prediction: Option<f64>,
}

impl RapierSettings {
    /// Speed (m/s) whose travel over one step is the default prediction distance.
    pub const DEFAULT_PREDICTION_SPEED: f64 = 1.0;
    /// The default natural frequency is this fraction of the substep rate `n/h`.
    pub const DEFAULT_FREQUENCY_FRACTION: f64 = 0.25;

    /// The natural frequency in use, Hz.
    pub fn natural_frequency(&self) -> f64 {
        self.natural_frequency
            .unwrap_or(Self::DEFAULT_FREQUENCY_FRACTION * self.iterations as f64 / self.step)
    }

    /// The prediction distance in use, m.
    pub fn prediction(&self) -> f64 {
        self.prediction
            .unwrap_or(Self::DEFAULT_PREDICTION_SPEED * self.step)
    }
}

impl Default for RapierSettings {
    fn default() -> Self {
        RapierSettings {
            step: 0.1,
            iterations: 4,
            natural_frequency: None,
            damping_ratio: 1.0,
            prediction: None,
        }
    }
}

impl RapierSettings {
    /// Parses `[formulation.rapier]` (errors name the line and key).
    pub fn from_table(t: &SettingsTable) -> Result<RapierSettings, CaseError> {
        let d = RapierSettings::default();
        let mut r = t.read();
        let s = RapierSettings {
            step: r.step(&STEP)?.unwrap_or(d.step),
            iterations: r.integer(&ITERATIONS)?.map_or(d.iterations, |n| n as usize),
            natural_frequency: r.bounded(&NATURAL_FREQUENCY)?,
            damping_ratio: r.bounded(&DAMPING_RATIO)?.unwrap_or(d.damping_ratio),
            prediction: r.bounded(&PREDICTION)?,
        };
        r.finish()?;
        Ok(s)
    }

    /// The settings of `scn`.
    pub fn of(scn: &Scenario) -> Result<RapierSettings, CaseError> {
        RapierSettings::from_table(&scn.settings_table(TABLE.name))
    }
}

/// Pairs with contacts seen by the solver, summed over steps.
pub const CONTACT_PAIR_STEPS: Counter = Counter::sum(
    "contact_pair_steps",
    "pairs with contacts seen by the solver (speculative ones included), summed over steps",
);
/// Most pairs with contacts in one step.
pub const MAX_CONTACT_PAIRS: Counter = Counter::value(
    "max_contact_pairs",
    Unit::Count,
    "most pairs with contacts in one step",
);
/// Kinetic energy given back by contacts, J.
pub const CONTACT_ENERGY_GAINED: Counter = Counter::value(
    "contact_energy_gained_j",
    Unit::Joule,
    "kinetic energy given back by contacts (steps in which contacts created energy)",
);
/// Sum of the integration defect of the substepped symplectic Euler, J.
pub const INTEGRATION_DEFECT: Counter = Counter::value(
    "integration_defect_j",
    Unit::Joule,
    "sum over steps of the integration defect of rapier's substepped symplectic Euler",
);

/// The counters of the formulation.
pub(super) const COUNTERS: &[&Counter] = &[&STEPS, &FORCE_EVALUATIONS, &CONTACT_PAIR_STEPS];

/// Largest speed at which rapier pushes a penetration out, m/s: twice the
/// fastest sea-ice drift (docs/physics.md §2: up to 0.5 m/s), instead of rapier's
/// game default of 3 length units per second.
pub const MAX_CORRECTIVE_VELOCITY: f64 = 1.0;

/// Collider user data of obstacles: obstacle `k` carries `OBSTACLE − k`
/// (floes carry their index).
pub(super) const OBSTACLE: u128 = u128::MAX;

/// The settings in use, with the case-dependent defaults resolved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resolved {
    /// Step `h`, s.
    pub step: f64,
    /// Substeps (rapier's solver iterations) per step.
    pub iterations: usize,
    /// Contact softness: natural frequency of the penetration spring, Hz.
    pub natural_frequency: f64,
    /// Damping ratio of that spring (dimensionless).
    pub damping_ratio: f64,
    /// Prediction (speculative contact) distance, m.
    pub prediction: f64,
    /// rapier's `length_unit`, m (the smallest floe radius).
    pub length_unit: f64,
}

impl Resolved {
    /// The settings of `scn` with their defaults resolved.
    pub fn of(scn: &Scenario) -> Result<Resolved, CaseError> {
        let s = RapierSettings::of(scn)?;
        let rmin = scn.min_floe_radius();
        let rmin = if rmin.is_finite() && rmin > 0.0 {
            rmin
        } else {
            1.0
        };
        Ok(Resolved {
            step: s.step,
            iterations: s.iterations,
            natural_frequency: s.natural_frequency(),
            damping_ratio: s.damping_ratio,
            prediction: s.prediction(),
            length_unit: rmin,
        })
    }

    /// rapier's integration parameters for these settings and a step `dt` (s).
    pub(super) fn integration_parameters(&self, dt: f64) -> IntegrationParameters {
        let softness = SpringCoefficients::new(self.natural_frequency, self.damping_ratio);
        let lu = self.length_unit;
        IntegrationParameters {
            dt,
            contact_softness: softness,
            static_contact_softness: softness,
            length_unit: lu,
            normalized_prediction_distance: self.prediction / lu,
            normalized_max_corrective_velocity: MAX_CORRECTIVE_VELOCITY / lu,
            normalized_max_linear_velocity: f64::MAX,
            num_solver_iterations: self.iterations,
            max_ccd_substeps: 0,
            contact_recycling: false,
            ..IntegrationParameters::default()
        }
    }
}
