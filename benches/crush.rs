//! CPU time of the crush stage (docs/physics.md §10) and of what a cut
//! makes a formulation rebuild.
//!
//! - `crush/cut_floe_pair`: one safe point that cuts the overlap of two
//!   10 m squares on a 0.1 m strip (the overlap, two cuts, two transfers):
//!   the report and `apply` of the stage;
//! - `crush/cut_floe_coast`: one that cuts a square's corner rammed 0.1 m
//!   into a straight coast;
//! - `crush/rebuild/<formulation>`: `Formulation::floes_changed` on the
//!   200-floe bay jam (`cases/fields/bay_jam_200.toml`), which every safe
//!   point that changed a floe triggers (the masses and inertias changed).
//!
//! Each iteration of the cuts works on a fresh copy of the scenario, the
//! state and the stage (made outside the timed routine). Criterion
//! measures wall time; all of it is single-threaded.
//!
//! `cargo bench --bench crush`

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use floebench::formulation::{build, FormulationOptions, Topology};
use floebench::formulation::{load_case, parse_case};
use floebench::fracture::crush::CrushStage;
use floebench::geometry::Vec2;
use floebench::model::Scenario;
use floebench::record::StageClock;
use floebench::state::System;
use std::hint::black_box;
use std::path::Path;

/// A case of `bodies` (TOML tables) with `[contact] crushing`.
fn case(bodies: &str) -> Scenario {
    let text = format!(
        "[case]\nversion = 1\nname = \"crush_bench\"\ndescription = \"bench\"\nduration = 1.0\n\
         output_interval = 1.0\n\n[contact]\nrestitution = 0.0\nfriction = 0.0\n\
         crushing = {{ strength = 1.0e6 }}\n\n{bodies}"
    );
    parse_case(&text, Path::new("bench.toml")).expect("bench case")
}

fn bench_cut(c: &mut Criterion, name: &str, scn: Scenario, sys: System, pair: (usize, usize)) {
    let stage = CrushStage::new(&scn);
    c.bench_function(name, |b| {
        b.iter_batched(
            || (scn.clone(), sys.clone(), stage.clone(), StageClock::new()),
            |(mut scn, mut sys, mut stage, mut clock)| {
                stage.crushed(&scn, &sys, &[pair]);
                black_box(stage.apply(&mut scn, &mut sys, &mut clock));
                (scn, sys)
            },
            BatchSize::SmallInput,
        )
    });
}

fn cuts(c: &mut Criterion) {
    let squares = "[[floe]]\nthickness = 1.0\npolygon = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]\n\
                   [[floe]]\nthickness = 1.0\npolygon = [[12.0, 0.0], [22.0, 0.0], [22.0, 10.0], [12.0, 10.0]]\n";
    let scn = case(squares);
    let mut sys = System::initial(&scn);
    sys.bodies[1].position = Vec2::new(14.9, 5.0);
    sys.bodies[0].velocity = Vec2::new(1.0, 0.0);
    bench_cut(c, "crush/cut_floe_pair", scn, sys, (0, 1));

    let coast = "[[floe]]\nthickness = 1.0\npolygon = [[5.0, 0.0], [0.0, 5.0], [-5.0, 0.0], [0.0, -5.0]]\n\
                 [[obstacle]]\npolygon = [[10.0, -50.0], [30.0, -50.0], [30.0, 50.0], [10.0, 50.0]]\n";
    let scn = case(coast);
    let mut sys = System::initial(&scn);
    sys.bodies[0].position = Vec2::new(5.1, 0.0);
    bench_cut(c, "crush/cut_floe_coast", scn, sys, (0, 1));
}

fn rebuilds(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/fields/bay_jam_200.toml");
    let scn = load_case(&path).expect("bundled case");
    let sys = System::initial(&scn);
    let old: Vec<usize> = scn.floes.iter().map(|f| f.id).collect();
    let mut g = c.benchmark_group("crush/rebuild");
    for name in ["moreau", "event-driven"] {
        let mut form = build(name, &scn, &FormulationOptions::default()).expect("formulation");
        g.bench_function(name, |b| {
            b.iter(|| {
                form.formulation
                    .floes_changed(&scn, &sys, &old)
                    .expect("rebuild")
            })
        });
    }
    g.finish();
}

criterion_group!(benches, cuts, rebuilds);
criterion_main!(benches);
