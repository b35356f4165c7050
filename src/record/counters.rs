//! Typed counters and settings.
//!
//! A counter is declared once, as a constant [`Counter`] next to the code
//! that writes it, with its name, unit, kind and meaning. A formulation
//! declares the counters it keeps when it is built ([`Counters::new`]), so a
//! read of a counter it does not keep is an error ([`UnknownCounter`]), not a
//! silent zero; a misspelt counter is a compile error.
//!
//! The settings a formulation runs with (its step, θ, contact distance, …)
//! are not counters: they are reported apart, as [`Settings`], in the
//! `settings` object of `summary.json`.

use serde::ser::{SerializeMap, Serializer};
use serde::Serialize;
use std::collections::BTreeMap;

/// The unit of a counter or a setting.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Unit {
    /// A number of things (steps, solves, pivots, contacts).
    #[serde(rename = "count")]
    Count,
    /// Metres.
    #[serde(rename = "m")]
    Metre,
    /// Seconds.
    #[serde(rename = "s")]
    Second,
    /// Metres per second.
    #[serde(rename = "m/s")]
    MetrePerSecond,
    /// Joules.
    #[serde(rename = "J")]
    Joule,
    /// Hertz.
    #[serde(rename = "Hz")]
    Hertz,
    /// Cubic metres.
    #[serde(rename = "m^3")]
    CubicMetre,
    /// A pure number (a ratio, a relative residual, θ).
    #[serde(rename = "-")]
    Dimensionless,
}

impl Unit {
    /// The symbol written into `metrics.csv` and `summary.json`.
    pub fn symbol(self) -> &'static str {
        match self {
            Unit::Count => "count",
            Unit::Metre => "m",
            Unit::Second => "s",
            Unit::MetrePerSecond => "m/s",
            Unit::Joule => "J",
            Unit::Hertz => "Hz",
            Unit::CubicMetre => "m^3",
            Unit::Dimensionless => "-",
        }
    }
}

/// How a counter accumulates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CounterKind {
    /// An integer count, added to ([`Counters::add`]); starts at 0.
    Sum,
    /// A real figure that keeps the largest value seen ([`Counters::max`]);
    /// unset until the first value.
    Max,
    /// A real figure set as a whole ([`Counters::set`]); unset until set.
    Value,
}

/// A counter's declaration: name, unit, kind and meaning.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Counter {
    /// The name in `summary.json` and `metrics.csv`.
    pub name: &'static str,
    /// Its unit.
    pub unit: Unit,
    /// How it accumulates.
    pub kind: CounterKind,
    /// What it counts, one line.
    pub doc: &'static str,
}

impl Counter {
    /// An integer count (unit [`Unit::Count`]).
    pub const fn sum(name: &'static str, doc: &'static str) -> Counter {
        Counter {
            name,
            unit: Unit::Count,
            kind: CounterKind::Sum,
            doc,
        }
    }

    /// The largest value of a figure in `unit`.
    pub const fn max(name: &'static str, unit: Unit, doc: &'static str) -> Counter {
        Counter {
            name,
            unit,
            kind: CounterKind::Max,
            doc,
        }
    }

    /// A figure in `unit`, set as a whole.
    pub const fn value(name: &'static str, unit: Unit, doc: &'static str) -> Counter {
        Counter {
            name,
            unit,
            kind: CounterKind::Value,
            doc,
        }
    }
}

/// A counter the run does not keep was read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("no counter `{name}` in this run; it keeps: {known}")]
pub struct UnknownCounter {
    /// The name asked for.
    pub name: String,
    /// The names the run keeps, comma-separated.
    pub known: String,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Slot {
    Count(u64),
    Real(Option<f64>),
}

/// A formulation's counters: the declared ones, with their values.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Counters {
    entries: BTreeMap<&'static str, (Counter, Slot)>,
}

impl Counters {
    /// Counters with `declared` kept (sums at 0, figures unset).
    pub fn new(declared: &[&Counter]) -> Counters {
        let mut c = Counters::default();
        c.declare(declared);
        c
    }

    /// Declares more counters (those already kept are left as they are).
    pub fn declare(&mut self, declared: &[&Counter]) {
        for c in declared {
            self.slot(c);
        }
    }

    fn slot(&mut self, c: &Counter) -> &mut Slot {
        &mut self
            .entries
            .entry(c.name)
            .or_insert_with(|| {
                let slot = match c.kind {
                    CounterKind::Sum => Slot::Count(0),
                    CounterKind::Max | CounterKind::Value => Slot::Real(None),
                };
                (*c, slot)
            })
            .1
    }

    /// Adds `n` to the count `c` (declared if it was not).
    pub fn add(&mut self, c: &Counter, n: u64) {
        match self.slot(c) {
            Slot::Count(k) => *k += n,
            Slot::Real(v) => *v = Some(v.unwrap_or(0.0) + n as f64),
        }
    }

    /// Keeps the largest value of `c` seen so far.
    pub fn max(&mut self, c: &Counter, x: f64) {
        match self.slot(c) {
            Slot::Real(v) => *v = Some(v.map_or(x, |m| m.max(x))),
            Slot::Count(k) => *k = (*k).max(x as u64),
        }
    }

    /// Sets the figure `c`.
    pub fn set(&mut self, c: &Counter, x: f64) {
        match self.slot(c) {
            Slot::Real(v) => *v = Some(x),
            Slot::Count(k) => *k = x as u64,
        }
    }

    fn unknown(&self, name: &str) -> UnknownCounter {
        UnknownCounter {
            name: name.to_string(),
            known: self.entries.keys().copied().collect::<Vec<_>>().join(", "),
        }
    }

    /// The count `c`; an error if the run does not keep it.
    pub fn count(&self, c: &Counter) -> Result<u64, UnknownCounter> {
        match self.entries.get(c.name) {
            Some((_, Slot::Count(k))) => Ok(*k),
            Some((_, Slot::Real(v))) => Ok(v.unwrap_or(0.0) as u64),
            None => Err(self.unknown(c.name)),
        }
    }

    /// The figure `c` (`None` while unset); an error if the run does not
    /// keep it.
    pub fn value(&self, c: &Counter) -> Result<Option<f64>, UnknownCounter> {
        self.by_name(c.name)
    }

    /// The counter called `name` as a real number (`None` for an unset
    /// figure); an error if the run does not keep it.
    pub fn by_name(&self, name: &str) -> Result<Option<f64>, UnknownCounter> {
        match self.entries.get(name) {
            Some((_, Slot::Count(k))) => Ok(Some(*k as f64)),
            Some((_, Slot::Real(v))) => Ok(*v),
            None => Err(self.unknown(name)),
        }
    }

    /// Adds every counter of `other`: counts are added, largest values kept,
    /// set values replaced.
    pub fn absorb(&mut self, other: &Counters) {
        for (c, slot) in other.entries.values() {
            match (c.kind, slot) {
                (_, Slot::Count(k)) => self.add(c, *k),
                (CounterKind::Max, Slot::Real(Some(v))) => self.max(c, *v),
                (_, Slot::Real(Some(v))) => self.set(c, *v),
                (_, Slot::Real(None)) => self.declare(&[c]),
            }
        }
    }

    /// Every kept counter with a value (sums always, figures once set), by
    /// name.
    pub fn iter(&self) -> impl Iterator<Item = (&Counter, f64)> + '_ {
        self.entries.values().filter_map(|(c, s)| match s {
            Slot::Count(k) => Some((c, *k as f64)),
            Slot::Real(v) => v.map(|v| (c, v)),
        })
    }
}

/// `{"name": {"value": v, "unit": "m"}, …}`, counts as integers.
impl Serialize for Counters {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        #[derive(Serialize)]
        struct Entry<V: Serialize> {
            value: V,
            unit: Unit,
        }
        let mut map = s.serialize_map(None)?;
        for (c, slot) in self.entries.values() {
            match slot {
                Slot::Count(k) => map.serialize_entry(
                    c.name,
                    &Entry {
                        value: *k,
                        unit: c.unit,
                    },
                )?,
                Slot::Real(Some(v)) => map.serialize_entry(
                    c.name,
                    &Entry {
                        value: *v,
                        unit: c.unit,
                    },
                )?,
                Slot::Real(None) => {}
            }
        }
        map.end()
    }
}

/// The value of a setting.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum SettingValue {
    /// A number in the setting's unit.
    Number(f64),
    /// A choice (e.g. a solver's name).
    Text(String),
}

/// One setting a formulation ran with, defaults resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct Setting {
    /// The name in `summary.json` and `metrics.csv`.
    pub name: &'static str,
    /// Its value.
    pub value: SettingValue,
    /// Its unit ([`Unit::Dimensionless`] for a choice).
    pub unit: Unit,
}

/// The settings a formulation ran with, in the order it lists them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Settings(pub Vec<Setting>);

impl Settings {
    /// Adds a number in `unit`.
    pub fn number(mut self, name: &'static str, value: f64, unit: Unit) -> Settings {
        self.0.push(Setting {
            name,
            value: SettingValue::Number(value),
            unit,
        });
        self
    }

    /// Adds a choice.
    pub fn text(mut self, name: &'static str, value: &str) -> Settings {
        self.0.push(Setting {
            name,
            value: SettingValue::Text(value.to_string()),
            unit: Unit::Dimensionless,
        });
        self
    }

    /// The choice called `name`, if there is one.
    pub fn get_text(&self, name: &str) -> Option<&str> {
        self.0
            .iter()
            .find(|s| s.name == name)
            .and_then(|s| match &s.value {
                SettingValue::Text(t) => Some(t.as_str()),
                SettingValue::Number(_) => None,
            })
    }

    /// The number called `name`, if there is one.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.0
            .iter()
            .find(|s| s.name == name)
            .and_then(|s| match s.value {
                SettingValue::Number(v) => Some(v),
                SettingValue::Text(_) => None,
            })
    }
}

/// `{"name": {"value": v, "unit": "s"}, …}` in the listed order.
impl Serialize for Settings {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        #[derive(Serialize)]
        struct Entry<'a> {
            value: &'a SettingValue,
            unit: Unit,
        }
        let mut map = s.serialize_map(Some(self.0.len()))?;
        for st in &self.0 {
            map.serialize_entry(
                st.name,
                &Entry {
                    value: &st.value,
                    unit: st.unit,
                },
            )?;
        }
        map.end()
    }
}

/// Counters that several formulations keep, declared once.
pub mod common {
    use super::{Counter, Unit};

    /// Steps taken (accepted).
    pub const STEPS: Counter = Counter::sum("steps", "steps taken");
    /// Evaluations of the environment forces of one floe.
    pub const FORCE_EVALUATIONS: Counter = Counter::sum(
        "force_evaluations",
        "evaluations of the environment forces of one floe",
    );
    /// Steps of the smooth integrator (accepted).
    pub const INTEGRATOR_STEPS: Counter = Counter::sum(
        "integrator_steps",
        "accepted steps of the smooth integrator",
    );
    /// Steps of the smooth integrator rejected by its error control.
    pub const INTEGRATOR_REJECTED_STEPS: Counter = Counter::sum(
        "integrator_rejected_steps",
        "steps of the smooth integrator rejected by its error control",
    );
    /// Impacts resolved (event-driven).
    pub const IMPACTS: Counter = Counter::sum("impacts", "impacts resolved");
    /// Deepest penetration the formulation saw, m.
    pub const MAX_PENETRATION: Counter = Counter::value(
        "max_penetration_m",
        Unit::Metre,
        "deepest penetration the formulation saw",
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: Counter = Counter::sum("a", "a count");
    const B: Counter = Counter::max("b_m", Unit::Metre, "a largest length");
    const C: Counter = Counter::sum("c", "not declared");

    #[test]
    fn reads_fail_on_counters_not_kept() {
        let mut c = Counters::new(&[&A, &B]);
        assert_eq!(c.count(&A), Ok(0));
        assert_eq!(c.value(&B), Ok(None));
        assert!(c.count(&C).is_err());
        assert!(c.by_name("a_typo").is_err());
        c.add(&A, 3);
        c.max(&B, -2.0);
        c.max(&B, -5.0);
        assert_eq!(c.count(&A), Ok(3));
        assert_eq!(c.value(&B), Ok(Some(-2.0)));
        let json = serde_json::to_string(&c).unwrap();
        assert_eq!(
            json,
            r#"{"a":{"value":3,"unit":"count"},"b_m":{"value":-2.0,"unit":"m"}}"#
        );
    }
}
