//! Case files, version 1: parsing and validation.
//!
//! The contract is `cases/README.md` (from `shared/docs/case-format.md`).
//! Every rule is checked here, and every error names the file, the line and
//! the key, or the floe's index. Loading either returns a whole [`Scenario`]
//! or an error: nothing is written anywhere before a case has loaded.

use super::field::generate_field;
use super::settings::{SettingsTable, TableSpec};
use super::{
    ContactLaw, Environment, Floe, FloeOrigin, Fluid, IntegratorKind, IntegratorSettings, Obstacle,
    Scenario, VelocitySeries, DEFAULT_ICE_DENSITY,
};
use crate::contact::{Aabb, BroadPhase};
use crate::geometry::{check_convex_ccw, sat_separation, Vec2};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::Spanned;

/// A case file that cannot be loaded: where, and what is wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}{}: {message}", file.display(), line.map(|l| format!(":{l}")).unwrap_or_default())]
pub struct CaseError {
    /// The case file.
    pub file: PathBuf,
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// What is wrong, naming the key or the floe.
    pub message: String,
}

// ---------------------------------------------------------------------------
// The file as written (serde layer). Unknown keys are errors everywhere.

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CaseFile {
    case: Spanned<CaseHeader>,
    environment: Option<Spanned<EnvSpec>>,
    contact: Spanned<ContactSpec>,
    #[serde(default)]
    floe: Vec<Spanned<FloeSpec>>,
    #[serde(default)]
    obstacle: Vec<Spanned<ObstacleSpec>>,
    #[serde(default)]
    field: Vec<Spanned<FieldSpec>>,
    formulation: Option<Spanned<BTreeMap<String, Spanned<toml::Table>>>>,
    integrator: Option<Spanned<IntegratorSpec>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CaseHeader {
    #[allow(dead_code)] // checked on the raw table before typed parsing
    version: i64,
    name: String,
    #[serde(default)]
    description: String,
    duration: f64,
    output_interval: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct EnvSpec {
    #[serde(default)]
    coriolis: f64,
    air: Option<FluidSpec>,
    water: Option<FluidSpec>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FluidSpec {
    density: f64,
    drag: f64,
    velocity: Option<[f64; 2]>,
    series: Option<Vec<[f64; 3]>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ContactSpec {
    restitution: f64,
    friction: f64,
    #[serde(default)]
    distance: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FloeSpec {
    polygon: Vec<[f64; 2]>,
    thickness: f64,
    #[serde(default = "default_density")]
    density: f64,
    #[serde(default)]
    velocity: [f64; 2],
    #[serde(default)]
    angular_velocity: f64,
}

fn default_density() -> f64 {
    DEFAULT_ICE_DENSITY
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ObstacleSpec {
    polygon: Vec<[f64; 2]>,
}

/// A `[[field]]` table as written: see [`super::field`].
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
struct IntegratorSpec {
    method: Option<String>,
    tolerance: Option<f64>,
    max_step: Option<f64>,
}

// ---------------------------------------------------------------------------
// Error location helpers.

struct Ctx<'a> {
    file: &'a Path,
    text: &'a str,
}

impl Ctx<'_> {
    fn line_of(&self, offset: usize) -> usize {
        let end = offset.min(self.text.len());
        self.text.as_bytes()[..end]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1
    }

    fn err(&self, span: Option<Range<usize>>, message: impl Into<String>) -> CaseError {
        CaseError {
            file: self.file.to_path_buf(),
            line: span.map(|s| self.line_of(s.start)),
            message: message.into(),
        }
    }

    /// The line where `key` is written inside `span`, if it can be found.
    fn key_line(&self, span: &Range<usize>, key: &str) -> Option<usize> {
        // A table's span may cover only its header: search on to the next header.
        let start = span.start.min(self.text.len());
        let end = span.end.min(self.text.len()).max(start);
        let mut offset = start;
        for (k, line) in self.text[start..].split_inclusive('\n').enumerate() {
            let header = line.trim_start().starts_with('[');
            if k > 0 && header && offset >= end {
                break;
            }
            if contains_key(line, key) {
                return Some(self.line_of(offset));
            }
            offset += line.len();
        }
        None
    }

    /// The error at the line where `key` is written inside `span`, or at the
    /// start of `span` when it cannot be found.
    fn key_err(&self, span: &Range<usize>, key: &str, message: impl Into<String>) -> CaseError {
        CaseError {
            file: self.file.to_path_buf(),
            line: Some(
                self.key_line(span, key)
                    .unwrap_or_else(|| self.line_of(span.start)),
            ),
            message: message.into(),
        }
    }
}

fn contains_key(line: &str, key: &str) -> bool {
    let code = line.split('#').next().unwrap_or("");
    let mut rest = code;
    while let Some(pos) = rest.find(key) {
        let before_ok = rest[..pos]
            .chars()
            .last()
            .is_none_or(|c| !(c.is_ascii_alphanumeric() || c == '_'));
        let after = rest[pos + key.len()..].trim_start();
        if before_ok && after.starts_with('=') {
            return true;
        }
        rest = &rest[pos + key.len()..];
    }
    false
}

fn finite2(v: [f64; 2]) -> bool {
    v[0].is_finite() && v[1].is_finite()
}

fn vec2(v: [f64; 2]) -> Vec2 {
    Vec2::new(v[0], v[1])
}

// ---------------------------------------------------------------------------

/// Reads and validates a case file; each `[formulation.<name>]` table is
/// checked by the parser in `tables` that has its name (an unknown table is
/// an error). [`crate::formulation::load_case`] passes the registry's.
pub fn load_case_with(path: &Path, tables: &[TableSpec]) -> Result<Scenario, CaseError> {
    let text = std::fs::read_to_string(path).map_err(|e| CaseError {
        file: path.to_path_buf(),
        line: None,
        message: format!("cannot read the case file: {e}"),
    })?;
    parse_case_with(&text, path, tables)
}

/// Parses and validates case text; `file` is used in messages (and, for
/// future keys holding paths, as the base of relative paths); `tables` as in
/// [`load_case_with`].
pub fn parse_case_with(
    text: &str,
    file: &Path,
    tables: &[TableSpec],
) -> Result<Scenario, CaseError> {
    let ctx = Ctx { file, text };
    // Syntax first, then the version, before any typed rule.
    let raw: toml::Table = toml::from_str(text).map_err(|e| ctx.err(e.span(), e.message()))?;
    check_version(&ctx, &raw)?;
    let case: CaseFile = toml::from_str(text).map_err(|e| ctx.err(e.span(), e.message()))?;
    build(&ctx, case, tables)
}

fn check_version(ctx: &Ctx, raw: &toml::Table) -> Result<(), CaseError> {
    let header = raw.get("case").and_then(|v| v.as_table()).ok_or_else(|| {
        ctx.err(
            None,
            "missing [case] table (with version = 1, name, duration, output_interval)",
        )
    })?;
    let whole = 0..ctx.text.len();
    match header.get("version") {
        None => Err(ctx.err(
            None,
            "missing key `version` in [case]; this reader knows version = 1",
        )),
        Some(toml::Value::Integer(1)) => Ok(()),
        Some(v) => Err(ctx.key_err(
            &whole,
            "version",
            format!("[case] version = {v} is not supported; this reader knows version = 1"),
        )),
    }
}

fn build(ctx: &Ctx, case: CaseFile, tables: &[TableSpec]) -> Result<Scenario, CaseError> {
    // [case]
    let hspan = case.case.span();
    let header = case.case.into_inner();
    if header.name.is_empty()
        || !header
            .name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
    {
        return Err(ctx.key_err(
            &hspan,
            "name",
            format!(
                "[case] name = {:?}: use only a-z, 0-9 and _ (it names output folders)",
                header.name
            ),
        ));
    }
    if !(header.duration.is_finite() && header.duration > 0.0) {
        return Err(ctx.key_err(
            &hspan,
            "duration",
            format!(
                "[case] duration = {} s must be finite and > 0",
                header.duration
            ),
        ));
    }
    if !(header.output_interval.is_finite() && header.output_interval > 0.0) {
        return Err(ctx.key_err(
            &hspan,
            "output_interval",
            format!(
                "[case] output_interval = {} s must be finite and > 0",
                header.output_interval
            ),
        ));
    }

    // [environment]
    let environment = match case.environment {
        None => Environment::default(),
        Some(env) => {
            let span = env.span();
            let env = env.into_inner();
            if !env.coriolis.is_finite() {
                return Err(ctx.key_err(
                    &span,
                    "coriolis",
                    "[environment] coriolis must be finite",
                ));
            }
            Environment {
                coriolis: env.coriolis,
                air: fluid(ctx, &span, "air", env.air)?,
                water: fluid(ctx, &span, "water", env.water)?,
            }
        }
    };

    // [contact]
    let cspan = case.contact.span();
    let c = case.contact.into_inner();
    if !(0.0..=1.0).contains(&c.restitution) {
        return Err(ctx.key_err(
            &cspan,
            "restitution",
            format!(
                "[contact] restitution = {} must be in [0, 1]",
                c.restitution
            ),
        ));
    }
    if !(c.friction.is_finite() && c.friction >= 0.0) {
        return Err(ctx.key_err(
            &cspan,
            "friction",
            format!(
                "[contact] friction = {} must be finite and >= 0",
                c.friction
            ),
        ));
    }
    if !(c.distance.is_finite() && c.distance >= 0.0) {
        return Err(ctx.key_err(
            &cspan,
            "distance",
            format!(
                "[contact] distance = {} m must be finite and >= 0",
                c.distance
            ),
        ));
    }
    let contact = ContactLaw {
        restitution: c.restitution,
        friction: c.friction,
        distance: c.distance,
    };

    // [[floe]]
    let mut floes = Vec::with_capacity(case.floe.len());
    let mut floe_spans = Vec::with_capacity(case.floe.len());
    for (i, spec) in case.floe.into_iter().enumerate() {
        let span = spec.span();
        let f = spec.into_inner();
        let what = format!("[[floe]] #{i}");
        let poly = polygon(ctx, &span, &what, &f.polygon)?;
        if !(f.thickness.is_finite() && f.thickness > 0.0) {
            return Err(ctx.key_err(
                &span,
                "thickness",
                format!(
                    "{what}: thickness = {} m must be finite and > 0",
                    f.thickness
                ),
            ));
        }
        if !(f.density.is_finite() && f.density > 0.0) {
            return Err(ctx.key_err(
                &span,
                "density",
                format!(
                    "{what}: density = {} kg/m^3 must be finite and > 0",
                    f.density
                ),
            ));
        }
        if !finite2(f.velocity) {
            return Err(ctx.key_err(
                &span,
                "velocity",
                format!("{what}: velocity must be finite"),
            ));
        }
        if !f.angular_velocity.is_finite() {
            return Err(ctx.key_err(
                &span,
                "angular_velocity",
                format!("{what}: angular_velocity must be finite"),
            ));
        }
        floes.push(Floe::from_world_polygon(
            &poly,
            f.thickness,
            f.density,
            vec2(f.velocity),
            f.angular_velocity,
            FloeOrigin::Listed(i),
        ));
        floe_spans.push(span);
    }

    // [[obstacle]]
    let mut obstacles = Vec::with_capacity(case.obstacle.len());
    let mut obstacle_spans = Vec::with_capacity(case.obstacle.len());
    for (i, spec) in case.obstacle.into_iter().enumerate() {
        let span = spec.span();
        let poly = polygon(
            ctx,
            &span,
            &format!("[[obstacle]] #{i}"),
            &spec.get_ref().polygon,
        )?;
        obstacles.push(Obstacle { polygon: poly });
        obstacle_spans.push(span);
    }

    // Listed floes must not overlap each other or an obstacle.
    check_overlaps(ctx, &floes, &floe_spans, &obstacles, &obstacle_spans)?;

    // [[field]]
    for (k, spec) in case.field.into_iter().enumerate() {
        let span = spec.span();
        let spec = spec.into_inner();
        validate_field(ctx, &span, k, &spec)?;
        let generated = generate_field(&spec, k)
            .map_err(|e| ctx.err(Some(span.clone()), format!("[[field]] #{k}: {e}")))?;
        // A field floe must not overlap a listed floe or an obstacle.
        let first = floes.len();
        for f in generated {
            floes.push(f);
        }
        check_field_against_fixed(ctx, &span, k, &floes, first, &obstacles)?;
    }

    // [formulation.*]: kept as written, each checked by its owner.
    let mut formulation_settings = BTreeMap::new();
    if let Some(spec) = case.formulation {
        let outer = spec.span();
        for (name, table) in spec.into_inner() {
            let span = table.span();
            let Some(owner) = tables.iter().find(|t| t.name == name) else {
                let known: Vec<&str> = tables.iter().map(|t| t.name).collect();
                let line = ctx
                    .key_line(&outer, &name)
                    .or(Some(ctx.line_of(span.start)));
                return Err(CaseError {
                    file: ctx.file.to_path_buf(),
                    line,
                    message: format!(
                        "unknown table [formulation.{name}]; known: {}",
                        known.join(", ")
                    ),
                });
            };
            let values = table.into_inner();
            let key_lines = values
                .keys()
                .filter_map(|k| ctx.key_line(&span, k).map(|l| (k.clone(), l)))
                .collect();
            let t = SettingsTable::new(
                &name,
                values,
                ctx.file.to_path_buf(),
                Some(ctx.line_of(span.start)),
                key_lines,
            );
            (owner.validate)(&t)?;
            formulation_settings.insert(name, t);
        }
    }

    // [integrator]
    let mut integrator = IntegratorSettings::default();
    if let Some(spec) = case.integrator {
        let span = spec.span();
        let spec = spec.into_inner();
        if let Some(m) = spec.method {
            integrator.method = m
                .parse::<IntegratorKind>()
                .map_err(|e| ctx.key_err(&span, "method", format!("[integrator] {e}")))?;
        }
        if let Some(tol) = spec.tolerance {
            if !(tol.is_finite() && tol > 0.0 && tol < 1.0) {
                return Err(ctx.key_err(
                    &span,
                    "tolerance",
                    format!("[integrator] tolerance = {tol} must be in (0, 1)"),
                ));
            }
            integrator.tolerance = tol;
        }
        if let Some(h) = spec.max_step {
            positive(ctx, &span, "integrator", "max_step", h)?;
            integrator.max_step = Some(h);
        }
    }

    Ok(Scenario {
        name: header.name,
        description: header.description,
        duration: header.duration,
        output_interval: header.output_interval,
        environment,
        contact,
        floes,
        obstacles,
        integrator,
        formulation_settings,
    })
}

fn positive(
    ctx: &Ctx,
    span: &Range<usize>,
    table: &str,
    key: &str,
    v: f64,
) -> Result<(), CaseError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(ctx.key_err(
            span,
            key,
            format!("[{table}] {key} = {v} must be finite and > 0"),
        ))
    }
}

fn fluid(
    ctx: &Ctx,
    span: &Range<usize>,
    which: &str,
    spec: Option<FluidSpec>,
) -> Result<Fluid, CaseError> {
    let Some(f) = spec else {
        return Ok(Fluid::none());
    };
    if !(f.density.is_finite() && f.density >= 0.0) {
        return Err(ctx.key_err(
            span,
            which,
            format!(
                "[environment] {which}.density = {} must be finite and >= 0",
                f.density
            ),
        ));
    }
    if !(f.drag.is_finite() && f.drag >= 0.0) {
        return Err(ctx.key_err(
            span,
            which,
            format!(
                "[environment] {which}.drag = {} must be finite and >= 0",
                f.drag
            ),
        ));
    }
    let velocity = match (f.velocity, f.series) {
        (Some(_), Some(_)) => {
            return Err(ctx.key_err(
                span,
                which,
                format!("[environment] {which}: give either velocity or series, not both"),
            ))
        }
        (Some(v), None) => {
            if !finite2(v) {
                return Err(ctx.key_err(
                    span,
                    which,
                    format!("[environment] {which}.velocity must be finite"),
                ));
            }
            VelocitySeries::Constant(vec2(v))
        }
        (None, Some(series)) => {
            if series.is_empty() {
                return Err(ctx.key_err(
                    span,
                    which,
                    format!("[environment] {which}.series needs at least one point [t, ux, uy]"),
                ));
            }
            let mut points = Vec::with_capacity(series.len());
            for (k, p) in series.iter().enumerate() {
                if !p.iter().all(|x| x.is_finite()) {
                    return Err(ctx.key_err(
                        span,
                        which,
                        format!("[environment] {which}.series point {k} is not finite"),
                    ));
                }
                if k > 0 && p[0] <= series[k - 1][0] {
                    return Err(ctx.key_err(
                        span,
                        which,
                        format!(
                            "[environment] {which}.series times must increase strictly (point {k}: t = {} after t = {})",
                            p[0],
                            series[k - 1][0]
                        ),
                    ));
                }
                points.push((p[0], Vec2::new(p[1], p[2])));
            }
            VelocitySeries::Series(points)
        }
        (None, None) => VelocitySeries::Constant(Vec2::zeros()),
    };
    Ok(Fluid {
        density: f.density,
        drag: f.drag,
        velocity,
    })
}

fn polygon(
    ctx: &Ctx,
    span: &Range<usize>,
    what: &str,
    pts: &[[f64; 2]],
) -> Result<Vec<Vec2>, CaseError> {
    let poly: Vec<Vec2> = pts.iter().map(|p| vec2(*p)).collect();
    check_convex_ccw(&poly)
        .map_err(|e| ctx.key_err(span, "polygon", format!("{what}: polygon: {e}")))?;
    Ok(poly)
}

/// Relative overlap tolerance at t = 0: touching polygons (a cradle) are
/// allowed, overlaps deeper than this fraction of the smaller size are not.
const OVERLAP_TOLERANCE: f64 = 1e-9;

fn check_overlaps(
    ctx: &Ctx,
    floes: &[Floe],
    floe_spans: &[Range<usize>],
    obstacles: &[Obstacle],
    obstacle_spans: &[Range<usize>],
) -> Result<(), CaseError> {
    let world: Vec<Vec<Vec2>> = floes
        .iter()
        .map(|f| f.shape.iter().map(|p| p + f.position).collect())
        .collect();
    let fixed: Vec<&[Vec2]> = obstacles.iter().map(|o| o.polygon.as_slice()).collect();
    let mut bodies: Vec<&[Vec2]> = world.iter().map(|w| w.as_slice()).collect();
    bodies.extend(fixed.iter().copied());
    if let Some(&(i, j)) = overlapping_pairs(&bodies, floes.len()).first() {
        let span = floe_spans.get(i).cloned();
        let msg = if j < floes.len() {
            format!(
                "[[floe]] #{i} and [[floe]] #{j} overlap at t = 0 (line {} and line {})",
                ctx.line_of(floe_spans[i].start),
                ctx.line_of(floe_spans[j].start)
            )
        } else {
            let k = j - floes.len();
            format!(
                "[[floe]] #{i} overlaps [[obstacle]] #{k} at t = 0 (obstacle at line {})",
                ctx.line_of(obstacle_spans[k].start)
            )
        };
        return Err(ctx.err(span, msg));
    }
    Ok(())
}

/// Pairs `(i, j)`, `i < j`, of polygons that overlap by more than the
/// tolerance, skipping pairs where both indices are `>= n_movable` (two
/// obstacles may overlap). Sweep and prune on x, so not all pairs.
pub(crate) fn overlapping_pairs(bodies: &[&[Vec2]], n_movable: usize) -> Vec<(usize, usize)> {
    let boxes: Vec<Aabb> = bodies
        .iter()
        .enumerate()
        .map(|(i, b)| Aabb::of_polygon(b, i >= n_movable))
        .collect();
    let mut candidates = Vec::new();
    BroadPhase::new().pairs(&boxes, 0.0, &mut candidates);
    candidates
        .into_iter()
        .filter(|&(i, j)| {
            let size = (boxes[i].max - boxes[i].min)
                .norm()
                .min((boxes[j].max - boxes[j].min).norm());
            sat_separation(bodies[i], bodies[j]) < -OVERLAP_TOLERANCE * size
        })
        .collect()
}

fn validate_field(
    ctx: &Ctx,
    span: &Range<usize>,
    k: usize,
    f: &FieldSpec,
) -> Result<(), CaseError> {
    let what = format!("[[field]] #{k}");
    let [lo, hi] = f.region;
    if !(finite2(lo) && finite2(hi) && lo[0] < hi[0] && lo[1] < hi[1]) {
        return Err(ctx.key_err(
            span,
            "region",
            format!("{what}: region must be [[xmin, ymin], [xmax, ymax]] with min < max"),
        ));
    }
    if f.count == 0 {
        return Err(ctx.key_err(span, "count", format!("{what}: count must be >= 1")));
    }
    if !(f.concentration > 0.0 && f.concentration <= 0.9) {
        return Err(ctx.key_err(
            span,
            "concentration",
            format!(
                "{what}: concentration = {} must be in (0, 0.9]",
                f.concentration
            ),
        ));
    }
    if !(finite2(f.radius) && f.radius[0] > 0.0 && f.radius[0] <= f.radius[1]) {
        return Err(ctx.key_err(
            span,
            "radius",
            format!("{what}: radius must be [min, max] with 0 < min <= max (m)"),
        ));
    }
    if !(f.sides[0] >= 3 && f.sides[0] <= f.sides[1] && f.sides[1] <= 64) {
        return Err(ctx.key_err(
            span,
            "sides",
            format!("{what}: sides must be [min, max] with 3 <= min <= max <= 64"),
        ));
    }
    if !(finite2(f.thickness) && f.thickness[0] > 0.0 && f.thickness[0] <= f.thickness[1]) {
        return Err(ctx.key_err(
            span,
            "thickness",
            format!("{what}: thickness must be [min, max] with 0 < min <= max (m)"),
        ));
    }
    if !(f.density.is_finite() && f.density > 0.0) {
        return Err(ctx.key_err(span, "density", format!("{what}: density must be > 0")));
    }
    if !finite2(f.velocity) {
        return Err(ctx.key_err(span, "velocity", format!("{what}: velocity must be finite")));
    }
    Ok(())
}

fn check_field_against_fixed(
    ctx: &Ctx,
    span: &Range<usize>,
    k: usize,
    floes: &[Floe],
    first: usize,
    obstacles: &[Obstacle],
) -> Result<(), CaseError> {
    let world: Vec<Vec<Vec2>> = floes
        .iter()
        .map(|f| f.shape.iter().map(|p| p + f.position).collect())
        .collect();
    let mut bodies: Vec<&[Vec2]> = world.iter().map(|w| w.as_slice()).collect();
    bodies.extend(obstacles.iter().map(|o| o.polygon.as_slice()));
    for (i, j) in overlapping_pairs(&bodies, floes.len()) {
        // Field floes do not overlap each other by construction; report the
        // first clash with something else.
        if j < first && i < first {
            continue;
        }
        let name = |idx: usize| -> String {
            if idx >= floes.len() {
                format!("[[obstacle]] #{}", idx - floes.len())
            } else {
                match floes[idx].origin {
                    FloeOrigin::Listed(n) => format!("[[floe]] #{n}"),
                    FloeOrigin::Field { field, index } => {
                        format!("floe {index} of [[field]] #{field} (floe index {idx})")
                    }
                }
            }
        };
        return Err(ctx.err(
            Some(span.clone()),
            format!(
                "[[field]] #{k}: {} overlaps {} at t = 0; move the region away from listed floes and obstacles",
                name(i),
                name(j)
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn key_lines_are_found_inside_inline_tables() {
        assert!(contains_key("air = { density = 1.3 }", "density"));
        assert!(!contains_key("# density = 1", "density"));
        assert!(!contains_key("xdensity = 1", "density"));
    }
}
