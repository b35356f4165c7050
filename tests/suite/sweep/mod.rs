//! `floebench sweep`: the observed orders that theory predicts, measured by
//! the sweep itself on small plans of the bundled cases; resuming; an
//! interrupted point; the tasks of a cluster job against the local run;
//! bad plans.
//!
//! This file holds what the submodules share: a plan written from bundled
//! cases, its loading, and a local sweep that returns what was done and the
//! observed orders. The tests are in the submodules, one topic each.

mod bad_plans;
mod cluster;
mod orders;
mod plans;
mod resume;

use crate::common::case_path;
use floebench::sweep::collect;
use floebench::sweep::execute::{run_local, ExecOptions, Executed};
use floebench::sweep::orders::Order;
use floebench::sweep::plan::{load_plan, Plan};
use floebench::sweep::points::points;
use std::path::{Path, PathBuf};

/// A plan of `cases` (bundled names) with `body` after `[sweep]`'s
/// `cases` line, written into `dir`.
fn plan_file(dir: &Path, cases: &[&str], body: &str) -> PathBuf {
    let list: Vec<String> = cases
        .iter()
        .map(|c| format!("{:?}", case_path(c).display().to_string()))
        .collect();
    let text = format!(
        "[sweep]\nversion = 1\nname = \"t\"\ncases = [{}]\n{body}\n",
        list.join(", ")
    );
    let path = dir.join("plan.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn load(path: &Path) -> Plan {
    load_plan(path).unwrap_or_else(|e| panic!("{e}"))
}

/// Runs every point of the plan at `path` into `out`; returns what was done
/// and the observed orders.
fn sweep(path: &Path, out: &Path) -> (Executed, Vec<Order>) {
    let plan = load(path);
    let pts = points(&plan);
    let done = run_local(
        &plan,
        &pts,
        out,
        ExecOptions {
            jobs: 2,
            progress: false,
        },
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let orders = collect(&plan, pts, out).orders();
    (done, orders)
}
