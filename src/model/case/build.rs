//! From the file as written ([`super::spec`]) to a [`Scenario`]: one
//! function per table, each checking every rule of its keys, in the order
//! of the file format (`[case]`, `[environment]`, `[contact]`, `[[floe]]`,
//! `[[obstacle]]`, `[[field]]`, `[formulation.*]`, `[integrator]`). The
//! `[environment]` table and its velocity fields are read in
//! `environment.rs`, the `[[field]]` tables in `fields.rs`.

use super::environment::{check_grid_times, environment};
use super::fields::{fields, floe_total, validate_field};
use super::overlap::check_overlaps;
use super::spec::{
    CaseFile, CaseHeader, ContactSpec, CrushingSpec, FloeSpec, IntegratorSpec, ObstacleSpec,
};
use super::warnings::find_warnings;
use super::{vec2, CaseError, Ctx};
use crate::geometry::{area_properties, check_simple_ccw, radius_about, Vec2};
use crate::model::limits::{self, check_count};
use crate::model::settings::{SettingsTable, TableSpec};
use crate::model::{
    CaseSource, ContactLaw, Crushing, Floe, FloeHistory, FloeOrigin, FractureSettings,
    IntegratorKind, IntegratorSettings, Obstacle, Scenario,
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
    let crushing_line = ctx.key_line(&case.contact.span(), "crushing");
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
    let field_lines: Vec<usize> = case
        .field
        .iter()
        .map(|f| ctx.line_of(f.span().start))
        .collect();
    fields(ctx, case.field, &mut floes, &obstacles)?;
    let mut key_lines: BTreeMap<String, usize> = case
        .fracture
        .as_ref()
        .map(|t| {
            ["model", "impact"]
                .into_iter()
                .filter_map(|k| {
                    ctx.key_line(&t.span(), k)
                        .map(|l| (format!("fracture.{k}"), l))
                })
                .collect()
        })
        .unwrap_or_default();
    if let Some(l) = crushing_line {
        key_lines.insert("contact.crushing".into(), l);
    }
    let formulation_settings = formulation_tables(ctx, case.formulation, tables, header.duration)?;
    let integrator = integrator(ctx, case.integrator, header.duration)?;
    let fracture = fracture_table(ctx, case.fracture, &floes)?;
    if contact.crushing.is_some() && fracture.lattice_impacts() {
        // The lattice resolves an impact as rigid bodies' contact in its
        // nodes, with no bound: it is not loaded by the crushing pressure
        // (docs/physics.md §10.2).
        return Err(CaseError {
            file: ctx.file.to_path_buf(),
            line: crushing_line,
            message: "[contact] crushing: not with [fracture] impact = \"lattice\" yet: the lattices resolve an impact without the crushing bound (use impact = \"rigid\", whose percussions read the bounded impulses)".to_string(),
        });
    }
    for (i, f) in floes.iter_mut().enumerate() {
        f.id = i;
    }
    // Every other rule first: an empty case is refused last.
    if floes.is_empty() {
        return Err(ctx.err(
            Some(hspan.clone()),
            format!(
                "case `{}` has no floe ({}): a case needs at least one floe (a [[floe]] table, or a [[field]] with count > 0)",
                header.name,
                match obstacles.len() {
                    0 => "and no obstacle".to_string(),
                    n => format!("only {n} obstacle{}", if n == 1 { "" } else { "s" }),
                }
            ),
        ));
    }
    let source = CaseSource {
        file: ctx.file.to_path_buf(),
        case_lines: ["duration", "output_interval", "name"]
            .into_iter()
            .filter_map(|k| ctx.key_line(&hspan, k).map(|l| (k.to_string(), l)))
            .chain([("case".to_string(), ctx.line_of(hspan.start))])
            .collect(),
        key_lines,
        floe_lines: floes
            .iter()
            .map(|f| match f.origin {
                FloeOrigin::Listed(k) => floe_spans.get(k).map(|s| ctx.line_of(s.start)),
                FloeOrigin::Field { field, .. } => field_lines.get(field).copied(),
            })
            .collect(),
        warnings: Vec::new(),
    };
    let history = FloeHistory::new(floes.len());
    let mut scn = Scenario {
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
        source,
    };
    find_warnings(&mut scn);
    Ok(scn)
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
    let crushing = match c.crushing {
        None => None,
        Some(k) => Some(ctx.at(&cspan, "crushing", crushing(k))?),
    };
    Ok(ContactLaw {
        restitution: c.restitution,
        friction: c.friction,
        distance: c.distance,
        crushing,
    })
}

/// `[contact] crushing`: one law, each number within its limit.
fn crushing(k: CrushingSpec) -> Result<Crushing, String> {
    let name = |l: &limits::Limit| format!("[contact] {}", l.key);
    match (k.strength, k.p0, k.exponent) {
        (Some(s), None, None) => Ok(Crushing::Strength {
            strength: limits::CRUSHING_STRENGTH.check(&name(&limits::CRUSHING_STRENGTH), s)?,
        }),
        (None, Some(p0), Some(ex)) => Ok(Crushing::PressureArea {
            p0: limits::CRUSHING_P0.check(&name(&limits::CRUSHING_P0), p0)?,
            exponent: limits::CRUSHING_EXPONENT.check(&name(&limits::CRUSHING_EXPONENT), ex)?,
        }),
        (Some(_), Some(_), _) | (Some(_), _, Some(_)) => Err(
            "[contact] crushing: give either `strength` (Pa) or `p0` and `exponent`, not both"
                .to_string(),
        ),
        (None, Some(_), None) => {
            Err("[contact] crushing: `p0` needs `exponent` (in [-1, 0])".to_string())
        }
        (None, None, Some(_)) => Err("[contact] crushing: `exponent` needs `p0` (Pa)".to_string()),
        (None, None, None) => {
            Err("[contact] crushing: give `strength` (Pa) or `p0` (Pa) and `exponent`".to_string())
        }
    }
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
        let which = f.origin.label();
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
