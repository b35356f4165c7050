//! A new formulation is one file and one registry line: this test writes one
//! (a frictionless event-driven scheme, built from the shared parts) as a
//! [`Formulation`] with its [`Entry`], and runs it through the same runner
//! and the same physical checks as the registered ones.

use crate::common::{case_text, counter, load, run as run_named, scenario};
use floebench::analysis::check;
use floebench::formulation::event_driven::EventDriven;
use floebench::formulation::{
    self, Context, Entry, Formulation, FormulationError, FormulationOptions, NotClaimed, REGISTRY,
};
use floebench::model::Scenario;
use floebench::record::{ContactLog, Counters, Settings};
use floebench::run::{RunOptions, RunResult, Runner};
use floebench::state::System;

/// The example: the event-driven scheme on the same case without friction
/// (`μ = 0` for every contact). Everything else is shared.
struct FrictionlessEventDriven {
    frictionless: Scenario,
    inner: EventDriven,
}

impl FrictionlessEventDriven {
    fn new(scn: &Scenario, opts: &FormulationOptions) -> Result<Self, String> {
        let mut frictionless = scn.clone();
        frictionless.contact.friction = 0.0;
        let inner = EventDriven::new(&frictionless, opts)?;
        Ok(FrictionlessEventDriven {
            frictionless,
            inner,
        })
    }
}

impl Formulation for FrictionlessEventDriven {
    fn advance(
        &mut self,
        _scn: &mut Scenario,
        sys: &mut System,
        t_end: f64,
        cx: &mut Context,
    ) -> Result<(), FormulationError> {
        self.inner.advance(&mut self.frictionless, sys, t_end, cx)
    }

    fn counters(&self) -> Counters {
        self.inner.counters()
    }

    fn settings(&self) -> Settings {
        self.inner.settings()
    }

    fn take_contact_log(&mut self) -> ContactLog {
        self.inner.take_contact_log()
    }
}

/// Its registry entry: the one line `REGISTRY` would get is `ENTRY,`.
const ENTRY: Entry = Entry {
    name: "event-driven-frictionless",
    description: "the event-driven scheme with every friction coefficient set to 0",
    build: |scn, opts| Ok(Box::new(FrictionlessEventDriven::new(scn, opts)?)),
    check: None,
    settings: None,
    resolves_contacts: true,
    dumps_lcps: true,
    supports_fracture: false,
    lattice_impacts: false,
    supports_crushing: false,
    not_claimed: &[NotClaimed {
        check: "sliding_stop",
        case: None,
        reason: "without friction a sliding floe never stops",
    }],
};

fn run(entry: &Entry, scn: &Scenario) -> RunResult {
    let mut f = (entry.build)(scn, &FormulationOptions::default()).unwrap();
    Runner::new(RunOptions::default()).run(scn, entry.name, f.as_mut())
}

/// The checks of a run with the claims of `entry`: (check, passed, claimed).
fn checks(entry: &Entry, scn: &Scenario, r: &RunResult) -> Vec<(String, bool, bool)> {
    check::check_run(scn, r)
        .into_iter()
        .map(|o| {
            let claimed = entry.not_claimed(&o.check, &o.case).is_none();
            (o.check, o.pass, claimed)
        })
        .collect()
}

#[test]
fn a_formulation_written_outside_the_library_runs_through_the_shared_machinery() {
    assert!(REGISTRY.iter().all(|e| e.name != ENTRY.name));
    // head_on has μ = 0.3 but a central impact without spin: friction does
    // nothing, so the example gives exactly the event-driven answer.
    let scn = load("head_on");
    let (a, b) = (run(&ENTRY, &scn), run_named(&scn, "event-driven"));
    assert_eq!(a.summary.formulation, "event-driven-frictionless");
    assert_eq!(a.final_state.bodies, b.final_state.bodies);
    for (check, pass, claimed) in checks(&ENTRY, &scn, &a) {
        assert!(pass || !claimed, "head_on: {check} fails and is claimed");
    }
    // On the sliding floe it does not stop (an unclaimed, known failure),
    // where the registered scheme does.
    let scn = load("sliding_floe");
    let (a, b) = (run(&ENTRY, &scn), run_named(&scn, "event-driven"));
    let stop = |r: &RunResult| {
        checks(&ENTRY, &scn, r)
            .into_iter()
            .find(|c| c.0 == "sliding_stop")
            .unwrap()
    };
    assert_eq!(stop(&a), ("sliding_stop".to_string(), false, false));
    assert!(stop(&b).1, "the event-driven floe stops");
    let v = a.final_state.bodies[0].velocity.norm();
    assert!(v > 0.04, "frictionless floe keeps sliding: {v} m/s");
}

#[test]
fn the_event_driven_scheme_can_solve_its_sustained_contacts_by_the_cone() {
    // The sliding floe is one sustained frictional contact: with the cone
    // relaxation the floe still stops (Coulomb holds on the cone), but it
    // separates from the wall at μ |u_T| (the relaxation's artefact), so the
    // sustained solve differs from Lemke's.
    let cone = scenario(&format!(
        "{}\n[formulation.event-driven]\nsolver = \"cone\"\n",
        case_text("sliding_floe")
    ));
    let ed = formulation::entry("event-driven").unwrap();
    let r = run_named(&cone, "event-driven");
    assert_eq!(r.summary.formulation, "event-driven");
    assert!(counter(&r, "cone_solves") > 0.0);
    let solver = r
        .summary
        .settings
        .0
        .iter()
        .find(|s| s.name == "solver")
        .unwrap();
    assert_eq!(
        solver.value,
        floebench::record::SettingValue::Text("cone".into())
    );
    let lemke = run_named(&load("sliding_floe"), "event-driven");
    assert_eq!(
        lemke.summary.counters.by_name("cone_solves").ok(),
        None,
        "the lcp solver keeps no cone counters"
    );
    for (check, pass, claimed) in checks(ed, &cone, &r) {
        eprintln!("event-driven with cone, sliding_floe: {check}: pass {pass}, claimed {claimed}");
    }
    assert!(r.final_state.bodies[0].velocity.norm() < 1e-6, "stops");
}
