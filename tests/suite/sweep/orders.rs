//! The observed orders that theory predicts, measured by the sweep itself:
//! rapier's free drift in its step, moreau's sliding distance in h, the
//! event-driven first impact in the contact distance.

use super::{plan_file, sweep};
use crate::common::{bouncing_expected, case_text, scenario, tempdir};
use floebench::analysis::check::wind_acceleration;
use floebench::sweep::orders::{Order, Span};

/// The orders of `metric` along `key`, in increasing value.
fn along<'a>(orders: &'a [Order], metric: &str, key: &str, span: Span) -> Vec<&'a Order> {
    orders
        .iter()
        .filter(|o| o.metric == metric && o.key == key && o.span == span)
        .collect()
}

#[test]
fn rapier_free_drift_position_error_is_first_order_in_its_step() {
    let dir = tempdir();
    let path = plan_file(
        dir.path(),
        &["free_drift"],
        "reference = \"event-driven\"\nmeasures = [\"position\"]\n\n\
         [[formulation]]\nname = \"rapier\"\ngrid = { step = [0.4, 0.2, 0.1, 0.05] }",
    );
    let (done, orders) = sweep(&path, &dir.path().join("out"));
    assert_eq!((done.run, done.skipped, done.references), (4, 0, 1));
    let p = along(&orders, "position", "step", Span::Successive);
    assert_eq!(p.len(), 3, "{orders:?}");
    for o in p {
        eprintln!(
            "rapier free drift: h {} -> {}: position error {:.4e} -> {:.4e}, order {:.5}",
            o.s_from, o.s_to, o.e_from, o.e_to, o.order
        );
        // Symplectic Euler under the drag: e = C h + O(h^2), so the order
        // of a halving moves from 1 by O(h/T) (T the drag time, 430 s):
        // measured 1.0002 at most.
        assert!((o.order - 1.0).abs() < 0.01, "{o:?}");
    }
}

#[test]
fn moreau_sliding_distance_error_is_second_order_in_h() {
    let dir = tempdir();
    let path = plan_file(
        dir.path(),
        &["sliding_floe"],
        "reference = \"exact\"\nmeasures = [\"check:sliding_distance\"]\n\n\
         [[formulation]]\nname = \"moreau\"\ngrid = { step = [1.0, 0.5, 0.25, 0.125] }",
    );
    let out = dir.path().join("out");
    let (done, orders) = sweep(&path, &out);
    assert_eq!((done.run, done.references), (4, 0));
    // The error is 1/2 mu a h^2 f (1 - f) (f: the fractional part of
    // t_stop / h, see tests/suite/moreau/closed_forms.rs): at most mu a h^2 / 8, second
    // order, with a factor f (1 - f) that changes from one h to the next, so
    // single halvings measure 3.37, 1.18, 1.46 and the order over the three
    // halvings 2.00.
    let all = along(&orders, "check:sliding_distance", "step", Span::Successive);
    assert_eq!(all.len(), 3, "{orders:?}");
    let overall = along(&orders, "check:sliding_distance", "step", Span::Overall);
    assert_eq!(overall.len(), 1);
    eprintln!(
        "moreau sliding distance: successive orders {:?}, overall {:.4}",
        all.iter().map(|o| o.order).collect::<Vec<_>>(),
        overall[0].order
    );
    assert!((overall[0].order - 2.0).abs() < 0.05, "{:?}", overall[0]);
    let scn = scenario(&case_text("sliding_floe"));
    let (a, mu, v0) = (wind_acceleration(&scn, 0), scn.contact.friction, 0.05);
    let dist = v0 * v0 / (2.0 * mu * a);
    for o in all {
        for (h, e) in [(o.s_from, o.e_from), (o.s_to, o.e_to)] {
            // The sweep's error is relative to the distance.
            assert!(
                e * dist <= mu * a * h * h / 8.0 * (1.0 + 1e-9),
                "h = {h}: {e}"
            );
        }
    }
}

#[test]
fn event_driven_first_impact_error_is_linear_in_the_contact_distance() {
    let dir = tempdir();
    let path = plan_file(
        dir.path(),
        &["bouncing_floe"],
        "reference = \"exact\"\nmeasures = [\"first_event\"]\n\n\
         [[formulation]]\nname = \"event-driven\"\ngrid = { \"contact.distance\" = [0.02, 0.01, 0.005] }",
    );
    let (_, orders) = sweep(&path, &dir.path().join("out"));
    let p = along(&orders, "first_event", "contact.distance", Span::Successive);
    assert_eq!(p.len(), 2, "{orders:?}");
    let b = bouncing_expected(&scenario(&case_text("bouncing_floe")));
    for o in p {
        eprintln!(
            "event-driven first impact: delta {} -> {}: error {:.4e} -> {:.4e} (x t1: {:.4} s, delta/(10 v1) = {:.4} s), order {:.4}",
            o.s_from,
            o.s_to,
            o.e_from,
            o.e_to,
            o.e_from * b.t1,
            0.1 * o.s_from / b.v1,
            o.order
        );
        // The impact is located at a gap of delta / 10, to 1e-3 delta: early
        // by delta / (10 v1) to 1 %, plus what the floe's acceleration over
        // that last tenth changes (measured: +0.01 % at 0.005 m, +1.01 % at
        // 0.01 m); the bound allows 1.5 %.
        for (d, e) in [(o.s_from, o.e_from), (o.s_to, o.e_to)] {
            let early = e * b.t1;
            assert!(
                early >= 0.0985 * d / b.v1 && early <= 0.1015 * d / b.v1,
                "delta = {d}: {early} s against delta/(10 v1) = {} s",
                0.1 * d / b.v1
            );
        }
        assert!((o.order - 1.0).abs() < 0.02, "{o:?}");
    }
}
