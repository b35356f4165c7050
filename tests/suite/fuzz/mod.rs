//! Seeded mutation fuzzing of the case files and of the LCP dumps.
//!
//! Each input is a bundled text (`cases/*.toml`, `cases/fields/*.toml`, or
//! a dump of `tests/data/lcp/`) with one to three mutations drawn by the
//! crate's SplitMix64 from a fixed seed: a number replaced by an extreme
//! (0, −x, 1e300, −1e308, 5e-324, `nan`, `inf`, a string, huge integers,
//! x × 1000, …), a line deleted, duplicated or swapped with another, the
//! keys of two lines swapped, a vector made longer or shorter.
//!
//! A case mutant goes through the library's case loading (`validate`); an
//! accepted one with at most [`MAX_RUN_FLOES`] floes (and floe lattices of
//! at most [`MAX_RUN_LATTICE_NODES`] nodes) is run by one
//! formulation of the registry (rotating among those that apply), its
//! duration cut to a few outputs and steps so that every run is cheap, and
//! its files are written by the library's writer into a fresh folder and
//! read back; one refused case in [`CLI_EVERY`] also goes through
//! `floebench run`, which must exit with one error line and no output
//! folder. A dump mutant goes through the strict dump reader and, when
//! read, through the LCP driver. The assertions:
//!
//! - no panic (validate, build, run, write, read, solve);
//! - no hang: every input ends within [`TIME_BOUND`] (hang detection only,
//!   far above the milliseconds an input takes);
//! - every error and every failed run's message is one line, with no Debug
//!   dump;
//! - no non-finite number in a run's result or in any file written, and a
//!   write that fails leaves no file (no partial file);
//! - a dump the driver reports solved passes its residual check, recomputed
//!   here; a failed solve is a counted outcome.
//!
//! In CI each test runs [`CI_COUNT`] inputs. A long run, printing the
//! counts by outcome:
//!
//! ```sh
//! FLOEBENCH_FUZZ_COUNT=100000 cargo test --release --test suite fuzz -- --nocapture
//! ```
//!
//! (`FLOEBENCH_FUZZ_SEED` changes the seed.) An input that breaks an
//! assertion is saved in `target/tmp/fuzz/` with its index and seed.
//!
//! This file holds what the submodules share: the limits, the tally of
//! outcomes and the driver that feeds the mutants of a corpus to a check
//! within the time bound. The mutator (and its own test) is in `mutations`,
//! the case files in `cases`, the LCP dumps in `dumps`.

mod cases;
mod dumps;
mod mutations;

use crate::common::{within_bound, Defect};
use floebench::rng::SplitMix64;
use mutations::mutate;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Inputs per test in CI (`FLOEBENCH_FUZZ_COUNT` overrides).
const CI_COUNT: usize = 2000;
/// The seed of the mutations (`FLOEBENCH_FUZZ_SEED` overrides).
const SEED: u64 = 17;
/// Accepted cases with more floes are loaded but not run (their runs would
/// dominate the budget; the generator and the loader still see them).
const MAX_RUN_FLOES: usize = 300;
/// Accepted lattice cases in which a floe's lattice holds more nodes than
/// this (its area over the area per node, `√3/2 s²` for spacing `s`: an
/// estimate) are loaded but not run, for the same reason: a percussion
/// costs `O(N^{3/2})`; `lattice_ram` at its spacing, 0.5 m, has about 230
/// nodes per floe by this estimate, and a mutant at 0.25 m (about 920) ran
/// 21 s on an idle core, beyond a hang detector's margin on a loaded machine.
const MAX_RUN_LATTICE_NODES: f64 = 500.0;
/// A run lasts at most this many output intervals…
const RUN_OUTPUTS: f64 = 3.0;
/// …and at most this many fixed steps (Moreau–Jean, rapier, explicit Euler)…
const RUN_STEPS: f64 = 50.0;
/// …and at most this many simulated seconds per floe (200 floes of the
/// coast field: 100 s; a lone floe: its whole bundled duration). Without
/// it a mutated field of large floes ran 30 s.
const RUN_FLOE_SECONDS: f64 = 20_000.0;
/// One refused case in this many also goes through `floebench run`.
const CLI_EVERY: u64 = 25;

/// A number from the environment, or `default`.
fn env_number<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|v| v.trim().parse().ok())
        .unwrap_or(default)
}

// ---------------------------------------------------------------------------
// Running one input within the time bound

/// A message must be one line, not empty, and no Debug dump.
fn one_line(what: &str, m: &str) -> Result<(), Defect> {
    let debug = ["Failed {", "message: \"", "Some(", "Err(", "Ok(", "\\n"];
    if m.trim().is_empty() || m.contains('\n') || debug.iter().any(|d| m.contains(d)) {
        Err(format!("{what} is not a one-line message: {m:?}"))
    } else {
        Ok(())
    }
}

/// Counts by outcome, and the defects with their inputs.
#[derive(Default)]
struct Tally {
    outcomes: BTreeMap<String, usize>,
    defects: Vec<String>,
    /// The slowest input: wall time and index.
    slowest: (Duration, usize),
}

impl Tally {
    fn count(&mut self, what: impl Into<String>) {
        *self.outcomes.entry(what.into()).or_default() += 1;
    }

    /// Records a defect of input `index` (its text saved for reproduction).
    fn defect(&mut self, kind: &str, index: usize, seed: u64, origin: &str, text: &str, d: Defect) {
        self.count(format!("DEFECT: {}", d.split(':').next().unwrap_or("")));
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fuzz");
        let saved = std::fs::create_dir_all(&dir)
            .and_then(|_| {
                let p = dir.join(format!("{kind}_{seed}_{index}.txt"));
                std::fs::write(&p, text).map(|_| p)
            })
            .map(|p| p.display().to_string())
            .unwrap_or_else(|e| format!("(not saved: {e})"));
        if self.defects.len() < 20 {
            self.defects.push(format!(
                "input {index} (seed {seed}, from {origin}, saved as {saved}): {d}"
            ));
        }
    }

    fn report(&self, title: &str, n: usize, elapsed: Duration) {
        println!(
            "fuzz {title}: {n} inputs in {:.1} s (slowest: input {}, {:.2} s)",
            elapsed.as_secs_f64(),
            self.slowest.1,
            self.slowest.0.as_secs_f64()
        );
        for (k, v) in &self.outcomes {
            println!("  {v:>8}  {k}");
        }
    }
}

/// The texts of the corpus: every file of `dirs` with extension `ext`.
fn corpus(dirs: &[PathBuf], ext: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for dir in dirs {
        let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == ext))
            .collect();
        paths.sort();
        for p in paths {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            out.push((name, std::fs::read_to_string(&p).unwrap()));
        }
    }
    assert!(!out.is_empty(), "no corpus in {dirs:?}");
    out
}

/// Runs `n` mutants of `corpus` through `check` and asserts no defect.
fn fuzz(
    title: &str,
    kind: &'static str,
    corpus: &[(String, String)],
    json: bool,
    check: fn(String, u64) -> Result<String, Defect>,
) {
    let n = env_number("FLOEBENCH_FUZZ_COUNT", CI_COUNT);
    let seed = env_number("FLOEBENCH_FUZZ_SEED", SEED);
    let mut rng = SplitMix64::new(seed ^ kind.len() as u64);
    let mut tally = Tally::default();
    let start = Instant::now();
    for index in 0..n {
        let (origin, text) = &corpus[rng.int_range(0, corpus.len() - 1)];
        let mutant = mutate(&mut rng, text, json);
        let pick = rng.next_u64();
        let m = mutant.clone();
        let began = Instant::now();
        let answer = within_bound(move || check(m, pick));
        tally.slowest = tally.slowest.max((began.elapsed(), index));
        match answer {
            Ok(outcome) => tally.count(outcome),
            Err(d) => {
                let hang = d.starts_with("hang");
                tally.defect(kind, index, seed, origin, &mutant, d);
                if hang {
                    // The hung thread keeps a core: stop here.
                    break;
                }
            }
        }
    }
    tally.report(title, n, start.elapsed());
    assert!(
        tally.defects.is_empty(),
        "{} defects, first ones:\n{}",
        tally.defects.len(),
        tally.defects.join("\n")
    );
}
