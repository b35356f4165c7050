//! The case file as written: the serde layer, one type per table. Unknown
//! keys are errors everywhere; the values are checked by [`super::build`].

use crate::model::DEFAULT_ICE_DENSITY;
use serde::{Deserialize, Deserializer};
use std::collections::BTreeMap;
use toml::Spanned;

/// An array of exactly `N` values: serde alone would take the first `N` of
/// a longer array (a vertex `[0.0, 5.0, 7.0]` read as `[0.0, 5.0]`).
struct Exact<T, const N: usize>([T; N]);

/// A sequence of `T`, whose errors say what was expected: `[x, y]` for a
/// point, not serde's `a sequence` (`velocity = 15.0`).
struct Seq<T>(
    std::marker::PhantomData<T>,
    fn(&mut std::fmt::Formatter) -> std::fmt::Result,
);

impl<'de, T: Deserialize<'de>> serde::de::Visitor<'de> for Seq<T> {
    type Value = Vec<T>;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        (self.1)(f)
    }

    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<T>, A::Error> {
        let mut v = Vec::new();
        while let Some(x) = seq.next_element()? {
            v.push(x);
        }
        Ok(v)
    }
}

/// `[a, b, …]` of exactly `N` values, said so.
struct Expect<const N: usize>;

impl<const N: usize> serde::de::Expected for Expect<N> {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        Expect::<N>::write(f)
    }
}

impl<const N: usize> Expect<N> {
    fn write(f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "an array of exactly {N} values")
    }

    fn write_list(f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "a list of arrays of exactly {N} values, [[…], …]")
    }
}

impl<'de, T: Deserialize<'de>, const N: usize> Deserialize<'de> for Exact<T, N> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = d.deserialize_seq(Seq::<T>(std::marker::PhantomData, Expect::<N>::write))?;
        let n = v.len();
        <[T; N]>::try_from(v)
            .map(Exact)
            .map_err(|_| serde::de::Error::invalid_length(n, &Expect::<N>))
    }
}

/// `[a, b, …]` of exactly `N` values.
fn exact<'de, D: Deserializer<'de>, T: Deserialize<'de>, const N: usize>(
    d: D,
) -> Result<[T; N], D::Error> {
    Exact::<T, N>::deserialize(d).map(|e| e.0)
}

/// An optional `[a, b, …]` of exactly `N` values.
fn exact_opt<'de, D: Deserializer<'de>, T: Deserialize<'de>, const N: usize>(
    d: D,
) -> Result<Option<[T; N]>, D::Error> {
    Option::<Exact<T, N>>::deserialize(d).map(|e| e.map(|e| e.0))
}

/// A list of `[a, b, …]`, each of exactly `N` values (polygons, series).
fn exact_list<'de, D: Deserializer<'de>, T: Deserialize<'de>, const N: usize>(
    d: D,
) -> Result<Vec<[T; N]>, D::Error> {
    ExactList::<T, N>::deserialize(d).map(|l| l.0)
}

/// A list of `[a, b, …]`, each of exactly `N` values, whose type error says so.
struct ExactList<T, const N: usize>(Vec<[T; N]>);

impl<'de, T: Deserialize<'de>, const N: usize> Deserialize<'de> for ExactList<T, N> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_seq(Seq::<Exact<T, N>>(
            std::marker::PhantomData,
            Expect::<N>::write_list,
        ))
        .map(|v| ExactList(v.into_iter().map(|e| e.0).collect()))
    }
}

/// An optional list of `[a, b, …]`, each of exactly `N` values.
fn exact_opt_list<'de, D: Deserializer<'de>, T: Deserialize<'de>, const N: usize>(
    d: D,
) -> Result<Option<Vec<[T; N]>>, D::Error> {
    Option::<ExactList<T, N>>::deserialize(d).map(|l| l.map(|l| l.0))
}

/// A box `[[xmin, ymin], [xmax, ymax]]`, each array of exactly 2 values.
fn exact_box<'de, D: Deserializer<'de>>(d: D) -> Result<[[f64; 2]; 2], D::Error> {
    Exact::<Exact<f64, 2>, 2>::deserialize(d).map(|e| e.0.map(|p| p.0))
}

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
    pub(super) fracture: Option<Spanned<toml::Table>>,
}

#[derive(Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "the table [case] (version, name, duration, output_interval)"
)]
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
#[serde(
    deny_unknown_fields,
    expecting = "the table [environment] (coriolis, air, water)"
)]
pub(super) struct EnvSpec {
    #[serde(default)]
    pub(super) coriolis: f64,
    pub(super) air: Option<Spanned<FluidSpec>>,
    pub(super) water: Option<Spanned<FluidSpec>>,
}

#[derive(Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "a table such as { density = 1.3, drag = 1.7e-3, velocity = [10.0, 0.0] }"
)]
pub(super) struct FluidSpec {
    pub(super) density: f64,
    pub(super) drag: f64,
    #[serde(default, deserialize_with = "exact_opt")]
    pub(super) velocity: Option<[f64; 2]>,
    #[serde(default, deserialize_with = "exact_opt_list")]
    pub(super) series: Option<Vec<[f64; 3]>>,
    /// `"uniform"` (default), `"linear"`, `"vortex"` or `"netcdf"`.
    pub(super) field: Option<String>,
    /// Linear: the point where `velocity` is given, m.
    #[serde(default, deserialize_with = "exact_opt")]
    pub(super) at: Option<[f64; 2]>,
    /// Linear: `[[du/dx, du/dy], [dv/dx, dv/dy]]`, 1/s.
    #[serde(default, deserialize_with = "exact_opt_box")]
    pub(super) gradient: Option<[[f64; 2]; 2]>,
    /// Linear: the box where the field is defined, m.
    #[serde(default, deserialize_with = "exact_opt_box")]
    pub(super) extent: Option<[[f64; 2]; 2]>,
    /// Linear, netcdf: `"error"` (default) or `"clamp"`.
    pub(super) outside: Option<String>,
    /// Linear, vortex: `[[t, factor], …]`.
    #[serde(default, deserialize_with = "exact_opt_list")]
    pub(super) scale: Option<Vec<[f64; 2]>>,
    /// Vortex: the centre at t = 0, m.
    #[serde(default, deserialize_with = "exact_opt")]
    pub(super) center: Option<[f64; 2]>,
    /// Vortex: the core radius, m.
    pub(super) radius: Option<f64>,
    /// Vortex: the peak azimuthal speed, m/s.
    pub(super) speed: Option<f64>,
    /// Vortex: the drift of the centre, m/s.
    #[serde(default, deserialize_with = "exact_opt")]
    pub(super) center_velocity: Option<[f64; 2]>,
    /// Netcdf: the file, relative to the case file.
    pub(super) file: Option<String>,
    /// Netcdf: the names of the two velocity components.
    #[serde(default, deserialize_with = "exact_opt")]
    pub(super) variables: Option<[String; 2]>,
    /// Netcdf on lon/lat: the reference point `[lon, lat]` of the local
    /// projection, degrees.
    #[serde(default, deserialize_with = "exact_opt")]
    pub(super) origin: Option<[f64; 2]>,
    /// Netcdf: the date of the run's t = 0 (`YYYY-MM-DD[ hh:mm:ss]`).
    pub(super) start: Option<String>,
}

/// An optional `[[a, b], [c, d]]`, each array of exactly 2 values.
fn exact_opt_box<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[[f64; 2]; 2]>, D::Error> {
    Option::<Exact<Exact<f64, 2>, 2>>::deserialize(d).map(|e| e.map(|e| e.0.map(|p| p.0)))
}

#[derive(Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "the table [contact] (restitution, friction)"
)]
pub(super) struct ContactSpec {
    pub(super) restitution: f64,
    pub(super) friction: f64,
    #[serde(default)]
    pub(super) distance: f64,
    #[serde(default)]
    pub(super) crushing: Option<CrushingSpec>,
}

/// `[contact] crushing = { strength }` or `{ p0, exponent }`.
#[derive(Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "crushing = { strength = Pa } or { p0 = Pa, exponent = ex }"
)]
pub(super) struct CrushingSpec {
    pub(super) strength: Option<f64>,
    pub(super) p0: Option<f64>,
    pub(super) exponent: Option<f64>,
}

#[derive(Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "a [[floe]] table (polygon, thickness)"
)]
pub(super) struct FloeSpec {
    #[serde(deserialize_with = "exact_list")]
    pub(super) polygon: Vec<[f64; 2]>,
    pub(super) thickness: f64,
    #[serde(default = "default_density")]
    pub(super) density: f64,
    #[serde(default, deserialize_with = "exact")]
    pub(super) velocity: [f64; 2],
    #[serde(default)]
    pub(super) angular_velocity: f64,
}

fn default_density() -> f64 {
    DEFAULT_ICE_DENSITY
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "an [[obstacle]] table (polygon)")]
pub(super) struct ObstacleSpec {
    #[serde(deserialize_with = "exact_list")]
    pub(super) polygon: Vec<[f64; 2]>,
}

/// A `[[field]]` table as written: see [`crate::model::field`].
#[derive(Deserialize, Debug, Clone)]
#[serde(
    deny_unknown_fields,
    expecting = "a [[field]] table (region, count, concentration, radius, sides, thickness, seed)"
)]
pub struct FieldSpec {
    /// Axis-aligned box `[[xmin, ymin], [xmax, ymax]]`, m.
    #[serde(deserialize_with = "exact_box")]
    pub region: [[f64; 2]; 2],
    /// Number of floes.
    pub count: usize,
    /// Target area fraction in (0, 0.9].
    pub concentration: f64,
    /// Circumradius range `[min, max]`, m.
    #[serde(deserialize_with = "exact")]
    pub radius: [f64; 2],
    /// Vertices per polygon `[min, max]`.
    #[serde(deserialize_with = "exact")]
    pub sides: [usize; 2],
    /// Thickness range `[min, max]`, m; each floe's is uniform in it.
    #[serde(deserialize_with = "exact")]
    pub thickness: [f64; 2],
    /// Density, kg/m³ (default 917).
    #[serde(default = "default_density")]
    pub density: f64,
    /// Initial velocity of every floe, m/s (default `[0, 0]`).
    #[serde(default, deserialize_with = "exact")]
    pub velocity: [f64; 2],
    /// Seed of the generator: same seed, same field.
    pub seed: u64,
    /// Depth of the notch cut into the middle of every edge, as a fraction
    /// (dimensionless, in `[0, 0.5]`) of the distance from the floe's
    /// centroid to the edge's midpoint; default 0: convex floes, as before
    /// the key existed (see [`crate::model::field`]).
    #[serde(default)]
    pub roughness: f64,
}

#[derive(Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "the table [integrator] (method, tolerance, max_step)"
)]
pub(super) struct IntegratorSpec {
    pub(super) method: Option<String>,
    pub(super) tolerance: Option<f64>,
    pub(super) max_step: Option<f64>,
}
