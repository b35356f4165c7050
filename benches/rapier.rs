//! CPU time per step of the rapier reference formulation on the 200-floe
//! field against a coast (`cases/fields/field_200_coast.toml`, the Moreau bench's
//! field), at the default settings (`h` = 0.1 s, 4 substeps).
//!
//! Two starting states: the field as generated (t = 0: drift, at most a
//! couple of contact pairs) and after 3 h of simulation (floes piling up
//! against the coast and each other, 150 to 200 contact pairs). Each
//! iteration is one step continuing the same run, so a benchmark covers
//! the steps that follow its starting state (criterion runs some 10⁴). The
//! measurement is the thread's CPU time (`CLOCK_THREAD_CPUTIME_ID`), not
//! wall time, so that other work on the machine does not inflate it.
//!
//! `cargo bench --bench rapier`

use criterion::measurement::{Measurement, ValueFormatter};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use floebench::formulation::rapier_ref::RapierReference;
use floebench::formulation::{Formulation, FormulationOptions};
use floebench::model::load_case;
use floebench::run::{thread_cpu_seconds, StageClock};
use floebench::state::System;
use std::hint::black_box;
use std::path::Path;

/// Thread CPU time, in nanoseconds.
struct ThreadCpu;

impl Measurement for ThreadCpu {
    type Intermediate = f64;
    type Value = f64;

    fn start(&self) -> f64 {
        thread_cpu_seconds()
    }

    fn end(&self, t0: f64) -> f64 {
        (thread_cpu_seconds() - t0) * 1e9
    }

    fn add(&self, a: &f64, b: &f64) -> f64 {
        a + b
    }

    fn zero(&self) -> f64 {
        0.0
    }

    fn to_f64(&self, v: &f64) -> f64 {
        *v
    }

    fn formatter(&self) -> &dyn ValueFormatter {
        &CpuFormatter
    }
}

/// Formats nanoseconds of CPU time.
struct CpuFormatter;

impl CpuFormatter {
    fn scale(typical_ns: f64) -> (f64, &'static str) {
        if typical_ns < 1e3 {
            (1.0, "ns cpu")
        } else if typical_ns < 1e6 {
            (1e-3, "µs cpu")
        } else if typical_ns < 1e9 {
            (1e-6, "ms cpu")
        } else {
            (1e-9, "s cpu")
        }
    }
}

impl ValueFormatter for CpuFormatter {
    fn scale_values(&self, typical: f64, values: &mut [f64]) -> &'static str {
        let (f, unit) = Self::scale(typical);
        values.iter_mut().for_each(|v| *v *= f);
        unit
    }

    fn scale_throughputs(&self, typical: f64, _: &Throughput, values: &mut [f64]) -> &'static str {
        self.scale_values(typical, values)
    }

    fn scale_for_machines(&self, _: &mut [f64]) -> &'static str {
        "ns cpu"
    }
}

fn rapier_step(c: &mut Criterion<ThreadCpu>) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("cases")
        .join("fields/field_200_coast.toml");
    let scn = match load_case(&path) {
        Ok(s) => s,
        Err(e) => panic!("{e}"),
    };
    let mut g = c.benchmark_group("rapier_step");
    g.sample_size(20);
    for warm_up in [0.0, 10800.0] {
        let mut form = match RapierReference::new(&scn, &FormulationOptions::default()) {
            Ok(f) => f,
            Err(e) => panic!("{e}"),
        };
        let h = form.settings().step;
        let mut sys = System::initial(&scn);
        let mut clock = StageClock::new();
        if warm_up > 0.0 {
            if let Err(e) = form.advance(&scn, &mut sys, warm_up, &mut clock) {
                panic!("{e}");
            }
        }
        let name = format!("field_200_coast/from_t={}h", warm_up / 3600.0);
        g.bench_function(name, |b| {
            b.iter(|| {
                let t = sys.t + h;
                if let Err(e) = black_box(form.advance(&scn, &mut sys, t, &mut clock)) {
                    panic!("{e}");
                }
            })
        });
        let pairs = form.counters().values["max_contact_pairs"];
        eprintln!("  (t = {:.0} s, up to {pairs} contact pairs)", sys.t);
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots().with_measurement(ThreadCpu);
    targets = rapier_step
}
criterion_main!(benches);
