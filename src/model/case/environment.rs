//! The `[environment]` table (docs/case-format.md): the Coriolis
//! parameter, the air and the water, and each fluid's velocity field
//! (uniform, `linear`, `vortex` or `netcdf`, [`crate::model::forcing`]),
//! every key checked against its limit; a gridded field is read here, from
//! its CF NetCDF file ([`crate::model::netcdf`]).

use super::spec::{EnvSpec, FluidSpec};
use super::{vec2, CaseError, Ctx};
use crate::geometry::Vec2;
use crate::model::forcing::{Extent, GridField, LinearField, Outside, Scale, VortexField};
use crate::model::limits;
use crate::model::{Environment, Fluid, VelocityField, VelocitySeries};
use std::ops::Range;
use toml::Spanned;

/// `[environment]` (optional: no wind, no current, no Coriolis force).
pub(super) fn environment(
    ctx: &Ctx,
    spec: Option<Spanned<EnvSpec>>,
) -> Result<Environment, CaseError> {
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
    // The keys of each field are checked before the typed reading
    // ([`check_field_keys`]); here only the field's name.
    if field_keys(kind).is_none() {
        return Err(ctx.key_err(
            span,
            "field",
            format!(
                "[environment] {which}.field = {kind:?}: expected \"uniform\", \"linear\", \"vortex\" or \"netcdf\""
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

/// The fields of a fluid's velocity, with the keys each takes (beside
/// `density`, `drag` and `field`), docs/case-format.md "Forcing fields".
const FIELDS: &[(&str, &[&str])] = &[
    ("uniform", &["velocity", "series"]),
    (
        "linear",
        &["velocity", "at", "gradient", "extent", "outside", "scale"],
    ),
    (
        "vortex",
        &["center", "radius", "speed", "center_velocity", "scale"],
    ),
    (
        "netcdf",
        &["file", "variables", "origin", "start", "outside"],
    ),
];

/// The keys field `kind` takes (`None` for an unknown field).
fn field_keys(kind: &str) -> Option<&'static [&'static str]> {
    FIELDS.iter().find(|f| f.0 == kind).map(|f| f.1)
}

/// `[environment]` as far as [`check_field_keys`] reads it: each fluid's
/// keys, whatever their values.
#[derive(serde::Deserialize)]
struct RawCase {
    environment: Option<Spanned<RawEnv>>,
}

#[derive(serde::Deserialize)]
struct RawEnv {
    air: Option<Spanned<toml::Table>>,
    water: Option<Spanned<toml::Table>>,
}

/// Refuses a key of another field in a fluid's table (`radius`, a vortex
/// key, in a uniform field), before the typed reading, whose message would
/// be about the value's type: the key is named, with the fields it belongs
/// to and the keys of the fluid's own field. An unknown key (a typo) and
/// an unknown field are left to the typed reading, which names them.
pub(super) fn check_field_keys(ctx: &Ctx) -> Result<(), CaseError> {
    let Ok(RawCase {
        environment: Some(env),
    }) = toml::from_str::<RawCase>(ctx.text)
    else {
        return Ok(());
    };
    let env_span = env.span();
    let env = env.into_inner();
    for (which, fluid) in [("air", env.air), ("water", env.water)] {
        let Some(fluid) = fluid else { continue };
        let span = if fluid.span().start < ctx.text.len() {
            fluid.span()
        } else {
            env_span.clone()
        };
        let table = fluid.into_inner();
        let kind = match table.get("field") {
            None => "uniform",
            Some(toml::Value::String(k)) => k.as_str(),
            Some(_) => continue,
        };
        let Some(allowed) = field_keys(kind) else {
            continue;
        };
        for key in table.keys() {
            let owners: Vec<String> = FIELDS
                .iter()
                .filter(|f| f.1.contains(&key.as_str()))
                .map(|f| format!("field = \"{}\"", f.0))
                .collect();
            if owners.is_empty() || allowed.contains(&key.as_str()) {
                continue;
            }
            return Err(ctx.key_err(
                &span,
                key,
                format!(
                    "[environment] {which}.{key} does not belong to field = \"{kind}\" (its keys: {}); `{key}` is a key of {}",
                    allowed.join(", "),
                    owners.join(" and ")
                ),
            ));
        }
    }
    Ok(())
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
pub(super) fn check_grid_times(
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
