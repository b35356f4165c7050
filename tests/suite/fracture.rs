//! Floes that break (docs/physics.md §9): the split conserves what it must,
//! the stress measure has its closed forms, the `[fracture]` table is
//! validated, `model = "none"` is no fracture, and the energy criterion's
//! critical ramming speed is its closed form.

use crate::common::{case_path, floebench, run, scenario, tempdir};
use floebench::analysis::check::ram_critical_speed_of;
use floebench::formulation::parse_case;
use floebench::fracture::split::{cut, cut_floe, split};
use floebench::fracture::stress::{mean_stress, moment, principal, yield_measure};
use floebench::fracture::Load;
use floebench::geometry::{area_properties, check_convex_ccw, cross, sat_separation, Vec2};
use floebench::model::fracture::FractureSettings;
use floebench::model::{Floe, FloeOrigin};
use floebench::rng::SplitMix64;
use floebench::state::BodyState;
use std::path::Path;

/// A random convex polygon: `n` points on an ellipse at sorted random
/// angles, about `c`.
fn convex(rng: &mut SplitMix64, n: usize, c: Vec2) -> Vec<Vec2> {
    let (a, b) = (rng.range(5.0, 50.0), rng.range(5.0, 50.0));
    let mut angles: Vec<f64> = (0..n)
        .map(|_| rng.range(0.0, std::f64::consts::TAU))
        .collect();
    angles.sort_by(f64::total_cmp);
    angles.dedup_by(|x, y| (*x - *y).abs() < 0.05);
    angles
        .iter()
        .map(|t| c + Vec2::new(a * t.cos(), b * t.sin()))
        .collect()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
}

#[test]
fn a_split_conserves_area_mass_momenta_and_kinetic_energy_and_makes_two_convex_pieces() {
    let mut rng = SplitMix64::new(13);
    let mut tested = 0;
    for _ in 0..400 {
        let n = 3 + (rng.next_u64() % 10) as usize;
        let c = Vec2::new(rng.range(-1e4, 1e4), rng.range(-1e4, 1e4));
        let poly = convex(&mut rng, n, c);
        if poly.len() < 3 || check_convex_ccw(&poly).is_err() {
            continue;
        }
        let thickness = rng.range(0.5, 3.0);
        let floe = Floe::from_world_polygon(
            &poly,
            thickness,
            917.0,
            Vec2::zeros(),
            0.0,
            FloeOrigin::Listed(0),
        );
        let b = BodyState {
            position: floe.position,
            angle: 0.0,
            velocity: Vec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)),
            angular_velocity: rng.range(-0.05, 0.05),
        };
        // A chord through a random interior point in a random direction.
        let w = rng.range(0.05, 0.95);
        let point = floe.position * w + poly[0] * (1.0 - w);
        let t = rng.range(0.0, std::f64::consts::PI);
        let dir = Vec2::new(t.cos(), t.sin());
        let Some(c) = cut_floe(&floe, &b, &point, &dir) else {
            continue;
        };
        let Some(pieces) = split(&floe, &b, &c) else {
            continue;
        };
        tested += 1;
        let (mut area, mut mass, mut p, mut l, mut e) = (0.0, 0.0, Vec2::zeros(), 0.0, 0.0);
        for q in &pieces {
            let shape: Vec<Vec2> = q.floe.shape.iter().map(|v| v + q.state.position).collect();
            check_convex_ccw(&shape).unwrap_or_else(|e| panic!("piece not convex, CCW: {e}"));
            area += q.floe.area;
            mass += q.floe.mass;
            p += q.state.velocity * q.floe.mass;
            let r = q.state.position - b.position;
            l += q.floe.inertia * q.state.angular_velocity
                + q.floe.mass * cross(&r, &q.state.velocity);
            e += q
                .floe
                .kinetic_energy(&q.state.velocity, q.state.angular_velocity);
            assert_eq!(q.floe.parent, Some(floe.id));
            assert_eq!(q.state.angle, 0.0);
        }
        assert!(
            rel(area, floe.area) <= 1e-12,
            "area {area} vs {}",
            floe.area
        );
        assert!(
            rel(mass, floe.mass) <= 1e-12,
            "mass {mass} vs {}",
            floe.mass
        );
        let p0 = b.velocity * floe.mass;
        let pscale = floe.mass * (b.velocity.norm() + b.angular_velocity.abs() * floe.radius);
        assert!((p - p0).norm() <= 1e-12 * pscale, "momentum {p} vs {p0}");
        let l0 = floe.inertia * b.angular_velocity;
        let lscale = pscale * floe.radius;
        assert!(
            (l - l0).abs() <= 1e-12 * lscale,
            "angular momentum {l} vs {l0}"
        );
        let e0 = floe.kinetic_energy(&b.velocity, b.angular_velocity);
        assert!(rel(e, e0) <= 1e-12, "kinetic energy {e} vs {e0}");
        // Non-overlapping: the pieces share the chord and nothing more.
        let world = |q: &floebench::fracture::split::Piece| -> Vec<Vec2> {
            q.floe.shape.iter().map(|v| v + q.state.position).collect()
        };
        let sep = sat_separation(&world(&pieces[0]), &world(&pieces[1]));
        assert!(sep >= -1e-9 * floe.radius, "pieces overlap by {}", -sep);
        assert!(c.length > 0.0 && c.length <= 2.0 * floe.radius * (1.0 + 1e-12));
    }
    assert!(tested >= 200, "only {tested} splits tested");
}

#[test]
fn a_chord_that_misses_or_grazes_the_floe_does_not_cut_it() {
    let square = [
        Vec2::new(0.0, 0.0),
        Vec2::new(10.0, 0.0),
        Vec2::new(10.0, 10.0),
        Vec2::new(0.0, 10.0),
    ];
    let x = Vec2::new(1.0, 0.0);
    assert!(cut(&square, &Vec2::new(0.0, 20.0), &x).is_none(), "misses");
    assert!(
        cut(&square, &Vec2::new(0.0, 10.0), &x).is_none(),
        "along an edge"
    );
    assert!(
        cut(&square, &Vec2::new(0.0, 0.0), &Vec2::new(1.0, -1.0)).is_none(),
        "touches a vertex"
    );
    let c = cut(&square, &Vec2::new(3.0, 3.0), &Vec2::new(1.0, 1.0)).unwrap_or_else(|| panic!());
    assert!(rel(c.length, 200f64.sqrt()) <= 1e-15, "the diagonal");
    assert_eq!(c.left.len(), 3);
    assert_eq!(c.right.len(), 3);
    let a = area_properties(&c.left).area + area_properties(&c.right).area;
    assert!(rel(a, 100.0) <= 1e-15);
}

/// A square of side `a` centred at the origin, thickness `h`.
fn square_loads(a: f64, f: f64, shear: bool) -> Vec<Load> {
    let load = |x: f64, y: f64, px: f64, py: f64| Load {
        floe: 0,
        other: 1,
        point: Vec2::new(x, y),
        impulse: Vec2::new(px, py),
    };
    if shear {
        vec![
            load(a / 2.0, 0.0, 0.0, f),
            load(-a / 2.0, 0.0, 0.0, -f),
            load(0.0, a / 2.0, f, 0.0),
            load(0.0, -a / 2.0, -f, 0.0),
        ]
    } else {
        vec![load(a / 2.0, 0.0, -f, 0.0), load(-a / 2.0, 0.0, f, 0.0)]
    }
}

#[test]
fn equal_and_opposite_impulses_on_opposite_faces_give_the_uniaxial_stress() {
    let (a, h, p, window) = (20.0, 1.5, 3.0e4, 7.0);
    let m = moment(&Vec2::zeros(), square_loads(a, p, false).iter());
    let s = mean_stress(&m, a * a, h, window);
    // The mean force p/window on a face of area a h: σ_xx = −(p/W)/(a h).
    let want = -(p / window) / (a * h);
    assert!(rel(s[0], want) <= 1e-15, "{} vs {want}", s[0]);
    assert_eq!(s[1], 0.0);
    assert_eq!(s[2], 0.0);
    let (s1, s2) = principal(&s);
    assert_eq!(s1, 0.0);
    assert!(rel(s2, want) <= 1e-15);
}

#[test]
fn a_pure_shear_load_gives_the_closed_form_principal_stresses() {
    let (a, h, p, window) = (20.0, 1.5, 3.0e4, 7.0);
    let m = moment(&Vec2::zeros(), square_loads(a, p, true).iter());
    let s = mean_stress(&m, a * a, h, window);
    let tau = (p / window) / (a * h);
    assert!(s[0].abs() <= 1e-15 * tau && s[2].abs() <= 1e-15 * tau);
    assert!(rel(s[1], tau) <= 1e-15);
    let (s1, s2) = principal(&s);
    assert!(rel(s1, tau) <= 1e-15 && rel(s2, -tau) <= 1e-15, "{s1} {s2}");
}

#[test]
fn the_yield_curves_hold_their_defining_points() {
    let mut s = FractureSettings::default();
    // Mohr: no stress is inside; the biaxial vertex is on the curve.
    assert!(yield_measure(&s, &[0.0; 3]) < 1.0);
    let q = s.mohr_q;
    let v = -((1.0 / q + 1.0) * s.mohr_sigma_c / (1.0 / q - q));
    assert!((yield_measure(&s, &[v, 0.0, v]) - 1.0).abs() <= 1e-12);
    assert!(yield_measure(&s, &[1.01 * v, 0.0, 1.01 * v]) > 1.0);
    // Hibler: uniaxial compression fails at 0.4 p (e = 2), p = P* at A = 1.
    s.yield_curve = "hibler".parse().unwrap_or_else(|e: String| panic!("{e}"));
    let p = s.hibler_p_star;
    assert!((yield_measure(&s, &[0.0, 0.0, -0.4 * p]) - 1.0).abs() <= 1e-12);
    assert!(yield_measure(&s, &[0.0, 0.0, -0.39 * p]) < 1.0);
    assert!(yield_measure(&s, &[0.0, 0.0, -0.41 * p]) > 1.0);
}

/// A 10 m square rammed into a coast at `SPEED` (also `cohesive::`).
pub(crate) const RAM: &str = r#"
[case]
version = 1
name = "ram"
duration = 4.0
output_interval = 0.5

[contact]
restitution = 0.5
friction = 0.0

[[floe]]
polygon = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]
thickness = 1.0
velocity = [SPEED, 0.0]

[[obstacle]]
polygon = [[10.02, -50.0], [30.0, -50.0], [30.0, 60.0], [10.02, 60.0]]

[formulation.moreau]
step = 0.5
"#;

#[test]
fn bad_fracture_tables_are_refused_with_file_line_and_key() {
    let base = RAM.replace("SPEED", "0.01");
    for (table, line, key) in [
        ("model = \"chord\"", 2, "model"),
        ("model = \"energy\"\ntoughness = -1.0", 3, "toughness"),
        ("model = \"stress\"\nyield = \"tresca\"", 3, "yield"),
        ("model = \"energy\"\nmin_area = 1e20", 3, "min_area"),
        ("model = \"stress\"\nwindow = 0.0", 3, "window"),
        ("model = \"energy\"\ntoughnes = 2.0", 3, "toughnes"),
        ("model = 3", 2, "model"),
        ("model = \"lattice\"\nrule = \"strain\"", 3, "rule"),
        ("model = \"lattice\"\nrule = \"griffith\"", 3, "rule"),
        ("model = \"lattice\"\ntrigger = \"never\"", 3, "trigger"),
        ("model = \"lattice\"\nyoung = 0.0", 3, "young"),
        ("model = \"lattice\"\ndamping = -0.5", 3, "damping"),
        ("model = \"lattice\"\nspacing = 0.0", 3, "spacing"),
        (
            "model = \"lattice\"\ncritical_strain = 2.0",
            3,
            "critical_strain",
        ),
        ("model = \"lattice\"\nrule = \"cohesive\"", 3, "rule"),
        ("model = \"lattice\"\nstrength = 3e5", 3, "strength"),
        (
            "model = \"lattice\"\nrule = \"cohesive\"\nstrength = 0.0",
            4,
            "strength",
        ),
        (
            "model = \"lattice\"\nrule = \"cohesive\"\nstrength = 3e5\nspacing = 0.8",
            5,
            "spacing",
        ),
        (
            "model = \"lattice\"\nrule = \"cohesive\"\nstrength = 3e5",
            4,
            "strength",
        ),
        ("model = \"lattice\"\nseed = -1", 3, "seed"),
        ("model = \"lattice\"\nseed = 1.5", 3, "seed"),
    ] {
        let text = format!("{base}\n[fracture]\n{table}\n");
        let at = base.lines().count() + 1 + line;
        let err = match parse_case(&text, Path::new("bad.toml")) {
            Ok(_) => panic!("accepted: {table}"),
            Err(e) => e.to_string(),
        };
        assert!(
            err.starts_with(&format!("bad.toml:{at}: [fracture] ")) && err.contains(key),
            "{table}: {err}"
        );
        assert_eq!(err.lines().count(), 1, "{err}");
    }
}

#[test]
fn model_none_gives_the_same_run_as_no_fracture_table() {
    let base = RAM.replace("SPEED", "0.05");
    let none = format!("{base}\n[fracture]\nmodel = \"none\"\ntoughness = 1.0\n");
    for name in ["event-driven", "moreau", "moreau-cone", "rapier"] {
        let a = run(&scenario(&base), name);
        let b = run(&scenario(&none), name);
        assert_eq!(a.trajectory, b.trajectory, "{name}");
        assert_eq!(a.energy, b.energy, "{name}");
        assert!(b.fractures.is_empty() && b.floes.len() == 1, "{name}");
    }
}

fn ram_at(speed: f64) -> floebench::model::Scenario {
    let mut scn = crate::common::load("fracture_ram");
    scn.floes[0].velocity = Vec2::new(speed, 0.0);
    scn
}

#[test]
fn the_energy_criterion_breaks_a_rammed_floe_exactly_above_its_critical_speed() {
    let scn = ram_at(0.02);
    let f = &scn.floes[0];
    let vc = ram_critical_speed_of(
        scn.fracture.toughness,
        f.thickness,
        10.0,
        scn.contact.restitution,
        f.mass,
    );
    assert!(rel(vc, 0.0155673) <= 1e-5, "the case's comment: {vc}");
    // The run's own critical speed: v0 sqrt(threshold / measure).
    let r = run(&scn, "event-driven");
    assert_eq!(r.fractures.len(), 1, "{:?}", r.fractures);
    let fr = &r.fractures[0];
    let measured = 0.02 * (fr.threshold / fr.measure).sqrt();
    assert!(rel(measured, vc) <= 1e-6, "v_c {measured} vs {vc}");
    assert_eq!(fr.parent, 0);
    assert_eq!(fr.children, vec![1, 2]);
    assert_eq!(r.floes.len(), 3);
    assert_eq!(r.floes[0].t_end, Some(fr.t));
    let metric = |name: &str| {
        floebench::analysis::metrics::run_metrics(&r)
            .iter()
            .find(|m| m.metric == name)
            .map(|m| m.value)
    };
    assert_eq!(metric("fractures"), Some(1.0));
    assert_eq!(metric("floes_final"), Some(2.0));
    assert!(metric("floe_area_min_final").is_some_and(|a| rel(a, 50.0) <= 1e-12));
    assert_eq!(r.summary.fracture_model, Some("energy"));
    for piece in &r.floes[1..] {
        assert_eq!(piece.parent, Some(0));
        assert_eq!(piece.t_birth, fr.t);
        assert!(rel(piece.area, 50.0) <= 1e-12, "{}", piece.area);
    }
    // Each piece leaves at e v0; the trajectory lists the pieces from the
    // fracture on, the parent before.
    let last = r
        .trajectory
        .iter()
        .filter(|row| row.t == 60.0)
        .collect::<Vec<_>>();
    assert_eq!(
        last.iter().map(|row| row.floe).collect::<Vec<_>>(),
        vec![1, 2]
    );
    for row in last {
        assert!(rel(row.vx, -0.01) <= 1e-9, "{}", row.vx);
    }
    // Just below and just above v_c, in every formulation that breaks
    // floes; the fixed-step schemes split between steps, at the end of the
    // impact step.
    for name in ["event-driven", "moreau", "moreau-cone"] {
        for (k, breaks) in [(1.0 - 1e-6, false), (1.0 + 1e-6, true)] {
            let r = run(&ram_at(vc * k), name);
            assert_eq!(
                r.fractures.len(),
                usize::from(breaks),
                "{name}: v0 = {k} v_c"
            );
        }
        let r = run(&scn, name);
        let fr = &r.fractures[0];
        let measured = 0.02 * (fr.threshold / fr.measure).sqrt();
        assert!(rel(measured, vc) <= 1e-6, "{name}: v_c {measured} vs {vc}");
        assert!(fr.conservation <= 1e-12, "{name}: {}", fr.conservation);
        let e = r.energy.last().unwrap_or_else(|| panic!());
        assert!(
            e.residual.abs() <= 1e-9 * r.summary.energy.exchanged,
            "{name}: {e:?}"
        );
    }
    // The energy spent on the crack, G h L, comes out of the impact's
    // dissipation ½ M v0² (1 − e²), at most all of it (here less than
    // G h L: the criterion asks for more than the impact loses), and the
    // ledger stays balanced.
    let e = r.energy.last().unwrap_or_else(|| panic!());
    let lost = 0.5 * f.mass * 0.02f64.powi(2) * (1.0 - scn.contact.restitution.powi(2));
    assert!(lost < fr.threshold);
    let l = &e.ledger;
    assert!(rel(l.fracture, fr.threshold.min(lost)) <= 1e-9, "{e:?}");
    assert!(rel(l.dissipated + l.fracture, lost) <= 1e-9, "{e:?}");
    assert!(
        e.residual.abs() <= 1e-9 * r.summary.energy.exchanged,
        "{e:?}"
    );
}

#[test]
fn the_stress_criterion_breaks_a_floe_whose_window_stress_leaves_the_mohr_triangle() {
    // The impact impulse (1 + e) M v0 = 2751 N·s over the 10 s window on a
    // 10 m face, 1 m thick: a uniaxial σ2 = −27.5 Pa, beyond the compressive
    // side σ1 + σ2 = −1.63 Pa of a Mohr triangle scaled down to σ_c = 10 Pa,
    // σ_11 = −1.35 Pa (and inside the default one, σ_c = 250 kPa).
    let base = RAM
        .replace("SPEED", "0.02")
        .replace("duration = 4.0", "duration = 40.0");
    // min_area = 50 m²: the halves may be made, and no cut of a half (into
    // pieces below 50 m²) is.
    let weak = "model = \"stress\"\nmohr_sigma_c = 10.0\nmohr_sigma_11 = -1.35\nmin_area = 50.0";
    for (table, breaks) in [(weak, true), ("model = \"stress\"", false)] {
        let scn = scenario(&format!("{base}\n[fracture]\n{table}\n"));
        let r = run(&scn, "event-driven");
        assert_eq!(r.fractures.len(), usize::from(breaks), "{table}");
        if let Some(f) = r.fractures.first() {
            assert_eq!(f.model, "stress");
            assert!(f.measure > 1.0 && f.threshold == 1.0);
            assert_eq!(f.energy, 0.0, "the stress criterion spends no crack energy");
            for piece in &r.floes[1..] {
                assert!(rel(piece.area, 50.0) <= 1e-12, "the Brazilian halves");
            }
        }
    }
}

/// The ram's 10 m square, 1 m thick, at rest against the coast, pressed by a wind of
/// 10 m/s: the contact carries the air force `F = ρ_a C_a |U|² A` = 22.1 N
/// on the middle of the face, a uniaxial floe-averaged stress
/// `σ_xx = −F (a/2) / (A h)` = −1.105 Pa once the window is full. The Mohr
/// triangle is scaled down so that this is twice the curve's stress.
fn pressed() -> String {
    let ram = RAM
        .replace("SPEED", "0.0")
        .replace("10.02", "10.0")
        .replace("duration = 4.0", "duration = 40.0");
    format!(
        "{ram}
[environment]
air   = {{ density = 1.3,    drag = 1.7e-3, velocity = [10.0, 0.0] }}
water = {{ density = 1024.0, drag = 5.0e-3, velocity = [0.0, 0.0] }}

[fracture]
model = \"stress\"
window = 10.0
mohr_sigma_c = 3.4
mohr_sigma_11 = -0.459
min_area = 50.0
"
    )
}

#[test]
fn a_floe_pressed_on_a_coast_breaks_under_the_stress_criterion_in_every_formulation() {
    // The sustained contact force, not an impact, loads the floe: the
    // window's mean stress grows as F t / W until the window is full, so
    // the floe breaks when it reaches the curve, at t* = W / m (m the
    // measure of the full window's stress), and not before. Each scheme
    // sees it at the end of a step that reaches t* (event-driven: its
    // sustained-contact steps, up to its contact horizon; moreau: h).
    let scn = scenario(&pressed());
    let (a, h) = (10.0, 1.0);
    let force = 1.3 * 1.7e-3 * 10.0f64.powi(2) * a * a;
    let sigma = -force * (a / 2.0) / (a * a * h);
    let full = yield_measure(&scn.fracture, &[sigma, 0.0, 0.0]);
    assert!((1.5..3.0).contains(&full), "the set-up: measure {full}");
    let t_star = scn.fracture.window / full;
    let ed = floebench::formulation::event_driven::EventDrivenSettings::of(&scn)
        .unwrap_or_else(|e| panic!("{e}"));
    let horizon = floebench::formulation::event_driven::contact_horizon(
        &scn,
        ed.penetration_tolerance(&scn),
        floebench::physics::SmoothIntegrator::new(&scn, None).drag_bound(),
    );
    assert!(
        horizon.is_finite(),
        "the event-driven step bound: {horizon} s"
    );
    println!("event-driven contact horizon {horizon} s, t* = {t_star} s");
    for (name, step) in [
        ("event-driven", horizon),
        ("moreau", 0.5),
        ("moreau-cone", 0.5),
        ("rapier", 0.1),
    ] {
        let r = run(&scn, name);
        assert_eq!(r.fractures.len(), 1, "{name}: {:?}", r.fractures);
        let f = &r.fractures[0];
        println!("{name}: broke at {} s, measure {}", f.t, f.measure);
        assert!(
            f.t >= t_star * (1.0 - 1e-9) && f.t <= t_star + step,
            "{name}: broke at {} s, t* = {t_star} s, step {step} s",
            f.t
        );
        assert!(
            f.measure > 1.0 && f.measure <= full * (1.0 + 1e-6),
            "{name}: {f:?}"
        );
        assert!(f.conservation <= 1e-12, "{name}: {}", f.conservation);
        // The Brazilian cut through the middle of the loaded face, along
        // the load: two halves.
        for piece in &r.floes[1..] {
            assert!(rel(piece.area, 50.0) <= 1e-9, "{name}: {}", piece.area);
        }
    }
}

#[test]
fn runs_that_break_differently_are_compared_by_each_initial_floes_material() {
    // The same ram, broken and whole: the two halves leave together at
    // e v0, so the material of floe 0 follows the whole floe's path.
    let broken = crate::common::load("fracture_ram");
    let mut whole = broken.clone();
    whole.fracture.model = floebench::model::fracture::FractureModel::None;
    for name in ["event-driven", "moreau"] {
        let a = run(&broken, name);
        let b = run(&whole, name);
        assert_eq!((a.fractures.len(), b.fractures.len()), (1, 0), "{name}");
        let d = floebench::analysis::divergence::divergence(&broken, &a, &b, 0.1)
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(
            d.samples.len(),
            b.energy.len(),
            "{name}: every output compared"
        );
        assert!(
            d.max_rms_position_rel <= 1e-12,
            "{name}: {}",
            d.max_rms_position_rel
        );
        assert!(d.max_angle_rad <= 1e-12, "{name}: {}", d.max_angle_rad);
        // The material rows of a run that did not break are its rows.
        assert_eq!(
            floebench::analysis::divergence::material_rows(&b),
            b.trajectory
        );
    }
}

#[test]
fn compare_writes_the_floe_size_distribution_of_a_fracture_case_and_none_elsewhere() {
    let dir = tempdir();
    let out = dir.path().join("reports");
    let o = floebench()
        .arg("compare")
        .arg(case_path("fracture_ram"))
        .arg(case_path("head_on"))
        .args(["--formulations", "event-driven,moreau", "--quiet", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(out.join("fracture_ram/floe_sizes.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("formulation,when,area_m2,count_at_least")
    );
    let rows: Vec<(String, String, f64, usize)> = lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f.len(), 4, "{l}");
            (
                f[0].to_string(),
                f[1].to_string(),
                f[2].parse().unwrap(),
                f[3].parse().unwrap(),
            )
        })
        .collect();
    // The start: the one initial floe of 100 m².
    let start: Vec<_> = rows.iter().filter(|r| r.1 == "start").collect();
    assert_eq!(start.len(), 1, "{rows:?}");
    assert!(start[0].0.is_empty() && rel(start[0].2, 100.0) < 1e-12 && start[0].3 == 1);
    // The end of each run: two pieces of 50 m² (one size), the count at
    // the smallest area the number of floes alive.
    for f in ["event-driven", "moreau"] {
        let end: Vec<_> = rows.iter().filter(|r| r.0 == f && r.1 == "end").collect();
        assert_eq!(end.len(), 1, "{f}: {rows:?}");
        assert!(rel(end[0].2, 50.0) < 1e-9 && end[0].3 == 2, "{f}: {end:?}");
    }
    for ext in ["png", "svg"] {
        let p = out.join(format!("fracture_ram/floe_sizes.{ext}"));
        assert!(
            std::fs::metadata(&p).is_ok_and(|m| m.len() > 1000),
            "{}",
            p.display()
        );
    }
    let md = std::fs::read_to_string(out.join("index.md")).unwrap();
    assert!(md.contains("fracture_ram/floe_sizes.png") && md.contains("**floe_sizes**"));
    // A case without a [fracture] table has none of it.
    for file in ["floe_sizes.csv", "floe_sizes.png", "floe_sizes.svg"] {
        assert!(!out.join("head_on").join(file).exists(), "head_on/{file}");
    }
    assert!(!md.contains("head_on/floe_sizes"));
}

#[test]
fn run_writes_the_floes_and_fractures_of_a_broken_run() {
    // `floebench run fracture_ram`: floes.json lists the parent (ended at
    // the fracture) and its two pieces (born then, parent 0), each outline
    // about its own centre of mass with the recorded area and mass; one row
    // of fractures.csv names them.
    let dir = tempdir();
    let out = dir.path().join("out");
    let o = floebench()
        .arg("run")
        .arg(case_path("fracture_ram"))
        .args(["--quiet", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(out.join("fractures.csv")).unwrap();
    let rows: Vec<&str> = text.lines().collect();
    assert_eq!(rows.len(), 2, "{text}");
    let f: Vec<&str> = rows[1].split(',').collect();
    assert_eq!((f[1], f[2], f[3]), ("0", "1;2", "energy"), "{text}");
    let t: f64 = f[0].parse().unwrap();
    let floes: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("floes.json")).unwrap()).unwrap();
    let floes = floes.as_array().unwrap();
    assert_eq!(floes.len(), 3);
    assert!(floes[0]["parent"].is_null() && floes[0]["t_end"].as_f64() == Some(t));
    for (id, g) in floes.iter().enumerate() {
        assert_eq!(g["id"], id);
        let poly: Vec<Vec2> = g["polygon"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| Vec2::new(p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
            .collect();
        let props = area_properties(&poly);
        let area = g["area"].as_f64().unwrap();
        assert!(
            rel(props.area, area) <= 1e-12,
            "{id}: {} vs {area}",
            props.area
        );
        assert!(
            props.centroid.norm() <= 1e-12 * area.sqrt(),
            "{id}: {:?}",
            props.centroid
        );
        let mass = g["mass"].as_f64().unwrap();
        let h = g["thickness"].as_f64().unwrap();
        assert!(rel(mass, 917.0 * h * area) <= 1e-12, "{id}: {mass}");
        if id > 0 {
            assert_eq!(g["parent"], 0);
            assert_eq!(g["t_birth"].as_f64(), Some(t));
            assert!(g["t_end"].is_null());
            assert!(rel(area, 50.0) <= 1e-12, "{id}: {area}");
        }
    }
}
