//! Whole runs of the bundled cases, fed by `cases/`: the CPU time each
//! formulation takes on each case, and how it grows with the number of floes.
//!
//! - one group per small case (`cases/*.toml`), one benchmark per
//!   formulation (`BenchmarkId` = formulation/case): a full run of the case,
//!   as `floebench run` does it;
//! - `scaling`: the `[[field]]` family `cases/fields/scaling_100.toml`,
//!   `scaling_1000.toml` (and, behind the filter name `heavy`,
//!   `field_10000.toml`): the first 600 s of drift of 100, 1,000 and 10,000
//!   floes at concentration 0.7 with the same floe sizes and forcing;
//! - `dense` (only when the filter names it): the jammed phase of the bay
//!   jam family `cases/fields/bay_jam_{200,2000,20000}.toml` (every
//!   formulation with the case's solvers) and of its `_nsgs` variants
//!   (`moreau+nsgs`, `event-driven+nsgs`: the iterative solver) and
//!   `_projected` variants (`moreau+projected`: NSGS capped at 300 sweeps,
//!   positions projected), each started
//!   (as `floebench run --from`) from the state of a `rapier` run of the
//!   case at the time its pack has jammed ([`dense_start`]: its kinetic
//!   energy three orders of magnitude below the drift's peak; 5,000 s for
//!   200 floes, 8,000 s for 2,000, whose pack still drifts at 5,000 s) and
//!   run for [`DENSE_SPAN`] s. Throughput is in simulated seconds, so
//!   criterion's `elem/s` is simulated seconds per CPU second. The states
//!   are read from `target/dense/bay_jam_<N>/trajectory.csv`; the 200-floe
//!   one is made when missing (about 30 s), the 2,000-floe one by
//!   `cargo run --release -- run cases/fields/bay_jam_2000.toml -f rapier -o target/dense/bay_jam_2000 --quiet`
//!   (465 s of CPU), and skipped with that message until it exists. The
//!   20,000-floe member starts from the last output of
//!   `target/dense/bay_jam_20000/trajectory.csv`, a jammed state that takes
//!   about an hour of CPU per 1,000 s to make (rapier to 6,000 s at the
//!   case's wind, then 4,000 s at 30 m/s: the commands are in
//!   docs/results/2026-12-07-dense-20000.md, "A jammed state and its
//!   window"), and is skipped until it exists. It runs
//!   [`DENSE_SPAN_20000`] s, and only `rapier`, `moreau+nsgs`,
//!   `event-driven+nsgs` and `moreau+projected`: the dense LCP of its
//!   29,366-contact group would need 37.7 GB (Lemke takes it with NSGS,
//!   counted, so it would not measure Lemke), and clarabel was not tried
//!   on it.
//!
//! The measurement is the thread's CPU time. Every formulation except
//! `free-drift` runs.
//!
//! ```sh
//! cargo bench --bench cases                 # small cases and scaling 100, 1000 (a few minutes)
//! cargo bench --bench cases -- head_on      # one case
//! cargo bench --bench cases -- heavy        # the scaling group with its 10,000-floe member (long)
//! cargo bench --bench cases -- dense        # the jammed bay, CPU per simulated second (long)
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

/// The simulated span of the dense benchmarks, s: long enough for many
/// sustained-contact steps of every formulation, short enough that the
/// slowest formulation on 200 floes takes seconds per sample.
const DENSE_SPAN: f64 = 20.0;

/// The simulated span of the 20,000-floe dense benchmarks, s: event-driven
/// takes about 23 s of CPU per simulated second there (10 samples of 5 s:
/// about 20 minutes).
const DENSE_SPAN_20000: f64 = 5.0;

/// The span of the dense benchmarks of `n` floes, s.
fn dense_span(n: usize) -> f64 {
    if n >= 20000 {
        DENSE_SPAN_20000
    } else {
        DENSE_SPAN
    }
}

/// The output time of the rapier run of `bay_jam_<n>` whose state starts
/// its dense benchmarks, s: the first output at which its pack's kinetic
/// energy is three orders of magnitude below the drift's peak (measured:
/// docs/results/2026-12-04-dense-packs-lemke.md, "Dense scaling"); `None`
/// for the last output (the 20,000-floe state, made by a chain of runs).
fn dense_start(n: usize) -> Option<f64> {
    match n {
        200 => Some(5000.0),
        2000 => Some(8000.0),
        _ => None,
    }
}

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

/// The jammed state of `bay_jam_<n>` (see the module doc): the case
/// restarted from its rapier run's state at [`dense_start`], for
/// [`dense_span`] s.
fn jammed(n: usize, variant: &str) -> Result<Scenario, String> {
    use floebench::run::output;
    let start = dense_start(n);
    let path = cases_dir()
        .join("fields")
        .join(format!("bay_jam_{n}{variant}.toml"));
    let mut scn = load_case(&path).map_err(|e| e.to_string())?;
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("target/dense")
        .join(format!("bay_jam_{n}"));
    let file = dir.join("trajectory.csv");
    if !file.is_file() {
        if n == 20000 {
            return Err(format!(
                "skipped: no {}; make it as docs/results/2026-12-07-dense-20000.md says (\"A jammed state and its window\")",
                file.display()
            ));
        }
        if n != 200 {
            return Err(format!(
                "skipped: no {}; make it with `cargo run --release -- run {} -f rapier -o {} --quiet`",
                file.display(),
                path.display(),
                dir.display()
            ));
        }
        eprintln!(
            "making the jammed state of {} (rapier, about 30 s)",
            scn.name
        );
        let mut f = build("rapier", &scn, &FormulationOptions::default())?;
        let r = Runner::new(RunOptions::default()).run(&scn, f.name(), f.formulation.as_mut());
        output::write_run(&dir, &r).map_err(|e| e.to_string())?;
    }
    let (t, bodies) = output::read_state(&file, start)?;
    floebench::state::restart(&mut scn, &bodies, floebench::model::Restart { file, t })?;
    scn.duration = dense_span(n);
    scn.output_interval = dense_span(n);
    Ok(scn)
}

fn dense(c: &mut Criterion<ThreadCpu>) {
    if !std::env::args().skip(1).any(|a| a.contains("dense")) {
        return;
    }
    let mut g = c.benchmark_group("dense");
    g.sample_size(10).warm_up_time(Duration::from_millis(100));
    // Each size with the case's solvers (Lemke, clarabel), then with the
    // iterative ones of `bay_jam_<n>_nsgs.toml` (NSGS; ids `<name>+nsgs`),
    // then moreau with the projection and a cap of 300 sweeps
    // (`bay_jam_<n>_projected.toml`; `moreau+projected`); at 20,000 floes
    // rapier alone with the case's (module doc).
    let iterative = ["moreau".to_string(), "event-driven".to_string()];
    let projected = ["moreau".to_string()];
    for n in [200, 2000, 20000] {
        g.throughput(Throughput::Elements(dense_span(n) as u64));
        let direct = if n >= 20000 {
            vec!["rapier".to_string()]
        } else {
            contact_formulations()
        };
        let variants = [
            ("", direct),
            ("_nsgs", iterative.to_vec()),
            ("_projected", projected.to_vec()),
        ];
        for (variant, names) in variants {
            let scn = match jammed(n, variant) {
                Ok(s) => s,
                Err(e) => {
                    eprintln!("bay_jam_{n}{variant}: {e}");
                    continue;
                }
            };
            for name in names {
                let label = format!("{name}{}", variant.replace('_', "+"));
                let id = BenchmarkId::new(label, n);
                g.bench_with_input(id, &scn, |b, scn| {
                    b.iter(|| black_box(run_once(scn, &name)))
                });
            }
        }
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots().with_measurement(ThreadCpu);
    targets = per_case, scaling, dense
}
criterion_main!(benches);
