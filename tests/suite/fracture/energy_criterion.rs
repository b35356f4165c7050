//! The energy criterion: a rammed floe breaks exactly above its critical
//! speed, in every formulation that breaks floes, and the crack's energy
//! comes out of the impact's dissipation.

use super::rel;
use crate::common::run;
use floebench::analysis::check::ram_critical_speed_of;
use floebench::geometry::Vec2;

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
