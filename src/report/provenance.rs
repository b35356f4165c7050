//! Where a report comes from: the floebench version and git commit (read
//! at build time by `build.rs`; `unknown` without git), the machine
//! (host name and CPU model where the system tells them, else `unknown`;
//! the cores) and the date (UTC).

/// The provenance of a report.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct Provenance {
    /// floebench's version (Cargo.toml).
    pub version: String,
    /// The git commit of the sources (`+modified`: they differed from it).
    pub commit: String,
    /// The host name.
    pub host: String,
    /// The CPU model.
    pub cpu: String,
    /// Cores available to the process.
    pub cores: usize,
    /// When, UTC, `YYYY-MM-DD HH:MM:SS UTC`.
    pub date: String,
}

/// The first line of a file, trimmed, if readable and not empty.
fn first_line(path: &str) -> Option<String> {
    let text = std::fs::read_to_string(path).ok()?;
    let line = text.lines().next()?.trim().to_string();
    (!line.is_empty()).then_some(line)
}

/// The CPU model from `/proc/cpuinfo` (Linux), if any.
fn cpu_model() -> Option<String> {
    let text = std::fs::read_to_string("/proc/cpuinfo").ok()?;
    text.lines()
        .filter_map(|l| l.split_once(':'))
        .find(|(k, _)| k.trim() == "model name" || k.trim() == "Hardware")
        .map(|(_, v)| v.trim().to_string())
        .filter(|v| !v.is_empty())
}

/// `YYYY-MM-DD HH:MM:SS UTC` of `secs` seconds after the Unix epoch (the
/// proleptic Gregorian calendar; the one date formatter,
/// [`crate::model::netcdf::cf::format_date`]).
pub fn utc(secs: u64) -> String {
    format!("{} UTC", crate::model::netcdf::cf::format_date(secs as f64))
}

impl Provenance {
    /// The provenance of a report made now, on this machine.
    pub fn current() -> Provenance {
        let unknown = || "unknown".to_string();
        let secs = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        Provenance {
            version: env!("CARGO_PKG_VERSION").to_string(),
            commit: option_env!("FLOEBENCH_COMMIT").map_or_else(unknown, str::to_string),
            host: first_line("/proc/sys/kernel/hostname")
                .or_else(|| first_line("/etc/hostname"))
                .unwrap_or_else(unknown),
            cpu: cpu_model().unwrap_or_else(unknown),
            cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
            date: utc(secs),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::utc;

    #[test]
    fn dates() {
        assert_eq!(utc(0), "1970-01-01 00:00:00 UTC");
        assert_eq!(utc(951_782_400), "2000-02-29 00:00:00 UTC");
        assert_eq!(utc(1_709_251_199), "2024-02-29 23:59:59 UTC");
    }
}
