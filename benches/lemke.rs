//! Lemke on contact LCPs of 4, 40 and 400 unknowns built from real impacts:
//! the impact LCP (docs/physics.md §3.1, Stewart–Trinkle friction, size 4m) that
//! the event-driven formulation assembles when a floe strikes
//! - a wall with one corner (1 contact, 4 unknowns),
//! - a row of 5 touching floes (10 contacts, 40 unknowns),
//! - a row of 50 touching floes (100 contacts, 400 unknowns),
//!
//! obliquely and spinning, so that friction is active; each on the dense
//! tableau and on the factorised (revised) basis (docs/physics.md §3.3),
//! whatever the driver's default threshold.
//!
//! `lemke_corpus`: the committed dumps of real runs (tests/data/lcp,
//! tests/data/lcp_bay: field_200_coast, narrow_channel, elastic_pool and
//! the bay jam, 4 to 271 unknowns), by size bucket of
//! `floebench lcp --time`; one iteration solves every dump of the bucket
//! with one work space and one output ([`solve_into`]).
//!
//! `lemke_small`: the buckets of at most 40 unknowns of the same dumps, by
//! the default driver (its small-problem rule) and with
//! `unpolished_below = 0`, which refines every candidate
//! (docs/physics.md §3.3, "Small problems").
//!
//! `cargo bench --bench lemke`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use floebench::contact::problem::{groups, ContactLcp, Friction, Gen};
use floebench::contact::BroadPhase;
use floebench::formulation::parse_case;
use floebench::lcp::solve_options::SMALL_N;
use floebench::lcp::timing::{bucket_label, bucket_of, dump_files, BUCKETS};
use floebench::lcp::{solve, solve_into, Lcp, LcpDump, LcpSolution, SolveOptions, Workspace};
use floebench::model::Scenario;
use floebench::state::{detect_contacts, System};
use std::hint::black_box;
use std::path::Path;

const HEAD: &str = "[case]\nversion = 1\nname = \"bench\"\nduration = 1.0\noutput_interval = 1.0\n[contact]\nrestitution = 0.5\nfriction = 0.3\n";

fn corner_on_wall() -> Scenario {
    let text = format!(
        "{HEAD}[[floe]]\npolygon = [[10.0, 5.0], [15.0, 0.0], [20.0, 5.0], [15.0, 10.0]]\nthickness = 1.0\nvelocity = [0.5, 0.2]\nangular_velocity = 0.05\n[[obstacle]]\npolygon = [[20.0, -50.0], [30.0, -50.0], [30.0, 50.0], [20.0, 50.0]]\n"
    );
    parse_case(&text, Path::new("bench.toml")).expect("bench case")
}

fn row(n: usize) -> Scenario {
    let mut text = HEAD.to_string();
    for k in 0..n {
        let x = 10.0 * k as f64;
        let v = if k == 0 {
            "velocity = [0.5, 0.2]\nangular_velocity = 0.02\n"
        } else {
            ""
        };
        text += &format!(
            "[[floe]]\npolygon = [[{x:?}, 0.0], [{:?}, 0.0], [{:?}, 10.0], [{x:?}, 10.0]]\nthickness = 1.0\n{v}",
            x + 10.0,
            x + 10.0
        );
    }
    parse_case(&text, Path::new("bench.toml")).expect("bench case")
}

/// The impact LCP of the first (only) contact group of a scenario at t = 0.
fn impact_lcp(scn: &Scenario) -> Lcp {
    let sys = System::initial(scn);
    let mut contacts = Vec::new();
    detect_contacts(
        scn,
        &sys.bodies,
        1e-3,
        &mut BroadPhase::new(),
        &mut contacts,
    );
    let g = groups(&contacts, scn.floes.len()).remove(0);
    let centres = sys.centres();
    let w: Vec<Gen> = sys.velocities();
    let zeros = vec![0.0; contacts.len()];
    ContactLcp::assemble(scn, &centres, &contacts, &g, &w, &zeros, Friction::Merged)
        .lcp()
        .clone()
}

fn lemke_on_impacts(c: &mut Criterion) {
    faer::set_global_parallelism(faer::Par::Seq);
    let mut g = c.benchmark_group("lemke_impact_lcp");
    let opts = SolveOptions::default();
    for scn in [corner_on_wall(), row(6), row(51)] {
        let lcp = impact_lcp(&scn);
        let sol = solve(&lcp, &opts);
        assert!(
            sol.status.is_solved(),
            "bench LCP of size {} unsolved",
            lcp.n
        );
        eprintln!(
            "LCP of {} unknowns: {} pivots, residual {:.2e}, status {}",
            lcp.n,
            sol.pivots,
            sol.residual,
            sol.status.as_str()
        );
        for (path, revised_from) in [("dense", usize::MAX), ("revised", 0)] {
            let o = SolveOptions {
                revised_from,
                ..opts.clone()
            };
            g.bench_with_input(BenchmarkId::new(path, lcp.n), &lcp, |b, lcp| {
                b.iter(|| black_box(solve(lcp, &o).pivots))
            });
        }
    }
    g.finish();
}

/// The committed dumps, grouped by size bucket.
fn corpus_buckets() -> Vec<Vec<Lcp>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let mut buckets: Vec<Vec<Lcp>> = vec![Vec::new(); BUCKETS.len()];
    for dir in ["lcp", "lcp_bay"] {
        for f in dump_files(&root.join(dir)).expect("committed dumps") {
            let lcp = LcpDump::read(&f)
                .expect("committed dump reads")
                .to_lcp()
                .expect("square");
            if let Some(b) = bucket_of(lcp.n) {
                buckets[b].push(lcp);
            }
        }
    }
    buckets
}

fn lemke_on_corpus(c: &mut Criterion) {
    faer::set_global_parallelism(faer::Par::Seq);
    let mut g = c.benchmark_group("lemke_corpus");
    let opts = SolveOptions::default();
    for (b, lcps) in corpus_buckets().iter().enumerate() {
        if lcps.is_empty() {
            continue;
        }
        let id = format!("{}_{}_dumps", bucket_label(b), lcps.len());
        bench_dumps(&mut g, id, lcps, &opts);
    }
    g.finish();
}

/// One benchmark of `g`: an iteration solves every LCP of `lcps` with one
/// work space and one output ([`solve_into`]).
fn bench_dumps(
    g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    id: String,
    lcps: &[Lcp],
    opts: &SolveOptions,
) {
    let mut ws = Workspace::default();
    let mut out = LcpSolution::empty();
    g.bench_function(id, |bch| {
        bch.iter(|| {
            let mut pivots = 0;
            for lcp in lcps {
                solve_into(&mut ws, lcp, opts, &mut out);
                pivots += out.pivots;
            }
            black_box(pivots)
        })
    });
}

/// `lemke_small`: the committed dumps of at most `SMALL_N` unknowns
/// (buckets 1–8 and 9–40), solved by the default driver with its
/// small-problem rule (`small`: `unpolished_below = 1e-13`, an accepted
/// candidate within it is not refined) and with `unpolished_below = 0`,
/// which refines every candidate (`refined`), one iteration solving every dump of the
/// bucket with one work space and one output.
fn lemke_on_small(c: &mut Criterion) {
    let mut g = c.benchmark_group("lemke_small");
    let variants = [
        ("small", SolveOptions::default()),
        (
            "refined",
            SolveOptions {
                unpolished_below: 0.0,
                ..SolveOptions::default()
            },
        ),
    ];
    for (b, lcps) in corpus_buckets().iter().enumerate() {
        if lcps.is_empty() || lcps.iter().any(|l| l.n > SMALL_N) {
            continue;
        }
        for (name, opts) in &variants {
            let id = format!("{name}/{}_{}_dumps", bucket_label(b), lcps.len());
            bench_dumps(&mut g, id, lcps, opts);
        }
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = lemke_on_impacts, lemke_on_corpus, lemke_on_small
}
criterion_main!(benches);
