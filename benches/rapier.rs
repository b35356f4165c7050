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

use criterion::{criterion_group, criterion_main, Criterion};
use floebench::formulation::load_case;
use floebench::formulation::rapier_ref::{RapierReference, MAX_CONTACT_PAIRS};
use floebench::formulation::{Context, FixedTopology, Formulation, FormulationOptions, Interrupt};
use floebench::record::StageClock;
use floebench::state::System;
use std::hint::black_box;
use std::path::Path;

#[path = "common/thread_cpu.rs"]
mod thread_cpu;
use thread_cpu::ThreadCpu;

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
        let h = form.resolved().step;
        let mut sys = System::initial(&scn);
        let mut clock = StageClock::new();
        // The field has no [fracture] table: its floe set never changes.
        let (mut topology, stop) = (FixedTopology, Interrupt::own());
        let mut cx = Context::new(&mut clock, &mut topology, &stop);
        let mut run_scn = scn.clone();
        if warm_up > 0.0 {
            if let Err(e) = form.advance(&mut run_scn, &mut sys, warm_up, &mut cx) {
                panic!("{e}");
            }
        }
        let name = format!("field_200_coast/from_t={}h", warm_up / 3600.0);
        g.bench_function(name, |b| {
            b.iter(|| {
                let t = sys.t + h;
                if let Err(e) = black_box(form.advance(&mut run_scn, &mut sys, t, &mut cx)) {
                    panic!("{e}");
                }
            })
        });
        let pairs = form
            .counters()
            .value(&MAX_CONTACT_PAIRS)
            .ok()
            .flatten()
            .unwrap_or(0.0);
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
