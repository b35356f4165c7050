//! The energy ledger of a run: one [`EnergySample`] per output time (a row
//! of `energy.csv`) and the run's [`EnergyTotals`] (`summary.json`'s
//! `energy`).
//!
//! Both hold the state's [`Ledger`], whose fields are listed once, in
//! [`Ledger::FIELDS`]; a sample's numbers are listed once, in
//! [`Column::all`]: its kinetic energy, the ledger's fields, its balance
//! residual. Every writer and reader of the ledger iterates these lists.

use crate::state::{Ledger, LedgerField};
use serde::Serialize;

/// One sample of the energy ledger.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct EnergySample {
    /// Time, s.
    pub t: f64,
    /// Kinetic energy, J.
    pub kinetic: f64,
    /// The cumulative exchanges since t = 0 (the state's ledger at `t`), J.
    #[serde(flatten)]
    pub ledger: Ledger,
    /// Balance residual `E(t) − E(0) − W_ext + D + F + L`, J.
    pub residual: f64,
}

impl EnergySample {
    /// The sample at time `t` (s) of kinetic energy `kinetic` and ledger
    /// `ledger`, for a kinetic energy `initial_kinetic` at t = 0 (J).
    pub fn new(t: f64, kinetic: f64, ledger: Ledger, initial_kinetic: f64) -> EnergySample {
        EnergySample {
            t,
            kinetic,
            ledger,
            residual: ledger.residual(kinetic, initial_kinetic),
        }
    }

    /// Every number of the sample but its time, with its column, in the
    /// order of [`Column::all`].
    pub fn values(&self) -> impl Iterator<Item = (Column, f64)> + '_ {
        Column::all().map(move |c| (c, c.of(self)))
    }
}

/// A column of `energy.csv` after its time `t`.
#[derive(Debug, Clone, Copy)]
pub enum Column {
    /// The kinetic energy `E`.
    Kinetic,
    /// A field of the ledger.
    Ledger(&'static LedgerField),
    /// The balance residual `E − E(0) − W_ext + D + F + L`.
    Residual,
}

impl Column {
    /// Every column, in the order of `energy.csv`: the kinetic energy, the
    /// fields of [`Ledger::FIELDS`], the residual.
    pub fn all() -> impl Iterator<Item = Column> {
        std::iter::once(Column::Kinetic)
            .chain(Ledger::FIELDS.iter().map(Column::Ledger))
            .chain(std::iter::once(Column::Residual))
    }

    /// Its name in `energy.csv`.
    pub fn name(self) -> &'static str {
        match self {
            Column::Kinetic => "kinetic",
            Column::Ledger(f) => f.name,
            Column::Residual => "residual",
        }
    }

    /// Its unit.
    pub fn unit(self) -> &'static str {
        match self {
            Column::Kinetic | Column::Residual => "J",
            Column::Ledger(f) => f.unit,
        }
    }

    /// What it is, in words (the runner's `non-finite …` end of a run).
    pub fn description(self) -> &'static str {
        match self {
            Column::Kinetic => "kinetic energy",
            Column::Ledger(f) => f.description,
            Column::Residual => "energy residual",
        }
    }

    /// Its value in sample `s`.
    pub fn of(self, s: &EnergySample) -> f64 {
        match self {
            Column::Kinetic => s.kinetic,
            Column::Ledger(f) => (f.get)(&s.ledger),
            Column::Residual => s.residual,
        }
    }
}

/// Energy totals of a run, J.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EnergyTotals {
    /// Kinetic energy at t = 0, J.
    pub initial_kinetic: f64,
    /// Kinetic energy at the end, J.
    pub final_kinetic: f64,
    /// The exchanges over the run: the ledger at the end, J.
    #[serde(flatten)]
    pub ledger: Ledger,
    /// Of the ledger's `dissipated`, the part fractures returned to the
    /// floes as their pieces' kinetic energy above their parents' (the
    /// lattice model's relative motion of the pieces, docs/physics.md
    /// §9.8), J: the sum of `fractures.csv`'s `kinetic_gain`; `dissipated`
    /// is net of it.
    pub fracture_kinetic_gain: f64,
    /// Final balance residual, J.
    pub residual: f64,
    /// Largest |residual| over the samples, J.
    pub max_abs_residual: f64,
    /// Scale of the exchanges, `E(0)` plus the absolute value of every
    /// field of the ledger (`|W_air| + |W_water| + |W_cor| + |D| + |F|`),
    /// J: the residual is judged relative to it.
    pub exchanged: f64,
}

impl EnergyTotals {
    /// The totals of the samples `energy` (in time order) of a run whose
    /// fractures gave their pieces `fracture_kinetic_gain` (J). Without a
    /// sample (a state not finite at t = 0) every total is zero.
    pub fn of(energy: &[EnergySample], fracture_kinetic_gain: f64) -> EnergyTotals {
        let e0 = energy.first().map_or(0.0, |s| s.kinetic);
        let last = energy.last().copied().unwrap_or(EnergySample {
            kinetic: e0,
            ..EnergySample::default()
        });
        EnergyTotals {
            initial_kinetic: e0,
            final_kinetic: last.kinetic,
            ledger: last.ledger,
            fracture_kinetic_gain,
            residual: last.residual,
            max_abs_residual: energy.iter().map(|s| s.residual.abs()).fold(0.0, f64::max),
            exchanged: last.ledger.values().fold(e0, |s, (_, v)| s + v.abs()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The columns are `energy.csv`'s, in its order.
    #[test]
    fn the_columns_are_those_of_energy_csv() {
        let names: Vec<&str> = Column::all().map(Column::name).collect();
        assert_eq!(
            names.join(","),
            "kinetic,work_air,work_water,work_coriolis,dissipated,fracture,vibration,dashpot,crushing,residual"
        );
    }

    /// A sample serializes with its ledger's fields between its kinetic
    /// energy and its residual, as `energy.csv` orders them.
    #[test]
    fn a_sample_serializes_in_the_order_of_its_columns() {
        let s = EnergySample::new(2.0, 3.0, Ledger::default(), 3.0);
        let json = serde_json::to_string(&s).unwrap();
        assert_eq!(
            json,
            r#"{"t":2.0,"kinetic":3.0,"work_air":0.0,"work_water":0.0,"work_coriolis":0.0,"dissipated":0.0,"fracture":0.0,"vibration":0.0,"dashpot":0.0,"crushing":0.0,"residual":0.0}"#
        );
    }
}
