//! Case-file mutants: the library's case loading, a short run of one
//! formulation with its files written and read back, and for some refused
//! cases `floebench run`.

use super::{
    corpus, fuzz, one_line, CLI_EVERY, MAX_RUN_FLOES, MAX_RUN_LATTICE_NODES, RUN_FLOE_SECONDS,
    RUN_OUTPUTS, RUN_STEPS,
};
use crate::common::{cases_dir, floebench, guarded, tempdir, Defect};
use floebench::formulation::moreau::MoreauSettings;
use floebench::formulation::rapier_ref::RapierSettings;
use floebench::formulation::{build, parse_case, FormulationOptions, REGISTRY};
use floebench::model::{IntegratorKind, Scenario};
use floebench::record::SettingValue;
use floebench::run::{output, EndReason, RunOptions, RunResult, Runner};
use std::path::Path;

/// The nodes of the case's largest floe lattice (0 without the lattice
/// model), estimated from each floe's area and lattice spacing.
fn lattice_nodes(scn: &Scenario) -> f64 {
    if scn.fracture.model != floebench::model::fracture::FractureModel::Lattice {
        return 0.0;
    }
    scn.floes
        .iter()
        .map(|f| {
            let s = floebench::fracture::strike::lattice_spacing(&scn.fracture, f.area, &f.shape);
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
    // A lattice run that broke a floe also writes its percussion record,
    // a case with obstacles the forces on them.
    let mut expected = vec![
        "energy.csv",
        "floes.json",
        "fractures.csv",
        "stress.csv",
        "summary.json",
        "trajectory.csv",
    ];
    if r.percussion.is_some() {
        expected.insert(3, output::PERCUSSION_FILE);
    }
    if r.summary.obstacles > 0 {
        expected.insert(3, output::OBSTACLES_FILE);
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
    let obstacles = match r.summary.obstacles {
        0 => None,
        _ => Some((output::OBSTACLES_FILE, r.obstacle_forces.len())),
    };
    for (name, rows) in [
        ("trajectory.csv", r.trajectory.len()),
        ("energy.csv", r.energy.len()),
        ("stress.csv", r.stress.len()),
    ]
    .into_iter()
    .chain(obstacles)
    {
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
