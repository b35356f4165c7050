//! The `[fracture]` table of a case (docs/case-format.md, docs/physics.md
//! §9) and the record of a changing floe set: the floes that ended and the
//! fractures of a run.
//!
//! The table is read with the shared [`SettingsReader`], so a bad value is
//! refused with the file, the line and the key, and every number is checked
//! against its [`Limit`] (listed in [`super::limits::CASE_LIMITS`],
//! documented in docs/case-format.md). An absent table, or `model = "none"`, is no
//! fracture: every formulation then runs exactly as without fracture.

use super::limits::fracture::{
    CONCENTRATION, CRITICAL_STRAIN, DAMPING, HIBLER_C, HIBLER_P_STAR, MIN_AREA, MOHR_Q,
    MOHR_SIGMA_11, MOHR_SIGMA_C, POISSON, POISSON_MAX, SEED, SPACING, STRENGTH, TOUGHNESS, WINDOW,
    YOUNG,
};
use super::limits::Limit;
use super::settings::SettingsTable;
use super::{CaseError, Floe};
use serde::Serialize;

mod choices;
mod cohesive;

pub use choices::{FractureModel, ImpactLaw, LatticeMesh, LatticeRule, Trigger, YieldCurve};
pub use cohesive::{cohesive_max_spacing, cohesive_onset_strain};

/// The largest lattice spacing for a floe of area `A`, as a fraction of
/// `√A`: four cells across, below which a lattice has no interior.
pub const MAX_SPACING_FRACTION: f64 = 0.25;

/// The lattice spacing (m) of a floe of area `area` (m²) and outline
/// `shape` (m) in the case's `[fracture]` table: `spacing`, or the default
/// [`DEFAULT_SPACING_FRACTION`] of `√A`; at most [`MAX_SPACING_FRACTION`]
/// of `√A`. With `impact = "lattice"` the default is also at most
/// [`max_spacing_across`] of the floe's narrowest width, so that the
/// default passes the check of [`MIN_NODES_ACROSS`] (a floe whose
/// `√A`/8 already passes keeps it: the rule changes only the spacing of
/// the narrow floes that the check used to refuse).
pub fn lattice_spacing(s: &FractureSettings, area: f64, shape: &[crate::geometry::Vec2]) -> f64 {
    let size = area.sqrt();
    let default = || {
        let d = DEFAULT_SPACING_FRACTION * size;
        if s.lattice_impacts() {
            d.min(max_spacing_across(min_width(shape)))
        } else {
            d
        }
    };
    s.spacing
        .unwrap_or_else(default)
        .min(MAX_SPACING_FRACTION * size)
}

/// The largest spacing (m) that puts [`MIN_NODES_ACROSS`] lattice nodes
/// across a width `width` (m): `width / (MIN_NODES_ACROSS − 1)`.
pub fn max_spacing_across(width: f64) -> f64 {
    width / (MIN_NODES_ACROSS - 1.0)
}

/// The fewest lattice nodes across a floe's narrowest width that
/// `impact = "lattice"` accepts (docs/physics.md §9.10): with fewer, the
/// lattice of a bar is a chain of single cells and has no bending or
/// interior wave to carry the impact.
pub const MIN_NODES_ACROSS: f64 = 3.0;

/// The narrowest width of a polygon, m: the least extent of its vertices
/// along the normals of its edges (its convex hull's width, attained with
/// a hull edge flush to a caliper).
pub fn min_width(shape: &[crate::geometry::Vec2]) -> f64 {
    let n = shape.len();
    (0..n)
        .filter_map(|k| {
            let d = shape[(k + 1) % n] - shape[k];
            let len = d.norm();
            (len > 0.0).then(|| {
                let normal = crate::geometry::Vec2::new(-d.y, d.x) / len;
                let (lo, hi) =
                    shape
                        .iter()
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                            let x = normal.dot(p);
                            (lo.min(x), hi.max(x))
                        });
                hi - lo
            })
        })
        .fold(f64::INFINITY, f64::min)
}

/// Default Young's modulus of the lattice model, Pa: the 8.95 GPa of
/// Balasoiu's (2020) numerics of sea ice.
pub const DEFAULT_YOUNG: f64 = 8.95e9;
/// Default dashpot ratio of the lattice model: 0.5, with which the 1D spall
/// threshold converges with resolution (docs/physics.md §7.1).
pub const DEFAULT_DAMPING: f64 = 0.5;
/// Default lattice spacing as a fraction of the floe's size `√A`: 1/8, about
/// 80 nodes in a square. A percussion costs `O(N^{3/2})` (`N` nodes times
/// the steps of a few transit times, `√N` each), so this keeps it at a few
/// milliseconds for every impact that passes the trigger.
pub const DEFAULT_SPACING_FRACTION: f64 = 0.125;

/// Default `G`, J/m²: the middle of the 1.5–3.5 J/m² of sea ice (FloeDyn's
/// documentation, from laboratory fracture toughness `K_IC` of 0.1–0.2
/// MPa·m^½ and `G = K_IC² / E'`; docs/physics.md §9.2).
pub const DEFAULT_TOUGHNESS: f64 = 2.5;
/// Default smoothing window of the stress criterion, s: 10 s, a few LCP
/// solves of the fixed-step schemes (1 s steps) and long enough that one
/// impact's impulse alone does not read as a stress.
pub const DEFAULT_WINDOW: f64 = 10.0;

/// The `[fracture]` table, defaults resolved.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FractureSettings {
    /// The criterion (default `none`).
    pub model: FractureModel,
    /// `G`, J/m² (default [`DEFAULT_TOUGHNESS`]).
    pub toughness: f64,
    /// A floe of smaller area never breaks, m² (default: a quarter of the
    /// smallest initial floe: two halvings).
    pub min_area: f64,
    /// The stress criterion's yield curve (default `mohr`).
    pub yield_curve: YieldCurve,
    /// The stress smoothing window, s (default [`DEFAULT_WINDOW`]).
    pub window: f64,
    /// Mohr–Coulomb `q` (default 5.2, SubZero).
    pub mohr_q: f64,
    /// Mohr–Coulomb `σ_c`, Pa (default 2.5e5, SubZero).
    pub mohr_sigma_c: f64,
    /// Mohr–Coulomb `σ_11`, Pa (default −3.375e4, SubZero).
    pub mohr_sigma_11: f64,
    /// Hibler `P*`, N/m² (default 2.25e5).
    pub hibler_p_star: f64,
    /// Hibler `C` (default 20).
    pub hibler_c: f64,
    /// Ice concentration `A` of Hibler's strength (default 1: compact ice).
    pub concentration: f64,
    /// Lattice model: Young's modulus, Pa (default [`DEFAULT_YOUNG`]).
    pub young: f64,
    /// Lattice model: dashpot ratio `β` (default [`DEFAULT_DAMPING`]).
    pub damping: f64,
    /// Lattice model: Poisson ratio (default 1/3: central springs only, no
    /// torsion springs, the lattice of the first lattice cases).
    pub poisson: f64,
    /// Lattice model: the lattice spacing, m (default `None`:
    /// [`DEFAULT_SPACING_FRACTION`] of each floe's `√A`).
    pub spacing: Option<f64>,
    /// Lattice model: the bond rule (default `toughness`, with `toughness`).
    pub rule: LatticeRule,
    /// Lattice model: the critical strain of `rule = "strain"` (required then).
    pub critical_strain: f64,
    /// Lattice model: the tensile strength `σ_t` of `rule = "cohesive"`,
    /// Pa (required then, refused with the other rules).
    pub strength: f64,
    /// Lattice model: when an impact is resolved in the lattice (default `bound`).
    pub trigger: Trigger,
    /// Lattice model: the seed of every floe's lattice (default 1).
    pub seed: u64,
    /// Lattice model: the mesh (default `random`).
    pub mesh: LatticeMesh,
    /// What sets the velocities after an impact (default `rigid`;
    /// `lattice` needs `model = "lattice"`, docs/physics.md §9.10).
    pub impact: ImpactLaw,
}

impl Default for FractureSettings {
    fn default() -> Self {
        FractureSettings {
            model: FractureModel::None,
            toughness: DEFAULT_TOUGHNESS,
            min_area: 0.0,
            yield_curve: YieldCurve::Mohr,
            window: DEFAULT_WINDOW,
            mohr_q: 5.2,
            mohr_sigma_c: 2.5e5,
            mohr_sigma_11: -3.375e4,
            hibler_p_star: 2.25e5,
            hibler_c: 20.0,
            concentration: 1.0,
            young: DEFAULT_YOUNG,
            damping: DEFAULT_DAMPING,
            poisson: POISSON_MAX,
            spacing: None,
            rule: LatticeRule::Toughness,
            critical_strain: f64::NAN,
            strength: f64::NAN,
            trigger: Trigger::Bound,
            seed: 1,
            mesh: LatticeMesh::Random,
            impact: ImpactLaw::Rigid,
        }
    }
}

impl FractureSettings {
    /// Whether floes can break.
    pub fn enabled(&self) -> bool {
        self.model != FractureModel::None
    }

    /// Whether the lattices resolve the impacts (`impact = "lattice"`).
    pub fn lattice_impacts(&self) -> bool {
        self.impact == ImpactLaw::Lattice
    }

    /// Reads the table for the initial `floes` (the default `min_area` is a
    /// quarter of the smallest one's area); errors name the line and key.
    pub fn from_table(t: &SettingsTable, floes: &[Floe]) -> Result<FractureSettings, CaseError> {
        let mut s = FractureSettings {
            min_area: 0.25 * floes.iter().map(|f| f.area).fold(f64::INFINITY, f64::min),
            ..FractureSettings::default()
        };
        if !s.min_area.is_finite() {
            s.min_area = 0.0;
        }
        let mut r = t.read();
        if let Some(m) = r.choice::<FractureModel>("model")? {
            s.model = m;
        }
        if let Some(y) = r.choice::<YieldCurve>("yield")? {
            s.yield_curve = y;
        }
        if let Some(rule) = r.choice::<LatticeRule>("rule")? {
            s.rule = rule;
        }
        if let Some(mesh) = r.choice::<LatticeMesh>("mesh")? {
            s.mesh = mesh;
        }
        if let Some(trigger) = r.choice::<Trigger>("trigger")? {
            s.trigger = trigger;
        }
        if let Some(impact) = r.choice::<ImpactLaw>("impact")? {
            s.impact = impact;
        }
        let numbers: [(&Limit, &mut f64); 12] = [
            (&TOUGHNESS, &mut s.toughness),
            (&MIN_AREA, &mut s.min_area),
            (&WINDOW, &mut s.window),
            (&MOHR_Q, &mut s.mohr_q),
            (&MOHR_SIGMA_C, &mut s.mohr_sigma_c),
            (&MOHR_SIGMA_11, &mut s.mohr_sigma_11),
            (&HIBLER_P_STAR, &mut s.hibler_p_star),
            (&HIBLER_C, &mut s.hibler_c),
            (&CONCENTRATION, &mut s.concentration),
            (&YOUNG, &mut s.young),
            (&DAMPING, &mut s.damping),
            (&POISSON, &mut s.poisson),
        ];
        for (limit, slot) in numbers {
            if let Some(v) = r.bounded(limit)? {
                *slot = v;
            }
        }
        s.spacing = r.bounded(&SPACING)?;
        let strain = r.bounded(&CRITICAL_STRAIN)?;
        let strength = r.bounded(&STRENGTH)?;
        if let Some(seed) = r.integer(&SEED)? {
            s.seed = u64::try_from(seed).unwrap_or(0);
        }
        r.finish()?;
        match (s.model, s.rule, strain) {
            (FractureModel::Lattice, LatticeRule::Strain, None) => return Err(t.error(
                Some("rule"),
                "rule = \"strain\" needs critical_strain (the bond strain at which a bond breaks)",
            )),
            (_, _, Some(e)) => s.critical_strain = e,
            _ => {}
        }
        s.check_cohesive(t, floes, strength)?;
        s.check_lattice_impacts(t, floes)?;
        Ok(s)
    }

    /// `impact = "lattice"` needs the lattice model and a lattice of at
    /// least [`MIN_NODES_ACROSS`] nodes across every floe's narrowest
    /// width (docs/physics.md §9.10).
    fn check_lattice_impacts(&self, t: &SettingsTable, floes: &[Floe]) -> Result<(), CaseError> {
        if !self.lattice_impacts() {
            return Ok(());
        }
        if self.model != FractureModel::Lattice {
            return Err(t.error(
                Some("impact"),
                format!(
                    "impact = \"lattice\" resolves impacts in the floes' lattices and needs model = \"lattice\" (got model = \"{}\")",
                    self.model.name()
                ),
            ));
        }
        for (i, f) in floes.iter().enumerate() {
            let width = min_width(&f.shape);
            let spacing = lattice_spacing(self, f.area, &f.shape);
            // The default spacing passes by construction ([`lattice_spacing`]);
            // an explicit one is refused with the value that would do.
            if width / spacing + 1.0 < MIN_NODES_ACROSS {
                let largest = floes
                    .iter()
                    .map(|f| max_spacing_across(min_width(&f.shape)))
                    .fold(f64::INFINITY, f64::min);
                return Err(t.error(
                    Some("spacing"),
                    format!(
                        "impact = \"lattice\": floe {i} ({}) is {} m across at its narrowest, and the lattice spacing {} m puts fewer than {MIN_NODES_ACROSS} nodes across it; spacing <= {} m would do for every floe (or leave spacing out: the default fits each floe)",
                        f.origin.label(),
                        crate::model::limits::show(width),
                        crate::model::limits::show(spacing),
                        crate::model::limits::show(largest)
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// One floe that existed during a run, as `floes.json` lists it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FloeRecord {
    /// Stable id (the `floe` column of `trajectory.csv`).
    pub id: usize,
    /// The floe it is a piece of (`null` for the initial floes).
    pub parent: Option<usize>,
    /// When it began, s.
    pub t_birth: f64,
    /// The orientation of its body frame at birth against its first
    /// ancestor's at t = 0, rad (0 for the initial floes).
    pub theta_birth: f64,
    /// When it broke, s (`null` if alive at the end).
    pub t_end: Option<f64>,
    /// Area, m².
    pub area: f64,
    /// Mass, kg.
    pub mass: f64,
    /// Polar moment of inertia about its centre of mass, kg·m².
    pub inertia: f64,
    /// Thickness, m.
    pub thickness: f64,
    /// Outline in its body frame (centre of mass at the origin, at angle 0
    /// of its trajectory), counter-clockwise, m.
    pub polygon: Vec<[f64; 2]>,
    /// Its outline in the world at the end of the run, counter-clockwise,
    /// m: written for the floes alive at the end of a run with `[contact]
    /// crushing` (whose outlines change, docs/physics.md §10), absent
    /// otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub world_polygon: Option<Vec<[f64; 2]>>,
}

impl FloeRecord {
    /// The record of `floe`, ended at `t_end` (s) or alive.
    pub fn of(floe: &Floe, t_end: Option<f64>) -> FloeRecord {
        FloeRecord {
            id: floe.id,
            parent: floe.parent,
            t_birth: floe.t_birth,
            theta_birth: floe.theta_birth,
            t_end,
            area: floe.area,
            mass: floe.mass,
            inertia: floe.inertia,
            thickness: floe.thickness,
            polygon: floe.shape.iter().map(|p| [p.x, p.y]).collect(),
            world_polygon: None,
        }
    }

    /// The record with its world outline at centre of mass `g` (m) and
    /// angle `theta` (rad) of its trajectory.
    pub fn at(self, g: &crate::geometry::Vec2, theta: f64) -> FloeRecord {
        let mut out = Vec::with_capacity(self.polygon.len());
        self.world_polygon(g, theta, &mut out);
        FloeRecord {
            world_polygon: Some(out.iter().map(|p| [p.x, p.y]).collect()),
            ..self
        }
    }
}

impl FloeRecord {
    /// The outline at centre `g` (m) and angle `theta` (rad) of its
    /// trajectory, into `out` (m).
    pub fn world_polygon(
        &self,
        g: &crate::geometry::Vec2,
        theta: f64,
        out: &mut Vec<crate::geometry::Vec2>,
    ) {
        let shape: Vec<crate::geometry::Vec2> = self
            .polygon
            .iter()
            .map(|p| crate::geometry::Vec2::new(p[0], p[1]))
            .collect();
        crate::geometry::place(&shape, g, theta, out);
    }
}

/// One fracture, a row of `fractures.csv`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FractureRecord {
    /// Time, s.
    pub t: f64,
    /// The floe that broke.
    pub parent: usize,
    /// The ids of its pieces.
    pub children: Vec<usize>,
    /// The criterion (`energy`, `stress`).
    pub model: &'static str,
    /// What the criterion measured (J for `energy`; the yield function,
    /// Pa, for `stress`).
    pub measure: f64,
    /// What it was compared with (J for `energy`: `G h L`; 0 for `stress`).
    pub threshold: f64,
    /// Energy the fracture took out of the contact dissipation into the
    /// ledger's `fracture` column, J.
    pub energy: f64,
    /// The kinetic energy the pieces have above the parent's, J: their
    /// relative motion, which the lattice model gives them (docs/physics.md
    /// §9.8) and takes from the ledger's `dissipated` column; ≥ 0 (the
    /// parent's rigid motion has the least kinetic energy of any motion
    /// with its linear and angular momentum), 0 for the chord cut.
    pub kinetic_gain: f64,
    /// The largest relative change the split made to what it conserves:
    /// area, mass, kinetic energy (each relative to the parent's), linear
    /// momentum (relative to `M (|v| + |ω| r)`) and angular momentum about
    /// the parent's centre of mass (relative to `M (|v| + |ω| r) r`), `r`
    /// the parent's radius (docs/physics.md §9.1; rounding only).
    pub conservation: f64,
}

/// The impact that started a recorded percussion, in the struck floe's
/// body frame (docs/physics.md §9.8).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ImpactRecord {
    /// The contact point (the pair's centre of pressure), m.
    pub point: [f64; 2],
    /// The unit normal, pointing into the struck floe.
    pub normal: [f64; 2],
    /// The equivalent approach speed `u_N`, m/s.
    pub speed: f64,
    /// The striker's effective mass along the normal, kg; `None` (`null`)
    /// for an obstacle (infinite).
    pub striker_mass: Option<f64>,
}

/// One percussion of the lattice model with its crack pattern: the
/// lattice at rest with every spring intact or broken, and the impact
/// (`percussion.json`, docs/physics.md §9.8). Positions are in the struck
/// floe's body frame (the frame of its `floes.json` polygon: centre of mass
/// at the origin); `position` and `angle` place it in the world at `t`
/// (`x_world = position + R(angle) x`, as its `trajectory.csv` row).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PercussionRecord {
    /// When, s (the fracture's `t`).
    pub t: f64,
    /// The floe struck (id), the fracture's `parent`.
    pub floe: usize,
    /// The ids of its pieces, the fracture's `children`.
    pub children: Vec<usize>,
    /// Its centre of mass at `t`, m.
    pub position: [f64; 2],
    /// Its angle at `t` (as `theta` of `trajectory.csv`), rad.
    pub angle: f64,
    /// The impacts, one per striker (every pair that loaded the floe in the
    /// solve, docs/physics.md §9.8).
    pub impacts: Vec<ImpactRecord>,
    /// The trigger bound `½ μ_G u_N²`, J (the fracture's `measure`).
    pub bound: f64,
    /// The floe's weakest bond's breaking energy, J (its `threshold`).
    pub weakest: f64,
    /// The lattice's loss (dashpots, broken bonds, ringing), J: a run
    /// keeps the percussion of largest loss (the earlier on a tie).
    pub loss: f64,
    /// What the ledger booked in its `fracture` column for it, J (the
    /// fracture's `energy`; at most `loss`).
    pub energy: f64,
    /// The lattice spacing asked for, m.
    pub spacing: f64,
    /// The nodes at rest, m.
    pub nodes: Vec<[f64; 2]>,
    /// Each spring's two nodes (indices into `nodes`).
    pub springs: Vec<[usize; 2]>,
    /// Whether each spring held (`false`: it broke), in the order of
    /// `springs`.
    pub intact: Vec<bool>,
    /// The springs that broke, in the order they broke (indices into
    /// `springs`).
    pub broken: Vec<usize>,
}

/// The floes that ended and the fractures of a run so far.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct FloeHistory {
    /// The floes that broke, with their end time.
    pub ended: Vec<FloeRecord>,
    /// Every fracture, in time order.
    pub fractures: Vec<FractureRecord>,
    /// The lattice model's percussion of largest loss that broke a floe
    /// (`percussion.json`; `None` for the other models and a run with no
    /// lattice fracture).
    pub percussion: Option<PercussionRecord>,
    /// The id the next piece gets.
    pub next_id: usize,
}

impl FloeHistory {
    /// The history of a case of `n` initial floes (ids `0..n`).
    pub fn new(n: usize) -> FloeHistory {
        FloeHistory {
            next_id: n,
            ..FloeHistory::default()
        }
    }
}
