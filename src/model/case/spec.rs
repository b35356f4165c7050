//! The case file as written: the serde layer, one type per table. Unknown
//! keys are errors everywhere; the values are checked by [`super::build`].

use crate::model::DEFAULT_ICE_DENSITY;
use serde::Deserialize;
use std::collections::BTreeMap;
use toml::Spanned;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CaseFile {
    pub(super) case: Spanned<CaseHeader>,
    pub(super) environment: Option<Spanned<EnvSpec>>,
    pub(super) contact: Spanned<ContactSpec>,
    #[serde(default)]
    pub(super) floe: Vec<Spanned<FloeSpec>>,
    #[serde(default)]
    pub(super) obstacle: Vec<Spanned<ObstacleSpec>>,
    #[serde(default)]
    pub(super) field: Vec<Spanned<FieldSpec>>,
    pub(super) formulation: Option<Spanned<BTreeMap<String, Spanned<toml::Table>>>>,
    pub(super) integrator: Option<Spanned<IntegratorSpec>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CaseHeader {
    #[allow(dead_code)] // checked on the raw table before typed parsing
    pub(super) version: i64,
    pub(super) name: String,
    #[serde(default)]
    pub(super) description: String,
    pub(super) duration: f64,
    pub(super) output_interval: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct EnvSpec {
    #[serde(default)]
    pub(super) coriolis: f64,
    pub(super) air: Option<FluidSpec>,
    pub(super) water: Option<FluidSpec>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FluidSpec {
    pub(super) density: f64,
    pub(super) drag: f64,
    pub(super) velocity: Option<[f64; 2]>,
    pub(super) series: Option<Vec<[f64; 3]>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ContactSpec {
    pub(super) restitution: f64,
    pub(super) friction: f64,
    #[serde(default)]
    pub(super) distance: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FloeSpec {
    pub(super) polygon: Vec<[f64; 2]>,
    pub(super) thickness: f64,
    #[serde(default = "default_density")]
    pub(super) density: f64,
    #[serde(default)]
    pub(super) velocity: [f64; 2],
    #[serde(default)]
    pub(super) angular_velocity: f64,
}

fn default_density() -> f64 {
    DEFAULT_ICE_DENSITY
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ObstacleSpec {
    pub(super) polygon: Vec<[f64; 2]>,
}

/// A `[[field]]` table as written: see [`crate::model::field`].
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct FieldSpec {
    /// Axis-aligned box `[[xmin, ymin], [xmax, ymax]]`, m.
    pub region: [[f64; 2]; 2],
    /// Number of floes.
    pub count: usize,
    /// Target area fraction in (0, 0.9].
    pub concentration: f64,
    /// Circumradius range `[min, max]`, m.
    pub radius: [f64; 2],
    /// Vertices per polygon `[min, max]`.
    pub sides: [usize; 2],
    /// Thickness range `[min, max]`, m; each floe's is uniform in it.
    pub thickness: [f64; 2],
    /// Density, kg/m³ (default 917).
    #[serde(default = "default_density")]
    pub density: f64,
    /// Initial velocity of every floe, m/s (default `[0, 0]`).
    #[serde(default)]
    pub velocity: [f64; 2],
    /// Seed of the generator: same seed, same field.
    pub seed: u64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct IntegratorSpec {
    pub(super) method: Option<String>,
    pub(super) tolerance: Option<f64>,
    pub(super) max_step: Option<f64>,
}
