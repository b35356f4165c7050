//! The lattice model in runs of `lattice_ram`: a fast ram breaks where a
//! slow one does not in every formulation, the spin check, and the record
//! of the largest percussion's crack with its figure in the report.

use crate::common::{case_path, run, scenario};
use floebench::analysis::check::check_run;
use floebench::fracture::lattice::percussion::Impact;
use floebench::fracture::lattice::Lattice;
use floebench::fracture::strike::{chain_options, lattice_spec, strike_all};
use floebench::geometry::Vec2;
use floebench::state::BodyState;

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
            // The pieces fly apart: their relative motion is counted.
            assert!(fr.kinetic_gain > 0.0 && fr.energy >= 0.0, "{name}: {fr:?}");
        }
        // The summary's total is the rows' sum, and the ledger, net of it,
        // balances.
        let e = &r.summary.energy;
        let gain: f64 = r.fractures.iter().map(|f| f.kinetic_gain).sum();
        assert_eq!(e.fracture_kinetic_gain, gain, "{name}");
        assert!(
            e.max_abs_residual <= 1e-9 * e.exchanged,
            "{name}: residual {} of {}",
            e.max_abs_residual,
            e.exchanged
        );
    }
}

#[test]
fn a_spin_that_prestresses_the_lattice_fails_the_spin_check() {
    // lattice_ram's floes spin little when they break (a pre-strain of at
    // most 2e-3 of their bonds' breaking strain); the 1 m/s diamond given
    // 1 rad/s (a rim speed of 5 m/s) is pre-strained by
    // (3 + 1/3)/8 · 917 · 5² / (E ε_c) = 0.039 of it when it breaks, above
    // the 1 % the lattice model neglects.
    let text = std::fs::read_to_string(case_path("lattice_ram")).unwrap();
    let ratio = |text: &str| {
        let scn = scenario(text);
        let r = run(&scn, "event-driven");
        let rows = check_run(&scn, &r);
        let row = rows
            .iter()
            .find(|o| o.check == "lattice_spin_prestress")
            .expect("the lattice model's spin check");
        (row.measured, row.pass)
    };
    let (calm, pass) = ratio(&text);
    // (0 in event-driven: its floes break at their first impact, unspun.)
    assert!(pass && calm < 2e-3, "{calm}");
    let spun = text.replacen(
        "velocity = [1.0, 0.0]",
        "velocity = [1.0, 0.0]\nangular_velocity = 1.0",
        1,
    );
    let (fast, pass) = ratio(&spun);
    let s = scenario(&text).fracture;
    let eps = (4.0 * s.toughness / (3.0 * s.young * 0.5)).sqrt();
    let expected = (3.0 + 1.0 / 3.0) / 8.0 * 917.0 * 25.0 / (s.young * eps);
    // At least the initial spin's (the impact may spin it further).
    assert!(
        !pass && fast >= expected * (1.0 - 1e-9),
        "{fast} {expected}"
    );
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
    let impacts: Vec<Impact> = rec
        .impacts
        .iter()
        .map(|i| Impact {
            point: Vec2::new(i.point[0], i.point[1]),
            normal: Vec2::new(i.normal[0], i.normal[1]),
            mass: i.striker_mass.unwrap_or(f64::INFINITY),
            speed: i.speed,
        })
        .collect();
    assert!(!impacts.is_empty());
    let again = strike_all(
        &l,
        &impacts,
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
