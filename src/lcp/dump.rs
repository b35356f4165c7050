//! JSON dumps of LCPs for reproducing a solve.
//!
//! Format: one JSON object with keys
//!
//! * `"M"`: the matrix as a list of n rows, each a list of n numbers;
//! * `"q"`: list of n numbers;
//! * `"z"`, `"w"`: the returned solution (or best candidate) and `M z + q`;
//! * `"t"`: simulation time (number);
//! * `"contacts"`: number of contacts (integer);
//! * `"friction_groups"` (optional): number of friction groups G of an LCP
//!   whose flush edge pairs share one friction resultant (docs/physics.md
//!   §3.1), written only when G differs from the number of contacts;
//! * `"pivots"`: total pivots (integer);
//! * `"status"`: string, e.g. `"Solved"`, `"SolvedByFallback"`, `"Failed"`.
//!
//! Numbers are written in shortest round-trip form and **read back bit for
//! bit**: [`LcpDump::read`] parses every number with Rust's correctly rounded
//! `f64` parser (serde_json's default float parser may be off by one ulp,
//! which could change a degenerate pivot sequence). Non-finite values are
//! written as the strings `"NaN"`, `"Infinity"`, `"-Infinity"`; on reading,
//! those strings, the bare tokens `NaN`/`Infinity`/`-Infinity` (as written by
//! Python's `json`) and `null` (read as NaN) are accepted.
//!
//! Reading is strict, and every error names the file and the key:
//!
//! * exactly the keys above, each once (an unknown, missing or repeated key
//!   is an error; only `friction_groups` may be absent);
//! * `M` is n×n and `q`, `z`, `w` have n entries;
//! * `contacts` = m is consistent with the unknowns of the contact layer
//!   (docs/output-format.md, "LCP dumps"): n = 4m with friction, n = m without, and
//!   n = m + 3G with `friction_groups` = G (1 ≤ G ≤ m);
//! * `status` is one of [`super::SolveStatus::as_str`]; a solved status
//!   requires finite `M`, `q` and a finite `z >= 0`;
//! * numbers are JSON numbers; the only strings accepted for a number are
//!   `"NaN"`, `"Infinity"` and `"-Infinity"` (counts: integers only).
//!
//! Files are written atomically: to a temporary file in the same directory,
//! flushed to disk, then renamed over the target.

use super::json_f64;
use super::solution::LcpSolution;
use super::{Lcp, LcpError};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// One LCP with its solution and context, as stored in a dump file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LcpDump {
    /// Matrix M as rows (JSON key `"M"`).
    #[serde(rename = "M", with = "json_f64::matrix")]
    pub m: Vec<Vec<f64>>,
    /// Vector q.
    #[serde(with = "json_f64::vector")]
    pub q: Vec<f64>,
    /// Returned `z` (solution or best candidate).
    #[serde(with = "json_f64::vector")]
    pub z: Vec<f64>,
    /// `w = M z + q`.
    #[serde(with = "json_f64::vector")]
    pub w: Vec<f64>,
    /// Simulation time.
    #[serde(with = "json_f64::scalar")]
    pub t: f64,
    /// Number of contacts behind this LCP.
    #[serde(with = "json_f64::count")]
    pub contacts: usize,
    /// Number of friction groups when some contacts share a friction
    /// resultant (`n = contacts + 3 G`); `None` otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction_groups: Option<usize>,
    /// Total pivots of the solve.
    #[serde(with = "json_f64::count")]
    pub pivots: usize,
    /// Status of the solve (see [`super::SolveStatus::as_str`]).
    pub status: String,
}

/// Errors of [`LcpDump::read`] and [`LcpDump::write`]; each names the file.
#[derive(Debug, thiserror::Error)]
pub enum DumpError {
    /// The file could not be read, written or renamed.
    #[error("{}: {source}", path.display())]
    Io {
        /// File concerned.
        path: PathBuf,
        /// Underlying error.
        source: std::io::Error,
    },
    /// The file is not valid JSON or lacks / mistypes a key.
    #[error("{}: invalid LCP dump: {source}", path.display())]
    Parse {
        /// File concerned.
        path: PathBuf,
        /// Underlying error.
        source: serde_json::Error,
    },
    /// A row of M has a length different from the number of rows.
    #[error("{}: row {row} of M has {len} entries, expected {expected} (M has {expected} rows)", path.display())]
    RowLength {
        /// File concerned.
        path: PathBuf,
        /// 0-based index of the offending row.
        row: usize,
        /// Its length.
        len: usize,
        /// Number of rows of M.
        expected: usize,
    },
    /// All rows of M have the same length, which differs from their number.
    #[error("{}: M is not square: {rows} rows of {cols} entries", path.display())]
    NotSquare {
        /// File concerned.
        path: PathBuf,
        /// Number of rows.
        rows: usize,
        /// Common row length.
        cols: usize,
    },
    /// A key that is not one of the documented ones.
    #[error("{}: invalid LCP dump: unknown key {key:?} (expected M, q, z, w, t, contacts, pivots, status)", path.display())]
    UnknownKey {
        /// File concerned.
        path: PathBuf,
        /// The key.
        key: String,
    },
    /// A documented key is missing.
    #[error("{}: invalid LCP dump: missing field `{key}`", path.display())]
    MissingKey {
        /// File concerned.
        path: PathBuf,
        /// The key.
        key: &'static str,
    },
    /// A key appears twice.
    #[error("{}: invalid LCP dump: key {key:?} appears more than once", path.display())]
    DuplicateKey {
        /// File concerned.
        path: PathBuf,
        /// The key.
        key: String,
    },
    /// The value of a key has the wrong type, or a number is written as a
    /// string, or is not a valid number.
    #[error("{}: invalid LCP dump: key {key:?}: {source}", path.display())]
    Value {
        /// File concerned.
        path: PathBuf,
        /// The key.
        key: &'static str,
        /// Underlying error.
        source: serde_json::Error,
    },
    /// `contacts` does not match the number of unknowns.
    #[error("{}: key \"contacts\" = {contacts} does not match n = {n} unknowns (expected n = 4 × contacts with friction, n = contacts without, n = contacts + 3 × friction_groups with that key)", path.display())]
    Contacts {
        /// File concerned.
        path: PathBuf,
        /// Value of `contacts`.
        contacts: usize,
        /// Number of unknowns (rows of M).
        n: usize,
    },
    /// `status` is not a status name, or contradicts the data.
    #[error("{}: key \"status\" = {status:?}: {reason}", path.display())]
    Status {
        /// File concerned.
        path: PathBuf,
        /// Value of `status`.
        status: String,
        /// What is wrong.
        reason: &'static str,
    },
    /// `q`, `z` or `w` does not have n entries.
    #[error("{}: vector {name} has {len} entries, expected n = {expected}", path.display())]
    VectorLength {
        /// File concerned.
        path: PathBuf,
        /// Key of the vector.
        name: &'static str,
        /// Its length.
        len: usize,
        /// n (number of rows of M).
        expected: usize,
    },
}

static TMP_COUNTER: AtomicU64 = AtomicU64::new(0);

impl LcpDump {
    /// Builds a dump from a problem and the driver's solution, of
    /// `contacts` contacts in `friction_groups` friction groups (`None`:
    /// one per contact, or no friction).
    pub fn from_solution(
        lcp: &Lcp,
        sol: &LcpSolution,
        t: f64,
        contacts: usize,
        friction_groups: Option<usize>,
    ) -> Self {
        let n = lcp.q.len();
        let m = if n > 0 && lcp.m.len() == n * n {
            lcp.m.chunks_exact(n).map(<[f64]>::to_vec).collect()
        } else {
            Vec::new()
        };
        Self {
            m,
            q: lcp.q.clone(),
            z: sol.z.clone(),
            w: sol.w.clone(),
            t,
            contacts,
            friction_groups,
            pivots: sol.pivots,
            status: sol.status.as_str().to_string(),
        }
    }

    /// Dimension n (number of rows of M).
    pub fn n(&self) -> usize {
        self.m.len()
    }

    /// The LCP `(M, q)` of this dump (errors if M is not n×n or q not n).
    pub fn to_lcp(&self) -> Result<Lcp, LcpError> {
        Lcp::from_rows(&self.m, self.q.clone())
    }

    /// Checks the shapes: M square n×n, `q`, `z`, `w` of length n. `path`
    /// is used only to name the file in the error.
    pub fn validate(&self, path: &Path) -> Result<(), DumpError> {
        let n = self.m.len();
        let path_buf = || path.to_path_buf();
        if let Some(first) = self.m.first() {
            let cols = first.len();
            if cols != n && self.m.iter().all(|r| r.len() == cols) {
                return Err(DumpError::NotSquare {
                    path: path_buf(),
                    rows: n,
                    cols,
                });
            }
        }
        if let Some((row, r)) = self.m.iter().enumerate().find(|(_, r)| r.len() != n) {
            return Err(DumpError::RowLength {
                path: path_buf(),
                row,
                len: r.len(),
                expected: n,
            });
        }
        for (name, v) in [("q", &self.q), ("z", &self.z), ("w", &self.w)] {
            if v.len() != n {
                return Err(DumpError::VectorLength {
                    path: path_buf(),
                    name,
                    len: v.len(),
                    expected: n,
                });
            }
        }
        let m = self.contacts;
        let consistent = match self.friction_groups {
            Some(g) => (1..=m).contains(&g) && Some(n) == g.checked_mul(3).map(|x| x + m),
            None => n == m || Some(n) == m.checked_mul(4),
        };
        if !consistent {
            return Err(DumpError::Contacts {
                path: path_buf(),
                contacts: m,
                n,
            });
        }
        let status_error = |reason| DumpError::Status {
            path: path_buf(),
            status: self.status.clone(),
            reason,
        };
        let solved = match self.status.as_str() {
            "Solved" | "SolvedByFallback" => true,
            "Failed" => false,
            _ => return Err(status_error("not one of Solved, SolvedByFallback, Failed")),
        };
        if solved {
            if !self
                .m
                .iter()
                .flatten()
                .chain(&self.q)
                .all(|x| x.is_finite())
            {
                return Err(status_error("a solved LCP needs finite M and q"));
            }
            if !self.z.iter().all(|x| x.is_finite() && *x >= 0.0) {
                return Err(status_error("a solved LCP needs a finite z >= 0"));
            }
        }
        Ok(())
    }

    /// Serialises to the JSON text of a dump file (one matrix row per line).
    pub fn to_json(&self) -> Result<String, serde_json::Error> {
        fn vec_json(v: &[f64]) -> Result<String, serde_json::Error> {
            serde_json::to_string(&v.iter().map(|&x| json_f64::Num(x)).collect::<Vec<_>>())
        }
        let mut s = String::from("{\n");
        s.push_str(&format!(
            "  \"t\": {},\n",
            serde_json::to_string(&json_f64::Num(self.t))?
        ));
        s.push_str(&format!("  \"contacts\": {},\n", self.contacts));
        if let Some(g) = self.friction_groups {
            s.push_str(&format!("  \"friction_groups\": {g},\n"));
        }
        s.push_str(&format!("  \"pivots\": {},\n", self.pivots));
        s.push_str(&format!(
            "  \"status\": {},\n",
            serde_json::to_string(&self.status)?
        ));
        s.push_str("  \"M\": [");
        for (i, row) in self.m.iter().enumerate() {
            s.push_str(if i == 0 { "\n    " } else { ",\n    " });
            s.push_str(&vec_json(row)?);
        }
        s.push_str(if self.m.is_empty() {
            "],\n"
        } else {
            "\n  ],\n"
        });
        s.push_str(&format!("  \"q\": {},\n", vec_json(&self.q)?));
        s.push_str(&format!("  \"z\": {},\n", vec_json(&self.z)?));
        s.push_str(&format!("  \"w\": {}\n", vec_json(&self.w)?));
        s.push_str("}\n");
        Ok(s)
    }

    /// Parses the JSON text of a dump (numbers read exactly, see the module
    /// doc) and validates the shapes; `path` only names the source in errors.
    pub fn from_json(text: &str, path: &Path) -> Result<Self, DumpError> {
        let quoted = quote_numbers(text);
        let entries: Entries =
            serde_json::from_str(&quoted).map_err(|source| DumpError::Parse {
                path: path.to_path_buf(),
                source,
            })?;
        const KEYS: [&str; 9] = [
            "M",
            "q",
            "z",
            "w",
            "t",
            "contacts",
            "pivots",
            "status",
            "friction_groups",
        ];
        let mut values: [Option<serde_json::Value>; 9] = Default::default();
        for (key, value) in entries.0 {
            let Some(k) = KEYS.iter().position(|&x| x == key) else {
                return Err(DumpError::UnknownKey {
                    path: path.to_path_buf(),
                    key,
                });
            };
            if values[k].is_some() {
                return Err(DumpError::DuplicateKey {
                    path: path.to_path_buf(),
                    key,
                });
            }
            values[k] = Some(value);
        }
        let groups = values[8].take();
        let mut take = |k: usize| -> Result<serde_json::Value, DumpError> {
            values[k].take().ok_or(DumpError::MissingKey {
                path: path.to_path_buf(),
                key: KEYS[k],
            })
        };
        let err = |k: usize| {
            move |source| DumpError::Value {
                path: path.to_path_buf(),
                key: KEYS[k],
                source,
            }
        };
        let dump = Self {
            m: json_f64::matrix::deserialize(take(0)?).map_err(err(0))?,
            q: json_f64::vector::deserialize(take(1)?).map_err(err(1))?,
            z: json_f64::vector::deserialize(take(2)?).map_err(err(2))?,
            w: json_f64::vector::deserialize(take(3)?).map_err(err(3))?,
            t: json_f64::scalar::deserialize(take(4)?).map_err(err(4))?,
            contacts: json_f64::count::deserialize(take(5)?).map_err(err(5))?,
            friction_groups: match groups {
                Some(v) => Some(json_f64::count::deserialize(v).map_err(err(8))?),
                None => None,
            },
            pivots: json_f64::count::deserialize(take(6)?).map_err(err(6))?,
            status: String::deserialize(take(7)?).map_err(err(7))?,
        };
        dump.validate(path)?;
        Ok(dump)
    }

    /// Writes the dump to `path` atomically (temporary file in the same
    /// directory, `fsync`, rename). Validates the shapes first.
    pub fn write(&self, path: impl AsRef<Path>) -> Result<(), DumpError> {
        let path = path.as_ref();
        self.validate(path)?;
        let io_err = |source| DumpError::Io {
            path: path.to_path_buf(),
            source,
        };
        let text = self
            .to_json()
            .map_err(|e| io_err(std::io::Error::other(e)))?;
        let Some(name) = path.file_name() else {
            return Err(io_err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "path has no file name",
            )));
        };
        let dir = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let tmp = dir.join(format!(
            ".{}.tmp.{}.{}",
            name.to_string_lossy(),
            std::process::id(),
            TMP_COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        let result = (|| -> std::io::Result<()> {
            let mut f = std::fs::File::create(&tmp)?;
            f.write_all(text.as_bytes())?;
            f.sync_all()?;
            drop(f);
            std::fs::rename(&tmp, path)
        })();
        if let Err(e) = result {
            let _ = std::fs::remove_file(&tmp);
            return Err(io_err(e));
        }
        Ok(())
    }

    /// Reads and validates a dump file.
    pub fn read(path: impl AsRef<Path>) -> Result<Self, DumpError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| DumpError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::from_json(&text, path)
    }
}

/// The top-level object of a dump as (key, value) pairs in file order, so
/// that repeated keys can be detected.
struct Entries(Vec<(String, serde_json::Value)>);

impl<'de> Deserialize<'de> for Entries {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = Entries;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a JSON object with the keys M, q, z, w, t, contacts, pivots, status")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut a: A,
            ) -> Result<Entries, A::Error> {
                let mut v = Vec::new();
                while let Some(e) = a.next_entry::<String, serde_json::Value>()? {
                    v.push(e);
                }
                Ok(Entries(v))
            }
        }
        d.deserialize_map(V)
    }
}

/// Rewrites every JSON number token outside string literals (and the bare
/// tokens `NaN`, `Infinity`, `-Infinity`) as a JSON string holding the same
/// text behind the tag [`json_f64::NUMBER_TAG`] (written as the escape
/// `\u0001`), so that the number is parsed by Rust's correctly rounded `f64`
/// parser rather than serde_json's, and can be told from a number written
/// as a string in the file. A string literal of the file that itself starts
/// with the escape `\u0001` gets `\u0002` instead, so that it cannot pass
/// for a number. Other text is copied unchanged. Line numbers of parse
/// errors are preserved.
fn quote_numbers(text: &str) -> String {
    let b = text.as_bytes();
    let mut out = String::with_capacity(text.len() + text.len() / 4);
    let mut i = 0;
    let mut plain_start = 0;
    while i < b.len() {
        let c = b[i];
        if c == b'"' {
            // Skip a string literal, honouring backslash escapes.
            if b.len() >= i + 7 && b[i + 1..i + 7].eq_ignore_ascii_case(b"\\u0001") {
                out.push_str(&text[plain_start..=i]);
                out.push_str("\\u0002");
                plain_start = i + 7;
                i += 6;
            }
            i += 1;
            while i < b.len() {
                match b[i] {
                    b'\\' => i += 2,
                    b'"' => {
                        i += 1;
                        break;
                    }
                    _ => i += 1,
                }
            }
            continue;
        }
        let token_len = if c == b'-' || c.is_ascii_digit() {
            if b[i..].starts_with(b"-Infinity") {
                "-Infinity".len()
            } else {
                b[i..]
                    .iter()
                    .take_while(|&&x| {
                        x.is_ascii_digit() || matches!(x, b'-' | b'+' | b'.' | b'e' | b'E')
                    })
                    .count()
            }
        } else if b[i..].starts_with(b"NaN") {
            3
        } else if b[i..].starts_with(b"Infinity") {
            "Infinity".len()
        } else {
            0
        };
        if token_len == 0 {
            i += 1;
            continue;
        }
        out.push_str(&text[plain_start..i]);
        out.push_str("\"\\u0001");
        out.push_str(&text[i..i + token_len]);
        out.push('"');
        i += token_len;
        plain_start = i;
    }
    out.push_str(&text[plain_start.min(text.len())..]);
    out
}
