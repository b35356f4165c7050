//! Lines through a grid and the observed convergence orders along them.
//!
//! A **line** is the points of one `[[formulation]]` on one case where one
//! grid key varies and the others are fixed (a one-key grid has one line
//! per case; a two-key grid has one line along each key per value of the
//! other). Along a line with numeric values `s_1 < s_2 < …` and errors
//! `e_i`, the **observed order** between successive values is
//!
//! ```text
//! p_i = ln(e_i / e_{i+1}) / ln(s_i / s_{i+1})
//! ```
//!
//! the exponent of `e ∝ s^p` fitted through the two points (and, for a
//! line of three values or more, the same between its smallest and largest
//! value: the **overall** order): 1 for a
//! first-order scheme refined in its step, 2 for a second-order one. A key
//! where a larger value is finer (`iterations`) gives a negative order
//! (`e ∝ 1/n`: −1). An order is given only where both points finished,
//! both runs completed and both errors are positive (a zero error, reached
//! exactly or at rounding, has no order).

use super::execute::PointResult;
use super::plan::{product, value_number, Plan, Setting};
use super::points::point_id;

/// Points of one formulation on one case along one grid key.
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    /// The case (index into [`Plan::cases`]).
    pub case: usize,
    /// The `[[formulation]]` (index into [`Plan::formulations`]).
    pub formulation: usize,
    /// The key that varies (empty for a grid without keys: one point).
    pub key: String,
    /// The other keys' values.
    pub fixed: Vec<Setting>,
    /// The key's values in the order written, with the point's id.
    pub points: Vec<(toml::Value, String)>,
}

impl Line {
    /// The fixed settings as `key=value;…` (empty when none).
    pub fn fixed_label(&self) -> String {
        self.fixed
            .iter()
            .map(Setting::label)
            .collect::<Vec<_>>()
            .join(";")
    }
}

/// The lines of `plan`. With `first_key_only`, only the lines along each
/// formulation's first grid key (the work–precision plots: each point on
/// one line); else along every key (the orders).
pub fn lines(plan: &Plan, first_key_only: bool) -> Vec<Line> {
    let mut out = Vec::new();
    for (fi, f) in plan.formulations.iter().enumerate() {
        for &c in &f.cases {
            let name = &plan.cases[c].scenario.name;
            if f.grid.is_empty() {
                out.push(Line {
                    case: c,
                    formulation: fi,
                    key: String::new(),
                    fixed: Vec::new(),
                    points: vec![(
                        toml::Value::String(String::new()),
                        point_id(name, f.entry.name, &[]),
                    )],
                });
                continue;
            }
            let keys = if first_key_only { 1 } else { f.grid.len() };
            for k in 0..keys {
                // Every combination of the other keys, in grid order.
                let others = f.grid.iter().enumerate().filter(|(j, _)| *j != k);
                let fixed_sets = product(others.map(|(_, g)| g));
                let g = &f.grid[k];
                for fixed in fixed_sets {
                    let points = g
                        .values
                        .iter()
                        .map(|v| {
                            // The point's settings in grid order.
                            let mut settings = fixed.clone();
                            settings.insert(
                                k,
                                Setting {
                                    key: g.key.clone(),
                                    value: v.clone(),
                                },
                            );
                            (v.clone(), point_id(name, f.entry.name, &settings))
                        })
                        .collect();
                    out.push(Line {
                        case: c,
                        formulation: fi,
                        key: g.key.clone(),
                        fixed,
                        points,
                    });
                }
            }
        }
    }
    out
}

/// The observed order `ln(e_a / e_b) / ln(s_a / s_b)` between the points
/// `(s_a, e_a)` and `(s_b, e_b)` (see the module doc); `None` unless both
/// values and both errors are positive and the values differ.
pub fn observed_order((sa, ea): (f64, f64), (sb, eb): (f64, f64)) -> Option<f64> {
    // `+ 0.0`: equal errors give an order of 0, not -0.
    (sa > 0.0 && sb > 0.0 && ea > 0.0 && eb > 0.0 && sa != sb)
        .then(|| (ea / eb).ln() / (sa / sb).ln() + 0.0)
}

/// A point of a line: (value of the key, error).
type Point = (f64, f64);

/// Which two points of a line an [`Order`] joins.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Span {
    /// Two successive values.
    Successive,
    /// The smallest and the largest value (lines of three points or more):
    /// the order over the whole refinement, which a factor that changes from
    /// one value to the next (such as where a step grid meets a stop time)
    /// does not move as much.
    Overall,
}

impl Span {
    /// `successive` or `overall`.
    pub fn as_str(self) -> &'static str {
        match self {
            Span::Successive => "successive",
            Span::Overall => "overall",
        }
    }
}

/// One observed order between two values of a line.
#[derive(Debug, Clone, PartialEq)]
pub struct Order {
    /// Case name.
    pub case: String,
    /// Formulation name.
    pub formulation: String,
    /// The key that varies.
    pub key: String,
    /// The other keys' values, `key=value;…`.
    pub fixed: String,
    /// The metric (error measure).
    pub metric: String,
    /// Between successive values, or between the smallest and the largest.
    pub span: Span,
    /// The smaller value of the key.
    pub s_from: f64,
    /// The larger value.
    pub s_to: f64,
    /// The error at `s_from`.
    pub e_from: f64,
    /// The error at `s_to`.
    pub e_to: f64,
    /// `ln(e_from / e_to) / ln(s_from / s_to)`.
    pub order: f64,
}

/// The observed orders of every line of `plan` (along every key) for each
/// metric in `metrics`, from the finished points (`result(id)`).
pub fn orders<'a>(
    plan: &Plan,
    metrics: &[String],
    result: impl Fn(&str) -> Option<&'a PointResult>,
) -> Vec<Order> {
    let mut out = Vec::new();
    for line in lines(plan, false) {
        let mut pts: Vec<(f64, &PointResult)> = line
            .points
            .iter()
            .filter_map(|(v, id)| Some((value_number(v)?, result(id)?)))
            .filter(|(_, r)| r.metric("completed").is_some_and(|m| m.value == 1.0))
            .collect();
        if pts.len() < 2 {
            continue;
        }
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let case = plan.cases[line.case].scenario.name.clone();
        let formulation = plan.formulations[line.formulation].entry.name.to_string();
        for metric in metrics {
            let se: Vec<(f64, f64)> = pts
                .iter()
                .filter_map(|(v, r)| Some((*v, r.metric(metric)?.value)))
                .collect();
            let mut pairs: Vec<(Span, Point, Point)> = se
                .windows(2)
                .map(|w| (Span::Successive, w[0], w[1]))
                .collect();
            if let (true, Some(&first), Some(&last)) = (se.len() > 2, se.first(), se.last()) {
                pairs.push((Span::Overall, first, last));
            }
            for (span, a, b) in pairs {
                let Some(order) = observed_order(a, b) else {
                    continue;
                };
                out.push(Order {
                    case: case.clone(),
                    formulation: formulation.clone(),
                    key: line.key.clone(),
                    fixed: line.fixed_label(),
                    metric: metric.clone(),
                    span,
                    s_from: a.0,
                    s_to: b.0,
                    e_from: a.1,
                    e_to: b.1,
                    order,
                });
            }
        }
    }
    out
}
