//! Serde helpers for `f64` data that must survive JSON exactly, including
//! non-finite values.
//!
//! Writing: finite values are JSON numbers (shortest round-trip form);
//! non-finite ones are the strings `"NaN"`, `"Infinity"`, `"-Infinity"`
//! (plain serde_json would write `null` and lose them).
//! Reading: a JSON number, one of the strings `"NaN"`, `"Infinity"`,
//! `"-Infinity"`, or `null` (read as NaN, as written by JavaScript for
//! non-finite numbers). Any other string is refused: a number written as a
//! string (`"1e-3"`) is an error. The dump reader hands numbers over as
//! strings tagged with [`NUMBER_TAG`] (see `dump::quote_numbers`), which
//! are parsed by Rust's correctly rounded `f64` parser.

use serde::de::{self, Deserializer, Visitor};
use serde::ser::Serializer;
use serde::{Deserialize, Serialize};
use std::fmt;

/// Prefix of a string that holds a JSON number token of a dump file (added
/// by the dump reader, never present in a valid file's strings).
pub(crate) const NUMBER_TAG: char = '\u{1}';

/// The strings that may stand for a number.
const NON_FINITE: [&str; 3] = ["NaN", "Infinity", "-Infinity"];

/// An `f64` with the JSON encoding described in the module doc.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Num(pub(crate) f64);

impl Serialize for Num {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let x = self.0;
        if x.is_finite() {
            s.serialize_f64(x)
        } else if x.is_nan() {
            s.serialize_str("NaN")
        } else if x > 0.0 {
            s.serialize_str("Infinity")
        } else {
            s.serialize_str("-Infinity")
        }
    }
}

struct NumVisitor;

impl<'de> Visitor<'de> for NumVisitor {
    type Value = Num;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a number, or a string holding a number, NaN or Infinity")
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Num, E> {
        Ok(Num(v))
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Num, E> {
        Ok(Num(v as f64))
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Num, E> {
        Ok(Num(v as f64))
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Num, E> {
        if let Some(token) = v.strip_prefix(NUMBER_TAG) {
            return token
                .parse::<f64>()
                .map(Num)
                .map_err(|_| E::custom(format!("invalid number {token:?}")));
        }
        if NON_FINITE.contains(&v) {
            return v
                .parse::<f64>()
                .map(Num)
                .map_err(|_| E::custom(format!("invalid number {v:?}")));
        }
        Err(E::custom(format!(
            "number written as a string: {v:?} (only \"NaN\", \"Infinity\" and \"-Infinity\" may be strings)"
        )))
    }

    fn visit_unit<E: de::Error>(self) -> Result<Num, E> {
        Ok(Num(f64::NAN))
    }

    fn visit_none<E: de::Error>(self) -> Result<Num, E> {
        Ok(Num(f64::NAN))
    }
}

impl<'de> Deserialize<'de> for Num {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(NumVisitor)
    }
}

/// `#[serde(with = "json_f64::scalar")]` for an `f64` field.
pub(crate) mod scalar {
    use super::Num;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub(crate) fn serialize<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
        Num(*x).serialize(s)
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        Num::deserialize(d).map(|n| n.0)
    }
}

/// `#[serde(with = "json_f64::vector")]` for a `Vec<f64>` field.
pub(crate) mod vector {
    use super::Num;
    use serde::{Deserialize, Deserializer, Serializer};

    pub(crate) fn serialize<S: Serializer>(v: &[f64], s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(v.iter().map(|&x| Num(x)))
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
        Vec::<Num>::deserialize(d).map(|v| v.into_iter().map(|n| n.0).collect())
    }
}

/// `#[serde(with = "json_f64::matrix")]` for a `Vec<Vec<f64>>` field.
pub(crate) mod matrix {
    use super::Num;
    use serde::{Deserialize, Deserializer, Serializer};

    pub(crate) fn serialize<S: Serializer>(m: &[Vec<f64>], s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(
            m.iter()
                .map(|row| row.iter().map(|&x| Num(x)).collect::<Vec<_>>()),
        )
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Vec<f64>>, D::Error> {
        Vec::<Vec<Num>>::deserialize(d).map(|m| {
            m.into_iter()
                .map(|r| r.into_iter().map(|n| n.0).collect())
                .collect()
        })
    }
}

/// `#[serde(with = "json_f64::count")]` for a `usize` written as a JSON
/// integer (a string holding one is refused).
pub(crate) mod count {
    use serde::de::{self, Deserializer, Visitor};
    use serde::Serializer;
    use std::fmt;

    pub(crate) fn serialize<S: Serializer>(x: &usize, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_u64(*x as u64)
    }

    struct CountVisitor;

    impl<'de> Visitor<'de> for CountVisitor {
        type Value = usize;

        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            f.write_str("a non-negative integer")
        }

        fn visit_u64<E: de::Error>(self, v: u64) -> Result<usize, E> {
            usize::try_from(v).map_err(|_| E::custom(format!("integer {v} too large")))
        }

        fn visit_i64<E: de::Error>(self, v: i64) -> Result<usize, E> {
            usize::try_from(v)
                .map_err(|_| E::custom(format!("expected a non-negative integer, got {v}")))
        }

        fn visit_str<E: de::Error>(self, v: &str) -> Result<usize, E> {
            match v.strip_prefix(super::NUMBER_TAG) {
                Some(token) => token.parse::<usize>().map_err(|_| {
                    E::custom(format!("expected a non-negative integer, got {token:?}"))
                }),
                None => Err(E::custom(format!(
                    "expected a non-negative integer, got the string {v:?}"
                ))),
            }
        }
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<usize, D::Error> {
        d.deserialize_any(CountVisitor)
    }
}
