//! Where a flight log lives, as PX4 names its logs: `YYYY-MM-DD/HH_MM_SS.ulg` below the log
//! directory, the UTC date and time at arming. A name and its time are the same thing here: a
//! log is known by its time [s since 1970-01-01 UTC], and only names in this exact form (zero
//! padded, a real calendar date) are logs. Dates use the proleptic Gregorian calendar. Pure.

/// Seconds in a day.
const DAY_S: u32 = 86_400;

/// The civil date (year, month 1–12, day 1–31) of day `days` after 1970-01-01. The count is
/// shifted to start on 0000-03-01, so that the leap day ends each year; a 400-year era has
/// 146 097 days, and within it the year, the day of the year and the month follow from the
/// 365/1460/36 524-day periods and the 153-day five-month blocks of March–July and
/// August–December.
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let day_of_era = z.rem_euclid(146_097);
    let year_of_era = (day_of_era - day_of_era / 1_460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    let month_from_march = (5 * day_of_year + 2) / 153;
    let day = day_of_year - (153 * month_from_march + 2) / 5 + 1;
    let month = if month_from_march < 10 {
        month_from_march + 3
    } else {
        month_from_march - 9
    };
    let year = year_of_era + era * 400 + i64::from(month <= 2);
    (year, month as u32, day as u32)
}

/// Days from 1970-01-01 to `year`-`month`-`day` (the inverse of [`civil_from_days`]).
fn days_from_civil(year: i64, month: u32, day: u32) -> i64 {
    let year = if month <= 2 { year - 1 } else { year };
    let era = year.div_euclid(400);
    let year_of_era = year - era * 400;
    let month_from_march = i64::from((month + 9) % 12);
    let day_of_year = (153 * month_from_march + 2) / 5 + i64::from(day) - 1;
    let day_of_era = year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year;
    era * 146_097 + day_of_era - 719_468
}

/// The log name of UTC time `utc_s` [s since 1970]: `YYYY-MM-DD/HH_MM_SS.ulg`.
pub fn log_name(utc_s: u32) -> String {
    let (year, month, day) = civil_from_days(i64::from(utc_s / DAY_S));
    let s = utc_s % DAY_S;
    format!(
        "{year:04}-{month:02}-{day:02}/{:02}_{:02}_{:02}.ulg",
        s / 3_600,
        s / 60 % 60,
        s % 60
    )
}

/// What PX4's logger says (an information STATUSTEXT) when the log of `utc_s` [s since 1970]
/// begins: `[logger] ./log/YYYY-MM-DD/HH_MM_SS.ulg`, the path from the directory the vehicle
/// keeps its logs in (PX4 SITL's is its working directory, the instance's `rootfs`).
pub fn logger_announcement(utc_s: u32) -> String {
    format!("[logger] ./log/{}", log_name(utc_s))
}

/// The date directory (`YYYY-MM-DD`) and file name (`HH_MM_SS.ulg`) of the log of `utc_s`.
pub fn log_dir_and_file(utc_s: u32) -> (String, String) {
    let name = log_name(utc_s);
    let (dir, file) = name.split_at(10);
    (dir.to_string(), file[1..].to_string())
}

/// The UTC time [s since 1970] a log name stands for; `None` when `name` is not exactly a log
/// name (another layout, not zero padded, no such date or time, before 1970 or past 2106).
pub fn parse_log_name(name: &str) -> Option<u32> {
    let b = name.as_bytes();
    if b.len() != 23 || !name.ends_with(".ulg") {
        return None;
    }
    let number = |from: usize, to: usize| -> Option<u32> {
        let digits = name.get(from..to)?;
        digits
            .bytes()
            .all(|c| c.is_ascii_digit())
            .then(|| digits.parse().ok())?
    };
    let separators = [(4, b'-'), (7, b'-'), (10, b'/'), (13, b'_'), (16, b'_')];
    if separators.iter().any(|(i, c)| b[*i] != *c) {
        return None;
    }
    let (year, month, day) = (number(0, 4)?, number(5, 7)?, number(8, 10)?);
    let (hour, minute, second) = (number(11, 13)?, number(14, 16)?, number(17, 19)?);
    if !(1..=12).contains(&month) || !(1..=31).contains(&day) || hour > 23 || minute > 59 || second > 59 {
        return None;
    }
    let days = days_from_civil(i64::from(year), month, day);
    let utc_s = days * i64::from(DAY_S) + i64::from(hour * 3_600 + minute * 60 + second);
    let utc_s = u32::try_from(utc_s).ok()?;
    // A day past the month's end (2026-02-30) names another date: not a log name.
    (log_name(utc_s) == name).then_some(utc_s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_carry_the_utc_date_and_time() {
        assert_eq!(log_name(0), "1970-01-01/00_00_00.ulg");
        // 2026-01-01T10:00:00Z and 2024-02-29T23:59:59Z (a leap day).
        assert_eq!(log_name(1_767_261_600), "2026-01-01/10_00_00.ulg");
        assert_eq!(log_name(1_709_251_199), "2024-02-29/23_59_59.ulg");
        assert_eq!(log_name(u32::MAX), "2106-02-07/06_28_15.ulg");
        assert_eq!(
            log_dir_and_file(1_767_261_600),
            ("2026-01-01".to_string(), "10_00_00.ulg".to_string())
        );
    }

    #[test]
    fn the_logger_announces_px4s_path_within_one_statustext() {
        let text = logger_announcement(1_767_261_600);
        assert_eq!(text, "[logger] ./log/2026-01-01/10_00_00.ulg");
        assert!(text.len() <= 50, "STATUSTEXT holds 50 bytes");
    }

    #[test]
    fn parsing_inverts_naming_over_centuries() {
        for utc_s in (0..u32::MAX - 86_399).step_by(7_777_777).chain([u32::MAX, 951_782_400]) {
            assert_eq!(parse_log_name(&log_name(utc_s)), Some(utc_s), "{}", log_name(utc_s));
        }
        assert_eq!(parse_log_name("2000-02-29/00_00_00.ulg"), Some(951_782_400));
    }

    #[test]
    fn only_exact_log_names_are_logs() {
        for bad in [
            "2026-02-30/10_00_00.ulg",
            "2025-02-29/10_00_00.ulg",
            "2026-13-01/10_00_00.ulg",
            "2026-01-01/24_00_00.ulg",
            "2026-01-01/10_60_00.ulg",
            "2026-1-01/10_00_00.ulg",
            "2026-01-01/10_00_00.ulog",
            "2026-01-01/10-00-00.ulg",
            "2026-01-01/+0_00_00.ulg",
            "1969-12-31/23_59_59.ulg",
            "2106-02-07/06_28_16.ulg",
            "2026-01-01_10_00_00.ulg",
            "sess001/log001.ulg",
            "",
        ] {
            assert_eq!(parse_log_name(bad), None, "{bad}");
        }
    }
}
