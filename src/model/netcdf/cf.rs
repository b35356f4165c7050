//! The pieces of the CF conventions the reader needs: dates and time
//! units (`"hours since 2020-01-01 00:00:00"`), velocity and coordinate
//! units.

/// Days from 1970-01-01 to the proleptic Gregorian date `y-m-d`
/// (H. Hinnant, *chrono-compatible low-level date algorithms*).
fn days_from_civil(y: i64, m: i64, d: i64) -> i64 {
    let y = if m <= 2 { y - 1 } else { y };
    let era = if y >= 0 { y } else { y - 399 } / 400;
    let yoe = y - era * 400;
    let mp = (m + 9) % 12;
    let doy = (153 * mp + 2) / 5 + d - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146097 + doe - 719468
}

/// Seconds from 1970-01-01 00:00:00 UTC to a date written
/// `YYYY-MM-DD`, optionally followed by `T` or a space and
/// `hh:mm[:ss[.fff]]`, and optionally `Z` or ` UTC` (proleptic Gregorian).
pub fn parse_date(s: &str) -> Result<f64, String> {
    let bad = || format!("`{s}` is not a date `YYYY-MM-DD[ hh:mm:ss]` (UTC)");
    let t = s.trim();
    let t = t
        .strip_suffix('Z')
        .or_else(|| t.strip_suffix("UTC"))
        .unwrap_or(t)
        .trim();
    let (date, time) = match t.split_once(['T', ' ']) {
        Some((d, tm)) => (d, tm.trim()),
        None => (t, ""),
    };
    let mut parts = date.splitn(3, '-');
    let num = |p: Option<&str>| p.and_then(|v| v.trim().parse::<i64>().ok());
    let (y, m, d) = match (num(parts.next()), num(parts.next()), num(parts.next())) {
        (Some(y), Some(m), Some(d)) if (1..=12).contains(&m) && (1..=31).contains(&d) => (y, m, d),
        _ => return Err(bad()),
    };
    let mut secs = 0.0;
    if !time.is_empty() {
        let f: Vec<&str> = time.split(':').collect();
        if f.len() < 2 || f.len() > 3 {
            return Err(bad());
        }
        let h: f64 = f[0].parse().map_err(|_| bad())?;
        let mi: f64 = f[1].parse().map_err(|_| bad())?;
        let se: f64 = f.get(2).map_or(Ok(0.0), |v| v.parse()).map_err(|_| bad())?;
        if !(0.0..24.0).contains(&h) || !(0.0..60.0).contains(&mi) || !(0.0..61.0).contains(&se) {
            return Err(bad());
        }
        secs = h * 3600.0 + mi * 60.0 + se;
    }
    Ok(days_from_civil(y, m, d) as f64 * 86400.0 + secs)
}

/// The date `YYYY-MM-DD hh:mm:ss` (UTC, proleptic Gregorian) of `secs`
/// seconds from 1970-01-01 00:00:00, to the second.
pub fn format_date(secs: f64) -> String {
    let total = secs.round() as i64;
    let days = total.div_euclid(86400);
    let s = total.rem_euclid(86400);
    // Hinnant's civil_from_days.
    let z = days + 719468;
    let era = if z >= 0 { z } else { z - 146096 } / 146097;
    let doe = z - era * 146097;
    let yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02} {:02}:{:02}:{:02}",
        s / 3600,
        (s % 3600) / 60,
        s % 60
    )
}

/// A CF time unit `"<unit> since <date>"`: (seconds per unit, seconds of
/// the reference date from 1970-01-01).
pub fn parse_time_units(units: &str) -> Result<(f64, f64), String> {
    let Some((unit, date)) = units.split_once(" since ") else {
        return Err(format!(
            "time units `{units}` are not CF (`<seconds|minutes|hours|days> since <date>`)"
        ));
    };
    let scale = match unit.trim().to_ascii_lowercase().as_str() {
        "seconds" | "second" | "secs" | "sec" | "s" => 1.0,
        "minutes" | "minute" | "mins" | "min" => 60.0,
        "hours" | "hour" | "hrs" | "hr" | "h" => 3600.0,
        "days" | "day" | "d" => 86400.0,
        other => {
            return Err(format!(
                "time units `{units}`: unknown unit `{other}` (seconds, minutes, hours or days)"
            ))
        }
    };
    Ok((scale, parse_date(date)?))
}

/// Whether `units` says metres per second, in any of CF's spellings.
pub fn is_metres_per_second(units: &str) -> bool {
    let u: String = units
        .to_ascii_lowercase()
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect();
    matches!(
        u.as_str(),
        "ms-1"
            | "ms**-1"
            | "ms^-1"
            | "m/s"
            | "m.s-1"
            | "m.s**-1"
            | "meter/second"
            | "metre/second"
            | "meters/second"
            | "metres/second"
            | "meterssecond-1"
            | "metressecond-1"
            | "meterspersecond"
            | "metrespersecond"
    )
}

/// What a coordinate's `units` make of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Axis {
    /// Projected, metres per unit.
    Metres(f64),
    /// Longitude, degrees east.
    Longitude,
    /// Latitude, degrees north.
    Latitude,
}

/// The kind of a horizontal coordinate from its CF `units`.
pub fn coordinate_axis(units: &str) -> Option<Axis> {
    let u = units.trim().to_ascii_lowercase();
    match u.as_str() {
        "m" | "meter" | "meters" | "metre" | "metres" => Some(Axis::Metres(1.0)),
        "km" | "kilometer" | "kilometers" | "kilometre" | "kilometres" => Some(Axis::Metres(1e3)),
        "degrees_east" | "degree_east" | "degree_e" | "degrees_e" | "degreee" | "degreese" => {
            Some(Axis::Longitude)
        }
        "degrees_north" | "degree_north" | "degree_n" | "degrees_n" | "degreen" | "degreesn" => {
            Some(Axis::Latitude)
        }
        _ => None,
    }
}

/// Whether a CF `calendar` attribute is the Gregorian one this reader uses.
pub fn gregorian(calendar: &str) -> bool {
    matches!(
        calendar.trim().to_ascii_lowercase().as_str(),
        "standard" | "gregorian" | "proleptic_gregorian"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_count_days_and_seconds_from_1970() {
        assert_eq!(parse_date("1970-01-01").unwrap(), 0.0);
        assert_eq!(parse_date("1970-01-02 00:00:01").unwrap(), 86401.0);
        // 2000 is a leap year: 10957 days from 1970 to 2000-01-01, +60 to March 1.
        assert_eq!(
            parse_date("2000-03-01T00:00:00Z").unwrap(),
            11017.0 * 86400.0
        );
        assert_eq!(parse_date("1900-01-01").unwrap(), -25567.0 * 86400.0);
        assert!(parse_date("2000-13-01").is_err());
        let (s, r) = parse_time_units("hours since 1900-01-01 00:00:00.0").unwrap();
        assert_eq!((s, r), (3600.0, -25567.0 * 86400.0));
        assert!(parse_time_units("hours after 1900-01-01").is_err());
        for d in [
            "1970-01-01 00:00:00",
            "2000-02-29 12:34:56",
            "1899-12-31 23:59:59",
        ] {
            assert_eq!(format_date(parse_date(d).unwrap()), d);
        }
    }

    #[test]
    fn units_are_recognised_in_their_cf_spellings() {
        assert!(is_metres_per_second("m s-1") && is_metres_per_second("m s**-1"));
        assert!(!is_metres_per_second("cm s-1") && !is_metres_per_second("knots"));
        assert_eq!(coordinate_axis("km"), Some(Axis::Metres(1e3)));
        assert_eq!(coordinate_axis("degrees_north"), Some(Axis::Latitude));
        assert_eq!(coordinate_axis("K"), None);
    }
}
