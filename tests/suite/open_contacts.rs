//! Moreau–Jean's open contacts (`[formulation.moreau] open_contacts`,
//! docs/physics.md §5.1 step 2): a contact whose predicted gap is open at
//! the start of a step is left out of the classical step's problem, so an
//! impulse of another contact can drive it shut unopposed; with
//! `open_contacts = "gap"` it enters the problem with the linearised gap and
//! stops the floes at contact.

use crate::common::{counter, run, scenario, with_formulation_table};
use floebench::formulation::parse_case;
use floebench::run::RunResult;
use std::path::Path;

/// Three 10 m squares in a row, frictionless and plastic, no forcing: A
/// at 1 m/s touching B at rest (a closed contact), C at rest 0.1 m beyond
/// B (an open one: its predicted gap at the start of the step is 0.1 m).
/// One step of 1 s. The A–B impulse sets A and B at 0.5 m/s; the θ-method
/// (θ = ½) moves B by `h (0 + 0.5)/2` = 0.25 m, so without C in the problem
/// B ends 0.15 m inside C.
fn chain_case() -> String {
    squares(
        "chain_with_a_gap",
        1.0,
        0.0,
        &[(0.0, 1.0), (10.0, 0.0), (20.1, 0.0)],
    )
}

/// A case of 10 m squares on the x axis, frictionless, restitution `e`,
/// no forcing, `duration` s with outputs every second: one floe per
/// `(left edge x, velocity along x)`, m and m/s.
fn squares(name: &str, duration: f64, e: f64, floes: &[(f64, f64)]) -> String {
    let mut text = format!(
        "[case]\nversion = 1\nname = \"{name}\"\nduration = {duration:?}\noutput_interval = 1.0\n\n[contact]\nrestitution = {e:?}\nfriction = 0.0\n"
    );
    for &(x, v) in floes {
        let r = x + 10.0;
        text += &format!(
            "\n[[floe]]\npolygon = [[{x:?}, 0.0], [{r:?}, 0.0], [{r:?}, 10.0], [{x:?}, 10.0]]\nthickness = 1.0\nvelocity = [{v:?}, 0.0]\n"
        );
    }
    text
}

/// The gap between B's right edge and C's left edge at the end, m.
fn gap_bc(r: &RunResult) -> f64 {
    let b = &r.final_state.bodies;
    (b[2].position.x - 5.0) - (b[1].position.x + 5.0)
}

fn chain(settings: &str) -> RunResult {
    run(
        &scenario(&with_formulation_table(
            &chain_case(),
            "moreau",
            &format!("step = 1.0\n{settings}"),
        )),
        "moreau",
    )
}

#[test]
fn an_open_contact_closed_by_another_impulse_stops_at_contact_with_the_gap_law() {
    for solver in ["", "solver = \"nsgs\"\ntolerance = 1e-10\n"] {
        let classical = chain(solver);
        let gap = chain(&format!("{solver}open_contacts = \"gap\""));
        // Classical: B driven 0.15 m into C.
        let g0 = gap_bc(&classical);
        assert!((g0 + 0.15).abs() < 1e-9, "{solver}: classical gap {g0} m");
        // With the gap law B stops at C's edge (to the solver's rounding).
        let g1 = gap_bc(&gap);
        assert!(g1.abs() < 1e-8, "{solver}: gap law {g1} m");
        // B–C is a flush edge pair: two open points, one or both pushing.
        assert_eq!(counter(&gap, "open_contacts"), 2.0, "{solver}");
        let pushing = counter(&gap, "open_contacts_pushing");
        assert!((1.0..=2.0).contains(&pushing), "{solver}: {pushing}");
        // Momentum (equal masses, no forcing) and the ledger hold in both.
        for r in [&classical, &gap] {
            let p: f64 = r.final_state.bodies.iter().map(|b| b.velocity.x).sum();
            assert!((p - 1.0).abs() < 1e-9, "{solver}: momentum {p}");
            let e = &r.summary.energy;
            assert!(e.ledger.dissipated > 0.0, "{e:?}");
            assert!(e.residual.abs() < 1e-9 * e.ledger.dissipated, "{e:?}");
        }
        // C took part: it moves with B (0.2 m/s apart at most, the speed
        // that closes 0.1 m over the step's θ h = 0.5 s).
        let b = &gap.final_state.bodies;
        assert!(b[2].velocity.x > 0.0, "{solver}: C at rest");
        let closing = b[1].velocity.x - b[2].velocity.x;
        assert!(closing <= 0.2 + 1e-8, "{solver}: closing at {closing} m/s");
    }
}

#[test]
fn open_contacts_refuses_unknown_values_and_a_theta_of_zero_at_its_line() {
    let cases = [
        ("open_contacts = \"sometimes\"", "unknown open_contacts"),
        (
            "theta = 0.0\nopen_contacts = \"gap\"",
            "open_contacts = \"gap\" needs theta > 0",
        ),
        ("open_contacts = 1", "must be a string"),
    ];
    for (settings, message) in cases {
        let text = with_formulation_table(&chain_case(), "moreau", settings);
        let line = text
            .lines()
            .position(|l| l.starts_with("open_contacts"))
            .map(|i| i + 1)
            .unwrap_or(0);
        let e = match parse_case(&text, Path::new("inline.toml")) {
            Ok(_) => panic!("{settings} was accepted"),
            Err(e) => e.to_string(),
        };
        assert!(e.contains(message), "{e}");
        assert!(e.contains(&format!("inline.toml:{line}")), "{e}");
    }
    // The two values are accepted.
    for v in ["inactive", "gap"] {
        let text =
            with_formulation_table(&chain_case(), "moreau", &format!("open_contacts = \"{v}\""));
        assert!(parse_case(&text, Path::new("inline.toml")).is_ok(), "{v}");
    }
}

/// Two 10 m squares, elastic and frictionless, no forcing: A at 1 m/s
/// towards B at rest, 0.7 m away. At `h` = 1 s, θ = γ = ½ the contact is
/// open at the first step (predicted gap 0.2 m) and the step would close
/// it (0.7 m < 1 m): the bare linearised gap would slow A to 0.4 m/s
/// there, a plastic impact before the impact.
fn free_approach() -> String {
    squares("free_approach", 3.0, 1.0, &[(0.0, 1.0), (10.7, 0.0)])
}

#[test]
fn the_gap_law_leaves_a_pair_closing_by_its_own_approach_to_newtons_law() {
    let run_it = |settings: &str| {
        run(
            &scenario(&with_formulation_table(
                &free_approach(),
                "moreau",
                &format!("step = 1.0\n{settings}"),
            )),
            "moreau",
        )
    };
    let classical = run_it("");
    let gap = run_it("open_contacts = \"gap\"");
    // The open contact was entered and never pushed: the runs are the same,
    // an elastic exchange of velocities by Newton's law.
    assert!(counter(&gap, "open_contacts") >= 2.0);
    assert_eq!(counter(&gap, "open_contacts_pushing"), 0.0);
    for (a, b) in classical
        .final_state
        .bodies
        .iter()
        .zip(&gap.final_state.bodies)
    {
        assert_eq!(a.position, b.position);
        assert_eq!(a.velocity, b.velocity);
    }
    let v: Vec<f64> = gap
        .final_state
        .bodies
        .iter()
        .map(|b| b.velocity.x)
        .collect();
    assert!(v[0].abs() < 1e-12 && (v[1] - 1.0).abs() < 1e-12, "{v:?}");
}
