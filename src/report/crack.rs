//! The crack figure of a percussion ([`PercussionRecord`], docs/physics.md
//! §9.8): a plan view of the struck floe's lattice at rest in its body
//! frame, the intact bonds in sky blue, the broken ones in vermillion, and
//! the impact as a black arrow along its normal ending at the contact
//! point. The one drawing of a crack: `floebench percussion-2d --plot` and
//! the comparison report's `crack_<formulation>` figures both call
//! [`draw`]. Rendered by [`super::plot::network_view`] (embedded DejaVu Sans).

use super::format::fmt_num;
use super::plot::{self, PlanView, PlotError, Series};
use crate::model::fracture::{ImpactRecord, PercussionRecord};
use std::path::{Path, PathBuf};

/// Palette index of the intact bonds (sky blue).
const INTACT: usize = 5;
/// Palette index of the broken bonds (vermillion).
const BROKEN: usize = 1;

/// The arrow's length as a fraction of the lattice's largest distance from
/// the origin (the floe's radius about its centre of mass).
const ARROW: f64 = 0.4;

/// A polyline, points `(x, y)` in metres; a NaN point is a gap.
type Polyline = Vec<(f64, f64)>;

/// The bonds of `rec` at rest as two broken polylines, `(intact, broken)`:
/// each spring a segment followed by a NaN point (a gap in the line).
fn bonds(rec: &PercussionRecord) -> (Polyline, Polyline) {
    let (mut intact, mut broken) = (Vec::new(), Vec::new());
    for (s, &ok) in rec.springs.iter().zip(&rec.intact) {
        let (Some(a), Some(b)) = (rec.nodes.get(s[0]), rec.nodes.get(s[1])) else {
            continue;
        };
        let list = if ok { &mut intact } else { &mut broken };
        list.extend([(a[0], a[1]), (b[0], b[1]), (f64::NAN, f64::NAN)]);
    }
    (intact, broken)
}

/// The impact arrows of `rec`, one per striker: a shaft of [`ARROW`] times
/// the lattice's radius along the normal, ending at the contact point, and
/// a head of two strokes at ±25°.
fn arrows(rec: &PercussionRecord) -> Polyline {
    let radius = rec
        .nodes
        .iter()
        .map(|p| p[0].hypot(p[1]))
        .fold(0.0, f64::max);
    let len = ARROW * radius;
    let head = 0.25 * len;
    let (c, s) = (25f64.to_radians().cos(), 25f64.to_radians().sin());
    let mut out = Vec::new();
    for i in &rec.impacts {
        let [px, py] = i.point;
        let [nx, ny] = i.normal;
        // The head's strokes point back along −n, turned by ±25°.
        let back = |sign: f64| {
            (
                px + head * (-c * nx + sign * s * ny),
                py + head * (-sign * s * nx - c * ny),
            )
        };
        out.extend([
            (px - len * nx, py - len * ny),
            (px, py),
            (f64::NAN, f64::NAN),
            back(1.0),
            (px, py),
            back(-1.0),
            (f64::NAN, f64::NAN),
        ]);
    }
    out
}

/// How `rec`'s impacts read: `u_N = … m/s, striker … kg` (or `an
/// obstacle`) for each striker, separated by `; `.
pub fn impact_text(rec: &PercussionRecord) -> String {
    let one = |i: &ImpactRecord| {
        let striker = match i.striker_mass {
            Some(m) => format!("striker {} kg", fmt_num(m)),
            None => "striker an obstacle".to_string(),
        };
        format!("u_N = {} m/s, {striker}", fmt_num(i.speed))
    };
    rec.impacts.iter().map(one).collect::<Vec<_>>().join("; ")
}

/// Draws `rec` under `title` into `<stem>.png` and `<stem>.svg`; returns
/// `[png, svg]`.
pub fn draw(rec: &PercussionRecord, title: &str, stem: &Path) -> Result<[PathBuf; 2], PlotError> {
    let (intact, broken) = bonds(rec);
    let paths = [
        Series {
            dash: Some(0),
            ..Series::new("bonds", INTACT, intact)
        },
        Series {
            dash: Some(0),
            ..Series::new(
                format!("broken bonds ({})", rec.broken.len()),
                BROKEN,
                broken,
            )
        },
        Series {
            dash: Some(0),
            ..Series::new(
                format!("impact: {}", impact_text(rec)),
                plot::EXACT,
                arrows(rec),
            )
        },
    ];
    plot::network_view(
        &PlanView {
            title,
            paths: &paths,
            obstacles: &[],
            labels: &[],
        },
        stem,
    )
}

/// How to read a crack figure of a run, for the report page.
pub fn caption(rec: &PercussionRecord, formulation: &str) -> String {
    format!(
        "the lattice of floe {} in the {formulation} run at its percussion of largest lattice loss (t = {} s, {} J lost in the lattice, {} J booked as fracture energy), at rest in the floe's body frame (m, centre of mass at the origin): intact bonds blue, the {} broken bonds red (they trace the crack), the black arrows the equivalent impacts, one per striker ({}), ending at the contact points; it left {} pieces (ids {:?}); data in {formulation}/percussion.json",
        rec.floe,
        fmt_num(rec.t),
        fmt_num(rec.loss),
        fmt_num(rec.energy),
        rec.broken.len(),
        impact_text(rec),
        rec.children.len(),
        rec.children,
    )
}
