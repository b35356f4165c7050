//! Writing a sweep's report from its finished points
//! ([`crate::sweep::Collected`]): data first, then the plots, then the page.
//!
//! ```text
//! <out>/sweep.csv                     case,formulation,settings,metric,value,unit (long format)
//! <out>/orders.csv                    case,formulation,key,fixed,metric,span,s_from,s_to,e_from,e_to,order
//! <out>/<case>/work_precision.*       per error measure: error against CPU time (log-log; a linear
//!                                     error axis where the errors are within a factor 1.5), one line
//!                                     per formulation (along its first grid key), settings marked
//! <out>/<case>/setting_<key>.*        per error measure: error against the key's value (log-log),
//!                                     each point after the first marked with the observed order
//! <out>/index.md, index.html          the page: the plan, the orders, per case the plots and points
//! ```
//!
//! `sweep.csv` holds, per finished point, `cpu` (s), `completed` and the
//! error metrics the plan's measures select, at full precision (Rust's
//! shortest round-trip form); the page rounds with
//! [`super::format::fmt_num`]. Everything but `cpu` is a deterministic
//! function of the plan, the cases and the code: two executions of a plan
//! (locally, on a cluster) give the same file but for the `cpu` rows.

use super::format::fmt_num;
use super::page::{self, Block};
use super::plot::{marked_panels, MarkedLine, MarkedPanel, Scale};
use super::ReportError;
use crate::fsio::write_atomic;
use crate::sweep::orders::{lines, observed_order, Line, Order, Span};
use crate::sweep::plan::{format_value, value_number};
use crate::sweep::Collected;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> ReportError + '_ {
    move |source| ReportError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// The metrics of `sweep.csv`: `cpu`, `completed`, then the error metrics.
fn csv_metrics(c: &Collected) -> Vec<String> {
    let mut m = vec!["cpu".to_string(), "completed".to_string()];
    m.extend(c.error_metrics());
    m
}

/// `sweep.csv`: `case,formulation,settings,metric,value,unit`, one row per
/// finished point and metric, in plan order.
pub fn sweep_csv(c: &Collected) -> String {
    let metrics = csv_metrics(c);
    let mut s = String::from("case,formulation,settings,metric,value,unit\n");
    for r in c.results.iter().flatten() {
        for name in &metrics {
            if let Some(m) = r.metric(name) {
                let _ = writeln!(
                    s,
                    "{},{},{},{},{},{}",
                    r.case, r.formulation, r.settings, m.name, m.value, m.unit
                );
            }
        }
    }
    s
}

/// `orders.csv`: one row per pair of successive values of a line.
pub fn orders_csv(orders: &[Order]) -> String {
    let mut s =
        String::from("case,formulation,key,fixed,metric,span,s_from,s_to,e_from,e_to,order\n");
    for o in orders {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{}",
            o.case,
            o.formulation,
            o.key,
            o.fixed,
            o.metric,
            o.span.as_str(),
            o.s_from,
            o.s_to,
            o.e_from,
            o.e_to,
            o.order
        );
    }
    s
}

/// The axis label of an error metric.
fn metric_label(name: &str, unit: &str) -> String {
    let what = match name {
        "position" => format!("max RMS Δx / {}", super::figures::DIAMETER),
        "kinetic_final" => "final kinetic energy error".to_string(),
        "dissipated" => "dissipated energy error".to_string(),
        other => format!("{} error", other.strip_prefix("check:").unwrap_or(other)),
    };
    if unit == "1" {
        format!("{what} (-)")
    } else {
        format!("{what} ({unit}, absolute)")
    }
}

/// The unit of `metric` among the finished points of case `case`.
fn unit_of(c: &Collected, case: &str, metric: &str) -> Option<String> {
    c.results
        .iter()
        .flatten()
        .filter(|r| r.case == case)
        .find_map(|r| r.metric(metric).map(|m| m.unit.clone()))
}

/// The legend label of a line: the formulation and the key that varies,
/// with the fixed settings.
fn line_label(c: &Collected, l: &Line) -> String {
    let name = c.plan.formulations[l.formulation].entry.name;
    let key = if l.key.is_empty() { "defaults" } else { &l.key };
    match l.fixed_label() {
        f if f.is_empty() => format!("{name}: {key}"),
        f => format!("{name}: {key} ({f})"),
    }
}

/// The label of the k-th point `(x, e)` of a line, given its points so far.
type Mark<'a> = dyn Fn(&Line, usize, &[(f64, f64, String)], (f64, f64)) -> String + 'a;

/// One panel per error metric of case `case`: `x(point)` and the marker
/// label of the k-th point of a line from its (x, y) so far.
fn panels(
    c: &Collected,
    case: usize,
    case_lines: &[&Line],
    x_label: &str,
    x_of: &dyn Fn(&Line, usize) -> Option<f64>,
    mark: &Mark,
) -> Vec<MarkedPanel> {
    let name = &c.plan.cases[case].scenario.name;
    let mut out = Vec::new();
    for metric in c.error_metrics() {
        let Some(unit) = unit_of(c, name, &metric) else {
            continue;
        };
        let mut plotted = Vec::new();
        for l in case_lines {
            let mut pts: Vec<(f64, f64, String)> = Vec::new();
            for (k, (_, id)) in l.points.iter().enumerate() {
                let Some(r) = c.result(id) else { continue };
                let (Some(x), Some(e)) = (x_of(l, k), r.metric(&metric)) else {
                    continue;
                };
                let label = mark(l, k, &pts, (x, e.value));
                pts.push((x, e.value, label));
            }
            if !pts.is_empty() {
                // The same colour and marker for a line in every panel.
                let k = case_lines
                    .iter()
                    .position(|o| std::ptr::eq(*o, *l))
                    .unwrap_or(0);
                plotted.push(MarkedLine {
                    label: line_label(c, l),
                    color: k,
                    marker: k,
                    points: pts,
                });
            }
        }
        // A measure that is zero (or not finite) at every point has nothing
        // to show on a log axis; the points table gives it.
        if !plotted.iter().flat_map(|l| &l.points).any(|p| p.1 > 0.0) {
            continue;
        }
        // Log–log shows an order as a slope; errors within a factor 1.5 of
        // each other (a measure the setting does not move) read better on a
        // linear axis, whose labels tell them apart.
        let ys = || {
            plotted
                .iter()
                .flat_map(|l| &l.points)
                .map(|p| p.1)
                .filter(|y| *y > 0.0)
        };
        let (lo, hi) = (ys().fold(f64::INFINITY, f64::min), ys().fold(0.0, f64::max));
        let log = hi >= 1.5 * lo;
        // A zero error has no place on a log axis: the panel says how many
        // were left out.
        let zeros = plotted
            .iter()
            .flat_map(|l| &l.points)
            .filter(|p| p.1 == 0.0)
            .count();
        out.push(MarkedPanel {
            title: match zeros {
                0 => metric.clone(),
                1 if log => format!("{metric} (1 point of error 0 not shown)"),
                n if log => format!("{metric} ({n} points of error 0 not shown)"),
                _ => metric.clone(),
            },
            x_label: x_label.to_string(),
            y_label: metric_label(&metric, &unit),
            x_scale: Scale::Log,
            y_scale: if log { Scale::Log } else { Scale::Linear },
            lines: plotted,
        });
    }
    out
}

/// Draws the plots of case `case` into `dir`; returns (alt text, stem).
fn case_plots(
    c: &Collected,
    case: usize,
    dir: &Path,
) -> Result<Vec<(String, String)>, ReportError> {
    let name = &c.plan.cases[case].scenario.name;
    let plot = |title: &str,
                stem: &str,
                panels: &[MarkedPanel]|
     -> Result<(String, String), ReportError> {
        let path = dir.join(stem);
        marked_panels(title, 2, panels, &path).map_err(|e| ReportError::Plot {
            path,
            message: e.to_string(),
        })?;
        Ok((title.to_string(), stem.to_string()))
    };
    let mut figs = Vec::new();
    // Work–precision: error against CPU, the lines along each first key.
    let wp_lines = lines(c.plan, true);
    let wp: Vec<&Line> = wp_lines.iter().filter(|l| l.case == case).collect();
    let cpu = |l: &Line, k: usize| {
        c.result(&l.points[k].1)
            .and_then(|r| r.metric("cpu"))
            .map(|m| m.value)
    };
    let value_mark = |l: &Line, k: usize, _: &[(f64, f64, String)], _: (f64, f64)| {
        if l.key.is_empty() {
            "defaults".to_string()
        } else {
            format_value(&l.points[k].0)
        }
    };
    let p = panels(c, case, &wp, "CPU time (s)", &cpu, &value_mark);
    if !p.is_empty() {
        figs.push(plot(
            &format!("{name}: work-precision (error against CPU time; points labelled with the first grid key)"),
            "work_precision",
            &p,
        )?);
    }
    // Error against each numeric key, every line along it.
    let all = lines(c.plan, false);
    let mut keys: Vec<&str> = Vec::new();
    for l in all.iter().filter(|l| l.case == case && !l.key.is_empty()) {
        let numeric = l.points.iter().all(|(v, _)| value_number(v).is_some());
        if numeric && l.points.len() > 1 && !keys.contains(&l.key.as_str()) {
            keys.push(&l.key);
        }
    }
    for key in keys {
        let along: Vec<&Line> = all
            .iter()
            .filter(|l| l.case == case && l.key == key)
            .collect();
        let value = |l: &Line, k: usize| value_number(&l.points[k].0);
        let order_mark = |_: &Line, _: usize, before: &[(f64, f64, String)], (x, e): (f64, f64)| {
            before
                .last()
                .and_then(|&(x0, e0, _)| observed_order((x0, e0), (x, e)))
                .map_or(String::new(), |p| format!("p = {}", fmt_num(p)))
        };
        let p = panels(c, case, &along, key, &value, &order_mark);
        if !p.is_empty() {
            figs.push(plot(
                &format!("{name}: error against {key} (p: observed order from the previous point)"),
                &format!("setting_{key}"),
                &p,
            )?);
        }
    }
    Ok(figs)
}

/// The orders table of the page: per line and metric, its successive
/// orders and the overall one.
fn orders_table(orders: &[Order]) -> Option<Block> {
    let mut rows: Vec<Vec<String>> = Vec::new();
    let mut last: Option<[&str; 5]> = None;
    for o in orders {
        let key = [
            o.case.as_str(),
            o.formulation.as_str(),
            o.key.as_str(),
            o.fixed.as_str(),
            o.metric.as_str(),
        ];
        if last != Some(key) {
            let mut row: Vec<String> = key.iter().map(|k| k.to_string()).collect();
            if row[3].is_empty() {
                row[3] = "-".into();
            }
            row.extend([String::new(), "-".into()]);
            rows.push(row);
            last = Some(key);
        }
        let Some(row) = rows.last_mut() else { continue };
        match o.span {
            Span::Successive => {
                if !row[5].is_empty() {
                    row[5].push_str(", ");
                }
                let _ = write!(
                    row[5],
                    "{} ({}→{})",
                    fmt_num(o.order),
                    format_num_value(o.s_from),
                    format_num_value(o.s_to)
                );
            }
            Span::Overall => row[6] = fmt_num(o.order),
        }
    }
    (!rows.is_empty()).then(|| Block::Table {
        header: [
            "case",
            "formulation",
            "key",
            "fixed",
            "measure",
            "successive orders p (from → to)",
            "overall p",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    })
}

/// A setting's value as the plan writes it (shortest form).
fn format_num_value(v: f64) -> String {
    format_value(&toml::Value::Float(v))
        .trim_end_matches(".0")
        .to_string()
}

/// The table of a case's finished points.
fn points_table(c: &Collected, case: &str) -> Option<Block> {
    let metrics = c.error_metrics();
    let shown: Vec<&String> = metrics
        .iter()
        .filter(|m| unit_of(c, case, m).is_some())
        .collect();
    let mut header: Vec<String> = ["formulation", "settings", "end", "CPU (s)"]
        .map(String::from)
        .to_vec();
    header.extend(shown.iter().map(|m| m.to_string()));
    let rows: Vec<Vec<String>> = c
        .results
        .iter()
        .flatten()
        .filter(|r| r.case == case)
        .map(|r| {
            let mut row = vec![
                r.formulation.clone(),
                r.settings.clone(),
                r.end.clone(),
                r.metric("cpu").map_or("-".into(), |m| fmt_num(m.value)),
            ];
            row.extend(
                shown
                    .iter()
                    .map(|m| r.metric(m).map_or("-".into(), |m| fmt_num(m.value))),
            );
            row
        })
        .collect();
    (!rows.is_empty()).then_some(Block::Table { header, rows })
}

/// Writes `sweep.csv`, `orders.csv`, the plots and the page of `c` into
/// `out`; `command` is quoted on the page. Returns the files of the page
/// and the data.
pub fn write_report(c: &Collected, out: &Path, command: &str) -> Result<Vec<PathBuf>, ReportError> {
    std::fs::create_dir_all(out).map_err(io_err(out))?;
    let orders = c.orders();
    let csv = out.join("sweep.csv");
    write_atomic(&csv, sweep_csv(c).as_bytes()).map_err(io_err(&csv))?;
    let ocsv = out.join("orders.csv");
    write_atomic(&ocsv, orders_csv(&orders).as_bytes()).map_err(io_err(&ocsv))?;

    let plan = c.plan;
    let missing = c.missing();
    let done = c.points.len() - missing.len();
    let mut blocks = vec![
        Block::Heading(1, format!("floebench sweep: {}", plan.name)),
        Block::Para(format!(
            "Produced by `{command}` (floebench {}) from the plan `{}`. Reference: **{}**. \
             {done} of {} points finished. CPU time is each run's own thread CPU seconds. \
             Errors are relative to the exact or reference value (absolute, in the unit shown, \
             where that value is 0); `position` is the largest RMS position difference from the \
             reference run over the output times, divided by the median floe diameter d_med; \
             `check:<id>` is the error of a physical check against its closed form. \
             Data: `sweep.csv`, `orders.csv`, one `points/<id>.json` per point.",
            env!("CARGO_PKG_VERSION"),
            plan.file.display(),
            plan.reference.label(),
            c.points.len(),
        )),
    ];
    if !missing.is_empty() {
        let mut names: Vec<String> = missing.iter().take(20).map(|p| p.id.clone()).collect();
        if missing.len() > 20 {
            names.push(format!("… and {} more", missing.len() - 20));
        }
        blocks.push(Block::Para(format!(
            "**Not finished** ({} points): {}",
            missing.len(),
            names.join(", ")
        )));
    }
    blocks.push(Block::Heading(2, "Plan".into()));
    blocks.push(Block::Table {
        header: ["formulation", "cases", "grid"].map(String::from).to_vec(),
        rows: plan
            .formulations
            .iter()
            .map(|f| {
                vec![
                    f.entry.name.to_string(),
                    f.cases
                        .iter()
                        .map(|&k| plan.cases[k].scenario.name.clone())
                        .collect::<Vec<_>>()
                        .join(", "),
                    if f.grid.is_empty() {
                        "defaults".into()
                    } else {
                        f.grid
                            .iter()
                            .map(|g| {
                                format!(
                                    "{} = [{}]",
                                    g.key,
                                    g.values
                                        .iter()
                                        .map(format_value)
                                        .collect::<Vec<_>>()
                                        .join(", ")
                                )
                            })
                            .collect::<Vec<_>>()
                            .join("; ")
                    },
                ]
            })
            .collect(),
    });
    blocks.push(Block::Heading(2, "Observed orders".into()));
    blocks.push(Block::Para(
        "p = ln(e_i / e_(i+1)) / ln(s_i / s_(i+1)) between successive values s of one grid key \
         (the others fixed): the exponent of e ∝ s^p (1: first order, 2: second; negative where a \
         larger value is finer, as iterations). Only completed runs with positive errors count."
            .into(),
    ));
    blocks.push(
        orders_table(&orders)
            .unwrap_or_else(|| Block::Para("No order: no key with two finished points.".into())),
    );
    for (k, case) in plan.cases.iter().enumerate() {
        let name = &case.scenario.name;
        if !c.points.iter().any(|p| p.case == k) {
            continue;
        }
        let figs = case_plots(c, k, &out.join(name))?;
        blocks.push(Block::Heading(2, name.clone()));
        blocks.push(Block::Para(format!(
            "`{}`: {} floes, {} obstacles, {} s. {}",
            case.path.display(),
            case.scenario.floes.len(),
            case.scenario.obstacles.len(),
            fmt_num(case.scenario.duration),
            case.scenario.description
        )));
        if !figs.is_empty() {
            blocks.push(Block::Figures(
                figs.iter()
                    .map(|(alt, stem)| {
                        (
                            alt.clone(),
                            format!("{name}/{stem}.png"),
                            format!("{name}/{stem}.svg"),
                        )
                    })
                    .collect(),
            ));
        }
        let zero: Vec<String> = c
            .error_metrics()
            .into_iter()
            .filter(|m| {
                let mut values = c
                    .results
                    .iter()
                    .flatten()
                    .filter(|r| &r.case == name)
                    .filter_map(|r| r.metric(m))
                    .peekable();
                values.peek().is_some() && values.all(|v| v.value == 0.0)
            })
            .collect();
        if !zero.is_empty() {
            blocks.push(Block::Para(format!(
                "Zero at every point (not plotted): {}.",
                zero.join(", ")
            )));
        }
        if let Some(t) = points_table(c, name) {
            blocks.push(t);
        }
    }
    let md = out.join("index.md");
    let html = out.join("index.html");
    write_atomic(&md, page::markdown(&blocks).as_bytes()).map_err(io_err(&md))?;
    let title = format!("floebench sweep: {}", plan.name);
    write_atomic(&html, page::html(&title, &blocks).as_bytes()).map_err(io_err(&html))?;
    Ok(vec![csv, ocsv, md, html])
}
