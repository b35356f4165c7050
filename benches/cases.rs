//! Whole runs of the bundled cases, fed by `cases/`: the CPU time each
//! formulation takes on each case, and how it grows with the number of floes.
//!
//! - one group per small case (`cases/*.toml`), one benchmark per
//!   formulation (`BenchmarkId` = formulation/case): a full run of the case,
//!   as `floebench run` does it;
//! - `scaling`: the `[[field]]` family `cases/fields/scaling_100.toml`,
//!   `scaling_1000.toml` (and, behind the filter name `heavy`,
//!   `field_10000.toml`): the first 600 s of drift of 100, 1,000 and 10,000
//!   floes at concentration 0.7 with the same floe sizes and forcing.
//!
//! The measurement is the thread's CPU time. Every formulation except
//! `free-drift` runs.
//!
//! ```sh
//! cargo bench --bench cases                 # small cases and scaling 100, 1000 (a few minutes)
//! cargo bench --bench cases -- head_on      # one case
//! cargo bench --bench cases -- heavy        # the scaling group with its 10,000-floe member (long)
//! ```

#[path = "common/thread_cpu.rs"]
mod thread_cpu;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use floebench::formulation::load_case;
use floebench::formulation::{build, FormulationOptions};
use floebench::model::Scenario;
use floebench::run::batch::{case_files, contact_formulations};
use floebench::run::{RunOptions, Runner};
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::Duration;
use thread_cpu::ThreadCpu;

/// The simulated span of the scaling benchmarks, s.
const SCALING_SPAN: f64 = 600.0;

fn cases_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("cases")
}

/// Whether the heavy benchmarks were asked for (filter name `heavy`).
fn heavy() -> bool {
    std::env::args().skip(1).any(|a| a.contains("heavy"))
}

/// One full run of `scn` by `name`; returns the time reached.
fn run_once(scn: &Scenario, name: &str) -> f64 {
    match build(name, scn, &FormulationOptions::default()) {
        Ok(mut f) => {
            let r = Runner::new(RunOptions::default()).run(scn, f.name(), f.formulation.as_mut());
            r.summary.t_reached
        }
        Err(e) => {
            eprintln!("{}: {name}: {e}", scn.name);
            f64::NAN
        }
    }
}

fn per_case(c: &mut Criterion<ThreadCpu>) {
    let files = match case_files(&[cases_dir()]) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("{e}");
            return;
        }
    };
    for path in files {
        let scn = match load_case(&path) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("{e}");
                continue;
            }
        };
        let mut g = c.benchmark_group(&scn.name);
        g.sample_size(10).warm_up_time(Duration::from_millis(500));
        for name in contact_formulations() {
            g.bench_with_input(BenchmarkId::new(&name, &scn.name), &scn, |b, scn| {
                b.iter(|| black_box(run_once(scn, &name)))
            });
        }
        g.finish();
    }
}

fn scaling(c: &mut Criterion<ThreadCpu>) {
    let mut members = vec!["scaling_100", "scaling_1000"];
    if heavy() {
        members.push("field_10000");
    }
    let group = if heavy() { "scaling_heavy" } else { "scaling" };
    let mut g = c.benchmark_group(group);
    g.sample_size(10).warm_up_time(Duration::from_millis(500));
    for member in members {
        let path = cases_dir().join("fields").join(format!("{member}.toml"));
        let mut scn = match load_case(&path) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("{e}");
                continue;
            }
        };
        scn.duration = SCALING_SPAN;
        scn.output_interval = SCALING_SPAN;
        g.throughput(Throughput::Elements(scn.floes.len() as u64));
        for name in contact_formulations() {
            let id = BenchmarkId::new(&name, scn.floes.len());
            g.bench_with_input(id, &scn, |b, scn| {
                b.iter(|| black_box(run_once(scn, &name)))
            });
        }
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots().with_measurement(ThreadCpu);
    targets = per_case, scaling
}
criterion_main!(benches);
