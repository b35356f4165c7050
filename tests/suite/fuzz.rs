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

use crate::common::{cases_dir, floebench, guarded, lcp_violation, tempdir, within_bound, Defect};
use floebench::formulation::moreau::MoreauSettings;
use floebench::formulation::rapier_ref::RapierSettings;
use floebench::formulation::{build, parse_case, FormulationOptions, REGISTRY};
use floebench::lcp::{residual, solve, LcpDump, SolveOptions};
use floebench::model::{IntegratorKind, Scenario};
use floebench::record::SettingValue;
use floebench::rng::SplitMix64;
use floebench::run::{output, EndReason, RunOptions, RunResult, Runner};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
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
// Mutations

/// The byte ranges of the numbers of `line` (outside a `#` comment when
/// `comments`).
fn number_spans(line: &str, comments: bool) -> Vec<(usize, usize)> {
    let code = if comments {
        line.split('#').next().unwrap_or("")
    } else {
        line
    };
    let b = code.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts = b[i].is_ascii_digit()
            || ((b[i] == b'-' || b[i] == b'+') && b.get(i + 1).is_some_and(u8::is_ascii_digit));
        let inside_word = i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_');
        if starts && !inside_word {
            let start = i;
            i += 1;
            while i < b.len()
                && (b[i].is_ascii_digit()
                    || b[i] == b'.'
                    || b[i] == b'e'
                    || b[i] == b'E'
                    || b[i] == b'_'
                    || ((b[i] == b'-' || b[i] == b'+') && matches!(b[i - 1], b'e' | b'E')))
            {
                i += 1;
            }
            spans.push((start, i));
        } else {
            i += 1;
        }
    }
    spans
}

/// A replacement for the number `x` (as written): extremes, special
/// values, strings, and changes of scale and type. `json` picks the
/// spellings of the dumps (`NaN`, `Infinity`, `null`).
fn extreme(rng: &mut SplitMix64, x: &str, json: bool) -> String {
    let v: f64 = x.replace('_', "").parse().unwrap_or(1.0);
    // Half the time a change a physicist might make (within the limits,
    // mostly): the runs see those.
    if rng.int_range(0, 1) == 0 {
        let factor = [0.5, 0.9, 1.1, 2.0, 3.0, -1.0, 0.0, 10.0, 0.1, 1.0001][rng.int_range(0, 9)];
        let w = v * factor;
        return if x.contains(['.', 'e', 'E']) || factor.fract() != 0.0 {
            format!("{w:?}")
        } else {
            format!("{}", w as i64)
        };
    }
    let choices: [&dyn Fn() -> String; 24] = [
        &|| "0".into(),
        &|| "0.0".into(),
        &|| format!("-{}", x.trim_start_matches('-')),
        &|| "1e300".into(),
        &|| "-1e308".into(),
        &|| "5e-324".into(),
        &|| "1e-12".into(),
        &|| if json { "NaN" } else { "nan" }.into(),
        &|| if json { "Infinity" } else { "inf" }.into(),
        &|| if json { "-Infinity" } else { "-inf" }.into(),
        &|| if json { "null" } else { "\"nan\"" }.into(),
        &|| format!("\"{x}\""),
        &|| "9223372036854775807".into(),
        &|| "4294967296".into(),
        &|| "-1".into(),
        &|| "1e15".into(),
        &|| format!("{:?}", v * 1000.0),
        &|| format!("{:?}", v / 1000.0),
        &|| format!("{:?}", v * 10.0),
        &|| format!("{:?}", v + 1.0),
        &|| format!("{}", v as i64),
        &|| format!("{:?}", v.trunc()),
        &|| "3e8".into(),
        &|| "1e9".into(),
    ];
    choices[rng.int_range(0, choices.len() - 1)]()
}

/// The key of a `key = value` (TOML) or `"key": value` (JSON) line, as a
/// byte range.
fn key_span(line: &str) -> Option<(usize, usize)> {
    let t = line.trim_start();
    let start = line.len() - t.len();
    if let Some(rest) = t.strip_prefix('"') {
        let end = rest.find('"')?;
        rest[end..]
            .contains(':')
            .then_some((start, start + end + 2))
    } else {
        let eq = t.find('=')?;
        let key = t[..eq].trim_end();
        let bare = !key.is_empty()
            && key
                .bytes()
                .all(|c| c.is_ascii_alphanumeric() || c == b'_' || c == b'-');
        bare.then_some((start, start + key.len()))
    }
}

/// `text` with one to three mutations.
fn mutate(rng: &mut SplitMix64, text: &str, json: bool) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    // One mutation most often, up to three.
    let rounds = [1, 1, 1, 2, 2, 3][rng.int_range(0, 5)];
    for _ in 0..rounds {
        if lines.is_empty() {
            break;
        }
        let k = rng.int_range(0, lines.len() - 1);
        match rng.int_range(0, 12) {
            // Numbers most often: they carry the physics.
            0..=7 => {
                let spans = number_spans(&lines[k], !json);
                let with: Vec<usize> = (0..lines.len())
                    .filter(|&i| !number_spans(&lines[i], !json).is_empty())
                    .collect();
                let k = if spans.is_empty() && !with.is_empty() {
                    with[rng.int_range(0, with.len() - 1)]
                } else {
                    k
                };
                let spans = number_spans(&lines[k], !json);
                if let Some(&(a, b)) = spans.get(rng.int_range(0, spans.len().max(1) - 1)) {
                    let new = extreme(rng, &lines[k][a..b], json);
                    lines[k].replace_range(a..b, &new);
                }
            }
            8 => {
                lines.remove(k);
            }
            9 => {
                let copy = lines[k].clone();
                lines.insert(k, copy);
            }
            10 => {
                let j = rng.int_range(0, lines.len() - 1);
                lines.swap(k, j);
            }
            11 => {
                // Swap the keys of two lines.
                let keyed: Vec<usize> = (0..lines.len())
                    .filter(|&i| key_span(&lines[i]).is_some())
                    .collect();
                if keyed.len() >= 2 {
                    let a = keyed[rng.int_range(0, keyed.len() - 1)];
                    let b = keyed[rng.int_range(0, keyed.len() - 1)];
                    if let (Some((a0, a1)), Some((b0, b1))) =
                        (key_span(&lines[a]), key_span(&lines[b]))
                    {
                        let (ka, kb) = (lines[a][a0..a1].to_string(), lines[b][b0..b1].to_string());
                        lines[a].replace_range(a0..a1, &kb);
                        let (b0, b1) = key_span(&lines[b]).unwrap_or((b0, b1));
                        lines[b].replace_range(b0..b1, &ka);
                    }
                }
            }
            _ => {
                // A vector one longer or one shorter.
                let line = &mut lines[k];
                let closes: Vec<usize> = line.match_indices(']').map(|(i, _)| i).collect();
                if let Some(&c) = closes.get(rng.int_range(0, closes.len().max(1) - 1)) {
                    if rng.int_range(0, 1) == 0 {
                        line.insert_str(c, ", 1.0");
                    } else if let Some(comma) = line[..c].rfind(',') {
                        if !line[comma..c].contains('[') && !line[comma..c].contains(']') {
                            line.replace_range(comma..c, "");
                        }
                    }
                }
            }
        }
    }
    let mut out = lines.join("\n");
    out.push('\n');
    out
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

// ---------------------------------------------------------------------------
// Case files

/// The nodes of the case's largest floe lattice (0 without the lattice
/// model), estimated from each floe's area and lattice spacing.
fn lattice_nodes(scn: &Scenario) -> f64 {
    if scn.fracture.model != floebench::model::fracture::FractureModel::Lattice {
        return 0.0;
    }
    scn.floes
        .iter()
        .map(|f| {
            let s = floebench::fracture::strike::lattice_spacing(&scn.fracture, f.area);
            f.area / (0.5 * 3f64.sqrt() * s * s)
        })
        .fold(0.0, f64::max)
}

/// Cuts the run to [`RUN_OUTPUTS`] outputs, [`RUN_STEPS`] fixed steps of
/// the formulation `name` and [`RUN_FLOE_SECONDS`], so that every run is
/// cheap.
fn shorten(scn: &mut Scenario, name: &str) -> Result<(), Defect> {
    let mut t = scn
        .duration
        .min(RUN_OUTPUTS * scn.output_interval)
        .min(RUN_FLOE_SECONDS / scn.floes.len().max(1) as f64);
    let step = match name {
        "moreau" | "moreau-cone" => MoreauSettings::of(scn).map(|s| s.step),
        "rapier" => RapierSettings::of(scn).map(|s| s.step),
        _ => Ok(f64::INFINITY),
    }
    .map_err(|e| format!("settings refused after validate: {e}"))?;
    t = t.min(RUN_STEPS * step);
    if scn.integrator.method == IntegratorKind::Euler {
        let bound = (0..scn.floes.len())
            .map(|i| scn.euler_stability_bound(i))
            .chain(scn.integrator.max_step)
            .fold(f64::INFINITY, f64::min);
        t = t.min(RUN_STEPS * bound);
    }
    scn.duration = t;
    Ok(())
}

/// Every number a run reports must be finite.
fn finite_result(r: &RunResult) -> Result<(), Defect> {
    let bad = |what: &str| Err(format!("non-finite number in the result: {what}"));
    for row in &r.trajectory {
        let v = [row.t, row.x, row.y, row.theta, row.vx, row.vy, row.omega];
        if !v.iter().all(|x| x.is_finite()) {
            return bad(&format!("trajectory row {row:?}"));
        }
    }
    for e in &r.energy {
        let mut v = std::iter::once(e.t).chain(e.values().map(|(_, v)| v));
        if !v.all(f64::is_finite) {
            return bad(&format!("energy sample {e:?}"));
        }
    }
    let s = &r.summary;
    let en = &s.energy;
    let mut totals = [s.t_reached, en.initial_kinetic, en.final_kinetic]
        .into_iter()
        .chain(en.ledger.values().map(|(_, v)| v))
        .chain([
            en.fracture_kinetic_gain,
            en.residual,
            en.max_abs_residual,
            en.exchanged,
            s.timing.cpu_total,
            s.timing.wall,
        ]);
    if !totals.all(f64::is_finite) {
        return bad("summary totals");
    }
    if let Some((c, v)) = s.counters.iter().find(|(_, v)| !v.is_finite()) {
        return bad(&format!("counter {} = {v}", c.name));
    }
    for setting in &s.settings.0 {
        if let SettingValue::Number(v) = setting.value {
            if !v.is_finite() {
                return bad(&format!("setting {} = {v}", setting.name));
            }
        }
    }
    let stages = &s.timing.stages;
    let mut times = vec![stages.total(), s.timing.cpu_other, s.timing.timer_overhead];
    if let Some(p) = &s.lcp_profile {
        times.push(p.timer_overhead);
        times.extend(p.buckets.iter().map(|b| b.seconds));
    }
    if !times.iter().all(|x| x.is_finite()) {
        return bad("timing");
    }
    Ok(())
}

/// Writes the run with the library's writer into a fresh folder and reads
/// every file back: all numbers finite, all rows there; a refused write
/// leaves no file.
fn write_and_read_back(r: &RunResult) -> Result<(), Defect> {
    let dir = tempdir();
    let listed = || -> Vec<String> {
        std::fs::read_dir(dir.path())
            .map(|d| {
                d.filter_map(|e| e.ok())
                    .map(|e| e.file_name().to_string_lossy().into_owned())
                    .collect()
            })
            .unwrap_or_default()
    };
    if let Err(e) = output::write_run(dir.path(), r) {
        let left = listed();
        return Err(if left.is_empty() {
            format!("non-finite output refused by the writer: {e}")
        } else {
            format!("partial file: the writer failed ({e}) and left {left:?}")
        });
    }
    let mut files = listed();
    files.sort();
    // A lattice run that broke a floe also writes its percussion record.
    let mut expected = vec![
        "energy.csv",
        "floes.json",
        "fractures.csv",
        "summary.json",
        "trajectory.csv",
    ];
    if r.percussion.is_some() {
        expected.insert(3, output::PERCUSSION_FILE);
    }
    if files != expected {
        return Err(format!("partial file: the folder holds {files:?}"));
    }
    if r.percussion.is_some() {
        let text = std::fs::read_to_string(dir.path().join(output::PERCUSSION_FILE))
            .map_err(|e| format!("unreadable output: percussion.json: {e}"))?;
        let v: serde_json::Value = serde_json::from_str(&text)
            .map_err(|e| format!("unreadable output: percussion.json: {e}"))?;
        // serde_json writes a non-finite number as null: only an
        // obstacle's striker mass may be null.
        let numbers = [
            "t", "angle", "bound", "weakest", "loss", "energy", "spacing",
        ];
        if numbers.iter().any(|k| !v[*k].is_number())
            || v["impacts"]
                .as_array()
                .is_none_or(|a| a.is_empty() || a.iter().any(|i| !i["speed"].is_number()))
            || v["nodes"].as_array().is_none_or(|a| {
                a.iter().any(|p| {
                    p.as_array()
                        .is_none_or(|xy| xy.iter().any(|x| !x.is_number()))
                })
            })
        {
            return Err(format!("non-finite number in percussion.json: {text}"));
        }
    }
    for (name, rows) in [
        ("trajectory.csv", r.trajectory.len()),
        ("energy.csv", r.energy.len()),
    ] {
        let text = std::fs::read_to_string(dir.path().join(name))
            .map_err(|e| format!("unreadable output: {name}: {e}"))?;
        let mut n = 0;
        for line in text.lines().skip(1) {
            n += 1;
            for field in line.split(',') {
                match field.parse::<f64>() {
                    Ok(v) if v.is_finite() => {}
                    _ => return Err(format!("non-finite number in {name}: {line}")),
                }
            }
        }
        if n != rows {
            return Err(format!("partial file: {name} holds {n} rows of {rows}"));
        }
    }
    let summary = std::fs::read_to_string(dir.path().join("summary.json"))
        .map_err(|e| format!("unreadable output: summary.json: {e}"))?;
    serde_json::from_str::<serde_json::Value>(&summary)
        .map_err(|e| format!("unreadable output: summary.json: {e}"))?;
    Ok(())
}

/// A case the library refuses, through the binary: `floebench run` exits
/// with an error of one line and writes nothing (no output folder).
fn refused_by_the_command(text: &str) -> Result<(), Defect> {
    let dir = tempdir();
    let case = dir.path().join("mutant.toml");
    let out = dir.path().join("out");
    std::fs::write(&case, text).map_err(|e| format!("cannot write the mutant: {e}"))?;
    let done = floebench()
        .arg("run")
        .arg(&case)
        .arg("-o")
        .arg(&out)
        .arg("--quiet")
        .output()
        .map_err(|e| format!("cannot start floebench: {e}"))?;
    let stderr = String::from_utf8_lossy(&done.stderr);
    if done.status.success() {
        return Err(format!(
            "`floebench run` accepted a case validate refuses: {stderr}"
        ));
    }
    let lines: Vec<&str> = stderr.lines().collect();
    if stderr.contains("panicked") || lines.len() != 1 || !lines[0].starts_with("error: ") {
        return Err(format!(
            "`floebench run` did not end with one error line: {stderr:?}"
        ));
    }
    if out.exists() {
        return Err(
            "partial file: `floebench run` created its output folder for a refused case".into(),
        );
    }
    Ok(())
}

/// One case mutant: validate, then (when accepted and small) a short run
/// by the formulation `pick` selects, written and read back.
fn check_case(text: String, pick: u64) -> Result<String, Defect> {
    let loaded = guarded("validate", || parse_case(&text, Path::new("mutant.toml")))?;
    let mut scn = match loaded {
        Err(e) => {
            one_line("the validate error", &e.to_string())?;
            if pick.is_multiple_of(CLI_EVERY) {
                refused_by_the_command(&text)?;
                return Ok("rejected by validate, and by `floebench run`".into());
            }
            return Ok("rejected by validate".into());
        }
        Ok(scn) => scn,
    };
    if scn.floes.len() > MAX_RUN_FLOES {
        return Ok("accepted, too many floes to run".into());
    }
    if lattice_nodes(&scn) > MAX_RUN_LATTICE_NODES {
        return Ok("accepted, lattices too fine to run".into());
    }
    let entries: Vec<_> = REGISTRY.iter().filter(|e| e.applies(&scn)).collect();
    let entry = entries[(pick % entries.len() as u64) as usize];
    shorten(&mut scn, entry.name)?;
    let opts = FormulationOptions::default();
    let mut inst = match guarded("build", || build(entry.name, &scn, &opts))? {
        Err(m) => {
            one_line("the formulation's refusal", &m)?;
            return Ok(format!("refused by {}", entry.name));
        }
        Ok(i) => i,
    };
    let r = guarded(&format!("run ({})", entry.name), || {
        Runner::new(RunOptions::default()).run(&scn, entry.name, inst.formulation.as_mut())
    })?;
    if let EndReason::Failed { message } = &r.summary.end {
        one_line("a failed run's message", message)?;
    }
    finite_result(&r)?;
    guarded("write", || write_and_read_back(&r))??;
    let end = match r.summary.end {
        EndReason::Completed => "completed",
        EndReason::Failed { .. } => "failed",
        EndReason::NonFinite { .. } => "non_finite",
        EndReason::Interrupted { .. } => "interrupted",
    };
    Ok(format!("ran {}: {end}", entry.name))
}

#[test]
fn mutated_cases_never_panic_hang_or_write_non_finite_numbers() {
    let root = cases_dir();
    let texts = corpus(&[root.clone(), root.join("fields")], "toml");
    fuzz("cases", "case", &texts, false, check_case);
}

// ---------------------------------------------------------------------------
// LCP dumps

/// One dump mutant: the strict reader, then the driver; a solved answer
/// must pass its residual check.
fn check_dump(text: String, _pick: u64) -> Result<String, Defect> {
    let read = guarded("the dump reader", || {
        LcpDump::from_json(&text, Path::new("mutant.json"))
    })?;
    let dump = match read {
        Err(e) => {
            one_line("the dump reader's error", &e.to_string())?;
            return Ok("rejected by the reader".into());
        }
        Ok(d) => d,
    };
    let lcp = match dump.to_lcp() {
        Err(e) => {
            one_line("the LCP's error", &e.to_string())?;
            return Ok("rejected: not an LCP".into());
        }
        Ok(l) => l,
    };
    let opts = SolveOptions::default();
    let sol = guarded("solve", || solve(&lcp, &opts))?;
    if !sol.status.is_solved() {
        return Ok("solve failed (counted)".into());
    }
    let r = residual(&lcp.m, &lcp.q, &sol.z);
    if r.is_nan() || r > opts.tolerance {
        return Err(format!(
            "false solve: {} with residual {r} above {}",
            sol.status, opts.tolerance
        ));
    }
    // An independent check: M z + q computed naively, relative to the
    // magnitudes (a residual of 1e-10 relative to |q|_2 is within 1e-8 of
    // them for these sizes, rounding included).
    if let Some(v) = lcp_violation(&lcp.m, &lcp.q, &sol.z, 1e-8) {
        return Err(format!("false solve: {}: {v}", sol.status));
    }
    Ok(format!("solved ({})", sol.status))
}

#[test]
fn mutated_lcp_dumps_never_panic_and_no_false_solve() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/lcp");
    let texts = corpus(&[dir], "json");
    fuzz("LCP dumps", "lcp", &texts, true, check_dump);
}

#[test]
fn mutations_change_the_text_and_keep_it_mostly_readable() {
    // The mutator itself: each mutant differs from its source; numbers are
    // found outside comments only.
    assert_eq!(
        number_spans("a = [1.5, -2e-3] # 7", true),
        vec![(5, 8), (10, 15)]
    );
    assert_eq!(number_spans("x1 = 3", true), vec![(5, 6)]);
    assert_eq!(key_span("  friction = 0.3"), Some((2, 10)));
    assert_eq!(key_span("  \"q\": [1.0]"), Some((2, 5)));
    let text = std::fs::read_to_string(cases_dir().join("head_on.toml")).unwrap();
    let mut rng = SplitMix64::new(1);
    let changed = (0..200)
        .filter(|_| mutate(&mut rng, &text, false) != text)
        .count();
    assert!(changed > 150, "only {changed} of 200 mutants differ");
}
