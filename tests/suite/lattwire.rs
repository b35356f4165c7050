//! The lattice model in the formulations (docs/physics.md §9.8): its
//! `[fracture]` keys are read, the trigger bound never skips an impact
//! that could break a bond, a k-piece split conserves mass and momenta, and
//! a fast ram breaks where a slow one does not, in every formulation.

use crate::common::{case_path, run, scenario};
use floebench::formulation::parse_case;
use floebench::fracture::lattice::percussion::Impact;
use floebench::fracture::lattice::Lattice;
use floebench::fracture::split::conservation_error;
use floebench::fracture::strike::{chain_options, lattice_spec, pieces, strike};
use floebench::geometry::{area_properties, check_convex_ccw, cross, sat_separation, Vec2};
use floebench::model::fracture::{FractureModel, FractureSettings};
use floebench::model::{Floe, FloeOrigin};
use floebench::state::BodyState;
use std::path::Path;

/// A 50 m² diamond (a 7.07 m square turned by 45°), h = 1 m.
fn diamond() -> Floe {
    let poly = [
        Vec2::new(0.0, 5.0),
        Vec2::new(5.0, 0.0),
        Vec2::new(10.0, 5.0),
        Vec2::new(5.0, 10.0),
    ];
    Floe::from_world_polygon(&poly, 1.0, 917.0, Vec2::zeros(), 0.0, FloeOrigin::Listed(0))
}

fn settings(spacing: f64) -> FractureSettings {
    FractureSettings {
        model: FractureModel::Lattice,
        min_area: 1.0,
        spacing: Some(spacing),
        ..FractureSettings::default()
    }
}

#[test]
fn lattice_keys_are_read() {
    // The refusals are in `fracture::bad_fracture_tables_are_refused_with_file_line_and_key`.
    let base = std::fs::read_to_string(case_path("fracture_ram")).unwrap();
    let base = &base[..base.find("[fracture]").unwrap()];
    let ok = format!(
        "{base}[fracture]\nmodel = \"lattice\"\nrule = \"strain\"\ncritical_strain = 1e-4\ntrigger = \"always\"\nseed = 7\nspacing = 2.0\nyoung = 1e9\ndamping = 0.3\npoisson = 0.3\n"
    );
    let s = parse_case(&ok, Path::new("ok.toml")).unwrap().fracture;
    assert_eq!(
        (s.critical_strain, s.seed, s.spacing, s.young, s.damping),
        (1e-4, 7, Some(2.0), 1e9, 0.3)
    );
    assert_eq!(s.poisson, 0.3);
    assert_eq!(lattice_spec(&s, &diamond()).poisson, 0.3);
    // A Poisson ratio past the reach of central and torsion springs is refused by key.
    let bad = ok.replace("poisson = 0.3", "poisson = 0.4");
    let err = parse_case(&bad, Path::new("bad.toml"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("poisson"), "{err}");
}

#[test]
fn the_trigger_bound_skips_only_impacts_that_break_no_bond() {
    // A sweep of impacts run whatever the bound (`trigger = "always"`): on
    // the corner, on a face, off-centre, by a coast and by floes of several
    // masses, from far below the weakest bond's energy to far above. An
    // impact whose bound is below the weakest bond must break none.
    let f = diamond();
    let s = settings(1.0);
    let l = Lattice::build(&f.shape, lattice_spec(&s, &f)).unwrap();
    let (mut below, mut broke_above) = (0, 0);
    let strikes = [
        (Vec2::new(5.0, 0.0), Vec2::new(-1.0, 0.0)),
        (Vec2::new(2.5, 2.5), Vec2::new(-1.0, -1.0).normalize()),
        (Vec2::new(3.5, 1.5), Vec2::new(-1.0, -1.0).normalize()),
        (Vec2::new(-1.0, -4.0), Vec2::new(0.0, 1.0)),
    ];
    for (point, normal) in strikes {
        for mass in [f64::INFINITY, 4.0 * f.mass, 0.2 * f.mass] {
            for k in 0..12 {
                let speed = 1e-3 * 2f64.powi(k) * 0.5;
                let impact = Impact {
                    point,
                    normal,
                    mass,
                    speed,
                };
                let o = strike(&l, impact, chain_options(&s), true, s.min_area, 917.0).unwrap();
                if o.bound < o.weakest {
                    below += 1;
                    assert_eq!(
                        o.broken, 0,
                        "{point:?} {mass} {speed}: bound {} weakest {}",
                        o.bound, o.weakest
                    );
                } else if o.broken > 0 {
                    broke_above += 1;
                }
            }
        }
    }
    assert!(
        below >= 12 && broke_above >= 12,
        "{below} below, {broke_above} broke above"
    );
}

#[test]
fn the_pieces_of_a_percussion_conserve_mass_and_momenta_and_partition_the_floe() {
    let f = diamond();
    let s = settings(0.5);
    let l = Lattice::build(&f.shape, lattice_spec(&s, &f)).unwrap();
    let impact = Impact {
        point: Vec2::new(5.0, 0.0),
        normal: Vec2::new(-1.0, 0.0),
        mass: f64::INFINITY,
        speed: 2.0,
    };
    let o = strike(&l, impact, chain_options(&s), false, s.min_area, 917.0).unwrap();
    let split = o.split.expect("a 2 m/s ram breaks the floe");
    assert!(split.pieces.len() >= 3, "{} pieces", split.pieces.len());
    // A parent moving, spinning and turned, far from the origin.
    let b = BodyState {
        position: Vec2::new(1.0e5, -2.0e4),
        angle: 0.7,
        velocity: Vec2::new(-0.3, 0.8),
        angular_velocity: 0.05,
    };
    let ps = pieces(&f, &b, &split).unwrap();
    assert_eq!(ps.len(), split.pieces.len());
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    let area: f64 = ps.iter().map(|p| p.floe.area).sum();
    let mass: f64 = ps.iter().map(|p| p.floe.mass).sum();
    let p: Vec2 = ps.iter().map(|p| p.state.velocity * p.floe.mass).sum();
    let lz: f64 = ps
        .iter()
        .map(|p| {
            p.floe.inertia * p.state.angular_velocity
                + p.floe.mass * cross(&(p.state.position - b.position), &p.state.velocity)
        })
        .sum();
    let scale = f.mass * (b.velocity.norm() + b.angular_velocity.abs() * f.radius);
    assert!(rel(area, f.area) < 1e-12, "area {area} {}", f.area);
    assert!(rel(mass, f.mass) < 1e-12, "mass {mass} {}", f.mass);
    assert!(
        (p - b.velocity * f.mass).norm() / scale < 1e-12,
        "momentum {p:?}"
    );
    assert!(
        (lz - f.inertia * b.angular_velocity).abs() / (scale * f.radius) < 1e-12,
        "angular momentum {lz} {}",
        f.inertia * b.angular_velocity
    );
    assert!(conservation_error(&f, &b, &ps, false) < 1e-12);
    // Convex, counter-clockwise, not overlapping; the pieces fly apart.
    let mut world = Vec::new();
    for q in &ps {
        let mut w = Vec::new();
        q.floe.world_polygon(&q.state.position, 0.0, &mut w);
        check_convex_ccw(&w).unwrap();
        assert!(area_properties(&w).area > 0.0);
        world.push(w);
    }
    for i in 0..world.len() {
        for j in i + 1..world.len() {
            let sep = sat_separation(&world[i], &world[j]);
            assert!(
                sep > -1e-9 * f.radius,
                "pieces {i} and {j} overlap by {sep}"
            );
        }
    }
    let k: f64 = ps
        .iter()
        .map(|q| {
            q.floe
                .kinetic_energy(&q.state.velocity, q.state.angular_velocity)
        })
        .sum();
    assert!(k > f.kinetic_energy(&b.velocity, b.angular_velocity));
}

#[test]
fn a_fast_ram_breaks_a_floe_and_a_slow_one_does_not_in_every_formulation() {
    let case = std::fs::read_to_string(case_path("lattice_ram")).unwrap();
    let scn = scenario(&case);
    for name in ["event-driven", "moreau", "moreau-cone", "rapier"] {
        let r = run(&scn, name);
        let broken: Vec<usize> = r.fractures.iter().map(|f| f.parent).collect();
        // Floes 0 and 1 (0.3 and 0.6 m/s) stay whole; 2 and 3 (1 and 2 m/s) break.
        assert!(
            !broken.contains(&0) && !broken.contains(&1),
            "{name}: {broken:?}"
        );
        assert!(
            broken.contains(&2) && broken.contains(&3),
            "{name}: {broken:?}"
        );
        for fr in &r.fractures {
            assert!(
                fr.children.len() >= 2 && fr.conservation < 1e-12,
                "{name}: {fr:?}"
            );
            assert!(fr.measure >= fr.threshold, "{name}: {fr:?}");
        }
    }
}

#[test]
fn a_lattice_run_records_the_crack_of_its_largest_percussion_and_the_report_draws_it() {
    use floebench::fracture::crack;
    use floebench::run::output::{write_run, PERCUSSION_FILE};
    let case = std::fs::read_to_string(case_path("lattice_ram")).unwrap();
    let scn = scenario(&case);
    let r = run(&scn, "event-driven");
    let rec = r.percussion.as_ref().expect("lattice_ram breaks floes");
    // It is one of the run's fractures: same instant, parent, pieces and booked energy.
    let row = r
        .fractures
        .iter()
        .find(|f| f.t == rec.t && f.parent == rec.floe)
        .unwrap_or_else(|| panic!("no fracture of floe {} at {} s", rec.floe, rec.t));
    assert_eq!(row.children, rec.children);
    assert_eq!(
        (row.energy, row.measure, row.threshold),
        (rec.energy, rec.bound, rec.weakest)
    );
    // Its crack is that percussion's: the same impact in the same lattice,
    // struck again, breaks the same springs in the same order and leaves as
    // many pieces as the fracture made.
    let parent = scn
        .floes
        .iter()
        .find(|f| f.id == rec.floe)
        .expect("an initial floe");
    let s = &scn.fracture;
    let l = Lattice::build(&parent.shape, lattice_spec(s, parent)).unwrap();
    let impact = Impact {
        point: Vec2::new(rec.impact.point[0], rec.impact.point[1]),
        normal: Vec2::new(rec.impact.normal[0], rec.impact.normal[1]),
        mass: rec.impact.striker_mass.unwrap_or(f64::INFINITY),
        speed: rec.impact.speed,
    };
    let again = strike(
        &l,
        impact,
        chain_options(s),
        false,
        s.min_area,
        parent.density * parent.thickness,
    )
    .unwrap()
    .split
    .expect("it broke");
    assert_eq!(again.bonds, rec.broken);
    assert_eq!(again.pieces.len(), rec.children.len());
    assert_eq!(again.loss, rec.loss);
    assert_eq!(rec.nodes.len(), l.nodes.len());
    assert_eq!(rec.springs.len(), l.springs.len());
    let broken = rec.intact.iter().filter(|&&ok| !ok).count();
    assert!(broken > 0);
    assert_eq!(broken, rec.broken.len());
    for &k in &rec.broken {
        assert!(!rec.intact[k], "spring {k}");
    }
    // The largest lattice loss of the run: the 2 m/s diamond's first impact
    // (floe 3) breaks more than the 1 m/s one's (floe 2), whose pieces
    // break again later with less.
    assert_eq!(rec.floe, 3, "{:?}", (rec.t, rec.loss));
    // percussion.json holds the same record.
    let dir = crate::common::tempdir();
    write_run(dir.path(), &r).unwrap();
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join(PERCUSSION_FILE)).unwrap()).unwrap();
    let intact = json["intact"].as_array().unwrap();
    assert_eq!(intact.len(), rec.springs.len());
    assert_eq!(
        intact.iter().filter(|b| b.as_bool() == Some(false)).count(),
        rec.broken.len()
    );
    assert_eq!(json["floe"].as_u64(), Some(rec.floe as u64));
    assert!(json["impact"]["striker_mass"].is_null(), "a coast");
    // The report draws it, one figure per formulation that recorded one.
    let out = dir.path().join("report");
    let comps = floebench::compare::compare(
        vec![(case_path("lattice_ram"), scn.clone())],
        &floebench::compare::CompareOptions {
            formulations: vec!["event-driven".into()],
            progress: false,
            chaos_probe: false,
            ..Default::default()
        },
    )
    .unwrap();
    floebench::report::compare::write_report(&comps, &out, "test").unwrap();
    let case_dir = out.join("lattice_ram");
    for ext in ["png", "svg"] {
        let f = case_dir.join(format!("crack_event-driven.{ext}"));
        assert!(std::fs::metadata(&f).unwrap().len() > 5000, "{f:?}");
    }
    assert!(case_dir.join("event-driven").join(PERCUSSION_FILE).exists());
    let md = std::fs::read_to_string(out.join("index.md")).unwrap();
    assert!(md.contains("lattice_ram/crack_event-driven.png"), "{md}");
    // A record is kept over another only for a larger loss.
    let mut history = floebench::model::fracture::FloeHistory::new(1);
    let pose = BodyState {
        position: Vec2::zeros(),
        angle: 0.0,
        velocity: Vec2::zeros(),
        angular_velocity: 0.0,
    };
    let mut row = row.clone();
    crack::keep(&mut history, &l, &again, &pose, &row);
    let mut less = again.clone();
    less.loss *= 0.5;
    row.t += 1.0;
    crack::keep(&mut history, &l, &less, &pose, &row);
    assert_eq!(history.percussion.as_ref().map(|p| p.t), Some(rec.t));
    let mut more = again.clone();
    more.loss *= 2.0;
    crack::keep(&mut history, &l, &more, &pose, &row);
    assert_eq!(history.percussion.as_ref().map(|p| p.t), Some(rec.t + 1.0));
}
