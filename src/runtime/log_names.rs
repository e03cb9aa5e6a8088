//! Where a flight's ULog file goes: `DIR/log/YYYY-MM-DD/HH_MM_SS.ulg` in UTC at arming, PX4's
//! naming (a second file within the same second gets `_1`, `_2`, … before the extension).

use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

/// Seconds since the Unix epoch at `t`, when after it.
pub fn unix_s(t: SystemTime) -> Option<u64> {
    t.duration_since(UNIX_EPOCH).ok().map(|d| d.as_secs())
}

/// The civil date (year, month, day) of day `days` since 1970-01-01 (proleptic Gregorian).
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let month = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let year = yoe + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

/// `("YYYY-MM-DD", "HH_MM_SS")` of `secs` since the Unix epoch, UTC.
pub fn utc_names(secs: u64) -> (String, String) {
    let (days, rest) = ((secs / 86_400) as i64, secs % 86_400);
    let (y, m, d) = civil_from_days(days);
    let (hh, mm, ss) = (rest / 3600, rest / 60 % 60, rest % 60);
    (format!("{y:04}-{m:02}-{d:02}"), format!("{hh:02}_{mm:02}_{ss:02}"))
}

/// The file of a flight armed at `now` in `dir/log/`, never `previous` (the file before).
pub fn flight_log_path(dir: &Path, now: SystemTime, previous: Option<&Path>) -> PathBuf {
    let (date, time) = utc_names(unix_s(now).unwrap_or(0));
    let folder = dir.join("log").join(date);
    let mut path = folder.join(format!("{time}.ulg"));
    let mut n = 0;
    while Some(path.as_path()) == previous || path.exists() {
        n += 1;
        path = folder.join(format!("{time}_{n}.ulg"));
    }
    path
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utc_names_follow_the_calendar() {
        assert_eq!(utc_names(0), ("1970-01-01".into(), "00_00_00".into()));
        // 2024-02-29 23:59:59 UTC (a leap day).
        assert_eq!(utc_names(1_709_251_199), ("2024-02-29".into(), "23_59_59".into()));
        assert_eq!(utc_names(1_798_761_600), ("2027-01-01".into(), "00_00_00".into()));
    }

    #[test]
    fn a_second_flight_in_the_same_second_gets_a_suffix() {
        let dir = Path::new("/nonexistent-rotorpilot");
        let t = UNIX_EPOCH + std::time::Duration::from_secs(3661);
        let first = flight_log_path(dir, t, None);
        assert_eq!(first, dir.join("log/1970-01-01/01_01_01.ulg"));
        assert_eq!(
            flight_log_path(dir, t, Some(&first)),
            dir.join("log/1970-01-01/01_01_01_1.ulg")
        );
    }
}
