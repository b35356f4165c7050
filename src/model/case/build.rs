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
use crate::geometry::{area_properties, check_simple_ccw, radius_about, Vec2};
use crate::model::field::generate_field;
use crate::model::forcing::{Extent, GridField, LinearField, Outside, Scale, VortexField};
use crate::model::limits::{self, check_count, Limit};
use crate::model::settings::{SettingsTable, TableSpec};
use crate::model::{
    ContactLaw, Environment, Floe, FloeHistory, FloeOrigin, Fluid, FractureSettings,
    IntegratorKind, IntegratorSettings, Obstacle, Scenario, VelocityField, VelocitySeries,
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
    let hspan = case.case.span();
    let header = header(ctx, case.case)?;
    let env_span = case.environment.as_ref().map_or(0..0, |e| e.span());
    let environment = environment(ctx, case.environment)?;
    for (which, fluid) in [("air", &environment.air), ("water", &environment.water)] {
        check_grid_times(ctx, &env_span, which, fluid, header.duration)?;
    }
    let contact = contact(ctx, case.contact)?;
    let (mut floes, floe_spans) = floes(ctx, case.floe)?;
    let (obstacles, obstacle_spans) = obstacles(ctx, case.obstacle)?;
    // Every field's numbers, the number of floes and the memory of a run
    // are checked before any field is generated.
    for (k, spec) in case.field.iter().enumerate() {
        validate_field(ctx, &spec.span(), k, spec.get_ref())?;
    }
    let total = floe_total(ctx, floes.len(), &case.field)?;
    check_memory(ctx, &hspan, &header, total)?;
    // Listed floes must not overlap each other or an obstacle.
    check_overlaps(ctx, &floes, &floe_spans, &obstacles, &obstacle_spans)?;
    fields(ctx, case.field, &mut floes, &obstacles)?;
    let formulation_settings = formulation_tables(ctx, case.formulation, tables, header.duration)?;
    let integrator = integrator(ctx, case.integrator, header.duration)?;
    let fracture = fracture_table(ctx, case.fracture, &floes)?;
    for (i, f) in floes.iter_mut().enumerate() {
        f.id = i;
    }
    let history = FloeHistory::new(floes.len());
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
        fracture,
        history,
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
    ctx.at(
        &hspan,
        "duration",
        limits::DURATION.check("[case] duration", header.duration),
    )?;
    ctx.at(
        &hspan,
        "output_interval",
        limits::OUTPUT_INTERVAL.check("[case] output_interval", header.output_interval),
    )?;
    ctx.at(
        &hspan,
        "output_interval",
        check_count(
            &limits::OUTPUTS,
            "[case] output_interval",
            header.output_interval,
            header.duration,
        ),
    )?;
    Ok(header)
}

/// `[environment]` (optional: no wind, no current, no Coriolis force).
fn environment(ctx: &Ctx, spec: Option<Spanned<EnvSpec>>) -> Result<Environment, CaseError> {
    Ok(match spec {
        None => Environment::default(),
        Some(env) => {
            let span = env.span();
            let env = env.into_inner();
            ctx.at(
                &span,
                "coriolis",
                limits::CORIOLIS.check("[environment] coriolis", env.coriolis),
            )?;
            Environment {
                coriolis: env.coriolis,
                air: fluid(ctx, &span, "air", env.air)?,
                water: fluid(ctx, &span, "water", env.water)?,
                outside: Default::default(),
            }
        }
    })
}

/// `[contact]`: restitution, friction, contact distance.
fn contact(ctx: &Ctx, spec: Spanned<ContactSpec>) -> Result<ContactLaw, CaseError> {
    let cspan = spec.span();
    let c = spec.into_inner();
    let rules = [
        (&limits::RESTITUTION, c.restitution),
        (&limits::FRICTION, c.friction),
        (&limits::CONTACT_DISTANCE, c.distance),
    ];
    for (limit, v) in rules {
        let name = format!("[contact] {}", limit.key);
        ctx.at(&cspan, limit.key, limit.check(&name, v))?;
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
        let rules = [
            (&limits::THICKNESS, f.thickness),
            (&limits::DENSITY, f.density),
            (&limits::ANGULAR_VELOCITY, f.angular_velocity),
        ];
        for (limit, v) in rules {
            ctx.at(
                &span,
                limit.key,
                limit.check(&format!("{what}: {}", limit.key), v),
            )?;
        }
        ctx.at(
            &span,
            "velocity",
            limits::SPEED.check_vector(&format!("{what}: velocity"), f.velocity),
        )?;
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
        obstacles.push(Obstacle::new(poly));
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
    duration: f64,
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
                Some(duration),
            );
            (owner.validate)(&t)?;
            formulation_settings.insert(name, t);
        }
    }
    Ok(formulation_settings)
}

/// `[fracture]` (optional: absent means no fracture), read by
/// [`FractureSettings::from_table`] with the line of each key.
fn fracture_table(
    ctx: &Ctx,
    spec: Option<Spanned<toml::Table>>,
    floes: &[Floe],
) -> Result<FractureSettings, CaseError> {
    let Some(spec) = spec else {
        return Ok(FractureSettings::default());
    };
    let span = spec.span();
    // The split (src/fracture/split.rs) cuts a convex floe along a chord.
    if let Some((i, f)) = floes.iter().enumerate().find(|(_, f)| !f.is_convex()) {
        let which = match f.origin {
            FloeOrigin::Listed(k) => format!("[[floe]] #{k}"),
            FloeOrigin::Field { field, index } => format!("[[field]] #{field} floe {index}"),
        };
        return Err(ctx.err(
            Some(span),
            format!(
                "[fracture]: floe {i} ({which}) is not convex; fracture splits convex floes only (docs/case-format.md \"Polygons\")"
            ),
        ));
    }
    let values = spec.into_inner();
    let key_lines = values
        .keys()
        .filter_map(|k| ctx.key_line(&span, k).map(|l| (k.clone(), l)))
        .collect();
    let t = SettingsTable::new(
        "fracture",
        values,
        ctx.file.to_path_buf(),
        Some(ctx.line_of(span.start)),
        key_lines,
        None,
    )
    .with_header("[fracture]");
    FractureSettings::from_table(&t, floes)
}

/// `[integrator]` (optional): method, tolerance, largest step (which also
/// bounds the number of steps over `duration`, s).
fn integrator(
    ctx: &Ctx,
    spec: Option<Spanned<IntegratorSpec>>,
    duration: f64,
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
            integrator.tolerance = ctx.at(
                &span,
                "tolerance",
                limits::TOLERANCE.check("[integrator] tolerance", tol),
            )?;
        }
        if let Some(h) = spec.max_step {
            let name = "[integrator] max_step";
            ctx.at(&span, "max_step", limits::STEP.check(name, h))?;
            ctx.at(
                &span,
                "max_step",
                check_count(&limits::STEPS, name, h, duration),
            )?;
            integrator.max_step = Some(h);
        }
    }
    Ok(integrator)
}

/// `air` or `water` of `[environment]`: density, drag and the velocity
/// field (docs/case-format.md, "Forcing fields").
fn fluid(
    ctx: &Ctx,
    env_span: &Range<usize>,
    which: &str,
    spec: Option<Spanned<FluidSpec>>,
) -> Result<Fluid, CaseError> {
    let Some(f) = spec else {
        return Ok(Fluid::none());
    };
    // Inline tables have their own span; a `[environment.air]` table points
    // at the environment's.
    let span = &if f.span().start < ctx.text.len() {
        f.span()
    } else {
        env_span.clone()
    };
    let f = f.into_inner();
    for (limit, v) in [(&limits::FLUID_DENSITY, f.density), (&limits::DRAG, f.drag)] {
        let name = format!("[environment] {which}.{}", limit.key);
        ctx.at(span, which, limit.check(&name, v))?;
    }
    let kind = f.field.as_deref().unwrap_or("uniform");
    let allowed: &[&str] = match kind {
        "uniform" => &["velocity", "series"],
        "linear" => &["velocity", "at", "gradient", "extent", "outside", "scale"],
        "vortex" => &["center", "radius", "speed", "center_velocity", "scale"],
        "netcdf" => &["file", "variables", "origin", "start", "outside"],
        other => {
            return Err(ctx.key_err(
                span,
                "field",
                format!(
                    "[environment] {which}.field = {other:?}: expected \"uniform\", \"linear\", \"vortex\" or \"netcdf\""
                ),
            ))
        }
    };
    if let Some(key) = f.written().into_iter().find(|k| !allowed.contains(k)) {
        return Err(ctx.key_err(
            span,
            key,
            format!(
                "[environment] {which}.{key} does not belong to field = \"{kind}\" (its keys: {})",
                allowed.join(", ")
            ),
        ));
    }
    let velocity = match kind {
        "linear" => VelocityField::Linear(linear_field(ctx, span, which, &f)?),
        "vortex" => VelocityField::Vortex(vortex_field(ctx, span, which, &f)?),
        "netcdf" => VelocityField::Grid(grid_field(ctx, span, which, &f)?),
        _ => VelocityField::Uniform(uniform_velocity(ctx, span, which, &f)?),
    };
    Ok(Fluid {
        density: f.density,
        drag: f.drag,
        velocity,
    })
}

/// A key that a field needs.
fn required<T: Clone>(
    ctx: &Ctx,
    span: &Range<usize>,
    which: &str,
    kind: &str,
    key: &str,
    v: &Option<T>,
) -> Result<T, CaseError> {
    v.clone().ok_or_else(|| {
        ctx.key_err(
            span,
            which,
            format!("[environment] {which}: field = \"{kind}\" needs `{key}`"),
        )
    })
}

/// A velocity `[u, v]` within the fluid speed limit, m/s.
fn fluid_velocity(
    ctx: &Ctx,
    span: &Range<usize>,
    which: &str,
    key: &str,
    v: [f64; 2],
) -> Result<Vec2, CaseError> {
    let name = format!("[environment] {which}.{key}");
    ctx.at(span, key, limits::FLUID_SPEED.check_vector(&name, v))?;
    Ok(vec2(v))
}

/// A point `[x, y]` within the coordinate limit, m.
fn fluid_point(
    ctx: &Ctx,
    span: &Range<usize>,
    which: &str,
    key: &str,
    v: [f64; 2],
) -> Result<Vec2, CaseError> {
    for (axis, c) in ["x", "y"].iter().zip(v) {
        let name = format!("[environment] {which}.{key}: {axis}");
        ctx.at(span, key, limits::COORDINATE.check(&name, c))?;
    }
    Ok(vec2(v))
}

/// `outside = "error" | "clamp"` (default error).
fn outside_rule(
    ctx: &Ctx,
    span: &Range<usize>,
    which: &str,
    v: &Option<String>,
) -> Result<Outside, CaseError> {
    match v.as_deref() {
        None | Some("error") => Ok(Outside::Error),
        Some("clamp") => Ok(Outside::Clamp),
        Some(other) => Err(ctx.key_err(
            span,
            "outside",
            format!("[environment] {which}.outside = {other:?}: expected \"error\" or \"clamp\""),
        )),
    }
}

/// Strictly increasing times within the series-time limit, one message.
fn increasing_times(
    ctx: &Ctx,
    span: &Range<usize>,
    which: &str,
    key: &str,
    times: impl Iterator<Item = f64>,
) -> Result<(), CaseError> {
    let mut last: Option<f64> = None;
    for (k, t) in times.enumerate() {
        let name = format!("[environment] {which}.{key} point {k}: t");
        ctx.at(span, key, limits::SERIES_TIME.check(&name, t))?;
        if let Some(prev) = last.filter(|&prev| t <= prev) {
            return Err(ctx.key_err(
                span,
                key,
                format!(
                    "[environment] {which}.{key} times must increase strictly (point {k}: t = {t} after t = {prev})"
                ),
            ));
        }
        last = Some(t);
    }
    Ok(())
}

/// `scale = [[t, factor], …]` of an analytic field (absent: 1).
fn scale_series(
    ctx: &Ctx,
    span: &Range<usize>,
    which: &str,
    v: &Option<Vec<[f64; 2]>>,
) -> Result<Scale, CaseError> {
    let Some(points) = v else {
        return Ok(Scale { points: Vec::new() });
    };
    if points.is_empty() {
        return Err(ctx.key_err(
            span,
            "scale",
            format!("[environment] {which}.scale needs at least one point [t, factor]"),
        ));
    }
    increasing_times(ctx, span, which, "scale", points.iter().map(|p| p[0]))?;
    for (k, p) in points.iter().enumerate() {
        let name = format!("[environment] {which}.scale point {k}: factor");
        ctx.at(span, "scale", limits::FIELD_SCALE.check(&name, p[1]))?;
    }
    Ok(Scale {
        points: points.iter().map(|p| (p[0], p[1])).collect(),
    })
}

/// `velocity` or `series` (or neither: calm), uniform in space.
fn uniform_velocity(
    ctx: &Ctx,
    span: &Range<usize>,
    which: &str,
    f: &FluidSpec,
) -> Result<VelocitySeries, CaseError> {
    Ok(match (f.velocity, &f.series) {
        (Some(_), Some(_)) => {
            return Err(ctx.key_err(
                span,
                which,
                format!("[environment] {which}: give either velocity or series, not both"),
            ))
        }
        (Some(v), None) => {
            let name = format!("[environment] {which}.velocity");
            ctx.at(span, which, limits::FLUID_SPEED.check_vector(&name, v))?;
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
                let name = format!("[environment] {which}.series point {k}");
                ctx.at(
                    span,
                    which,
                    limits::SERIES_TIME.check(&format!("{name}: t"), p[0]),
                )?;
                ctx.at(
                    span,
                    which,
                    limits::FLUID_SPEED.check_vector(&format!("{name}: velocity"), [p[1], p[2]]),
                )?;
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
    })
}

/// `field = "linear"`: `velocity` at `at`, `gradient`, `extent` (required:
/// the field grows without bound, and its largest speed over the extent
/// bounds the steps), optional `outside`, `scale`.
fn linear_field(
    ctx: &Ctx,
    span: &Range<usize>,
    which: &str,
    f: &FluidSpec,
) -> Result<LinearField, CaseError> {
    let velocity = required(ctx, span, which, "linear", "velocity", &f.velocity)?;
    let velocity = fluid_velocity(ctx, span, which, "velocity", velocity)?;
    let at = fluid_point(ctx, span, which, "at", f.at.unwrap_or([0.0, 0.0]))?;
    let gradient = required(ctx, span, which, "linear", "gradient", &f.gradient)?;
    for (r, row) in gradient.iter().enumerate() {
        for (c, g) in row.iter().enumerate() {
            let name = format!("[environment] {which}.gradient[{r}][{c}]");
            ctx.at(span, "gradient", limits::VELOCITY_GRADIENT.check(&name, *g))?;
        }
    }
    let [lo, hi] = required(ctx, span, which, "linear", "extent", &f.extent)?;
    let min = fluid_point(ctx, span, which, "extent", lo)?;
    let max = fluid_point(ctx, span, which, "extent", hi)?;
    if !(min.x < max.x && min.y < max.y) {
        return Err(ctx.key_err(
            span,
            "extent",
            format!(
                "[environment] {which}.extent = [[{}, {}], [{}, {}]]: the lower corner must be below and left of the upper one",
                lo[0], lo[1], hi[0], hi[1]
            ),
        ));
    }
    let extent = Extent { min, max };
    let field = LinearField {
        velocity,
        at,
        gradient,
        extent,
        outside: outside_rule(ctx, span, which, &f.outside)?,
        scale: scale_series(ctx, span, which, &f.scale)?,
    };
    check_field_speed(ctx, span, which, &VelocityField::Linear(field.clone()))?;
    Ok(field)
}

/// The largest speed of a field within the fluid speed limit.
fn check_field_speed(
    ctx: &Ctx,
    span: &Range<usize>,
    which: &str,
    field: &VelocityField,
) -> Result<(), CaseError> {
    let name = format!("[environment] {which}: the field's largest speed");
    ctx.at(
        span,
        which,
        limits::FLUID_SPEED.check(&name, field.max_speed()),
    )
    .map(|_| ())
}

/// `field = "vortex"`: `center`, `radius`, `speed`, optional
/// `center_velocity` and `scale`.
fn vortex_field(
    ctx: &Ctx,
    span: &Range<usize>,
    which: &str,
    f: &FluidSpec,
) -> Result<VortexField, CaseError> {
    let center = required(ctx, span, which, "vortex", "center", &f.center)?;
    let center = fluid_point(ctx, span, which, "center", center)?;
    let radius = required(ctx, span, which, "vortex", "radius", &f.radius)?;
    let name = format!("[environment] {which}.radius");
    ctx.at(span, "radius", limits::VORTEX_RADIUS.check(&name, radius))?;
    let speed = required(ctx, span, which, "vortex", "speed", &f.speed)?;
    let name = format!("[environment] {which}.speed");
    ctx.at(span, "speed", limits::FLUID_SPEED.check(&name, speed))?;
    let drift = fluid_velocity(
        ctx,
        span,
        which,
        "center_velocity",
        f.center_velocity.unwrap_or([0.0, 0.0]),
    )?;
    let field = VortexField {
        center,
        radius,
        speed,
        center_velocity: drift,
        scale: scale_series(ctx, span, which, &f.scale)?,
    };
    check_field_speed(ctx, span, which, &VelocityField::Vortex(field.clone()))?;
    Ok(field)
}

/// `field = "netcdf"`: `file` (relative to the case file), `variables`
/// (ERA5's `u10`, `v10` for air and Copernicus Marine's `uo`, `vo` for
/// water by default), `origin` for lon/lat grids, `start`, `outside`.
fn grid_field(
    ctx: &Ctx,
    span: &Range<usize>,
    which: &str,
    f: &FluidSpec,
) -> Result<GridField, CaseError> {
    let file = required(ctx, span, which, "netcdf", "file", &f.file)?;
    let variables = f.variables.clone().unwrap_or_else(|| {
        let names = if which == "air" {
            ["u10", "v10"]
        } else {
            ["uo", "vo"]
        };
        names.map(String::from)
    });
    if let Some(o) = f.origin {
        let ok = o[0].is_finite() && o[1].is_finite() && o[0].abs() <= 360.0 && o[1].abs() < 90.0;
        if !ok {
            return Err(ctx.key_err(
                span,
                "origin",
                format!(
                    "[environment] {which}.origin = [{}, {}]: give [longitude, latitude] in degrees, |lon| <= 360 and |lat| < 90",
                    o[0], o[1]
                ),
            ));
        }
    }
    let base = ctx.file.parent().unwrap_or(std::path::Path::new(""));
    let path = base.join(&file);
    let request = crate::model::netcdf::GridRequest {
        variables: variables.clone(),
        origin: f.origin,
        start: f.start.clone(),
    };
    let data = crate::model::netcdf::read_grid(&path, &request)
        .map_err(|e| ctx.key_err(span, "file", format!("[environment] {which}.file: {e}")))?;
    let max_speed = data
        .u
        .iter()
        .zip(&data.v)
        .map(|(u, v)| u.hypot(*v))
        .fold(0.0, f64::max);
    let n = data.x.len() * data.y.len();
    let uniform_in_space = data
        .u
        .chunks(n)
        .zip(data.v.chunks(n))
        .all(|(u, v)| u.iter().all(|a| *a == u[0]) && v.iter().all(|b| *b == v[0]));
    let field = GridField {
        file,
        variables,
        outside: outside_rule(ctx, span, which, &f.outside)?,
        data: std::sync::Arc::new(data),
        max_speed,
        uniform_in_space,
    };
    check_field_speed(ctx, span, which, &VelocityField::Grid(field.clone()))?;
    Ok(field)
}

/// The time axis of a gridded field covers the run (`[0, duration]`)
/// unless `outside = "clamp"`.
fn check_grid_times(
    ctx: &Ctx,
    span: &Range<usize>,
    which: &str,
    fluid: &Fluid,
    duration: f64,
) -> Result<(), CaseError> {
    let VelocityField::Grid(g) = &fluid.velocity else {
        return Ok(());
    };
    let t = &g.data.t;
    if g.outside == Outside::Clamp || t.len() < 2 {
        return Ok(());
    }
    let (t0, t1) = (t[0], t[t.len() - 1]);
    if t0 > 0.0 || t1 < duration {
        return Err(ctx.key_err(
            span,
            "file",
            format!(
                "[environment] {which}.file: {}: the time axis covers [{t0}, {t1}] s of the run, not [0, {duration}] s (`start` sets the date of t = 0; `outside = \"clamp\"` holds the first and last records)",
                g.file
            ),
        ));
    }
    Ok(())
}

fn polygon(
    ctx: &Ctx,
    span: &Range<usize>,
    what: &str,
    pts: &[[f64; 2]],
) -> Result<Vec<Vec2>, CaseError> {
    // The count first: the self-intersection test is quadratic in the
    // vertices.
    ctx.at(
        span,
        "polygon",
        limits::VERTICES.check_integer(&format!("{what}: polygon vertices"), pts.len() as i128),
    )?;
    for (k, p) in pts.iter().enumerate() {
        for (axis, v) in ["x", "y"].iter().zip(p) {
            let name = format!("{what}: polygon vertex {k}: {axis}");
            ctx.at(span, "polygon", limits::COORDINATE.check(&name, *v))?;
        }
    }
    let poly: Vec<Vec2> = pts.iter().map(|p| vec2(*p)).collect();
    check_simple_ccw(&poly)
        .map_err(|e| ctx.key_err(span, "polygon", format!("{what}: polygon: {e}")))?;
    if crate::geometry::decompose::convex_parts(&poly).is_none() {
        return Err(ctx.key_err(
            span,
            "polygon",
            format!(
                "{what}: polygon: cannot be split into convex parts (nearly degenerate outline)"
            ),
        ));
    }
    let r = radius_about(&poly, &area_properties(&poly).centroid);
    let name = format!("{what}: polygon circumradius");
    ctx.at(span, "polygon", limits::RADIUS.check(&name, r))?;
    Ok(poly)
}

/// The numbers of a `[[field]]` table, each within its limit.
fn validate_field(
    ctx: &Ctx,
    span: &Range<usize>,
    k: usize,
    f: &FieldSpec,
) -> Result<(), CaseError> {
    let what = format!("[[field]] #{k}");
    let named = |key: &str| format!("{what}: {key}");
    for (c, corner) in f.region.iter().enumerate() {
        for (axis, v) in ["x", "y"].iter().zip(corner) {
            let name = named(&format!("region corner {c}: {axis}"));
            ctx.at(span, "region", limits::COORDINATE.check(&name, *v))?;
        }
    }
    let [lo, hi] = f.region;
    if !(lo[0] < hi[0] && lo[1] < hi[1]) {
        return Err(ctx.key_err(
            span,
            "region",
            format!("{what}: region must be [[xmin, ymin], [xmax, ymax]] with min < max"),
        ));
    }
    ctx.at(
        span,
        "count",
        limits::FLOES.check_integer(&named("count"), f.count as i128),
    )?;
    ctx.at(
        span,
        "concentration",
        limits::CONCENTRATION.check(&named("concentration"), f.concentration),
    )?;
    let sides = f.sides.map(|n| n as f64);
    ordered_pair(ctx, span, &what, "radius", &limits::RADIUS, f.radius)?;
    ordered_pair(ctx, span, &what, "sides", &limits::VERTICES, sides)?;
    ordered_pair(
        ctx,
        span,
        &what,
        "thickness",
        &limits::THICKNESS,
        f.thickness,
    )?;
    ctx.at(
        span,
        "density",
        limits::DENSITY.check(&named("density"), f.density),
    )?;
    ctx.at(
        span,
        "velocity",
        limits::SPEED.check_vector(&named("velocity"), f.velocity),
    )?;
    ctx.at(
        span,
        "roughness",
        limits::ROUGHNESS.check(&named("roughness"), f.roughness),
    )?;
    // A notch doubles the vertices of a floe, within the polygon limit.
    if f.roughness > 0.0 && 2.0 * sides[1] > limits::VERTICES.max {
        return Err(ctx.key_err(
            span,
            "roughness",
            format!(
                "{what}: roughness > 0 doubles the vertices of each floe: sides max must be at most {} (got {})",
                limits::show(limits::VERTICES.max / 2.0),
                f.sides[1]
            ),
        ));
    }
    Ok(())
}

/// A range `[min, max]` of a field (`key`: `radius`, `sides`, `thickness`):
/// both ends within `limit`, `min <= max`.
fn ordered_pair(
    ctx: &Ctx,
    span: &Range<usize>,
    what: &str,
    key: &str,
    limit: &Limit,
    pair: [f64; 2],
) -> Result<(), CaseError> {
    for (end, v) in ["min", "max"].iter().zip(pair) {
        let name = format!("{what}: {key} {end}");
        let checked = if limit.integer {
            limit.check_integer(&name, v as i128).map(|_| v)
        } else {
            limit.check(&name, v)
        };
        ctx.at(span, key, checked)?;
    }
    if pair[0] > pair[1] {
        return Err(ctx.key_err(
            span,
            key,
            format!("{what}: {key} must be [min, max] with min <= max"),
        ));
    }
    Ok(())
}

/// The number of floes of the case, listed and generated, within the limit
/// (checked before any field is generated); the error names the field that
/// goes over.
fn floe_total(ctx: &Ctx, listed: usize, fields: &[Spanned<FieldSpec>]) -> Result<usize, CaseError> {
    let listed_name = "the listed [[floe]] tables";
    if listed > 0 {
        limits::FLOES
            .check_integer(listed_name, listed as i128)
            .map_err(|m| ctx.err(None, m))?;
    }
    let mut total = listed as i128;
    for (k, spec) in fields.iter().enumerate() {
        let count = spec.get_ref().count;
        total += count as i128;
        if !limits::FLOES.admits(total as f64) {
            return Err(ctx.key_err(
                &spec.span(),
                "count",
                format!(
                    "[[field]] #{k}: count = {count} brings the case to {total} floes, above the limit of {} floes: {}",
                    limits::show(limits::FLOES.max),
                    limits::FLOES.why
                ),
            ));
        }
    }
    Ok(total as usize)
}

/// The memory a run of the case needs, estimated before any field is
/// generated ([`limits::run_memory_bytes`]), within [`limits::RUN_BYTES`];
/// the error points at the output interval.
fn check_memory(
    ctx: &Ctx,
    hspan: &Range<usize>,
    header: &CaseHeader,
    floes: usize,
) -> Result<(), CaseError> {
    let outputs = limits::output_count(header.duration, header.output_interval);
    let bytes = limits::run_memory_bytes(floes as f64, outputs);
    if limits::RUN_BYTES.admits(bytes) {
        return Ok(());
    }
    Err(ctx.key_err(
        hspan,
        "output_interval",
        format!(
            "[case] output_interval = {} s: {} outputs of {floes} floes need about {} of memory, above the limit of {}: {}; use a larger output_interval or fewer floes",
            limits::show(header.output_interval),
            limits::show(outputs),
            limits::show_bytes(bytes),
            limits::show_bytes(limits::RUN_BYTES.max),
            limits::RUN_BYTES.why
        ),
    ))
}

fn vec2(v: [f64; 2]) -> Vec2 {
    Vec2::new(v[0], v[1])
}
