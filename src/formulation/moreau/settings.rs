//! The Moreau–Jean formulations' settings (`[formulation.moreau]`, read by
//! `moreau` and `moreau-cone`), their counters and constants
//! (docs/physics.md §5).

use super::*;
use crate::formulation::{floe_length_scale, DEFAULT_PENETRATION_FRACTION};

/// `[formulation.moreau]`, read by both entries.
pub const TABLE: TableSpec = TableSpec {
    name: "moreau",
    validate: |t| MoreauSettings::from_table(t).map(|_| ()),
    limits: &[
        STEP,
        THETA,
        GAMMA,
        PREDICT_FROM,
        TOLERANCE,
        MAX_ITERATIONS,
        RELAXATION,
        PROJECTION_DEPTH,
    ],
};

/// The bound of `projection_depth`, m.
pub const PROJECTION_DEPTH: Limit = Limit::range(
    "projection_depth",
    "[formulation.moreau]",
    0.0,
    1e3,
    "m",
    "a penetration tolerated before the positions are projected: above 0 (a contact projected to a zero gap would leave its activation tolerance and rattle), at most a kilometre (a floe's size)",
)
.exclusive_min();

/// The bound of `predict_from`, unknowns (an LCP size).
pub const PREDICT_FROM: Limit = Limit::range(
    "predict_from",
    "[formulation.moreau]",
    1.0,
    1e9,
    "",
    "a contact LCP has at most 4 unknowns per contact; 1e9 unknowns would be a dense matrix of 8e18 bytes",
)
.integers();

/// The bound of `theta`.
pub const THETA: Limit = Limit::range(
    "theta",
    "[formulation.moreau]",
    0.0,
    1.0,
    "",
    "a weight of the θ-method: 0 explicit, 1 implicit",
);

/// The bound of `gamma`.
pub const GAMMA: Limit = Limit::range(
    "gamma",
    "[formulation.moreau]",
    0.0,
    1.0,
    "",
    "a weight of the predicted gap within the step",
);

/// Settings of the Moreau–Jean formulation (`[formulation.moreau]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoreauSettings {
    /// `step`: time step `h`, s (default 1.0: an upper bound, see the
    /// module doc).
    pub step: f64,
    /// `theta`: θ of the θ-method on the smooth forces and the positions, in
    /// [0, 1] (default 0.5: trapezoidal, exact for constant forces).
    pub theta: f64,
    /// `gamma`: γ of the predicted gap `g + h γ u_N` activating a contact, in
    /// [0, 1] (default 0.5, Acary & Brogliato's choice).
    pub gamma: f64,
    /// `solver`: the one-step contact solver, `"lcp"` (default: Lemke,
    /// exact Coulomb), `"cone"` (the convex relaxation, clarabel), `"nsgs"`
    /// or `"apgd"` (the iterative solvers, [`crate::iterative`]); the entry
    /// `moreau-cone` overrides it with `"cone"`.
    pub solver: SolverKind,
    /// `warm_start`: start each LCP from the basis of its contacts' last
    /// accepted solution (default [`DEFAULT_WARM_START`]: off, as it changes
    /// results at the rounding level; see [`ContactSolver::with_warm_start`]).
    pub warm_start: bool,
    /// `warm_lemke`: with the warm start on, when principal pivoting from
    /// the guessed basis is rejected, run Lemke's path from that basis
    /// before the cold attempts (default [`DEFAULT_WARM_LEMKE`]; see
    /// [`ContactSolver::with_warm_lemke`]). Without the warm start it does
    /// nothing.
    pub warm_lemke: bool,
    /// `predict_from`: LCPs of at least this many unknowns (and no
    /// warm-start guess) are solved from a basis predicted by block
    /// Gauss–Seidel (default [`DEFAULT_PREDICT_FROM`]: absent, off; see
    /// [`ContactSolver::with_predict_from`]).
    pub predict_from: Option<usize>,
    /// `merge_friction`: one friction resultant per flush edge pair (the
    /// contacts of one body pair whose tangential columns agree to
    /// [`crate::contact::problem::FRICTION_MERGE_TOLERANCE`]) in the LCPs,
    /// bounded by `μ` times the sum of their normal impulses (default
    /// [`DEFAULT_MERGE_FRICTION`]: on; see
    /// [`ContactSolver::with_merge_friction`] and docs/physics.md §3.1).
    /// The cone program keeps one cone per point either way.
    pub merge_friction: bool,
    /// `solver = "nsgs"` or `"apgd"`: the iterative solver and its
    /// `tolerance`, `max_iterations`, `relaxation` (default `None`: the
    /// direct `solver`; see [`crate::iterative`]). With it, `solver` above
    /// is `"lcp"` and unused.
    pub iterative: Option<IterativeOptions>,
    /// `projection`: after each step, project the positions so that no
    /// contact of the step stays penetrated deeper than `projection_depth`
    /// (docs/physics.md §5.1 step 5, Acary 2012's direct projection;
    /// default off: the classical scheme, whose positions are never
    /// projected).
    pub projection: bool,
    /// `projection_depth`: the penetration the projection leaves, m
    /// (default `None`: [`DEFAULT_PENETRATION_FRACTION`] of the smallest
    /// floe radius, the event-driven default penetration tolerance); only
    /// with `projection = true`.
    pub projection_depth: Option<f64>,
    /// `open_contacts`: what becomes of a detected contact whose predicted
    /// gap is open (default [`OpenContacts::Inactive`], the classical
    /// scheme; docs/physics.md §5.1 step 2).
    pub open_contacts: OpenContacts,
}

/// What a step does with a detected contact whose predicted gap
/// `g + h γ u_N⁻` is open (`[formulation.moreau] open_contacts`,
/// docs/physics.md §5.1 step 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OpenContacts {
    /// `"inactive"` (default): left out of the step's contact problem, the
    /// classical index set of Acary & Brogliato (2008, ch. 10). The
    /// impulses of the step's other contacts can close it unopposed.
    Inactive,
    /// `"gap"`: kept in the problem with the linearised non-penetration
    /// constraint of Stewart & Trinkle (1996) and Anitescu & Potra (1997),
    /// `g + h ((1 − θ) u_N⁻ + θ u_N⁺) ≥ 0`, relaxed to the pair's own
    /// approach speed: `u_N⁺ ≥ −max(c, −u_N⁻)`. It pushes only if the
    /// step's other impulses would close it faster than both; a pair that
    /// closes by its own approach strikes by Newton's law at the next step.
    Gap,
}

impl OpenContacts {
    /// The key's value in a case file.
    pub fn name(self) -> &'static str {
        match self {
            OpenContacts::Inactive => "inactive",
            OpenContacts::Gap => "gap",
        }
    }
}

impl std::str::FromStr for OpenContacts {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "inactive" => Ok(OpenContacts::Inactive),
            "gap" => Ok(OpenContacts::Gap),
            other => Err(format!(
                "unknown open_contacts `{other}`; expected `inactive` or `gap`"
            )),
        }
    }
}

impl Default for MoreauSettings {
    fn default() -> Self {
        MoreauSettings {
            step: 1.0,
            theta: 0.5,
            gamma: 0.5,
            solver: SolverKind::Lcp,
            warm_start: DEFAULT_WARM_START,
            warm_lemke: DEFAULT_WARM_LEMKE,
            predict_from: DEFAULT_PREDICT_FROM,
            merge_friction: DEFAULT_MERGE_FRICTION,
            iterative: None,
            projection: false,
            projection_depth: None,
            open_contacts: OpenContacts::Inactive,
        }
    }
}

impl MoreauSettings {
    /// Parses `[formulation.moreau]` (errors name the line and key).
    pub fn from_table(t: &SettingsTable) -> Result<MoreauSettings, CaseError> {
        let d = MoreauSettings::default();
        let mut r = t.read();
        let step = r.step(&STEP)?.unwrap_or(d.step);
        let theta = r.bounded(&THETA)?.unwrap_or(d.theta);
        let gamma = r.bounded(&GAMMA)?.unwrap_or(d.gamma);
        let (solver, iterative) = read_solver(&mut r, d.solver)?;
        let projection = r.boolean("projection")?.unwrap_or(d.projection);
        let projection_depth = r.bounded(&PROJECTION_DEPTH)?;
        if projection_depth.is_some() && !projection {
            return Err(r.error(
                PROJECTION_DEPTH.key,
                "projection_depth needs projection = true (the positions are otherwise never projected)",
            ));
        }
        let open_contacts = r
            .choice::<OpenContacts>("open_contacts")?
            .unwrap_or(d.open_contacts);
        if open_contacts == OpenContacts::Gap && theta == 0.0 {
            return Err(r.error(
                "open_contacts",
                "open_contacts = \"gap\" needs theta > 0 (with theta = 0 the positions do not use the step's new velocities, so no impulse can keep a gap open)",
            ));
        }
        let s = MoreauSettings {
            open_contacts,
            projection,
            projection_depth,
            step,
            theta,
            gamma,
            solver,
            iterative,
            warm_start: r.boolean("warm_start")?.unwrap_or(d.warm_start),
            warm_lemke: r.boolean("warm_lemke")?.unwrap_or(d.warm_lemke),
            merge_friction: r.boolean("merge_friction")?.unwrap_or(d.merge_friction),
            predict_from: r
                .integer(&PREDICT_FROM)?
                .map_or(d.predict_from, |k| usize::try_from(k).ok()),
        };
        r.finish()?;
        Ok(s)
    }

    /// The settings of `scn`.
    pub fn of(scn: &Scenario) -> Result<MoreauSettings, CaseError> {
        MoreauSettings::from_table(&scn.settings_table(TABLE.name))
    }

    /// The projection's depth on `scn`, m, or `None` without projection.
    pub fn projection_depth(&self, scn: &Scenario) -> Option<f64> {
        self.projection.then(|| {
            self.projection_depth
                .unwrap_or(DEFAULT_PENETRATION_FRACTION * floe_length_scale(scn))
        })
    }
}

/// Active contacts over every step.
pub const ACTIVE_CONTACTS: Counter =
    Counter::sum("active_contacts", "active contacts over every step");
/// Most active contacts in one step.
pub const ACTIVE_CONTACTS_MAX: Counter = Counter::max(
    "active_contacts_max",
    Unit::Count,
    "most active contacts in one step",
);
/// Contact groups over every step.
pub const CONTACT_GROUPS: Counter =
    Counter::sum("contact_groups", "connected contact groups over every step");
/// Group solves that increased the kinetic energy.
pub const CONTACT_ENERGY_INCREASES: Counter = Counter::sum(
    "contact_energy_increases",
    "group solves that increased the kinetic energy of the group",
);
/// Largest kinetic energy created by one group solve, J.
pub const CONTACT_ENERGY_INCREASE_MAX: Counter = Counter::max(
    "contact_energy_increase_max_j",
    Unit::Joule,
    "largest kinetic energy created by one group solve",
);
/// Open contacts entered in the contact problems (`open_contacts = "gap"`).
pub const OPEN_CONTACTS: Counter = Counter::sum(
    "open_contacts",
    "contacts whose predicted gap was open, entered in the step's problem with the linearised gap (open_contacts = \"gap\")",
);
/// Open contacts that pushed: the classical scheme would have let the
/// step's impulses close them.
pub const OPEN_CONTACTS_PUSHING: Counter = Counter::sum(
    "open_contacts_pushing",
    "open contacts that received a normal impulse: the step's velocities would have closed them (with open_contacts = \"inactive\" they are left out and penetrate)",
);
/// Steps in which contact impulses changed a velocity.
pub const STEPS_WITH_IMPULSES: Counter = Counter::sum(
    "steps_with_impulses",
    "steps in which contact impulses changed a velocity",
);

/// The counters of the formulation (the contact solver adds its own).
pub(super) const COUNTERS: &[&Counter] = &[
    &STEPS,
    &FORCE_EVALUATIONS,
    &ACTIVE_CONTACTS,
    &CONTACT_GROUPS,
    &CONTACT_ENERGY_INCREASES,
    &STEPS_WITH_IMPULSES,
    &ACTIVE_CONTACTS_MAX,
    &CONTACT_ENERGY_INCREASE_MAX,
    &MAX_PENETRATION,
];

/// The counters of the open contacts, kept only by runs that enter them
/// (`open_contacts = "gap"`).
pub(super) const OPEN_CONTACT_COUNTERS: &[&Counter] = &[&OPEN_CONTACTS, &OPEN_CONTACTS_PUSHING];

/// The projection's counters, kept only by runs that project
/// (`projection = true`).
pub(super) const PROJECTION_COUNTERS: &[&Counter] = &[
    &PROJECTIONS,
    &PROJECTIONS_UNCONVERGED,
    &PROJECTION_RESIDUAL_MAX,
    &PROJECTION_DEPTH_MAX,
    &PROJECTIONS_INCOMPLETE,
    &PROJECTION_LEFT_MAX,
];

/// Steps after which every detection–projection pass was used and a
/// contact was still deeper than `projection_depth`.
pub const PROJECTIONS_INCOMPLETE: Counter = Counter::sum(
    "projections_incomplete",
    "steps whose detection-projection passes ran out with a contact still deeper than projection_depth",
);
/// Deepest penetration left by a step whose passes ran out, m.
pub const PROJECTION_LEFT_MAX: Counter = Counter::max(
    "projection_left_max_m",
    Unit::Metre,
    "deepest penetration left after a step whose detection-projection passes ran out",
);

/// Group projections made.
pub const PROJECTIONS: Counter = Counter::sum(
    "projections",
    "groups whose positions were projected after a step ([formulation.moreau] projection, docs/physics.md §5.1 step 5)",
);
/// Group projections whose solve stopped above its tolerance.
pub const PROJECTIONS_UNCONVERGED: Counter = Counter::sum(
    "projections_unconverged",
    "group projections whose Gauss-Seidel solve stopped at max_iterations above its tolerance (the answer reached is applied)",
);
/// Largest residual of a projection's solve.
pub const PROJECTION_RESIDUAL_MAX: Counter = Counter::max(
    "projection_residual_max",
    Unit::Dimensionless,
    "largest relative natural-map residual of a projection's solve",
);
/// Deepest predicted penetration a projection removed, m.
pub const PROJECTION_DEPTH_MAX: Counter = Counter::max(
    "projection_depth_max_m",
    Unit::Metre,
    "deepest penetration predicted at the end of a step, before its projection",
);

/// Rounding allowance of the activation test `g + h γ u_N ≤ ε`, as a
/// fraction of the smallest floe radius. Without it a resting contact whose
/// predicted gap is `+1e-20` m (rounding in the split of the impulse between
/// two contact points) is dropped, the floe pivots on the other point and
/// the rocking grows: measured on `sliding_floe`, 0.26 m of penetration
/// after 1000 steps with ε = 0.
pub const ACTIVATION_TOLERANCE_FRACTION: f64 = 1e-9;

/// A velocity change below this fraction of the group's largest free
/// velocity component does not make a step a contact step in
/// [`Moreau::contact_steps`] (it is still applied): the cone's interior
/// point is never exactly zero.
pub(super) const NEGLIGIBLE_VELOCITY_FRACTION: f64 = 1e-9;

/// Keeps at most this many contact-step records.
pub(super) const MAX_RECORDS: usize = 100_000;
