//! `floebench percussion-1d` and `percussion-2d`: resolve one percussion of
//! the fracture models (a chain of bars, a floe's lattice) and print its
//! pieces.

use super::{plural, Outcome, INTERRUPTED};
use floebench::fracture::chain::Stop;
use floebench::fracture::chain::{BarSpec, BondRule, Chain, ChainOptions, Material};
use floebench::fracture::lattice::rectangle::FaceStrike;
use floebench::fracture::lattice::LatticeSpec;
use floebench::model::limits::fracture::POISSON_MAX;
use floebench::model::DEFAULT_ICE_DENSITY;
use floebench::report::format::fmt_num;
use std::path::PathBuf;
use std::process::ExitCode;

/// The arguments of `floebench percussion-1d`.
#[derive(clap::Args)]
pub struct Args1d {
    /// A bar, left to right, touching the previous one:
    /// LENGTH,NODES,VELOCITY (m, number of masses, m/s); give at least one.
    #[arg(long = "bar", required = true, value_name = "L,N,V", value_parser = parse_bar)]
    bars: Vec<BarSpec>,
    /// Density, kg/m³.
    #[arg(long, default_value_t = DEFAULT_ICE_DENSITY)]
    density: f64,
    /// Young's modulus, Pa.
    #[arg(long, default_value_t = 8.95e9)]
    young: f64,
    /// Cross-section, m².
    #[arg(long, default_value_t = 1.0)]
    area: f64,
    /// Dashpot ratio beta (-): c = beta sqrt(k m); 0 for none.
    #[arg(long, default_value_t = 0.5)]
    damping: f64,
    /// Bonds break when their tension passes this force, N [default: never].
    #[arg(long, conflicts_with = "toughness")]
    strength: Option<f64>,
    /// Bonds break when their energy passes G A, G in J/m² [default: never].
    #[arg(long)]
    toughness: Option<f64>,
    /// Safety factor on the stable step, in (0, 1].
    #[arg(long, default_value_t = 0.9)]
    safety: f64,
    /// Internal energy, as a fraction of the initial energy, under which
    /// the waves have settled (-).
    #[arg(long, default_value_t = 1e-3)]
    settle: f64,
    /// Transit times of the longest bar after the contact ended after
    /// which the run stops even if the waves ring on.
    #[arg(long, default_value_t = 4.0)]
    settle_transits: f64,
    /// Transit times of the longest bar after which the run stops in any case.
    #[arg(long, default_value_t = 200.0)]
    limit_transits: f64,
    /// Also write the final nodes as CSV (node,bar,fragment,x,v) to FILE.
    #[arg(long, value_name = "FILE")]
    nodes: Option<PathBuf>,
}

/// The arguments of `floebench percussion-2d`.
#[derive(clap::Args)]
pub struct Args2d {
    /// Floe size WIDTH,HEIGHT, m.
    #[arg(long, value_name = "W,H", default_value = "10,10", value_parser = parse_pair)]
    size: (f64, f64),
    /// Lattice spacing, m.
    #[arg(long, default_value_t = 0.5)]
    spacing: f64,
    /// Thickness, m.
    #[arg(long, default_value_t = 1.0)]
    thickness: f64,
    /// Density, kg/m³.
    #[arg(long, default_value_t = DEFAULT_ICE_DENSITY)]
    density: f64,
    /// Young's modulus, Pa.
    #[arg(long, default_value_t = 8.95e9)]
    young: f64,
    /// Poisson ratio (-), in (-1, 1/3]: 1/3 is central springs alone,
    /// below it torsion springs at the triangle corners (ice: 0.3)
    /// [default: 1/3].
    #[arg(long)]
    poisson: Option<f64>,
    /// Seed of the lattice's nodes.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Dashpot ratio beta (-): c = beta sqrt(k m); 0 for none.
    #[arg(long, default_value_t = 0.5)]
    damping: f64,
    /// Bonds break past this strain (-) [default: never].
    #[arg(long, conflicts_with = "toughness")]
    strain: Option<f64>,
    /// Bonds break when their energy passes G h w, G in J/m² [default: never].
    #[arg(long)]
    toughness: Option<f64>,
    /// Relative normal speed of the impact, m/s.
    #[arg(long)]
    speed: f64,
    /// The striker's effective mass, kg [default: a fixed coast, the
    /// floe moving at SPEED into it].
    #[arg(long)]
    mass: Option<f64>,
    /// Height of the contact point on the left face, m [default: its middle].
    #[arg(long)]
    at: Option<f64>,
    /// Draw the lattice, its broken bonds red, into STEM.png and STEM.svg.
    #[arg(long, value_name = "STEM")]
    plot: Option<PathBuf>,
}

/// `floebench percussion-1d`: runs the chain, prints the pieces as CSV on
/// stdout and the summary on stderr, and writes the nodes if asked.
pub fn run_1d(args: Args1d) -> Outcome {
    let material = Material {
        density: args.density,
        young: args.young,
        area: args.area,
    };
    let options = ChainOptions {
        damping: args.damping,
        bond: match (args.strength, args.toughness) {
            (Some(f), _) => BondRule::Force(f),
            (None, Some(g)) => BondRule::Toughness(g),
            (None, None) => BondRule::Unbreakable,
        },
        safety: args.safety,
        settle: args.settle,
        settle_transits: args.settle_transits,
        limit_transits: args.limit_transits,
    };
    let bars = &args.bars;
    let mut chain = Chain::new(&material, bars, options)?;
    let o = chain.run();
    println!("fragment,first,last,mass,length,centre,velocity");
    for (i, f) in o.fragments.iter().enumerate() {
        println!(
            "{i},{},{},{},{},{},{}",
            f.first, f.last, f.mass, f.length, f.centre, f.velocity
        );
    }
    eprintln!(
        "{}: t = {} s ({} steps of {} s), contact ended at {} s; {} broken, {} pieces",
        o.reason.name(),
        fmt_num(o.t),
        o.steps,
        fmt_num(o.dt),
        fmt_num(o.contact_end),
        plural(o.broken.len(), "bond"),
        o.fragments.len()
    );
    eprintln!(
        "energy: initial {} J, kinetic {} J, elastic {} J, fracture {} J, dissipated {} J",
        fmt_num(o.initial_energy),
        fmt_num(o.energies.kinetic),
        fmt_num(o.energies.elastic),
        fmt_num(o.energies.fracture),
        fmt_num(o.dissipated)
    );
    if o.bars.len() == 2 && bars[0].velocity != bars[1].velocity {
        eprintln!(
            "restitution of bars 0 and 1: {}",
            fmt_num(o.restitution(0, 1, bars[0].velocity, bars[1].velocity))
        );
    }
    if let Some(path) = &args.nodes {
        let pieces = &o.fragments;
        let mut text = String::from("node,bar,fragment,x,v\n");
        for i in 0..chain.len() {
            let frag = pieces
                .iter()
                .position(|f| f.first <= i && i <= f.last)
                .unwrap_or(0);
            text.push_str(&format!(
                "{i},{},{frag},{},{}\n",
                chain.bar[i], chain.x[i], chain.v[i]
            ));
        }
        std::fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    }
    Ok(status(o.reason))
}

/// `floebench percussion-2d`: strikes the floe ([`FaceStrike`]), prints the
/// pieces as CSV on stdout and the summary on stderr, and draws the crack
/// if asked.
pub fn run_2d(args: Args2d) -> Outcome {
    let spec = LatticeSpec {
        spacing: args.spacing,
        thickness: args.thickness,
        density: args.density,
        young: args.young,
        // Exactly 1/3 without --poisson (central springs alone).
        poisson: args.poisson.unwrap_or(POISSON_MAX),
        seed: args.seed,
        ..LatticeSpec::default()
    };
    let options = ChainOptions {
        damping: args.damping,
        bond: match (args.strain, args.toughness) {
            (Some(e), _) => BondRule::Strain(e),
            (None, Some(g)) => BondRule::Toughness(g),
            (None, None) => BondRule::Unbreakable,
        },
        ..ChainOptions::default()
    };
    let strike = FaceStrike {
        size: args.size,
        speed: args.speed,
        mass: args.mass,
        at: args.at.unwrap_or(0.5 * args.size.1),
    };
    strike.on_face().map_err(|e| format!("--at {e}"))?;
    let struck = strike.run(spec, options)?;
    let o = &struck.outcome;
    println!("piece,nodes,mass,x,y,vx,vy,omega,hull_area");
    for (i, f) in o.fragments.iter().enumerate() {
        println!(
            "{i},{},{},{},{},{},{},{},{}",
            f.nodes.len(),
            f.mass,
            f.centre.x,
            f.centre.y,
            f.velocity.x,
            f.velocity.y,
            f.angular_velocity,
            f.area
        );
    }
    eprintln!(
        "{}: t = {} s ({} steps of {} s, {} nodes), contact ended at {} s; {} broken, {} pieces",
        o.reason.name(),
        fmt_num(o.t),
        o.steps,
        fmt_num(o.dt),
        struck.lattice.nodes.len(),
        fmt_num(o.contact_end),
        plural(o.broken.len(), "bond"),
        o.fragments.len()
    );
    eprintln!(
        "energy: initial {} J, impact {} J, striker's work {} J, fracture {} J (broken bonds {} J); hull area error {}; striker {} -> {} m/s",
        fmt_num(o.initial_energy),
        fmt_num(o.impact_energy),
        fmt_num(o.work),
        fmt_num(o.fracture_energy),
        fmt_num(o.energies.fracture),
        fmt_num(o.hull_area_error),
        fmt_num(o.striker_velocity[0]),
        fmt_num(o.striker_velocity[1])
    );
    if let Some(stem) = &args.plot {
        // The springs at rest (the crack pattern on the floe as it was).
        let title = format!(
            "percussion at {} m/s: {} broken, {} pieces",
            fmt_num(strike.speed),
            plural(o.broken.len(), "bond"),
            o.fragments.len()
        );
        let [png, svg] = floebench::report::crack::draw(&struck.record(), &title, stem)
            .map_err(|e| e.to_string())?;
        eprintln!("wrote {} and {}", png.display(), svg.display());
    }
    Ok(status(o.reason))
}

/// The exit status of a percussion that stopped for `reason`:
/// [`INTERRUPTED`] when a signal stopped it (its state then printed).
fn status(reason: Stop) -> ExitCode {
    if reason == Stop::Interrupted {
        ExitCode::from(INTERRUPTED)
    } else {
        ExitCode::SUCCESS
    }
}

/// A `--bar` of `percussion-1d`: `LENGTH,NODES,VELOCITY`.
fn parse_bar(s: &str) -> Result<BarSpec, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let [l, n, v] = parts.as_slice() else {
        return Err(format!("expected LENGTH,NODES,VELOCITY, got {s:?}"));
    };
    let num = |x: &str, what: &str| x.parse::<f64>().map_err(|e| format!("{what} {x:?}: {e}"));
    Ok(BarSpec {
        length: num(l, "length")?,
        nodes: n
            .parse::<usize>()
            .map_err(|e| format!("nodes {n:?}: {e}"))?,
        velocity: num(v, "velocity")?,
    })
}

/// `W,H` of `percussion-2d --size`.
fn parse_pair(s: &str) -> Result<(f64, f64), String> {
    let (a, b) = s
        .split_once(',')
        .ok_or_else(|| format!("expected W,H, got {s:?}"))?;
    let num = |x: &str| x.trim().parse::<f64>().map_err(|e| format!("{x:?}: {e}"));
    Ok((num(a)?, num(b)?))
}
