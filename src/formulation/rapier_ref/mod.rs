//! rapier as the regularised reference formulation.
//!
//! The widely used Rust physics engine [rapier] (`rapier2d-f64` 0.36.1, on
//! parry2d-f64 0.31) runs the same case files as the nonsmooth schemes, so
//! that researchers can see what a soft-constraint engine gives against
//! them. **Described once, in docs/physics.md §8**: the mapping of a case
//! onto rapier (each floe a dynamic body at its centre of mass with the
//! floe's own mass and inertia, obstacles fixed, the environment forces of
//! the project's one force law [`ForceModel::forces`] held constant over a
//! step, `e` and `μ` combined by `Max`, the game safeguards that change the
//! physics off), its scheme (TGS-soft: substeps of one soft projected
//! Gauss–Seidel sweep and one rigid relax sweep, restitution after the
//! substeps on new contacts only), the parameters and why their defaults
//! differ from rapier's game defaults (`settings.rs`,
//! [`RapierSettings`]), the energy ledger (dissipation from kinetic
//! energy and work, the integration defect `δ` of the substepped
//! symplectic Euler left in the residual), the counters and how the CPU
//! time is split between stages. rapier's glam types meet the project's
//! `Vec2` in one place, `convert.rs`.
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
mod settings;
mod step;

pub use settings::*;

use super::{
    advance_on_grid, check_output_grid, Context, Entry, FixedGrid, FixedStep, Formulation,
    FormulationError, FormulationOptions, NotClaimed,
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
    check: Some(check),
    settings: Some(TABLE),
    resolves_contacts: true,
    dumps_lcps: false,
    supports_fracture: true,
    lattice_impacts: false,
    supports_crushing: false,
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

/// The contact material of every collider: the case's `e` and `μ` with
/// the `Max` combine rule (so every pair gets exactly them), no skin.
fn material(c: ColliderBuilder, e: f64, mu: f64) -> ColliderBuilder {
    c.restitution(e)
        .restitution_combine_rule(CoefficientCombineRule::Max)
        .friction(mu)
        .friction_combine_rule(CoefficientCombineRule::Max)
        .contact_skin(0.0)
}

/// Inserts floe `i` (at its position, angle and velocity at t = 0) as a dynamic
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
    let rb = convert::dynamic_body(
        &floe.position,
        floe.angle,
        &floe.velocity,
        floe.angular_velocity,
    )
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

/// What `rapier` refuses in a case ([`Entry::check`]): output times off
/// the grid of the step of `[formulation.rapier]`.
fn check(scn: &Scenario) -> Result<(), CaseError> {
    let settings = Resolved::of(scn)?;
    check_output_grid(
        scn,
        ENTRY.name,
        &scn.settings_table(TABLE.name),
        "step",
        settings.step,
    )
}

impl RapierReference {
    /// Sets up rapier for `scn`. Fails if parry rejects a polygon.
    pub fn new(scn: &Scenario, _opts: &FormulationOptions) -> Result<RapierReference, String> {
        check(scn).map_err(|e| e.to_string())?;
        let settings = Resolved::of(scn).map_err(|e| e.to_string())?;
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
                .user_data(OBSTACLE - k as u128);
            colliders.insert_with_parent(material(collider, e, mu), h, &mut bodies);
        }
        let synced = System::initial(scn).bodies;
        // Rapier's own reading of each starting angle (in (−π, π]), from
        // which the next step's turn is measured.
        let rapier_angle = handles
            .iter()
            .map(|&h| bodies.get(h).map_or(0.0, |rb| convert::read_body(rb).1))
            .collect();
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
            rapier_angle,
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
                // Obstacle k carries OBSTACLE − k: its body id is n + k.
                None => (None, n + (OBSTACLE - data) as usize),
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
}

impl FixedStep for RapierReference {
    fn grid(&mut self) -> &mut FixedGrid {
        &mut self.grid
    }

    fn resume(&mut self, cur: &System) {
        self.sync_in(&cur.bodies);
    }

    fn fixed_step(
        &mut self,
        scn: &Scenario,
        sys: &mut System,
        cx: &mut Context,
    ) -> Result<(), FormulationError> {
        self.step(scn, sys, self.settings.step, cx)
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
        // Steps of h on the grid t_k = k h.
        advance_on_grid(self, scn, sys, t_end, cx)
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
