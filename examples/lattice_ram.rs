//! The critical ramming speed of the lattice model (docs/physics.md §7.3)
//! as the lattice spacing shrinks: a square floe 1 m thick rammed face-on
//! (mid-face) into a fixed coast, for each spacing and seed the critical
//! speed by bisection ([`critical_ram_speed_by`]), a break being two
//! pieces of 3 nodes or more (the default, `--min-nodes N` for N), two
//! pieces of at least a fraction `F` of the floe's mass each
//! (`--mass-fraction F`), or the first broken bond (`--first-bond`, the
//! onset of damage); the bond rule a critical
//! strain (`--strain E`) or a toughness (`--toughness G`); the mesh the
//! seeded random one (`--mesh random`, the default) or the regular
//! triangular one (`--mesh triangular`, rotated by `--angle DEG` degrees),
//! whose variants 1, 2, … in place of seeds are offsets of the lattice
//! from the centroid ([`Mesh::triangular_variant`]). Writes one CSV row per spacing
//! and seed to `--csv PATH` (or stdout), and on stderr the mean and
//! standard deviation over the seeds per spacing, the differences between
//! successive spacings, their rate (the slope of `log |v̄(s) − v̄(s/2)|`
//! against `log s`, least squares) and the limit it extrapolates to (the
//! finest mean plus the geometric sum of the differences still to come).
//!
//! `cargo run --release --example lattice_ram -- --strain 1e-4 [--poisson 0.3]
//! [--mesh triangular [--angle 30]] [--first-bond | --mass-fraction 0.05 |
//! --min-nodes 3] [--seeds 3] [--size 10] [--tol 1e-3]
//! [--csv ram.csv] 1 0.5 0.25`

use floebench::fracture::chain::{BondRule, ChainOptions};
use floebench::fracture::lattice::percussion::{critical_ram_speed_by, mean_and_deviation, Break};
use floebench::fracture::lattice::{Lattice, LatticeSpec, Mesh};
use floebench::geometry::Vec2;
use std::io::Write;

/// The command line.
struct Args {
    bond: BondRule,
    poisson: f64,
    triangular: bool,
    angle: f64,
    criterion: Break,
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
        triangular: false,
        angle: 0.0,
        criterion: Break::Pieces(3),
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
            "--mesh" => {
                a.triangular = match it.next().map(String::as_str) {
                    Some("random") => false,
                    Some("triangular") => true,
                    m => return Err(format!("--mesh: random or triangular, got {m:?}")),
                }
            }
            "--first-bond" => a.criterion = Break::FirstBond,
            "--mass-fraction" => a.criterion = Break::MassFraction(number(flag, it.next())?),
            "--min-nodes" => a.criterion = Break::Pieces(number(flag, it.next())? as usize),
            "--angle" => a.angle = number(flag, it.next())?.to_radians(),
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
    writeln!(
        out,
        "size,spacing,mesh,seed,angle_deg,offset_1,offset_2,nodes,poisson,rule,value,criterion,v_c"
    )
    .map_err(io)?;
    let (rule, value) = match a.bond {
        BondRule::Strain(e) => ("strain", e),
        BondRule::Toughness(g) => ("toughness", g),
        BondRule::Force(f) => ("force", f),
        BondRule::Cohesive { strength, .. } => ("cohesive", strength),
        BondRule::Unbreakable => ("none", 0.0),
    };
    let criterion = match a.criterion {
        Break::Pieces(n) => format!("pieces>={n}"),
        Break::MassFraction(q) => format!("mass>={q}"),
        Break::FirstBond => "first-bond".into(),
    };
    let mut means = Vec::new();
    for &spacing in &a.spacings {
        let mut speeds = Vec::new();
        for seed in 1..=a.seeds {
            let mesh = if a.triangular {
                Mesh::triangular_variant(a.angle, seed)
            } else {
                Mesh::Random
            };
            let spec = LatticeSpec {
                spacing,
                thickness: 1.0,
                poisson: a.poisson,
                seed,
                mesh,
                ..LatticeSpec::default()
            };
            let lattice = Lattice::build(&square, spec)?;
            let v = critical_ram_speed_by(
                &lattice,
                Vec2::new(0.0, 0.5 * l),
                Vec2::new(1.0, 0.0),
                options,
                a.criterion,
                a.tol,
                1e3,
            )?;
            let n = lattice.nodes.len();
            let (name, off) = match mesh {
                Mesh::Triangular { offset, .. } => ("triangular", offset),
                Mesh::Random => ("random", [0.0; 2]),
            };
            writeln!(
                out,
                "{l},{spacing},{name},{seed},{},{},{},{n},{},{rule},{value},{criterion},{v}",
                a.angle.to_degrees(),
                off[0],
                off[1],
                a.poisson
            )
            .map_err(io)?;
            out.flush().map_err(io)?;
            speeds.push(v);
        }
        let (mean, sd) = mean_and_deviation(&speeds);
        means.push(mean);
        eprintln!("spacing {spacing}: mean v_c {mean:.4} m/s, standard deviation {sd:.4}");
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
        let rate = sxy / sxx;
        eprintln!("rate of the differences (slope of log|dv| on log s): {rate:.3}");
        // Differences shrinking by r = 2^-rate per halving sum, after the
        // last one, to d r / (1 − r) (signed): the extrapolated limit.
        let r = 0.5f64.powf(rate);
        if rate > 0.0 && a.spacings.windows(2).all(|w| w[1] == 0.5 * w[0]) {
            let last = means[means.len() - 1];
            let d = last - means[means.len() - 2];
            eprintln!(
                "extrapolated limit (geometric, ratio {r:.3} per halving): {:.4} m/s",
                last + d * r / (1.0 - r)
            );
        }
    }
    Ok(())
}
