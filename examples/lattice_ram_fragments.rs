//! What the percussion itself does to `cases/lattice_ram.toml`'s diamond
//! (a 50 m² square turned by 45°, 1 m thick) rammed corner first into a
//! fixed coast at `--speed U` m/s, for each spacing, before the run's
//! `min_area` merges the small components into their neighbours
//! (src/fracture/strike.rs): per spacing, the means over `--seeds N` seeds
//! (1..=N) of the broken bonds, the fracture energy (J: broken bonds and
//! softening, `Energies::fracture`), the area off the largest component
//! (m²), the number of other components, and how many of them reach
//! 0.25 m² and 1 m² (areas from the node masses, `m / (ρ h)`). The bond
//! rule is the case's toughness 2.5 J/m² (`--toughness G`) or the cohesive
//! rule (`--cohesive STRENGTH`, Pa, with the same toughness); `--damping B`
//! the dashpot ratio (0.5). Prints a Markdown table
//! (docs/results/2026-12-06-lattice-mesh.md, 2026-12-07 "striker
//! stiffness").
//!
//! `cargo run --release --example lattice_ram_fragments -- --speed 2
//! [--toughness 2.5] [--cohesive 3e5] [--damping 0.5] [--seeds 3] 0.5 0.35 0.25`

use clap::Parser;
use floebench::fracture::chain::{BondRule, ChainOptions};
use floebench::fracture::lattice::percussion::ram;
use floebench::fracture::lattice::{Lattice, LatticeSpec};
use floebench::geometry::Vec2;

/// The command line.
#[derive(Parser)]
struct Args {
    /// The ramming speed, m/s.
    #[arg(long)]
    speed: f64,
    /// The bonds' toughness `G`, J/m².
    #[arg(long, default_value_t = 2.5)]
    toughness: f64,
    /// The cohesive rule's tensile strength, Pa (default: the toughness rule).
    #[arg(long)]
    cohesive: Option<f64>,
    /// The dashpot ratio `β`.
    #[arg(long, default_value_t = 0.5)]
    damping: f64,
    /// Seeds 1..=N.
    #[arg(long, default_value_t = 3)]
    seeds: u64,
    /// The spacings, m.
    #[arg(required = true)]
    spacings: Vec<f64>,
}

fn main() -> Result<(), String> {
    let a = Args::parse();
    if a.speed.is_nan() || a.speed <= 0.0 || a.seeds == 0 {
        return Err("give a positive --speed and at least one seed".into());
    }
    let diamond = [
        Vec2::new(0.0, 5.0),
        Vec2::new(5.0, 0.0),
        Vec2::new(10.0, 5.0),
        Vec2::new(5.0, 10.0),
    ];
    let bond = match a.cohesive {
        Some(strength) => BondRule::Cohesive {
            toughness: a.toughness,
            strength,
        },
        None => BondRule::Toughness(a.toughness),
    };
    let options = ChainOptions {
        bond,
        damping: a.damping,
        ..ChainOptions::default()
    };
    println!("| spacing (m) | broken bonds | fracture energy (J) | area off the largest (m²) | other components | of ≥ 0.25 m² | of ≥ 1 m² | E h ℓ / κ̄ (m) |");
    println!("|---|---|---|---|---|---|---|---|");
    let n = a.seeds as f64;
    for &spacing in &a.spacings {
        let mut sums = [0.0; 7];
        for seed in 1..=a.seeds {
            let spec = LatticeSpec {
                spacing,
                seed,
                ..LatticeSpec::default()
            };
            let lattice = Lattice::build(&diamond, spec)?;
            let total: f64 = lattice.mass.iter().sum::<f64>() / (spec.density * spec.thickness);
            // The corner at (10, 5) into a coast beyond it: the floe moves
            // along +x, the striker pushes along −x.
            let out = ram(
                &lattice,
                Vec2::new(10.0, 5.0),
                Vec2::new(-1.0, 0.0),
                a.speed,
                options,
            )?;
            let mut areas: Vec<f64> = out
                .fragments
                .iter()
                .map(|f| f.mass / (spec.density * spec.thickness))
                .collect();
            areas.sort_by(|x, y| y.total_cmp(x));
            let others = &areas[1.min(areas.len())..];
            let row = [
                out.broken.len() as f64,
                out.energies.fracture,
                total - areas.first().copied().unwrap_or(0.0),
                others.len() as f64,
                others.iter().filter(|&&x| x >= 0.25).count() as f64,
                others.iter().filter(|&&x| x >= 1.0).count() as f64,
                spec.young * spec.thickness * outline_spacing(&lattice) / mean_k(&lattice),
            ];
            sums.iter_mut().zip(row).for_each(|(s, r)| *s += r / n);
        }
        println!(
            "| {spacing} | {:.0} | {:.0} | {:.2} | {:.1} | {:.2} | {:.2} | {:.3} |",
            sums[0], sums[1], sums[2], sums[3], sums[4], sums[5], sums[6]
        );
    }
    Ok(())
}

/// The mean stiffness of the lattice's springs, N/m.
fn mean_k(lattice: &Lattice) -> f64 {
    lattice.springs.iter().map(|s| s.stiffness).sum::<f64>() / lattice.springs.len() as f64
}

/// The mean distance between consecutive outline nodes (the first ones,
/// in order along the outline), m.
fn outline_spacing(lattice: &Lattice) -> f64 {
    let nb = lattice.on_boundary.iter().take_while(|&&b| b).count();
    (0..nb)
        .map(|i| (lattice.nodes[(i + 1) % nb] - lattice.nodes[i]).norm())
        .sum::<f64>()
        / nb as f64
}
