//! JSON dumps of LCPs for reproducing a solve.
//!
//! Format: one JSON object with keys
//!
//! * `"M"`: the matrix as a list of n rows, each a list of n numbers;
//! * `"q"`: list of n numbers;
//! * `"z"`, `"w"`: the returned solution (or best candidate) and `M z + q`;
//! * `"t"`: simulation time (number);
//! * `"contacts"`: number of contacts (integer);
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
//! Files are written atomically: to a temporary file in the same directory,
//! flushed to disk, then renamed over the target.

use super::json_f64;
use super::solve::LcpSolution;
use super::{Lcp, LcpError};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// One LCP with its solution and context, as stored in a dump file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
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
    /// Builds a dump from a problem and the driver's solution.
    pub fn from_solution(lcp: &Lcp, sol: &LcpSolution, t: f64, contacts: usize) -> Self {
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
        let dump: Self = serde_json::from_str(&quoted).map_err(|source| DumpError::Parse {
            path: path.to_path_buf(),
            source,
        })?;
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

/// Rewrites every JSON number token outside string literals (and the bare
/// tokens `NaN`, `Infinity`, `-Infinity`) as a JSON string holding the same
/// text, so that the number is parsed by Rust's correctly rounded `f64`
/// parser rather than serde_json's. Other text, including string literals,
/// is copied unchanged. Line numbers of parse errors are preserved.
fn quote_numbers(text: &str) -> String {
    let b = text.as_bytes();
    let mut out = String::with_capacity(text.len() + text.len() / 4);
    let mut i = 0;
    let mut plain_start = 0;
    while i < b.len() {
        let c = b[i];
        if c == b'"' {
            // Skip a string literal, honouring backslash escapes.
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
        out.push('"');
        out.push_str(&text[i..i + token_len]);
        out.push('"');
        i += token_len;
        plain_start = i;
    }
    out.push_str(&text[plain_start.min(text.len())..]);
    out
}
