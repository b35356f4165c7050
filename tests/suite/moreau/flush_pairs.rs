//! Flush edge pairs: one merged friction resultant per body pair, with the
//! same dynamics as friction per point.

use super::{largest_difference, problems_with};
use crate::common::scenario;
use floebench::contact::problem::Friction;
use floebench::contact::NarrowOptions;
use floebench::lcp::{solve, SolveOptions};
use floebench::model::Scenario;

/// A square floe flush on a straight wall, a second one on top of it
/// rotated by `theta` (rad) about its lower-left corner, both driven into
/// the wall and towards each other (friction 0.3).
fn flush_pair_case(theta: f64) -> Scenario {
    let (c, s) = (theta.cos(), theta.sin());
    let corner = |x: f64, y: f64| format!("[{}, {}]", x * c - y * s, 10.0 + x * s + y * c);
    let text = format!(
        r#"[case]
version = 1
name = "flush_pair"
duration = 1.0
output_interval = 1.0

[contact]
restitution = 0.0
friction = 0.3

[[floe]]
polygon = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]
thickness = 1.0
velocity = [0.3, 0.05]

[[floe]]
polygon = [{}, {}, {}, {}]
thickness = 1.0
velocity = [0.2, -0.1]
angular_velocity = 0.01

[[obstacle]]
polygon = [[10.0, -100.0], [20.0, -100.0], [20.0, 200.0], [10.0, 200.0]]
"#,
        corner(0.0, 0.0),
        corner(10.0, 0.0),
        corner(10.0, 10.0),
        corner(0.0, 10.0)
    );
    scenario(&text)
}

#[test]
fn flush_edge_pairs_share_one_friction_resultant_with_the_same_dynamics() {
    // Exactly flush (θ = 0): each of the three body pairs (floe 1–wall,
    // floe 2–wall, floe 1–floe 2) touches at two corners with equal
    // tangential columns, so the merged LCP has one friction group per pair
    // (n = 6 + 3·3 = 15 instead of 24), and it must give the same velocity
    // changes as the LCP with friction per point, each member within its
    // own Coulomb cone.
    // Every facing edge pair clipped to two points, as the event-driven
    // scheme detects them.
    let every_facing_pair = NarrowOptions {
        parallel_tolerance: std::f64::consts::FRAC_PI_2,
        ..NarrowOptions::default()
    };
    let scn = flush_pair_case(0.0);
    let (per_point, w) = problems_with(&scn, 0.2, Friction::PerPoint, &every_facing_pair);
    let (merged, _) = problems_with(&scn, 0.2, Friction::Merged, &every_facing_pair);
    assert_eq!((per_point.len(), merged.len()), (1, 1));
    let (a, b) = (&per_point[0], &merged[0]);
    assert_eq!((a.m, a.lcp().n, a.friction_groups), (6, 24, 6));
    assert_eq!((b.m, b.lcp().n, b.friction_groups), (6, 15, 3));
    assert_eq!(b.merged_groups(), Some(3));
    let v_scale = w.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let sa = solve(a.lcp(), &SolveOptions::default());
    let sb = solve(b.lcp(), &SolveOptions::default());
    assert!(sa.status.is_solved() && sb.status.is_solved());
    let err = largest_difference(&a.velocity_changes(&sa.z), &b.velocity_changes(&sb.z));
    assert!(err <= 1e-9 * v_scale, "velocity changes differ by {err:e}");
    let (lam, beta) = (b.normal(&sb.z), b.tangential(&sb.z));
    let mut sliding = 0;
    for (l, t) in lam.iter().zip(&beta) {
        assert!(
            t.abs() <= 0.3 * l * (1.0 + 1e-9) + 1e-12,
            "|β| = {t} > μ λ = {}",
            0.3 * l
        );
        sliding += usize::from(t.abs() > 0.29 * l && *l > 0.0);
    }
    // The pairs' total tangential impulses agree (the sums of the members').
    let (ta, tb) = (a.tangential(&sa.z), beta);
    for pair in [0..2, 2..4, 4..6] {
        let (x, y): (f64, f64) = (ta[pair.clone()].iter().sum(), tb[pair].iter().sum());
        assert!(
            (x - y).abs() <= 1e-9 * x.abs().max(y.abs()).max(1e-300),
            "{x} vs {y}"
        );
    }
    assert!(
        sliding > 0,
        "no contact slides: the test would not see the cone"
    );
    // Rotated by 0.01 rad, floe 2's pairs still touch at two points each,
    // but with tangents 0.01 apart, far above the merge tolerance (1e-3):
    // only floe 1–wall is merged.
    let (rotated, _) = problems_with(
        &flush_pair_case(0.01),
        0.2,
        Friction::Merged,
        &every_facing_pair,
    );
    assert_eq!(rotated.len(), 1);
    assert_eq!((rotated[0].m, rotated[0].friction_groups), (6, 5));
    assert_eq!(rotated[0].lcp().n, 6 + 3 * 5);
}
