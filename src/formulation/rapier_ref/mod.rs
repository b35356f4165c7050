//! rapier as the regularised reference formulation (docs/physics.md §8).
//!
//! The widely used Rust physics engine [rapier] (`rapier2d-f64` 0.36.1, on
//! parry2d-f64 0.31) runs the same case files as the nonsmooth schemes, so
//! that researchers can see what a soft-constraint engine gives against them.
//!
//! # Mapping of a scenario onto rapier
//!
//! - Each floe is a dynamic rigid body whose origin is the floe's centre of
//!   mass, with one convex polygon collider (the floe's outline about the
//!   centre of mass, taken as it is: no convex hull); a non-convex floe has
//!   one compound collider of its convex parts ([`crate::geometry::decompose`],
//!   built in `convert.rs`). The collider carries the
//!   floe's own mass `M` and polar inertia `I` about the centre of mass (its
//!   density is not used), so rapier integrates the same bodies as the other
//!   formulations. Sleeping is disabled, linear and angular damping are zero,
//!   and rapier's angular speed cap is lifted (`allow_fast_rotation`).
//! - Each obstacle is a fixed body with one convex polygon collider in world
//!   coordinates (a compound of its convex parts when it is not convex).
//! - No gravity. The environment forces (docs/physics.md §2) are computed
//!   by the project's one force law, [`ForceModel::forces`] (Dunavant
//!   quadrature of the water drag), from the state at the start of each step,
//!   and given to rapier with `add_force`/`add_torque` after clearing the
//!   previous step's (rapier keeps user forces until they are reset). They
//!   are held constant over the step and its substeps: an explicit,
//!   first-order treatment of the drag, so a free-drift trajectory differs
//!   from the project's integrator by `O(h)`.
//! - Every collider has the case's restitution `e` and friction `μ` with the
//!   combine rule `Max`: the pair's coefficient is `max(e, e) = e`, exactly
//!   the case's value, whatever pair touches.
//! - rapier's continuous collision detection is turned off
//!   (`max_ccd_substeps = 0`): its motion clamping drops part of a step's
//!   motion, which would break the trajectory and the energy ledger. The
//!   speculative contacts within the prediction distance (below) stop
//!   approaching bodies instead.
//! - rapier's linear velocity cap is lifted (`Real::MAX`); contact recycling
//!   is off, so every contact is recomputed at every step (its `dist` is
//!   never stale).
//!
//! # The scheme (as far as rapier documents it)
//!
//! One call to `PhysicsPipeline::step(dt)` is one step `h`:
//!
//! 1. collision detection at the poses at the start of the step: broad phase
//!    (a BVH), then contact manifolds (at most 2 points in 2D) for every pair
//!    closer than the prediction distance; separated points within it are
//!    *speculative* contacts;
//! 2. the TGS-soft solver ("temporal Gauss–Seidel with soft constraints",
//!    after Catto's *Solver2D*, 2024): the step is cut into `iterations`
//!    substeps `h/n`; each substep adds the external impulse `F h/n` to the
//!    velocities, runs one projected Gauss–Seidel sweep on the contacts with
//!    a soft penetration bias (a damped spring of natural frequency
//!    `natural_frequency` and damping ratio `damping_ratio`), integrates the
//!    positions with those velocities (symplectic Euler), then runs one rigid
//!    sweep without bias ("relax"). Friction is solved in the relax sweep
//!    only. A speculative contact lets the bodies close their gap within the
//!    substep but not more;
//! 3. after the last substep, restitution (Box2D style): every contact that
//!    is *new* (it carried no impulse at the previous step) and was
//!    approaching at the start of the step has its normal velocity driven to
//!    `−e` times that approach velocity. A contact that persists from one step
//!    to the next never bounces: this is how rapier reaches the accumulation
//!    point of a bouncing body;
//! 4. the contact impulses are stored and warm-start the next step.
//!
//! # Parameters (`[formulation.rapier]`)
//!
//! | key | unit | default | meaning |
//! | --- | --- | --- | --- |
//! | `step` | s | 0.1 | step `h`, on the grid `t_k = k h` from t = 0; a case whose `output_interval` or `duration` is not a multiple of it is refused (the scheme reports only states of its grid) |
//! | `iterations` | – | 4 | substeps `n` (rapier's solver iterations) per step |
//! | `natural_frequency` | Hz | `n/(4h)` = 10 | contact softness: frequency of the spring that pushes penetration out (a quarter of the substep rate) |
//! | `damping_ratio` | – | 1 | its damping ratio (critical: no overshoot) |
//! | `prediction` | m | `h` × 1 m/s = 0.1 | speculative contact distance: approaches up to 1 m/s stop at contact |
//!
//! Why these and not rapier's game defaults (1/60 s, 30 Hz with ratio 10,
//! 2 cm): see [`RapierSettings`] and docs/results/2026-12-04-formulations-notes.md ("The rapier
//! reference").
//!
//! Derived, not settable: rapier's `length_unit` is the smallest floe
//! radius (it scales rapier's internal tolerances, e.g. the broad phase's
//! fat-AABB margin `0.04 length_unit`); the largest speed at which a
//! penetration is pushed out is [`MAX_CORRECTIVE_VELOCITY`]; fixed bodies
//! get the same softness as floe–floe contacts (rapier's default would make
//! them twice as stiff).
//!
//! # Energy ledger
//!
//! Per step of length `h`, with the forces `F` (torque `τ`) from the start
//! state, the displacement `ΔG` and rotation `Δθ` over the step, and the
//! kinetic energies `E₀`, `E₁` at its start and end:
//!
//! - work of each environment force: `W = F · ΔG + τ Δθ` (the exact work of a
//!   force held constant along the actual path), split into air, water and
//!   Coriolis;
//! - contact dissipation: `D += E₀ + W − E₁`, summed over the floes that
//!   belong to a pair with contacts seen by the solver during the step
//!   (speculative ones included). For the other floes, `E₀ + W − E₁` is the
//!   kinetic-energy defect of rapier's substepped symplectic Euler under a
//!   constant force, `δ = h² (|F|²/M + τ²/I) / (2n)` over `n` substeps (plus
//!   the effect of rapier's linearised rotation, `atan(ω h/n)` per substep),
//!   and it is left in the ledger's residual `E − E₀ − W + D`, which is then
//!   `−Σδ`: the integration error, as for the other formulations. Free flight
//!   gives `D = 0` exactly; `Σδ` is reported as `integration_defect_j`.
//!
//! The dissipation is therefore measured from kinetic energy and work, not
//! from rapier's contact impulses (accumulated over substeps with a soft
//! bias, their power is not available per substep). Steps where contacts
//! *gave* energy (`D` decreasing) are summed in the counter
//! `contact_energy_gained_j`.
//!
//! # Counters and CPU time
//!
//! `steps`, `contact_pair_steps` (sum over steps of the pairs with contacts
//! seen by the solver, speculative ones included), `max_contact_pairs`,
//! `max_penetration_m` (the most negative manifold `dist`, i.e. at the
//! start of each step, as rapier's narrow phase saw it), `force_evaluations`,
//! and the settings in use. rapier's `step` is one call: its CPU time
//! (thread CPU time) is split between the stages in the proportions of
//! rapier's own stage timers (crate feature `profiler`, wall clock):
//! collision detection → `detection`, island construction, constraint
//! collection and solver → `solve`, the rest (user changes, position
//! update) → `integration`. The evaluation of the environment forces is
//! charged to `integration`.
//!
//! # References
//!
//! - S. Crozet et al., rapier, <https://rapier.rs> (user guide, "Integration
//!   parameters", "Rigid-body forces"), crate `rapier2d-f64` 0.36.1.
//! - E. Catto (2024), *Solver2D*, <https://box2d.org/posts/2024/02/solver2d/>
//!   (soft step, substepping, relax iterations, restitution after the solve).
//! - M. Macklin et al. (2019), *Small steps in physics simulation*, SCA '19
//!   (substepping).
//!
//! [rapier]: https://rapier.rs

mod convert;

use super::{
    check_output_grid, Context, Entry, FixedGrid, Formulation, FormulationError,
    FormulationOptions, NotClaimed,
};
use crate::contact::Load;
use crate::model::limits::{Limit, STEP};
use crate::model::{CaseError, Scenario, SettingsTable, TableSpec};
use crate::physics::{ForceModel, Forces};
use crate::record::counters::common::{FORCE_EVALUATIONS, MAX_PENETRATION, STEPS};
use crate::record::{
    ContactEvent, ContactLog, Counter, Counters, ImpulseRecord, Settings, Stage, Unit,
};
use crate::state::{BodyState, System};
use rapier2d_f64::prelude::{
    BroadPhaseBvh, CCDSolver, CoefficientCombineRule, ColliderBuilder, ColliderSet,
    ImpulseJointSet, IntegrationParameters, IslandManager, MultibodyJointSet, NarrowPhase,
    PhysicsPipeline, RigidBodyBuilder, RigidBodyHandle, RigidBodySet, SoftBodySet,
    SpringCoefficients,
};

/// The registry entry (see [`crate::formulation::REGISTRY`]).
pub const ENTRY: Entry = Entry {
    name: "rapier",
    description: "rapier2d-f64 0.36: soft contacts (TGS-soft, substeps), restitution on new contacts only; the regularised reference",
    build: |scn, opts| Ok(Box::new(RapierReference::new(scn, opts)?)),
    settings: Some(TABLE),
    resolves_contacts: true,
    dumps_lcps: false,
    supports_fracture: true,
    not_claimed: &[
        NotClaimed {
            check: "ram_critical_speed",
            case: None,
            reason: "the step's impact impulse is not (1 + e) M v0: sequential restitution over the two-point manifold of the soft contact (as head_on_v1); on fracture_ram the critical speed it implies is 0.01622 m/s against 0.01557 m/s (+4.2 %)",
        },
        NotClaimed {
            check: "head_on_v1",
            case: None,
            reason: "restitution applied in one sequential Gauss-Seidel sweep over a two-point manifold: face-on rebound velocities are off, with a spin the set-up cannot produce",
        },
        NotClaimed {
            check: "head_on_v2",
            case: None,
            reason: "as head_on_v1: sequential restitution over a two-point manifold",
        },
        NotClaimed {
            check: "symmetry",
            case: None,
            reason: "sequential restitution over two-point manifolds gives face-on impacts a spin the set-up cannot produce, so mirror images drift apart",
        },
        NotClaimed {
            check: "coulomb",
            case: None,
            reason: "friction is solved in the relax sweeps against the normal impulse of the sweep; the step's accumulated impulses can leave the cone (some tangential impulses beside a zero normal one)",
        },
        NotClaimed {
            check: "bouncing_rest",
            case: None,
            reason: "the face-on floe rebounds short and rocks on its corners; once a rebound is about a h the contact persists, gets no restitution and sticks: it rests early",
        },
        NotClaimed {
            check: "energy_conserved",
            case: None,
            reason: "restitution only on new contacts and soft (spring) contacts: e = 1 collisions lose or gain energy",
        },
        NotClaimed {
            check: "impact_energy",
            case: None,
            reason: "soft contacts push penetrations out with a spring and give energy back (touching rows, pools, piles)",
        },
        NotClaimed {
            check: "penetration",
            case: None,
            reason: "soft contacts penetrate by design (a resting floe sits a/(2 pi f)^2 into the wall; colliding floes overlap)",
        },
        NotClaimed {
            check: "cradle_outcome",
            case: None,
            reason: "neither the sequential nor the simultaneous answer: soft contacts and sequential restitution spread the momentum over the row",
        },
        NotClaimed {
            check: "cradle_physical",
            case: None,
            reason: "as cradle_outcome",
        },
        NotClaimed {
            check: "cannon_velocities",
            case: None,
            reason: "face-on impacts with restitution miss the head-on law (two-point manifolds, sequential restitution)",
        },
        NotClaimed {
            check: "energy_ledger",
            case: None,
            reason: "the residual is minus the sum of rapier's integration defect h^2 |F|^2 / (2 n M) per step (first order in h), not a 1e-10 integration",
        },
    ],
};

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
const COUNTERS: &[&Counter] = &[&STEPS, &FORCE_EVALUATIONS, &CONTACT_PAIR_STEPS];

/// Largest speed at which rapier pushes a penetration out, m/s: twice the
/// fastest sea-ice drift (docs/physics.md §2: up to 0.5 m/s), instead of rapier's
/// game default of 3 length units per second.
pub const MAX_CORRECTIVE_VELOCITY: f64 = 1.0;

/// Collider user data of obstacles (floes carry their index).
const OBSTACLE: u128 = u128::MAX;

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
    fn integration_parameters(&self, dt: f64) -> IntegrationParameters {
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

/// The contact material of every collider: the case's `e` and `μ` with
/// the `Max` combine rule (so every pair gets exactly them), no skin.
fn material(c: ColliderBuilder, e: f64, mu: f64) -> ColliderBuilder {
    c.restitution(e)
        .restitution_combine_rule(CoefficientCombineRule::Max)
        .friction(mu)
        .friction_combine_rule(CoefficientCombineRule::Max)
        .contact_skin(0.0)
}

/// Inserts floe `i` (at its position, angle 0, its velocity) as a dynamic
/// body with its convex collider carrying the floe's own mass and inertia;
/// restitution `e`, friction `mu`.
fn insert_floe(
    bodies: &mut RigidBodySet,
    colliders: &mut ColliderSet,
    floe: &crate::model::Floe,
    i: usize,
    e: f64,
    mu: f64,
) -> Result<RigidBodyHandle, String> {
    let rb = convert::dynamic_body(&floe.position, 0.0, &floe.velocity, floe.angular_velocity)
        .can_sleep(false)
        .linear_damping(0.0)
        .angular_damping(0.0)
        .allow_fast_rotation(true)
        .build();
    let h = bodies.insert(rb);
    let collider = convert::polygon_collider(&floe.shape, &floe.parts)
        .ok_or_else(|| format!("rapier: floe {}: parry rejects its polygon", floe.id))?
        .mass_properties(convert::mass_properties(floe.mass, floe.inertia))
        .user_data(i as u128);
    colliders.insert_with_parent(material(collider, e, mu), h, bodies);
    Ok(h)
}

/// The rapier reference formulation.
pub struct RapierReference {
    settings: Resolved,
    params: IntegrationParameters,
    pipeline: PhysicsPipeline,
    islands: IslandManager,
    broad_phase: BroadPhaseBvh,
    narrow_phase: NarrowPhase,
    bodies: RigidBodySet,
    colliders: ColliderSet,
    impulse_joints: ImpulseJointSet,
    multibody_joints: MultibodyJointSet,
    soft_bodies: SoftBodySet,
    ccd: CCDSolver,
    /// One body per floe, in the scenario's order.
    handles: Vec<RigidBodyHandle>,
    /// The shared force law (quadratures).
    model: ForceModel,
    /// The state rapier holds, as last read or written (to detect a caller
    /// that changed the state between calls).
    synced: Vec<BodyState>,
    /// Rapier's rotation angle of each floe at the last read, rad in (−π, π].
    rapier_angle: Vec<f64>,
    forces: Vec<Forces>,
    /// Per floe, over the current step: `E₀ + W − E₁` (J) and the free-flight defect `δ` (J).
    balance: Vec<(f64, f64, f64)>,
    log: ContactLog,
    /// Per floe: whether it belonged to a pair with contacts seen by the
    /// solver (speculative ones included) during the current step.
    touched: Vec<bool>,
    /// Contact points with an impulse in the last step.
    step_points: usize,
    counters: Counters,
    max_penetration: f64,
    max_pairs: u64,
    energy_gained: f64,
    integration_defect: f64,
    /// The state on the step grid `t_k = k h` (rapier's bodies hold the
    /// same).
    grid: FixedGrid,
}

impl std::fmt::Debug for RapierReference {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RapierReference")
            .field("settings", &self.settings)
            .field("floes", &self.handles.len())
            .finish_non_exhaustive()
    }
}

impl RapierReference {
    /// Sets up rapier for `scn`. Fails if parry rejects a polygon.
    pub fn new(scn: &Scenario, _opts: &FormulationOptions) -> Result<RapierReference, String> {
        let settings = Resolved::of(scn).map_err(|e| e.to_string())?;
        check_output_grid(scn, ENTRY.name, "[formulation.rapier] step", settings.step)?;
        let params = settings.integration_parameters(settings.step);
        let mut bodies = RigidBodySet::new();
        let mut colliders = ColliderSet::new();
        let (e, mu) = (scn.contact.restitution, scn.contact.friction);
        let mut handles = Vec::with_capacity(scn.floes.len());
        for (i, floe) in scn.floes.iter().enumerate() {
            handles.push(insert_floe(&mut bodies, &mut colliders, floe, i, e, mu)?);
        }
        for (k, obstacle) in scn.obstacles.iter().enumerate() {
            let h = bodies.insert(RigidBodyBuilder::fixed().build());
            let collider = convert::polygon_collider(&obstacle.polygon, &obstacle.parts)
                .ok_or_else(|| format!("rapier: obstacle {k}: parry rejects its polygon"))?
                .user_data(OBSTACLE);
            colliders.insert_with_parent(material(collider, e, mu), h, &mut bodies);
        }
        let synced = System::initial(scn).bodies;
        let pipeline = PhysicsPipeline::new();
        Ok(RapierReference {
            settings,
            params,
            pipeline,
            islands: IslandManager::new(),
            broad_phase: BroadPhaseBvh::new(),
            narrow_phase: NarrowPhase::new(),
            bodies,
            colliders,
            impulse_joints: ImpulseJointSet::new(),
            multibody_joints: MultibodyJointSet::new(),
            soft_bodies: SoftBodySet::new(),
            ccd: CCDSolver::new(),
            handles,
            model: ForceModel::new(&scn.floes),
            rapier_angle: vec![0.0; synced.len()],
            synced,
            forces: vec![Forces::default(); scn.floes.len()],
            balance: vec![(0.0, 0.0, 0.0); scn.floes.len()],
            log: ContactLog::recording(),
            touched: vec![false; scn.floes.len()],
            step_points: 0,
            counters: Counters::new(COUNTERS),
            max_penetration: 0.0,
            max_pairs: 0,
            energy_gained: 0.0,
            integration_defect: 0.0,
            grid: FixedGrid::new(settings.step),
        })
    }

    /// The contact impulses of the last step on the floes, as loads of the
    /// fracture criterion (an obstacle is keyed by its collider, past the
    /// floes' ids).
    fn loads(&self, scn: &Scenario) -> Vec<Load> {
        let n = scn.floes.len();
        let body = |c: rapier2d_f64::prelude::ColliderHandle| -> (Option<usize>, usize) {
            let data = self.colliders.get(c).map_or(OBSTACLE, |c| c.user_data);
            match usize::try_from(data).ok().filter(|&i| i < n) {
                Some(i) => (Some(i), i),
                None => (None, n + c.into_raw_parts().0 as usize),
            }
        };
        let mut out = Vec::new();
        for pair in self.narrow_phase.contact_pairs() {
            let (Some(c1), Some(c2)) = (
                self.colliders.get(pair.collider1),
                self.colliders.get(pair.collider2),
            ) else {
                continue;
            };
            let (f1, k1) = body(pair.collider1);
            let (f2, k2) = body(pair.collider2);
            for m in pair.manifolds() {
                for (point, normal, tangent, lambda, beta) in convert::manifold_impulses(m, c1, c2)
                {
                    let p = normal * lambda + tangent * beta;
                    if let Some(i) = f2 {
                        out.push(Load {
                            floe: i,
                            other: k1,
                            point,
                            impulse: p,
                        });
                    }
                    if let Some(i) = f1 {
                        out.push(Load {
                            floe: i,
                            other: k2,
                            point,
                            impulse: -p,
                        });
                    }
                }
            }
        }
        out
    }

    /// Follows a change of the floe set (a fracture): every floe whose id at
    /// its index is not `old[i]` (a piece) gets a new body, the parent's
    /// body removed; the per-floe buffers and the force model follow.
    fn rebuild_bodies(
        &mut self,
        scn: &Scenario,
        cur: &System,
        old: &[usize],
    ) -> Result<(), String> {
        let (e, mu) = (scn.contact.restitution, scn.contact.friction);
        for (i, floe) in scn.floes.iter().enumerate() {
            if old.get(i) == Some(&floe.id) {
                continue;
            }
            if let Some(&h) = self.handles.get(i) {
                self.bodies.remove(
                    h,
                    &mut self.islands,
                    &mut self.colliders,
                    &mut self.impulse_joints,
                    &mut self.multibody_joints,
                    &mut self.soft_bodies,
                    true,
                );
            }
            let h = insert_floe(&mut self.bodies, &mut self.colliders, floe, i, e, mu)?;
            if i < self.handles.len() {
                self.handles[i] = h;
                self.rapier_angle[i] = 0.0;
            } else {
                self.handles.push(h);
                self.rapier_angle.push(0.0);
                self.forces.push(Forces::default());
                self.balance.push((0.0, 0.0, 0.0));
                self.touched.push(false);
            }
        }
        self.synced.clone_from(&cur.bodies);
        self.model = ForceModel::new(&scn.floes);
        Ok(())
    }

    /// The settings in use, defaults resolved.
    pub fn resolved(&self) -> &Resolved {
        &self.settings
    }

    /// Mass (kg) and polar inertia about the centre of mass (kg·m²) of floe
    /// `i` as rapier holds them (to check that they are the floe model's).
    pub fn body_mass_properties(&self, i: usize) -> Option<(f64, f64)> {
        let rb = self.bodies.get(*self.handles.get(i)?)?;
        let mp = rb.mass_properties().local_mprops;
        Some((mp.mass(), mp.principal_inertia()))
    }

    /// Writes `bodies` into rapier if they are not what it holds.
    fn sync_in(&mut self, bodies: &[BodyState]) {
        if bodies == self.synced.as_slice() {
            return;
        }
        for (i, b) in bodies.iter().enumerate() {
            if self.synced.get(i) == Some(b) {
                continue;
            }
            if let Some(rb) = self.bodies.get_mut(self.handles[i]) {
                convert::write_body(rb, b);
                self.rapier_angle[i] = convert::read_body(rb).1;
            }
        }
        self.synced = bodies.to_vec();
    }

    /// One rapier step of length `h` from `sys` at `sys.t`.
    fn step(
        &mut self,
        scn: &Scenario,
        sys: &mut System,
        h: f64,
        cx: &mut Context,
    ) -> Result<(), FormulationError> {
        let t = sys.t;
        // Environment forces from the start state, by the shared force law.
        cx.clock.time(Stage::Integration, || {
            for (i, b) in sys.bodies.iter().enumerate() {
                let f = self.model.forces(&scn.environment, i, t, b);
                self.forces[i] = f;
                if let Some(rb) = self.bodies.get_mut(self.handles[i]) {
                    convert::set_wrench(rb, &f.force(), f.torque());
                }
            }
        });
        self.counters
            .add(&FORCE_EVALUATIONS, sys.bodies.len() as u64);

        self.params.dt = h;
        // rapier's own stage timers run only in the steps the clock times
        // (they read the clock a dozen times per step).
        let timed = cx.clock.start_split();
        if timed.is_timed() {
            self.pipeline.counters.enable();
        }
        self.pipeline.step(
            rapier2d_f64::math::Vector::ZERO,
            &self.params,
            &mut self.islands,
            &mut self.broad_phase,
            &mut self.narrow_phase,
            &mut self.bodies,
            &mut self.colliders,
            &mut self.impulse_joints,
            &mut self.multibody_joints,
            &mut self.soft_bodies,
            &mut self.ccd,
            &(),
            &(),
        );
        if timed.is_timed() {
            let split = self.stage_split();
            cx.clock.stop_split(timed, split);
            self.pipeline.counters.disable();
        } else {
            cx.clock.stop_split(timed, [0.0; 3]);
        }
        self.counters.add(&STEPS, 1);

        // Read back; work of each force along the actual displacement.
        let n = self.settings.iterations as f64;
        for (i, b) in sys.bodies.iter_mut().enumerate() {
            let Some(rb) = self.bodies.get(self.handles[i]) else {
                continue;
            };
            let (g, a, v, w) = convert::read_body(rb);
            let mut da = a - self.rapier_angle[i];
            if da > std::f64::consts::PI {
                da -= 2.0 * std::f64::consts::PI;
            } else if da < -std::f64::consts::PI {
                da += 2.0 * std::f64::consts::PI;
            }
            self.rapier_angle[i] = a;
            let next = BodyState {
                position: g,
                angle: b.angle + da,
                velocity: v,
                angular_velocity: w,
            };
            if !next.is_finite() {
                return Err(FormulationError::Other(format!(
                    "rapier: floe {i}: non-finite state at t = {} s",
                    t + h
                )));
            }
            let dg = g - b.position;
            let f = &self.forces[i];
            let (wa, ww, wc) = f.works(&dg, da);
            sys.ledger.work_air += wa;
            sys.ledger.work_water += ww;
            sys.ledger.work_coriolis += wc;
            let floe = &scn.floes[i];
            let kinetic = |b: &BodyState| {
                0.5 * floe.mass * b.velocity.norm_squared()
                    + 0.5 * floe.inertia * b.angular_velocity * b.angular_velocity
            };
            let defect =
                h * h * (f.force().norm_squared() / floe.mass + f.torque().powi(2) / floe.inertia)
                    / (2.0 * n);
            self.balance[i] = (kinetic(b) + wa + ww + wc, kinetic(&next), defect);
            *b = next;
        }
        sys.t = t + h;
        self.synced.clone_from(&sys.bodies);

        // Contacts of this step: which floes they touched, pairs, penetration.
        self.scan_contacts(t);
        let mut d = 0.0;
        let (mut before, mut after, mut floes) = (0.0, 0.0, 0usize);
        for (&(e0w, e1, defect), &touched) in self.balance.iter().zip(&self.touched) {
            if touched {
                d += e0w - e1;
                before += e0w;
                after += e1;
                floes += 1;
            } else {
                self.integration_defect += defect;
            }
        }
        sys.ledger.dissipated += d;
        if cx.topology.reads().percussions {
            // The step's impulses, delivered over the step [t, t + h]
            // (docs/physics.md §9.3); the floes break between steps.
            let loads = self.loads(scn);
            cx.topology.percussion(scn, sys, &loads, t, t + h, d);
        }
        if floes > 0 && self.step_points > 0 {
            self.log.push_event(ContactEvent {
                t,
                contacts: self.step_points,
                energy_before: before,
                energy_after: after,
            });
        }
        if d < 0.0 {
            self.energy_gained -= d;
        }
        Ok(())
    }

    /// Splits the CPU time of one rapier step between the stages, in the
    /// proportions of rapier's own (wall-clock) stage timers.
    /// The fractions of the last step spent in detection, solve and the
    /// rest (integration), from rapier's own stage timers.
    fn stage_split(&self) -> [f64; 3] {
        let c = &self.pipeline.counters;
        let total = c.step_time.time().as_secs_f64();
        let detection = c.stages.collision_detection_time.time().as_secs_f64();
        let solve = c.stages.solver_time.time().as_secs_f64()
            + c.stages.island_construction_time.time().as_secs_f64()
            + c.stages
                .island_constraints_collection_time
                .time()
                .as_secs_f64();
        if total > 0.0 && detection + solve <= total {
            [detection, solve, total - detection - solve]
        } else {
            [0.0, 1.0, 0.0]
        }
    }

    /// After a step: the floes that received a contact impulse, the pairs
    /// with contacts seen by the solver, and the deepest penetration (at the
    /// start of the step, where rapier's narrow phase computed the manifolds).
    fn scan_contacts(&mut self, t: f64) {
        self.touched.iter_mut().for_each(|t| *t = false);
        let mut pairs = 0u64;
        let mut deepest = 0.0f64;
        self.step_points = 0;
        for pair in self.narrow_phase.contact_pairs() {
            for m in pair.manifolds() {
                for p in &m.points {
                    deepest = deepest.max(-p.dist);
                    // Impulses of the step (summed over its substeps).
                    if p.data.impulse != 0.0 || p.data.tangent_impulse[0] != 0.0 {
                        self.step_points += 1;
                        self.log.push_impulse(ImpulseRecord {
                            t,
                            normal: p.data.impulse,
                            tangent: p.data.tangent_impulse[0],
                            mu: m.data.friction,
                            slack: 0.0,
                        });
                    }
                }
            }
            if !pair.has_any_active_contact() {
                continue;
            }
            pairs += 1;
            for c in [pair.collider1, pair.collider2] {
                let floe = self.colliders.get(c).map_or(OBSTACLE, |c| c.user_data);
                if let Some(t) = usize::try_from(floe)
                    .ok()
                    .and_then(|i| self.touched.get_mut(i))
                {
                    *t = true;
                }
            }
        }
        self.counters.add(&CONTACT_PAIR_STEPS, pairs);
        self.max_pairs = self.max_pairs.max(pairs);
        self.max_penetration = self.max_penetration.max(deepest);
    }
}

impl Formulation for RapierReference {
    fn advance(
        &mut self,
        scn: &mut Scenario,
        sys: &mut System,
        t_end: f64,
        cx: &mut Context,
    ) -> Result<(), FormulationError> {
        let (mut cur, _, steps) = self.grid.begin(sys, t_end)?;
        self.sync_in(&cur.bodies);
        // Steps of h on the grid t_k = k h.
        for _ in 0..steps {
            cx.poll_interrupt(cur.t)?;
            self.step(scn, &mut cur, self.settings.step, cx)?;
            self.grid.stepped(&mut cur);
            // The safe point: between steps (docs/physics.md §9.5).
            if let Some(old) = cx.change_floes(scn, &mut cur) {
                self.floes_changed(scn, &cur, &old)?;
            }
        }
        self.grid.finish(sys, cur, t_end);
        Ok(())
    }

    fn floes_changed(
        &mut self,
        scn: &Scenario,
        sys: &System,
        old: &[usize],
    ) -> Result<(), FormulationError> {
        // The parent's body is removed and the pieces' inserted.
        self.rebuild_bodies(scn, sys, old)
            .map_err(FormulationError::Other)
    }

    fn counters(&self) -> Counters {
        let mut c = self.counters.clone();
        c.set(&MAX_PENETRATION, self.max_penetration);
        c.set(&MAX_CONTACT_PAIRS, self.max_pairs as f64);
        c.set(&CONTACT_ENERGY_GAINED, self.energy_gained);
        c.set(&INTEGRATION_DEFECT, self.integration_defect);
        c
    }

    fn settings(&self) -> Settings {
        let s = &self.settings;
        Settings::default()
            .number("step_s", s.step, Unit::Second)
            .number("iterations", s.iterations as f64, Unit::Count)
            .number("natural_frequency_hz", s.natural_frequency, Unit::Hertz)
            .number("damping_ratio", s.damping_ratio, Unit::Dimensionless)
            .number("prediction_m", s.prediction, Unit::Metre)
            .number("length_unit_m", s.length_unit, Unit::Metre)
            .number(
                "max_corrective_velocity_m_per_s",
                MAX_CORRECTIVE_VELOCITY,
                Unit::MetrePerSecond,
            )
    }

    fn take_contact_log(&mut self) -> ContactLog {
        std::mem::replace(&mut self.log, ContactLog::recording())
    }
}
