//! The points of a plan: every (case, formulation, combination of the
//! grid), each with a file name and a fingerprint, and the tasks that run
//! them (the reference runs first, then the points, alone or in chunks).
//!
//! A point's **id** names its result file, `points/<id>.json`:
//! `<case>__<formulation>__<key>=<value>__…` (`defaults` for an empty
//! grid), characters other than `[A-Za-z0-9._=-]` written `_`. Two
//! `[[formulation]]` tables that produce the same point share it (it runs
//! once). Its **fingerprint** digests the case file's text, the
//! formulation, the settings and the reference: a result file whose
//! fingerprint differs (the case or the reference changed) is not reused.

use super::digest;
use super::plan::{settings_label, table_of, Plan, Reference, Setting};

/// One point of a plan.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    /// The file name of its result (see the module doc).
    pub id: String,
    /// The case (index into [`Plan::cases`]).
    pub case: usize,
    /// The formulation (registry name).
    pub formulation: &'static str,
    /// The `[formulation.<table>]` it reads, if any.
    pub table: Option<&'static str>,
    /// Its settings, in the grid's key order.
    pub settings: Vec<Setting>,
    /// The fingerprint (16 hex digits).
    pub fingerprint: String,
}

/// A unit of work: the reference run of one case, or some points.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Task {
    /// The reference run of case `0` (index into [`Plan::cases`]).
    Reference(usize),
    /// These points (indices into [`points`]).
    Points(Vec<usize>),
}

fn safe(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '=' | '-') {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// The id of a point (see the module doc).
pub fn point_id(case: &str, formulation: &str, settings: &[Setting]) -> String {
    let mut parts = vec![safe(case), safe(formulation)];
    if settings.is_empty() {
        parts.push("defaults".into());
    }
    parts.extend(settings.iter().map(|s| safe(&s.label())));
    parts.join("__")
}

/// The fingerprint of the reference run of case `case` (16 hex digits).
pub fn reference_fingerprint(plan: &Plan, case: usize) -> String {
    let c = &plan.cases[case];
    format!(
        "{:016x}",
        digest(format!("{:016x}\n{}", c.digest, plan.reference.label()).as_bytes())
    )
}

/// Every point of `plan`, in plan order (cases of each `[[formulation]]`,
/// then its combinations), each once.
pub fn points(plan: &Plan) -> Vec<Point> {
    let mut out: Vec<Point> = Vec::new();
    for f in &plan.formulations {
        for &c in &f.cases {
            for settings in f.combinations() {
                let case = &plan.cases[c];
                let id = point_id(&case.scenario.name, f.entry.name, &settings);
                if out.iter().any(|p| p.id == id) {
                    continue;
                }
                let key = format!(
                    "{:016x}\n{}\n{}\n{}",
                    case.digest,
                    f.entry.name,
                    settings_label(&settings),
                    plan.reference.label()
                );
                out.push(Point {
                    id,
                    case: c,
                    formulation: f.entry.name,
                    table: table_of(f.entry),
                    settings,
                    fingerprint: format!("{:016x}", digest(key.as_bytes())),
                });
            }
        }
    }
    out
}

/// The tasks of `plan`: one per reference run (none for `reference =
/// "exact"`), then the points in chunks of `chunk` (at least 1), in order.
pub fn tasks(plan: &Plan, points: &[Point], chunk: usize) -> Vec<Task> {
    let mut out: Vec<Task> = match plan.reference {
        Reference::Exact => Vec::new(),
        Reference::Run { .. } => (0..plan.cases.len())
            .filter(|&c| points.iter().any(|p| p.case == c))
            .map(Task::Reference)
            .collect(),
    };
    let idx: Vec<usize> = (0..points.len()).collect();
    out.extend(idx.chunks(chunk.max(1)).map(|c| Task::Points(c.to_vec())));
    out
}

/// A digest of the whole plan's work (every reference and point
/// fingerprint, in order, and the chunking): a task list written for one
/// plan is refused for another.
pub fn plan_digest(plan: &Plan, points: &[Point], chunk: usize) -> String {
    let mut key = format!("chunk {chunk}\n");
    for t in tasks(plan, points, chunk) {
        match t {
            Task::Reference(c) => {
                key.push_str(&format!("reference {}\n", reference_fingerprint(plan, c)))
            }
            Task::Points(ps) => {
                for p in ps {
                    key.push_str(&format!(
                        "point {} {}\n",
                        points[p].id, points[p].fingerprint
                    ));
                }
            }
        }
    }
    format!("{:016x}", digest(key.as_bytes()))
}
