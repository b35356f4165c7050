//! The parameters of a case and of its runs, as the report page states
//! them: forcing, floes (thickness, density, initial velocities), contact
//! law, and each formulation's settings (defaults resolved). Values quoted
//! from the case file are printed as given; resolved settings by
//! [`super::format::fmt_num`].

use super::format::fmt_num;
use super::page::Block;
use crate::analysis::comparison::CaseComparison;
use crate::model::forcing::{Outside, Scale};
use crate::model::{Fluid, Scenario, VelocityField, VelocitySeries};
use crate::record::{SettingValue, Unit};

/// Floes listed one by one, at most; beyond, a summary.
const LISTED: usize = 6;

/// `(x, y)`.
fn pair(x: f64, y: f64) -> String {
    format!("({x}, {y})")
}

/// A velocity series: constant, or its points (the first and last of a long one).
fn series(v: &VelocitySeries) -> String {
    match v {
        VelocitySeries::Constant(u) => format!("{} m/s", pair(u.x, u.y)),
        VelocitySeries::Series(points) => {
            let at = |p: &(f64, crate::geometry::Vec2)| {
                format!("{} m/s at {} s", pair(p.1.x, p.1.y), p.0)
            };
            if points.len() <= LISTED {
                format!(
                    "piecewise linear: {}",
                    points.iter().map(at).collect::<Vec<_>>().join(", ")
                )
            } else {
                format!(
                    "piecewise linear, {} points, from {} to {}",
                    points.len(),
                    points.first().map(at).unwrap_or_default(),
                    points.last().map(at).unwrap_or_default()
                )
            }
        }
    }
}

/// `, scaled by a factor …` when a scale series is given.
fn scaled(s: &Scale) -> String {
    if s.points.is_empty() {
        return String::new();
    }
    let pts: Vec<String> = s
        .points
        .iter()
        .map(|p| format!("{} at {} s", p.1, p.0))
        .collect();
    if pts.len() <= LISTED {
        format!(
            ", scaled by a factor piecewise linear in time: {}",
            pts.join(", ")
        )
    } else {
        format!(
            ", scaled by a factor piecewise linear in time ({} points)",
            pts.len()
        )
    }
}

/// A velocity field: uniform (constant or series), linear, vortex or gridded.
fn field(v: &VelocityField) -> String {
    let outside = |o: Outside| match o {
        Outside::Error => "",
        Outside::Clamp => ", clamped outside",
    };
    match v {
        VelocityField::Uniform(s) => series(s),
        VelocityField::Linear(f) => format!(
            "linear field: {} m/s at {} m, gradient [[{}, {}], [{}, {}]] 1/s on [{}, {}] × [{}, {}] m{}{}",
            pair(f.velocity.x, f.velocity.y),
            pair(f.at.x, f.at.y),
            f.gradient[0][0],
            f.gradient[0][1],
            f.gradient[1][0],
            f.gradient[1][1],
            f.extent.min.x,
            f.extent.max.x,
            f.extent.min.y,
            f.extent.max.y,
            outside(f.outside),
            scaled(&f.scale)
        ),
        VelocityField::Vortex(f) => format!(
            "Rankine vortex: centre {} m, core radius {} m, peak speed {} m/s, drift {} m/s{}",
            pair(f.center.x, f.center.y),
            f.radius,
            f.speed,
            pair(f.center_velocity.x, f.center_velocity.y),
            scaled(&f.scale)
        ),
        VelocityField::Grid(g) => format!(
            "gridded from {} (variables {}, {}; {} × {} nodes, {} times; largest speed {} m/s{})",
            g.file,
            g.variables[0],
            g.variables[1],
            g.data.x.len(),
            g.data.y.len(),
            g.data.t.len(),
            fmt_num(g.max_speed),
            outside(g.outside)
        ),
    }
}

/// A fluid: `ρ = …, C = …, velocity …`, or `none`.
fn fluid(f: &Fluid, velocity_word: &str) -> String {
    if f.drag_factor() == 0.0 {
        return "none".into();
    }
    format!(
        "density {} kg/m³, drag coefficient {}, {velocity_word} {}",
        f.density,
        f.drag,
        field(&f.velocity)
    )
}

/// `a m` when all equal (as given), else `a–b m` rounded ([`fmt_num`]).
fn range(values: impl Iterator<Item = f64>, unit: &str) -> String {
    let v: Vec<f64> = values.collect();
    let (lo, hi) = v
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| {
            (l.min(x), h.max(x))
        });
    if v.is_empty() {
        "-".into()
    } else if lo == hi {
        format!("{lo} {unit}")
    } else {
        // A range is drawn (a field's floes), not quoted: rounded.
        format!("{}–{} {unit}", fmt_num(lo), fmt_num(hi))
    }
}

/// The initial velocities of the floes.
fn velocities(scn: &Scenario) -> String {
    let moving: Vec<(usize, &crate::model::Floe)> = scn
        .floes
        .iter()
        .enumerate()
        .filter(|(_, f)| f.velocity.norm() != 0.0 || f.angular_velocity != 0.0)
        .collect();
    if moving.is_empty() {
        return "every floe at rest".into();
    }
    if moving.len() <= LISTED {
        let one = |(i, f): &(usize, &crate::model::Floe)| {
            let spin = if f.angular_velocity != 0.0 {
                format!(", spin {} rad/s", f.angular_velocity)
            } else {
                String::new()
            };
            format!("floe {i} {} m/s{spin}", pair(f.velocity.x, f.velocity.y))
        };
        let rest = scn.floes.len() - moving.len();
        let mut s = moving.iter().map(one).collect::<Vec<_>>().join("; ");
        if rest > 0 {
            s.push_str(&format!("; the {rest} others at rest"));
        }
        return s;
    }
    let fastest = moving
        .iter()
        .map(|(_, f)| f.velocity.norm())
        .fold(0.0, f64::max);
    format!(
        "{} of {} floes moving, speeds up to {} m/s",
        moving.len(),
        scn.floes.len(),
        fmt_num(fastest)
    )
}

/// The case's parameters, one item each.
pub(super) fn case_parameters(scn: &Scenario) -> Block {
    let env = &scn.environment;
    let c = &scn.contact;
    Block::List(vec![
        format!("wind (air): {}", fluid(&env.air, "wind")),
        format!("ocean (water): {}", fluid(&env.water, "current")),
        format!("Coriolis parameter f = {} 1/s", env.coriolis),
        format!(
            "{}: thickness {}, density {}; {}",
            count(scn.floes.len(), "floe"),
            range(scn.floes.iter().map(|f| f.thickness), "m"),
            range(scn.floes.iter().map(|f| f.density), "kg/m³"),
            count(scn.obstacles.len(), "obstacle")
        ),
        format!("initial velocities: {}", velocities(scn)),
        format!(
            "contact: restitution e = {}, friction μ = {}, distance {}",
            c.restitution,
            c.friction,
            if c.distance == 0.0 {
                "chosen by each formulation".to_string()
            } else {
                format!("{} m", c.distance)
            }
        ),
        format!(
            "duration {} s, outputs every {} s",
            scn.duration, scn.output_interval
        ),
    ])
}

/// A resolved setting's number: as written when short (`0.1`, `4`), else
/// by [`fmt_num`].
fn setting_number(v: f64) -> String {
    let plain = format!("{v}");
    if plain.len() <= 8 {
        plain
    } else {
        fmt_num(v)
    }
}

/// `1 floe`, `2 floes`.
fn count(n: usize, what: &str) -> String {
    format!("{n} {what}{}", if n == 1 { "" } else { "s" })
}

/// Each formulation's settings, defaults resolved (as its `summary.json`).
pub(super) fn settings_table(comp: &CaseComparison) -> Block {
    let rows = comp
        .runs
        .iter()
        .map(|r| {
            let settings: Vec<String> = r
                .summary
                .settings
                .0
                .iter()
                .map(|s| match &s.value {
                    SettingValue::Number(v)
                        if matches!(s.unit, Unit::Dimensionless | Unit::Count) =>
                    {
                        format!("{} = {}", s.name, setting_number(*v))
                    }
                    SettingValue::Number(v) => {
                        format!("{} = {} {}", s.name, setting_number(*v), s.unit.symbol())
                    }
                    SettingValue::Text(t) => format!("{} = {t}", s.name),
                })
                .collect();
            vec![
                r.summary.formulation.clone(),
                if settings.is_empty() {
                    "-".into()
                } else {
                    settings.join(", ")
                },
            ]
        })
        .collect();
    Block::Table {
        header: vec!["formulation".into(), "settings (defaults resolved)".into()],
        rows,
    }
}
