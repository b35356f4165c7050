//! The repeat check (`compare --repeat`, [`physics_difference`]) compares
//! every output of a run but its timing: two runs that break differently,
//! or whose percussions differ, are not reported identical; two runs of the
//! same case are.

use crate::common::{load, run};
use floebench::run::repeat::{merge, physics_difference};
use floebench::run::RunResult;

/// `x` with its last bit flipped: the smallest difference there is.
fn flip(x: f64) -> f64 {
    f64::from_bits(x.to_bits() ^ 1)
}

/// The difference `physics_difference` finds between `a` and `b`, which
/// must mention every one of `words`.
fn found(a: &RunResult, b: &RunResult, words: &[&str]) {
    let d = physics_difference(a, b).unwrap_or_else(|| panic!("reported identical: {words:?}"));
    for w in words {
        assert!(d.contains(w), "`{w}` not in `{d}`");
    }
}

/// `a` changed by `change`.
fn changed(a: &RunResult, change: impl FnOnce(&mut RunResult)) -> RunResult {
    let mut b = a.clone();
    change(&mut b);
    b
}

#[test]
fn two_runs_that_break_differently_are_not_reported_identical() {
    let scn = load("fracture_ram");
    let a = run(&scn, "moreau");
    assert!(!a.fractures.is_empty(), "the floe breaks");
    // Two runs of the same case are identical, whatever their timing.
    let again = changed(&run(&scn, "moreau"), |r| {
        r.summary.timing.cpu_total *= 2.0;
        r.summary.timing.wall *= 3.0;
        if let Some(p) = &mut r.summary.lcp_profile {
            p.buckets.iter_mut().for_each(|b| b.seconds += 1.0);
        }
    });
    assert_eq!(physics_difference(&a, &again), None);

    // Only the fracture energy of the ledger, at one sample.
    let k = a.energy.len() / 2;
    assert!(a.energy[k].ledger.fracture > 0.0);
    let energy = changed(&a, |r| {
        r.energy[k].ledger.fracture = flip(r.energy[k].ledger.fracture);
    });
    found(&a, &energy, &["energy: fracture", "J"]);
    // Only the fracture energy of the totals (summary.json).
    let total = changed(&a, |r| {
        r.summary.energy.ledger.fracture = flip(r.summary.energy.ledger.fracture);
    });
    found(&a, &total, &["summary.json", "energy.fracture"]);
    let gain = changed(&a, |r| {
        r.summary.energy.fracture_kinetic_gain = flip(r.summary.energy.fracture_kinetic_gain);
    });
    found(&a, &gain, &["summary.json", "energy.fracture_kinetic_gain"]);
    // Only a fracture: its energy, its pieces, or the fracture itself.
    let record = changed(&a, |r| r.fractures[0].energy = flip(r.fractures[0].energy));
    found(&a, &record, &["fractures.csv", "fracture 1", "`energy`"]);
    let pieces = changed(&a, |r| r.fractures[0].children.reverse());
    found(&a, &pieces, &["fractures.csv", "children[0]"]);
    let unbroken = changed(&a, |r| {
        r.fractures.pop();
        r.summary.fractures -= 1;
    });
    found(&a, &unbroken, &["fractures"]);
    // Only the number of fractures, or of floes at the end.
    let count = changed(&a, |r| r.summary.fractures += 1);
    found(&a, &count, &["fractures"]);
    let floes = changed(&a, |r| r.summary.floes_at_end -= 1);
    found(&a, &floes, &["floes at the end"]);
    // Only a piece (floes.json).
    let piece = changed(&a, |r| {
        let f = r.floes.last_mut().unwrap();
        f.area = flip(f.area);
    });
    found(&a, &piece, &["floes.json", "`area`"]);

    // A repeat that broke differently is a finding; the identical one is not.
    let merged = merge("fracture_ram: moreau", vec![a.clone(), again, record]).unwrap();
    assert_eq!(merged.findings.len(), 1, "{:?}", merged.findings);
    assert!(
        merged.findings[0].contains("repeat 3 of 3")
            && merged.findings[0].contains("fractures.csv"),
        "{:?}",
        merged.findings
    );
}

#[test]
fn two_runs_whose_percussions_differ_are_not_reported_identical() {
    let scn = load("lattice_ram");
    let a = run(&scn, "moreau");
    assert!(a.percussion.is_some(), "a lattice run that breaks a floe");
    assert_eq!(physics_difference(&a, &run(&scn, "moreau")), None);
    let none = changed(&a, |r| r.percussion = None);
    found(&a, &none, &["percussion.json", "and none"]);
    found(&none, &a, &["percussion.json", "no percussion"]);
    let loss = changed(&a, |r| {
        let p = r.percussion.as_mut().unwrap();
        p.loss = flip(p.loss);
    });
    found(&a, &loss, &["percussion.json", "`loss`"]);
    let node = changed(&a, |r| {
        let p = r.percussion.as_mut().unwrap();
        let last = p.nodes.len() - 1;
        p.nodes[last][1] = flip(p.nodes[last][1]);
    });
    found(&a, &node, &["percussion.json", "`nodes[", "][1]`"]);
    let crack = changed(&a, |r| {
        let p = r.percussion.as_mut().unwrap();
        p.broken.pop();
    });
    found(&a, &crack, &["percussion.json", "`broken`"]);
}

/// Bit for bit: `-0` is not `0`, in a record as in the ledger.
#[test]
fn the_repeat_check_tells_minus_zero_from_zero_in_every_output() {
    let scn = load("fracture_ram");
    let a = run(&scn, "moreau");
    assert_eq!(a.summary.energy.ledger.work_air, 0.0);
    let ledger = changed(&a, |r| r.summary.energy.ledger.work_air = -0.0);
    found(&a, &ledger, &["summary.json", "energy.work_air", "-0.0"]);
    let k = a.energy.len() - 1;
    let sample = changed(&a, |r| r.energy[k].ledger.work_water = -0.0);
    found(&a, &sample, &["energy: work_water"]);
    let record = changed(&a, |r| r.floes[0].theta_birth = -0.0);
    found(&a, &record, &["floes.json", "`theta_birth`"]);
}
