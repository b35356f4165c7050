//! The critical ramming speed of the lattice model (docs/physics.md §7.3)
//! as the lattice spacing shrinks: a square floe 1 m thick rammed face-on
//! (mid-face) into a fixed coast, for each spacing and seed the critical
//! speed by bisection ([`critical_ram_speed`]); the bond rule a critical
//! strain (`--strain E`) or a toughness (`--toughness G`). Writes one CSV
//! row per spacing and seed to `--csv PATH` (or stdout), and on stderr the
//! mean over the seeds per spacing, the differences between successive
//! spacings and their rate (the slope of `log |v̄(s) − v̄(s/2)|` against
//! `log s`, least squares).
//!
//! `cargo run --release --example lattice_ram -- --strain 1e-4 [--poisson 0.3]
//! [--seeds 3] [--size 10] [--tol 1e-3] [--csv ram.csv] 1 0.5 0.25`

use floebench::fracture::chain::{BondRule, ChainOptions};
use floebench::fracture::lattice::percussion::critical_ram_speed;
use floebench::fracture::lattice::{Lattice, LatticeSpec};
use floebench::geometry::Vec2;
use std::io::Write;

/// The command line.
struct Args {
    bond: BondRule,
    poisson: f64,
    seeds: u64,
    size: f64,
    tol: f64,
    csv: Option<String>,
    spacings: Vec<f64>,
}

fn number(flag: &str, value: Option<&String>) -> Result<f64, String> {
    let v = value.ok_or(format!("{flag} needs a value"))?;
    v.parse()
        .map_err(|e| format!("{flag}: {v:?} is not a number: {e}"))
}

fn parse() -> Result<Args, String> {
    let argv: Vec<String> = std::env::args().skip(1).collect();
    let mut a = Args {
        bond: BondRule::Unbreakable,
        poisson: 1.0 / 3.0,
        seeds: 3,
        size: 10.0,
        tol: 1e-3,
        csv: None,
        spacings: Vec::new(),
    };
    let mut it = argv.iter();
    while let Some(flag) = it.next() {
        match flag.as_str() {
            "--strain" => a.bond = BondRule::Strain(number(flag, it.next())?),
            "--toughness" => a.bond = BondRule::Toughness(number(flag, it.next())?),
            "--poisson" => a.poisson = number(flag, it.next())?,
            "--seeds" => a.seeds = number(flag, it.next())? as u64,
            "--size" => a.size = number(flag, it.next())?,
            "--tol" => a.tol = number(flag, it.next())?,
            "--csv" => a.csv = Some(it.next().ok_or("--csv needs a path")?.clone()),
            s => a.spacings.push(number("a spacing", Some(&s.to_string()))?),
        }
    }
    if a.bond == BondRule::Unbreakable {
        return Err("give a bond rule: --strain E or --toughness G".into());
    }
    if a.spacings.is_empty() || a.seeds == 0 {
        return Err("give at least one spacing and one seed".into());
    }
    Ok(a)
}

fn main() -> Result<(), String> {
    let a = parse()?;
    let l = a.size;
    let square = [
        Vec2::new(0.0, 0.0),
        Vec2::new(l, 0.0),
        Vec2::new(l, l),
        Vec2::new(0.0, l),
    ];
    let options = ChainOptions {
        bond: a.bond,
        ..ChainOptions::default()
    };
    let mut out: Box<dyn Write> = match &a.csv {
        Some(p) => Box::new(std::fs::File::create(p).map_err(|e| format!("{p}: {e}"))?),
        None => Box::new(std::io::stdout()),
    };
    let io = |e: std::io::Error| e.to_string();
    writeln!(out, "size,spacing,seed,nodes,poisson,rule,value,v_c").map_err(io)?;
    let (rule, value) = match a.bond {
        BondRule::Strain(e) => ("strain", e),
        BondRule::Toughness(g) => ("toughness", g),
        BondRule::Force(f) => ("force", f),
        BondRule::Unbreakable => ("none", 0.0),
    };
    let mut means = Vec::new();
    for &spacing in &a.spacings {
        let mut sum = 0.0;
        for seed in 1..=a.seeds {
            let spec = LatticeSpec {
                spacing,
                thickness: 1.0,
                poisson: a.poisson,
                seed,
                ..LatticeSpec::default()
            };
            let lattice = Lattice::build(&square, spec)?;
            // Pieces of at least 3 nodes: a broken-off node is debris.
            let v = critical_ram_speed(
                &lattice,
                Vec2::new(0.0, 0.5 * l),
                Vec2::new(1.0, 0.0),
                options,
                3,
                a.tol,
                1e3,
            )?;
            let n = lattice.nodes.len();
            writeln!(
                out,
                "{l},{spacing},{seed},{n},{},{rule},{value},{v}",
                a.poisson
            )
            .map_err(io)?;
            out.flush().map_err(io)?;
            sum += v;
        }
        means.push(sum / a.seeds as f64);
        eprintln!(
            "spacing {spacing}: mean v_c {:.4} m/s",
            sum / a.seeds as f64
        );
    }
    // |v̄(s_i) − v̄(s_{i+1})| against s_i, and the slope of their logs.
    let diffs: Vec<(f64, f64)> = means
        .windows(2)
        .zip(&a.spacings)
        .map(|(w, &s)| (s, (w[1] - w[0]).abs()))
        .collect();
    eprintln!("differences between successive spacings: {diffs:?}");
    if diffs.len() >= 2 && diffs.iter().all(|d| d.1 > 0.0) {
        let pts: Vec<(f64, f64)> = diffs.iter().map(|(s, d)| (s.ln(), d.ln())).collect();
        let n = pts.len() as f64;
        let (mx, my) = (
            pts.iter().map(|p| p.0).sum::<f64>() / n,
            pts.iter().map(|p| p.1).sum::<f64>() / n,
        );
        let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
        let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
        eprintln!(
            "rate of the differences (slope of log|dv| on log s): {:.3}",
            sxy / sxx
        );
    }
    Ok(())
}
