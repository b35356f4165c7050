//! The crush stage (docs/physics.md §10): the cut of a reported pair's
//! overlap, the crushed ice to ridges or to the coast, and what it
//! conserves. The stage is driven directly (no formulation): a scenario
//! from a small case, floes placed overlapping in a `System`, then the
//! stage's `crushed` and `apply`.

use crate::common::{load, scenario};
use floebench::formulation::{
    build, Context, FixedTopology, FormulationOptions, Interrupt, Topology,
};
use floebench::fracture::crush::overlap::Overlap;
use floebench::fracture::crush::{CrushStage, DEPTH_TOLERANCE};
use floebench::fracture::topology::RunTopology;
use floebench::geometry::{cross, is_strictly_convex, Vec2};
use floebench::model::Scenario;
use floebench::record::{Counters, StageClock};
use floebench::run::{RunOptions, Runner, TrajectoryRow};
use floebench::state::System;

/// A case of `floes` (TOML `[[floe]]` tables) and `obstacles`, with
/// crushing when `crushing`.
fn case(floes: &str, obstacles: &str, crushing: bool) -> Scenario {
    let law = if crushing {
        "crushing = { strength = 1.0e6 }"
    } else {
        ""
    };
    scenario(&format!(
        r#"
[case]
version = 1
name = "crush_stage"
description = "floes placed overlapping by the test"
duration = 1.0
output_interval = 1.0

[contact]
restitution = 0.0
friction = 0.0
{law}

{floes}
{obstacles}
"#
    ))
}

/// A 10 m square (corners at 0 and 10) of thickness `h` and density `rho`.
fn square(x0: f64, h: f64, rho: f64) -> String {
    format!(
        "[[floe]]\npolygon = [[{x0}, 0.0], [{}, 0.0], [{}, 10.0], [{x0}, 10.0]]\nthickness = {h}\ndensity = {rho}\n",
        x0 + 10.0,
        x0 + 10.0
    )
}

/// A diamond (a square turned by 45°) of half-diagonal 5 m about the origin.
const DIAMOND: &str =
    "[[floe]]\npolygon = [[5.0, 0.0], [0.0, 5.0], [-5.0, 0.0], [0.0, -5.0]]\nthickness = 1.0\n";
/// A straight coast whose face is the line x = 10.
const COAST: &str =
    "[[obstacle]]\npolygon = [[10.0, -50.0], [30.0, -50.0], [30.0, 50.0], [10.0, 50.0]]\n";

/// Mass, linear momentum and angular momentum about the origin of the
/// floes of `sys`, and the sum of the absolute values of the angular
/// momentum's terms (its scale).
fn totals(scn: &Scenario, sys: &System) -> (f64, Vec2, f64, f64) {
    let (mut m, mut p, mut l, mut scale) = (0.0, Vec2::zeros(), 0.0, 0.0);
    for (f, b) in scn.floes.iter().zip(&sys.bodies) {
        m += f.mass;
        p += b.velocity * f.mass;
        let terms = [
            f.inertia * b.angular_velocity,
            f.mass * cross(&b.position, &b.velocity),
        ];
        l += terms[0] + terms[1];
        scale += terms[0].abs() + terms[1].abs();
    }
    (m, p, l, scale)
}

fn counter(c: &Counters, name: &str) -> f64 {
    c.by_name(name).unwrap().unwrap()
}

fn world(scn: &Scenario, sys: &System, k: usize) -> Vec<Vec2> {
    let mut out = Vec::new();
    scn.floes[k].world_polygon(&sys.bodies[k].position, sys.bodies[k].angle, &mut out);
    out
}

/// Reports `pairs` to `stage` and applies it at once.
fn crush(
    stage: &mut dyn Topology,
    scn: &mut Scenario,
    sys: &mut System,
    pairs: &[(usize, usize)],
) -> Option<Vec<usize>> {
    stage.crushed(scn, sys, pairs);
    assert!(stage.pending(), "a reported pair waits for the safe point");
    let changed = stage.apply(scn, sys, &mut StageClock::new());
    assert!(!stage.pending());
    changed
}

/// A square's corner pushed 0.1 m into a straight coast loses exactly the
/// overlap triangle (0.01 m²), stays convex with its face on the coast,
/// keeps its rigid velocity field, and the coast's deposit books the
/// mass, the momentum and the kinetic energy the floe lost.
#[test]
fn a_corner_in_a_coast_loses_exactly_the_triangle() {
    let mut scn = case(DIAMOND, COAST, true);
    let mut sys = System::initial(&scn);
    let b0 = floebench::state::BodyState {
        position: Vec2::new(5.1, 0.0),
        angle: 0.0,
        velocity: Vec2::new(1.0, 0.5),
        angular_velocity: 0.01,
    };
    sys.bodies[0] = b0;
    let (a0, m0) = (scn.floes[0].area, scn.floes[0].mass);
    let (_, p0, l0, lscale) = totals(&scn, &sys);
    let k0 = sys.kinetic_energy(&scn);
    let mut stage = CrushStage::new(&scn);
    let old = crush(&mut stage, &mut scn, &mut sys, &[(0, 1)]);
    assert_eq!(old, Some(vec![0]));

    let f = &scn.floes[0];
    assert!(
        ((a0 - f.area) - 0.01).abs() <= 1e-12,
        "area lost {}",
        a0 - f.area
    );
    assert!(
        f.is_convex() && is_strictly_convex(&f.shape),
        "{:?}",
        f.shape
    );
    let poly = world(&scn, &sys, 0);
    let max_x = poly.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max);
    assert!(
        (max_x - 10.0).abs() <= 1e-12,
        "the face is the coast's: {max_x}"
    );
    assert_eq!(sys.bodies[0].angle, b0.angle, "the floe keeps its angle");
    // The rigid velocity field at the new centre of mass.
    let r = sys.bodies[0].position - b0.position;
    let rigid = b0.velocity + Vec2::new(-r.y, r.x) * b0.angular_velocity;
    assert!(
        (sys.bodies[0].velocity - rigid).norm() <= 1e-15,
        "{:?}",
        sys.bodies[0].velocity
    );
    assert_eq!(sys.bodies[0].angular_velocity, b0.angular_velocity);

    let d = stage.deposits()[0];
    let crushed_mass = 917.0 * 1.0 * 0.01;
    assert!(
        (d.mass_kg - crushed_mass).abs() <= 1e-12 * m0,
        "{}",
        d.mass_kg
    );
    assert!(((f.mass + d.mass_kg) - m0).abs() <= 1e-12 * m0, "mass");
    let (_, p1, l1, _) = totals(&scn, &sys);
    let pd = Vec2::new(d.momentum[0], d.momentum[1]);
    assert!(
        (p1 + pd - p0).norm() <= 1e-12 * p0.norm(),
        "momentum {:?}",
        p1 + pd - p0
    );
    assert!(
        (l1 + d.angular_momentum - l0).abs() <= 1e-12 * lscale,
        "angular momentum"
    );
    let k1 = sys.kinetic_energy(&scn);
    assert!(
        (sys.ledger.crushing - (k0 - k1)).abs() <= 1e-12 * k0,
        "ledger"
    );
    assert!(
        (d.kinetic_energy_j - (k0 - k1)).abs() <= 1e-12 * k0,
        "deposit's energy"
    );
    let c = stage.counters();
    assert_eq!(counter(&c, "crush_cuts"), 1.0);
    assert!((counter(&c, "crushed_volume_m3") - 0.01).abs() <= 1e-12);
    assert!((counter(&c, "deposited_volume_m3") - 0.01).abs() <= 1e-12);
    assert_eq!(counter(&c, "ridged_volume_m3"), 0.0);
    assert_eq!(stage.take_reshaped(), vec![0]);
}

/// Two squares overlapping on a 0.1 m strip: each loses half of it and
/// gets the other's half as thickness; mass, linear and angular momentum
/// are conserved to 1e-12, the ledger's `crushing` is the kinetic energy
/// lost, and no overlap is left.
#[test]
fn two_floes_on_a_strip_each_lose_half() {
    let floes = format!("{}{}", square(0.0, 1.0, 917.0), square(12.0, 1.0, 917.0));
    let mut scn = case(&floes, "", true);
    let mut sys = System::initial(&scn);
    sys.bodies[0].velocity = Vec2::new(1.0, 0.2);
    sys.bodies[0].angular_velocity = 0.03;
    sys.bodies[1].position = Vec2::new(14.9, 5.0);
    sys.bodies[1].velocity = Vec2::new(-0.5, 0.1);
    sys.bodies[1].angular_velocity = -0.02;
    let (m0, p0, l0, lscale) = totals(&scn, &sys);
    let k0 = sys.kinetic_energy(&scn);
    // Through the run's composite stage, reported as (b, a): the same pair.
    let mut stage = RunTopology::new(&scn);
    assert!(crush(&mut stage, &mut scn, &mut sys, &[(1, 0), (0, 1)]).is_some());

    for f in &scn.floes {
        assert!((f.area - 99.5).abs() <= 1e-12, "area {}", f.area);
        assert!(
            (f.thickness - 100.0 / 99.5).abs() <= 1e-12,
            "thickness {}",
            f.thickness
        );
    }
    let (m1, p1, l1, _) = totals(&scn, &sys);
    assert!((m1 - m0).abs() <= 1e-12 * m0, "mass {m1} against {m0}");
    assert!(
        (p1 - p0).norm() <= 1e-12 * p0.norm(),
        "momentum {:?}",
        p1 - p0
    );
    assert!(
        (l1 - l0).abs() <= 1e-12 * lscale,
        "angular momentum {} against {}",
        l1,
        l0
    );
    let k1 = sys.kinetic_energy(&scn);
    assert!(k1 < k0, "the merge of the ice is inelastic");
    assert!((sys.ledger.crushing - (k0 - k1)).abs() <= 1e-12 * k0);
    let residual = sys.ledger.residual(k1, k0);
    assert!(
        residual.abs() <= 1e-12 * k0,
        "the balance closes: {residual}"
    );
    let (a, b) = (world(&scn, &sys, 0), world(&scn, &sys, 1));
    let part = vec![vec![0, 1, 2, 3]];
    let left = Overlap::of(&a, &part, &b, &part).map_or(0.0, |o| o.area());
    assert!(left <= 1e-12, "overlap left {left}");
    let c = stage.counters();
    assert_eq!(counter(&c, "crush_cuts"), 2.0);
    assert!((counter(&c, "crushed_volume_m3") - 1.0).abs() <= 1e-12);
    assert!((counter(&c, "ridged_volume_m3") - 1.0).abs() <= 1e-12);
}

/// Floes of different densities: the ice crushed from one goes to the
/// other as the thickness of the receiver's density, `Δh = m / (ρ A)`, so
/// the mass is exact.
#[test]
fn ice_joins_a_floe_of_another_density_by_mass() {
    let floes = format!("{}{}", square(0.0, 1.0, 917.0), square(12.0, 2.0, 850.0));
    let mut scn = case(&floes, "", true);
    let mut sys = System::initial(&scn);
    sys.bodies[1].position = Vec2::new(14.9, 5.0);
    sys.bodies[0].velocity = Vec2::new(0.3, 0.0);
    let (m0, p0, ..) = totals(&scn, &sys);
    let mut stage = CrushStage::new(&scn);
    crush(&mut stage, &mut scn, &mut sys, &[(0, 1)]);
    // Each loses 0.5 m² at its own thickness and density.
    let (from_a, from_b) = (917.0 * 1.0 * 0.5, 850.0 * 2.0 * 0.5);
    let ha = 1.0 + from_b / (917.0 * 99.5);
    let hb = 2.0 + from_a / (850.0 * 99.5);
    assert!(
        (scn.floes[0].thickness - ha).abs() <= 1e-12 * ha,
        "{}",
        scn.floes[0].thickness
    );
    assert!(
        (scn.floes[1].thickness - hb).abs() <= 1e-12 * hb,
        "{}",
        scn.floes[1].thickness
    );
    let (m1, p1, ..) = totals(&scn, &sys);
    assert!((m1 - m0).abs() <= 1e-12 * m0, "mass {m1} against {m0}");
    assert!((p1 - p0).norm() <= 1e-12 * p0.norm());
    // The volumes: crushed at the cut floes' thickness, ridged at the
    // receivers' density.
    let c = stage.counters();
    assert!((counter(&c, "crushed_volume_m3") - 1.5).abs() <= 1e-12);
    let ridged = from_a / 850.0 + from_b / 917.0;
    assert!((counter(&c, "ridged_volume_m3") - ridged).abs() <= 1e-12);
}

/// An overlap thinner than the depth tolerance is not cut: nothing
/// changes, and it is counted.
#[test]
fn an_overlap_below_the_tolerance_is_not_cut() {
    let floes = format!("{}{}", square(0.0, 1.0, 917.0), square(12.0, 1.0, 917.0));
    let mut scn = case(&floes, "", true);
    let mut sys = System::initial(&scn);
    let depth = 0.5 * DEPTH_TOLERANCE * scn.floes[0].radius;
    sys.bodies[1].position = Vec2::new(15.0 - depth, 5.0);
    let (before, state) = (scn.floes.clone(), sys.clone());
    let mut stage = CrushStage::new(&scn);
    assert_eq!(crush(&mut stage, &mut scn, &mut sys, &[(0, 1)]), None);
    assert_eq!(sys, state);
    assert_eq!(scn.floes[0].shape, before[0].shape);
    assert_eq!(scn.floes[1].thickness, before[1].thickness);
    let c = stage.counters();
    assert_eq!(counter(&c, "crush_cuts"), 0.0);
    assert_eq!(counter(&c, "crush_pairs_below_tolerance"), 1.0);
}

/// A cut that would leave less than the smallest area, and a floe of
/// several convex parts, are refused and counted; the floe is kept whole.
#[test]
fn cuts_too_deep_or_of_non_convex_floes_are_refused() {
    let mut scn = case(DIAMOND, COAST, true);
    let mut sys = System::initial(&scn);
    sys.bodies[0].position = Vec2::new(14.5, 0.0);
    let shape = scn.floes[0].shape.clone();
    let mut stage = CrushStage::new(&scn);
    assert_eq!(crush(&mut stage, &mut scn, &mut sys, &[(0, 1)]), None);
    assert_eq!(scn.floes[0].shape, shape);
    assert_eq!(counter(&stage.counters(), "crush_cuts_refused"), 1.0);

    let l_floe = "[[floe]]\npolygon = [[0.0, 0.0], [10.0, 0.0], [10.0, 4.0], [4.0, 4.0], [4.0, 10.0], [0.0, 10.0]]\nthickness = 1.0\n";
    let mut scn = case(l_floe, COAST, true);
    let mut sys = System::initial(&scn);
    sys.bodies[0].position.x += 0.5;
    let mut stage = CrushStage::new(&scn);
    assert_eq!(crush(&mut stage, &mut scn, &mut sys, &[(0, 1)]), None);
    assert_eq!(counter(&stage.counters(), "crush_cuts_refused"), 1.0);
}

/// Without `[contact] crushing` the stage ignores reports, keeps no
/// counters and writes no deposit.
#[test]
fn without_crushing_the_stage_does_nothing() {
    let mut scn = case(DIAMOND, COAST, false);
    let mut sys = System::initial(&scn);
    sys.bodies[0].position = Vec2::new(5.1, 0.0);
    let mut stage = RunTopology::new(&scn);
    stage.crushed(&scn, &sys, &[(0, 1)]);
    assert!(!stage.pending());
    assert_eq!(
        stage.apply(&mut scn, &mut sys, &mut StageClock::new()),
        None
    );
    assert!(stage.crush.deposits().is_empty());
    assert_eq!(stage.counters(), Counters::default());
}

/// A formulation reports through its context (`Context::crushed`), and
/// the safe point's `change_floes` cuts, its time charged to the clock's
/// crushing stage.
#[test]
fn the_context_passes_the_report_on_and_charges_the_cut() {
    let mut scn = case(DIAMOND, COAST, true);
    let mut sys = System::initial(&scn);
    sys.bodies[0].position = Vec2::new(5.1, 0.0);
    let mut stage = RunTopology::new(&scn);
    let mut clock = StageClock::new();
    let interrupt = Interrupt::default();
    let mut cx = Context::new(&mut clock, &mut stage, &interrupt);
    cx.crushed(&scn, &sys, &[(0, 1)]);
    assert_eq!(cx.change_floes(&mut scn, &mut sys), Some(vec![0]));
    assert_eq!(cx.change_floes(&mut scn, &mut sys), None);
    assert!(clock.monotonic_times().crushing > 0.0);
    assert!(clock.monotonic_times().solve == 0.0);
}

/// Without crushing the runner's composite topology changes nothing: a
/// bundled case run by the runner has the trajectory of the same
/// formulation driven with the fixed topology, bit for bit.
#[test]
fn a_case_without_crushing_runs_as_with_the_fixed_topology() {
    for (name, form) in [("head_on", "moreau"), ("l_shaped_corner", "event-driven")] {
        let scn = load(name);
        let opts = FormulationOptions::default();
        let mut f = build(form, &scn, &opts).unwrap();
        let run = Runner::new(RunOptions::default()).run(&scn, f.name(), f.formulation.as_mut());

        let mut g = build(form, &scn, &opts).unwrap();
        let mut own = scn.clone();
        let mut sys = System::initial(&own);
        let (mut clock, mut fixed, interrupt) =
            (StageClock::new(), FixedTopology, Interrupt::default());
        let mut rows: Vec<TrajectoryRow> = Vec::new();
        let keep = |sys: &System, scn: &Scenario, rows: &mut Vec<TrajectoryRow>| {
            for (b, fl) in sys.bodies.iter().zip(&scn.floes) {
                rows.push(TrajectoryRow::of(sys.t, fl.id, b));
            }
        };
        keep(&sys, &own, &mut rows);
        for t in floebench::run::output_times(own.duration, own.output_interval) {
            let mut cx = Context::new(&mut clock, &mut fixed, &interrupt);
            g.formulation
                .advance(&mut own, &mut sys, t, &mut cx)
                .unwrap();
            sys.t = t;
            keep(&sys, &own, &mut rows);
        }
        assert_eq!(run.trajectory, rows, "{name} by {form}");
    }
}

/// A run with crushing reports the crush stage: its counters (zeros when
/// nothing was reported), one deposit per obstacle, the floes' world
/// outlines at the end in `floes.json`, and the `crushing_energy` metric;
/// a run without it has none of them.
#[test]
fn a_run_with_crushing_reports_the_stage() {
    let text = |crushing: bool| case(DIAMOND, COAST, crushing);
    let run = crate::common::run(&text(true), "moreau");
    let s = &run.summary;
    let deposits = &s.crushing.as_ref().expect("crushing summary").deposits;
    assert_eq!(deposits.len(), 1);
    assert_eq!(deposits[0].mass_kg, 0.0);
    for name in [
        "crushed_volume_m3",
        "ridged_volume_m3",
        "deposited_volume_m3",
        "crush_cuts",
        "crush_cuts_refused",
    ] {
        assert_eq!(s.counters.by_name(name).unwrap(), Some(0.0), "{name}");
    }
    let world = run.floes[0].world_polygon.as_ref().expect("world outline");
    let last = run.trajectory.last().unwrap();
    let expected = {
        let mut out = Vec::new();
        run.floes[0].world_polygon(&Vec2::new(last.x, last.y), last.theta, &mut out);
        out
    };
    for (w, e) in world.iter().zip(&expected) {
        assert_eq!([e.x, e.y], *w);
    }
    let metrics = floebench::analysis::metrics::run_metrics(&run);
    assert!(metrics.iter().any(|m| m.metric == "crushing_energy"));

    let plain = crate::common::run(&text(false), "moreau");
    assert!(plain.summary.crushing.is_none() && plain.floes[0].world_polygon.is_none());
    assert!(plain.summary.counters.by_name("crush_cuts").is_err());
    let metrics = floebench::analysis::metrics::run_metrics(&plain);
    assert!(!metrics.iter().any(|m| m.metric.contains("crush")));
}
