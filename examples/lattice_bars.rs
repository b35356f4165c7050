//! Saint-Venant's check of the two-lattice impact (docs/physics.md §9.9):
//! two bars of ice end-on, `L1` striking `L2` at rest at `--speed`, both
//! unbreakable lattices without dashpots, for each spacing given; one CSV
//! row per spacing on stdout: the effective restitution against
//! `min(L1, L2)/max(L1, L2)`, the energy split, the momentum error, the
//! cost.
//!
//! `cargo run --release --example lattice_bars -- [--lengths 100,200]
//! [--width 10] [--speed 1] [--mesh random|triangular] [--damping 0]
//! [--safety 0.9]
//! 2.5 1.25 0.625`

use floebench::fracture::chain::ChainOptions;
use floebench::fracture::lattice::bars::Bars;
use floebench::fracture::lattice::{LatticeSpec, Mesh};
use std::time::Instant;

fn main() {
    if let Err(e) = run() {
        eprintln!("lattice_bars: {e}");
        std::process::exit(2);
    }
}

fn run() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let mut bars = Bars {
        lengths: (100.0, 200.0),
        width: 10.0,
        speed: 1.0,
        offset: 0.0,
        gap: 0.0,
    };
    let mut mesh = Mesh::Random;
    let mut damping = 0.0;
    let mut safety = ChainOptions::default().safety;
    let mut spacings = Vec::new();
    let number = |s: Option<String>, what: &str| -> Result<f64, String> {
        let s = s.ok_or(format!("{what} needs a value"))?;
        s.parse().map_err(|_| format!("{what}: not a number: {s}"))
    };
    while let Some(a) = args.next() {
        match a.as_str() {
            "--lengths" => {
                let s = args.next().ok_or("--lengths needs L1,L2")?;
                let (a, b) = s.split_once(',').ok_or("--lengths needs L1,L2")?;
                bars.lengths = (number(Some(a.into()), "L1")?, number(Some(b.into()), "L2")?);
            }
            "--width" => bars.width = number(args.next(), "--width")?,
            "--speed" => bars.speed = number(args.next(), "--speed")?,
            "--damping" => damping = number(args.next(), "--damping")?,
            "--safety" => safety = number(args.next(), "--safety")?,
            "--mesh" => {
                mesh = match args.next().as_deref() {
                    Some("random") => Mesh::Random,
                    Some("triangular") => Mesh::triangular_variant(0.0, 1),
                    other => return Err(format!("--mesh random|triangular, got {other:?}")),
                }
            }
            s => spacings.push(number(Some(s.into()), "spacing")?),
        }
    }
    if spacings.is_empty() {
        spacings = vec![2.5, 1.25, 0.625];
    }
    let options = ChainOptions {
        damping,
        safety,
        ..ChainOptions::default()
    };
    println!(
        "spacing,l1,l2,e_eff,saint_venant,relative_error,rigid_J,vibration_J,damping_J,\
         energy_defect_rel,momentum_error_rel,contact_end_s,t_s,steps,stop,cpu_s"
    );
    for s in spacings {
        let spec = LatticeSpec {
            spacing: s,
            mesh,
            ..LatticeSpec::default()
        };
        let clock = Instant::now();
        let o = bars.run(spec, options)?;
        let cpu = clock.elapsed().as_secs_f64();
        let sv = bars.saint_venant();
        let dp = (o.momentum[1] - o.momentum[0]).norm() / o.momentum[0].norm();
        println!(
            "{s},{},{},{:.5},{sv:.5},{:.4},{:.6e},{:.6e},{:.6e},{:.3e},{dp:.3e},{:.6},{:.6},{},{},{cpu:.2}",
            bars.lengths.0,
            bars.lengths.1,
            o.restitution,
            (o.restitution - sv) / sv,
            o.rigid_energy(),
            o.vibration(),
            o.damping,
            o.energy_defect() / o.initial_energy,
            o.contact_end,
            o.t,
            o.steps,
            o.reason.name(),
        );
    }
    Ok(())
}
