//! Saint-Venant's bars through the runner (docs/physics.md §9.10): the case
//! `cases/lattice_bars.toml` (the 100 m bar at 1 m/s end-on into a bar at
//! rest, `impact = "lattice"`, unbreakable lattices without dashpots) with
//! the struck bar `L2` long and the lattices at each spacing given, run by
//! each formulation given; one CSV row per run on stdout: the effective
//! restitution read from the trajectory's last output,
//! `(v2 − v1)·x / 1 m/s`, against Saint-Venant's `min(L1, L2)/max(L1, L2)`,
//! the momentum error, the energy split and the cost.
//!
//! `cargo run --release --example lattice_bars_runner -- [--lengths 200,300,100]
//! [--formulations event-driven,moreau] [--mesh random|triangular] 2.5 1.25 0.625`
//! (`--mesh` sets the case's `[fracture] mesh`; default the case's, random).

use floebench::formulation::{build, parse_case, FormulationOptions};
use floebench::run::{RunOptions, RunResult, Runner};
use std::path::Path;

/// The striking bar's length and speed in `cases/lattice_bars.toml`.
const L1: f64 = 100.0;
const SPEED: f64 = 1.0;

fn main() {
    if let Err(e) = run() {
        eprintln!("lattice_bars_runner: {e}");
        std::process::exit(2);
    }
}

/// The text of `cases/lattice_bars.toml` with the struck bar `l2` long and
/// the lattices at `spacing` (their mesh `mesh` when given).
fn case_text(l2: f64, spacing: f64, mesh: Option<&str>) -> Result<String, String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/lattice_bars.toml");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let end = 101.0 + l2;
    let replaced = text
        .replace(
            "[[101.0, 0.0], [301.0, 0.0], [301.0, 10.0], [101.0, 10.0]]",
            &format!("[[101.0, 0.0], [{end:?}, 0.0], [{end:?}, 10.0], [101.0, 10.0]]"),
        )
        .replace("spacing = 2.5", &format!("spacing = {spacing:?}"));
    if !replaced.contains(&format!("spacing = {spacing:?}"))
        || !replaced.contains(&format!("{end:?}"))
    {
        return Err(format!("{}: not the expected bars", path.display()));
    }
    // `[fracture]` is the case's last table.
    Ok(match mesh {
        Some(m) => format!("{replaced}\nmesh = \"{m}\"\n"),
        None => replaced,
    })
}

/// `(v2 − v1)·x / SPEED` at the trajectory's last output, and the pair's
/// linear momentum error there relative to the initial momentum.
fn outcome(r: &RunResult, masses: [f64; 2]) -> Result<(f64, f64), String> {
    let last = r.trajectory.last().ok_or("an empty trajectory")?;
    let at_end: Vec<_> = r.trajectory.iter().filter(|row| row.t == last.t).collect();
    let v = |i: usize| {
        at_end
            .iter()
            .find(|row| row.floe == i)
            .map(|row| (row.vx, row.vy))
            .ok_or(format!("no floe {i} at the last output"))
    };
    let (a, b) = (v(0)?, v(1)?);
    let p0 = masses[0] * SPEED;
    let p = (masses[0] * a.0 + masses[1] * b.0 - p0).hypot(masses[0] * a.1 + masses[1] * b.1);
    Ok(((b.0 - a.0) / SPEED, p / p0))
}

fn run() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let mut lengths = vec![200.0, 300.0, 100.0];
    let mut formulations = vec!["event-driven".to_string(), "moreau".to_string()];
    let mut spacings = Vec::new();
    let mut mesh = None;
    while let Some(a) = args.next() {
        match a.as_str() {
            "--lengths" => {
                let s = args.next().ok_or("--lengths needs L2,L2,...")?;
                lengths = s
                    .split(',')
                    .map(|x| {
                        x.parse()
                            .map_err(|_| format!("--lengths: not a number: {x}"))
                    })
                    .collect::<Result<_, _>>()?;
            }
            "--mesh" => mesh = Some(args.next().ok_or("--mesh needs random or triangular")?),
            "--formulations" => {
                let s = args.next().ok_or("--formulations needs a,b,...")?;
                formulations = s.split(',').map(str::to_string).collect();
            }
            s => spacings.push(
                s.parse()
                    .map_err(|_| format!("spacing: not a number: {s}"))?,
            ),
        }
    }
    if spacings.is_empty() {
        spacings = vec![2.5, 1.25, 0.625];
    }
    println!(
        "l1,l2,spacing,formulation,e_eff,saint_venant,relative_error,momentum_error_rel,\
         kinetic_final_J,vibration_J,dissipated_J,lattice_impacts,lattice_steps,cpu_lattice_s,cpu_s"
    );
    for &l2 in &lengths {
        for &s in &spacings {
            let text = case_text(l2, s, mesh.as_deref())?;
            let scn = parse_case(&text, Path::new("cases/lattice_bars.toml"))
                .map_err(|e| e.to_string())?;
            let masses = [scn.floes[0].mass, scn.floes[1].mass];
            let sv = L1.min(l2) / L1.max(l2);
            for name in &formulations {
                let mut f = build(name, &scn, &FormulationOptions::default())?;
                let r =
                    Runner::new(RunOptions::default()).run(&scn, f.name(), f.formulation.as_mut());
                let (e_eff, dp) = outcome(&r, masses)?;
                let s_ = &r.summary;
                let count = |c: &str| s_.counters.by_name(c).ok().flatten().unwrap_or(f64::NAN);
                println!(
                    "{L1},{l2},{s},{name},{e_eff:.5},{sv:.5},{:.4},{dp:.3e},{:.6e},{:.6e},{:.6e},{},{},{:.3},{:.3}",
                    (e_eff - sv) / sv,
                    s_.energy.final_kinetic,
                    r.final_state.ledger.vibration,
                    r.final_state.ledger.dissipated,
                    count("lattice_impacts"),
                    count("lattice_impact_steps"),
                    s_.timing.stages.lattice,
                    s_.timing.cpu_total,
                );
            }
        }
    }
    Ok(())
}
