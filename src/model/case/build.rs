//! From the file as written ([`super::spec`]) to a [`Scenario`]: one
//! function per table, each checking every rule of its keys, in the order
//! of the file format (`[case]`, `[environment]`, `[contact]`, `[[floe]]`,
//! `[[obstacle]]`, `[[field]]`, `[formulation.*]`, `[integrator]`).

use super::overlap::{check_field_against_fixed, check_overlaps};
use super::spec::{
    CaseFile, CaseHeader, ContactSpec, EnvSpec, FieldSpec, FloeSpec, FluidSpec, IntegratorSpec,
    ObstacleSpec,
};
use super::{CaseError, Ctx};
use crate::geometry::{check_convex_ccw, Vec2};
use crate::model::field::generate_field;
use crate::model::settings::{SettingsTable, TableSpec};
use crate::model::{
    ContactLaw, Environment, Floe, FloeOrigin, Fluid, IntegratorKind, IntegratorSettings, Obstacle,
    Scenario, VelocitySeries,
};
use std::collections::BTreeMap;
use std::ops::Range;
use toml::Spanned;

/// Items of a table array with the span of each table.
type WithSpans<T> = (Vec<T>, Vec<Range<usize>>);

/// The [`Scenario`] of a parsed file, every table checked in file order
/// (the first error is the one reported).
pub(super) fn build(
    ctx: &Ctx,
    case: CaseFile,
    tables: &[TableSpec],
) -> Result<Scenario, CaseError> {
    let header = header(ctx, case.case)?;
    let environment = environment(ctx, case.environment)?;
    let contact = contact(ctx, case.contact)?;
    let (mut floes, floe_spans) = floes(ctx, case.floe)?;
    let (obstacles, obstacle_spans) = obstacles(ctx, case.obstacle)?;
    // Listed floes must not overlap each other or an obstacle.
    check_overlaps(ctx, &floes, &floe_spans, &obstacles, &obstacle_spans)?;
    fields(ctx, case.field, &mut floes, &obstacles)?;
    let formulation_settings = formulation_tables(ctx, case.formulation, tables)?;
    let integrator = integrator(ctx, case.integrator)?;
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
        restart: None,
    })
}

/// `[case]`: the name (it names output folders), the duration and the
/// output interval.
fn header(ctx: &Ctx, spec: Spanned<CaseHeader>) -> Result<CaseHeader, CaseError> {
    let hspan = spec.span();
    let header = spec.into_inner();
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
    Ok(header)
}

/// `[environment]` (optional: no wind, no current, no Coriolis force).
fn environment(ctx: &Ctx, spec: Option<Spanned<EnvSpec>>) -> Result<Environment, CaseError> {
    Ok(match spec {
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
    })
}

/// `[contact]`: restitution, friction, contact distance.
fn contact(ctx: &Ctx, spec: Spanned<ContactSpec>) -> Result<ContactLaw, CaseError> {
    let cspan = spec.span();
    let c = spec.into_inner();
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
    Ok(ContactLaw {
        restitution: c.restitution,
        friction: c.friction,
        distance: c.distance,
    })
}

/// `[[floe]]`: the listed floes, with the span of each table.
fn floes(ctx: &Ctx, specs: Vec<Spanned<FloeSpec>>) -> Result<WithSpans<Floe>, CaseError> {
    let mut floes = Vec::with_capacity(specs.len());
    let mut floe_spans = Vec::with_capacity(specs.len());
    for (i, spec) in specs.into_iter().enumerate() {
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
    Ok((floes, floe_spans))
}

/// `[[obstacle]]`: the fixed obstacles, with the span of each table.
fn obstacles(
    ctx: &Ctx,
    specs: Vec<Spanned<ObstacleSpec>>,
) -> Result<WithSpans<Obstacle>, CaseError> {
    let mut obstacles = Vec::with_capacity(specs.len());
    let mut obstacle_spans = Vec::with_capacity(specs.len());
    for (i, spec) in specs.into_iter().enumerate() {
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
    Ok((obstacles, obstacle_spans))
}

/// `[[field]]`: each field's floes, generated and appended to `floes`
/// (listed floes and earlier fields); none may overlap a floe already there
/// or an obstacle.
fn fields(
    ctx: &Ctx,
    specs: Vec<Spanned<FieldSpec>>,
    floes: &mut Vec<Floe>,
    obstacles: &[Obstacle],
) -> Result<(), CaseError> {
    for (k, spec) in specs.into_iter().enumerate() {
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
        check_field_against_fixed(ctx, &span, k, floes, first, obstacles)?;
    }
    Ok(())
}

/// `[formulation.*]`: each table kept as written and checked by its owner
/// in `tables` (an unknown table is an error).
fn formulation_tables(
    ctx: &Ctx,
    spec: Option<Spanned<BTreeMap<String, Spanned<toml::Table>>>>,
    tables: &[TableSpec],
) -> Result<BTreeMap<String, SettingsTable>, CaseError> {
    let mut formulation_settings = BTreeMap::new();
    if let Some(spec) = spec {
        let outer = spec.span();
        for (name, table) in spec.into_inner() {
            let span = table.span();
            let Some(owner) = tables.iter().find(|t| t.name == name) else {
                let known: Vec<&str> = tables.iter().map(|t| t.name).collect();
                // One spelling: a table is named like the formulation on the
                // command line (`event-driven`, not `event_driven`).
                let hint = tables
                    .iter()
                    .find(|t| t.name == name.replace('_', "-"))
                    .map_or(String::new(), |t| {
                        format!(" (did you mean [formulation.{}]? tables take the formulation's name as on the command line)", t.name)
                    });
                let line = ctx
                    .key_line(&outer, &name)
                    .or(Some(ctx.line_of(span.start)));
                return Err(CaseError {
                    file: ctx.file.to_path_buf(),
                    line,
                    message: format!(
                        "unknown table [formulation.{name}]; known: {}{hint}",
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
    Ok(formulation_settings)
}

/// `[integrator]` (optional): method, tolerance, largest step.
fn integrator(
    ctx: &Ctx,
    spec: Option<Spanned<IntegratorSpec>>,
) -> Result<IntegratorSettings, CaseError> {
    let mut integrator = IntegratorSettings::default();
    if let Some(spec) = spec {
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
    Ok(integrator)
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

fn finite2(v: [f64; 2]) -> bool {
    v[0].is_finite() && v[1].is_finite()
}

fn vec2(v: [f64; 2]) -> Vec2 {
    Vec2::new(v[0], v[1])
}
