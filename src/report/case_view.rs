//! The picture of a case before it runs (`floebench show`): its floes at
//! their initial positions (those of `[[field]]` tables included, as the
//! case loads them), its obstacles, arrows of the wind, the current and
//! the floes' initial velocities at t = 0, a scale bar, drawn as a panel
//! of the snapshots ([`super::plot::case_view`]).

use super::figures::{obstacle_polygons, polygon};
use super::format::fmt_sig;
use super::plot::{self, Arrow, Panel, EXACT};
use super::{plot_err, ReportError};
use crate::geometry::Vec2;
use crate::model::forcing::{OutsideLog, VelocityField};
use crate::model::Scenario;
use std::path::{Path, PathBuf};

/// The longest arrow of each kind (wind, current, floe velocities), as a
/// fraction of the larger side of the case's extent: each kind has its own
/// scale, its labels give the speeds.
const ARROW_FRACTION: f64 = 0.15;

/// Points per side of the grid where a field that varies in space is drawn
/// (its arrows: `FIELD_POINTS × FIELD_POINTS`).
const FIELD_POINTS: usize = 5;

/// Palette colour of the wind's arrows (vermillion).
const WIND: usize = 1;

/// Palette colour of the current's arrows (bluish green).
const CURRENT: usize = 2;

/// The extent `(min, max)` of the floes and obstacles of `panel`, m.
fn extent(panel: &Panel) -> (Vec2, Vec2) {
    let mut lo = Vec2::new(f64::INFINITY, f64::INFINITY);
    let mut hi = -lo;
    for p in panel.floes.iter().chain(&panel.obstacles).flatten() {
        if p.0.is_finite() && p.1.is_finite() {
            lo = Vec2::new(lo.x.min(p.0), lo.y.min(p.1));
            hi = Vec2::new(hi.x.max(p.0), hi.y.max(p.1));
        }
    }
    if lo.x > hi.x {
        (Vec2::zeros(), Vec2::new(1.0, 1.0))
    } else {
        (lo, hi)
    }
}

/// `v` m/s for the labels: three significant digits.
fn speed(v: f64) -> String {
    format!("{} m/s", fmt_sig(v, 3))
}

/// Arrows `(at, velocity)` drawn from `at`, scaled so that the fastest
/// is `longest` metres long, each labelled with its speed (the title says
/// what each colour is); still arrows are left out.
fn scaled(vectors: &[(Vec2, Vec2)], longest: f64, color: usize) -> Vec<Arrow> {
    let top = vectors.iter().map(|(_, u)| u.norm()).fold(0.0, f64::max);
    if !(top > 0.0 && top.is_finite()) {
        return Vec::new();
    }
    vectors
        .iter()
        .filter(|(_, u)| u.norm() > 0.0)
        .map(|(p, u)| {
            let q = p + u * (longest / top);
            Arrow {
                from: (p.x, p.y),
                to: (q.x, q.y),
                color,
                label: speed(u.norm()),
            }
        })
        .collect()
}

/// The arrows of a fluid's velocity `field` at t = 0 over the extent
/// `(lo, hi)`: one above it when the field is uniform in space (its
/// `slot`-th place there), else a grid of [`FIELD_POINTS`]² inside it.
fn fluid_arrows(
    field: &VelocityField,
    (lo, hi): (Vec2, Vec2),
    slot: usize,
    color: usize,
) -> Vec<Arrow> {
    let side = (hi.x - lo.x).max(hi.y - lo.y).max(f64::MIN_POSITIVE);
    let longest = ARROW_FRACTION * side;
    let log = OutsideLog::default();
    let points: Vec<(Vec2, Vec2)> = if let Some(series) = field.uniform() {
        let at = Vec2::new(lo.x + slot as f64 * 0.45 * side, hi.y + 0.12 * side);
        vec![(at, series.at(0.0))]
    } else {
        let n = FIELD_POINTS;
        let step = |a: f64, b: f64, k: usize| a + (b - a) * (k as f64 + 0.5) / n as f64;
        (0..n * n)
            .map(|k| Vec2::new(step(lo.x, hi.x, k % n), step(lo.y, hi.y, k / n)))
            .map(|p| (p, field.at(&p, 0.0, &log)))
            .collect()
    };
    scaled(&points, longest, color)
}

/// Draws `scn` as it starts into the PNG file `png` and returns it: the
/// floes (numbered where they are large enough), the obstacles, the wind
/// and the current at t = 0 (only those that exert a force: a fluid of
/// drag factor `ρ C` = 0 is left out), the floes' initial velocities, a
/// scale bar; the title names the case and what the arrows are.
pub fn draw(scn: &Scenario, png: &Path) -> Result<PathBuf, ReportError> {
    let mut world = Vec::new();
    let floes: Vec<Vec<(f64, f64)>> = scn
        .floes
        .iter()
        .map(|f| {
            f.world_polygon(&f.position, f.angle, &mut world);
            polygon(world.iter().copied())
        })
        .collect();
    let mut panel = Panel {
        title: String::new(),
        labels: (0..floes.len()).map(|i| i.to_string()).collect(),
        floes,
        obstacles: obstacle_polygons(scn),
        arrows: Vec::new(),
        scale_bar: true,
    };
    let ext = extent(&panel);
    let side = (ext.1.x - ext.0.x).max(ext.1.y - ext.0.y);
    let mut kinds = Vec::new();
    // The floes' velocities first: their labels win a place over the
    // fluids'.
    let velocities: Vec<(Vec2, Vec2)> =
        scn.floes.iter().map(|f| (f.position, f.velocity)).collect();
    let moving = scaled(&velocities, ARROW_FRACTION * side, EXACT);
    if !moving.is_empty() {
        kinds.push("floe velocities (black)");
    }
    panel.arrows.extend(moving);
    let env = &scn.environment;
    let fluids = [
        (&env.air, "wind (vermillion)", WIND),
        (&env.water, "current (green)", CURRENT),
    ];
    for (k, (fluid, what, color)) in fluids.into_iter().enumerate() {
        if fluid.drag_factor() > 0.0 {
            let arrows = fluid_arrows(&fluid.velocity, ext, k, color);
            if !arrows.is_empty() {
                kinds.push(what);
            }
            panel.arrows.extend(arrows);
        }
    }
    panel.title = if kinds.is_empty() {
        "at t = 0 s: no wind, no current, no floe moving".into()
    } else {
        format!(
            "at t = 0 s; arrows: {}, each kind to its own scale",
            kinds.join(", ")
        )
    };
    let title = format!(
        "{}: {} floes, {} obstacles",
        scn.name,
        scn.floes.len(),
        scn.obstacles.len()
    );
    plot::case_view(&title, &panel, png).map_err(plot_err(png))
}
