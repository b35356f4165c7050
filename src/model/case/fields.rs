//! The `[[field]]` tables (docs/case-format.md): the numbers of each
//! seeded floe field checked before any is generated, the total number of
//! floes, and the generation of the fields' floes ([`crate::model::field`]).

use super::overlap::check_field_against_fixed;
use super::spec::FieldSpec;
use super::{CaseError, Ctx};
use crate::model::field::generate_field;
use crate::model::limits::{self, Limit};
use crate::model::{Floe, Obstacle};
use std::ops::Range;
use toml::Spanned;

/// `[[field]]`: each field's floes, generated and appended to `floes`
/// (listed floes and earlier fields); none may overlap a floe already there
/// or an obstacle.
pub(super) fn fields(
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

/// The numbers of a `[[field]]` table, each within its limit.
pub(super) fn validate_field(
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
pub(super) fn floe_total(
    ctx: &Ctx,
    listed: usize,
    fields: &[Spanned<FieldSpec>],
) -> Result<usize, CaseError> {
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
