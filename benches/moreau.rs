//! CPU time per Moreau–Jean step on the 200-floe field against the coast
//! (`cases/fields/field_200_coast.toml`, h = 1 s), for both one-step solvers: the
//! Stewart–Trinkle LCP by Lemke (`moreau`) and the Anitescu–Tasora cone
//! program by clarabel (`moreau-cone`).
//!
//! The field starts loose (no contact at t = 0), so it is first compacted by
//! running `moreau` (Lemke) for `COMPACTION` = 2 h of simulated time (a few
//! seconds of CPU): the floes reach the coast and pile up (72 active
//! contacts in 11 groups in the timed step, printed by the bench). Each
//! iteration then advances a copy of that state by one step of 1 s
//! (detection, θ-method forces, contact problems, positions), with a
//! formulation set up once per solver. A second group times the step of the
//! loose field at t = 0 (no contact: detection and forces alone). Criterion
//! measures wall time; a step is single-threaded, so it is the step's CPU
//! time on an otherwise idle core.
//!
//! `cargo bench --bench moreau`

use criterion::{criterion_group, criterion_main, Criterion};
use floebench::formulation::load_case;
use floebench::formulation::moreau::{MoreauSettings, ACTIVE_CONTACTS, CONTACT_GROUPS};
use floebench::formulation::{build, Context, FixedTopology, FormulationOptions, Interrupt};
use floebench::model::Scenario;
use floebench::record::StageClock;
use floebench::state::System;
use std::hint::black_box;
use std::path::Path;

/// Simulated time of the compaction run, s.
const COMPACTION: f64 = 7200.0;

fn field() -> Scenario {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/fields/field_200_coast.toml");
    load_case(&path).expect("bundled case")
}

fn bench_steps(c: &mut Criterion, group: &str, scn: &Scenario, state: &System) {
    let mut g = c.benchmark_group(group);
    g.sample_size(20);
    for name in ["moreau", "moreau-cone"] {
        let mut form = build(name, scn, &FormulationOptions::default()).expect("formulation");
        let h = MoreauSettings::of(scn).expect("settings").step;
        let mut clock = StageClock::new();
        // The field has no [fracture] table: its floe set never changes.
        let (mut topology, stop) = (FixedTopology, Interrupt::own());
        let mut cx = Context::new(&mut clock, &mut topology, &stop);
        // The run's own copy of the case (a formulation may change its floe
        // set; without a [fracture] table it does not).
        let mut run_scn = scn.clone();
        // One step first, to report the contact problem being timed.
        let mut probe = state.clone();
        form.formulation
            .advance(&mut run_scn, &mut probe, state.t + h, &mut cx)
            .expect("step");
        let counts = form.formulation.counters();
        eprintln!(
            "{group}/{name}: t = {} s, {} active contacts in {} groups",
            state.t,
            counts.count(&ACTIVE_CONTACTS).expect("kept"),
            counts.count(&CONTACT_GROUPS).expect("kept")
        );
        g.bench_function(name, |b| {
            b.iter_batched(
                || state.clone(),
                |mut s| {
                    let r = form
                        .formulation
                        .advance(&mut run_scn, &mut s, state.t + h, &mut cx);
                    black_box((r.is_ok(), s.t))
                },
                criterion::BatchSize::SmallInput,
            )
        });
    }
    g.finish();
}

fn moreau_step(c: &mut Criterion) {
    let scn = field();
    let start = System::initial(&scn);
    bench_steps(c, "moreau_step_field_200_t0", &scn, &start);
    let mut sys = start;
    let mut form = build("moreau", &scn, &FormulationOptions::default()).expect("formulation");
    let mut run_scn = scn.clone();
    let (mut clock, mut topology, stop) = (StageClock::new(), FixedTopology, Interrupt::own());
    form.formulation
        .advance(
            &mut run_scn,
            &mut sys,
            COMPACTION,
            &mut Context::new(&mut clock, &mut topology, &stop),
        )
        .expect("compaction run");
    bench_steps(c, "moreau_step_field_200_compacted", &scn, &sys);
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = moreau_step
}
criterion_main!(benches);
