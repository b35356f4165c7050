//! Generation of `[[field]]` floe fields: the 10,000-floe case must load in a
//! few seconds (requirement: linear cost, no all-pairs loop; docs/case-format.md, [[field]]).
//!
//! `cargo bench --bench field`

use criterion::{criterion_group, criterion_main, Criterion};
use floebench::formulation::load_case;
use std::hint::black_box;
use std::path::Path;

fn field_generation(c: &mut Criterion) {
    let mut g = c.benchmark_group("field_generation");
    g.sample_size(10);
    for case in ["field_200_coast", "field_10000"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("cases/fields")
            .join(format!("{case}.toml"));
        g.bench_function(case, |b| {
            b.iter(|| black_box(load_case(&path).map(|s| s.floes.len())))
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = field_generation
}
criterion_main!(benches);
