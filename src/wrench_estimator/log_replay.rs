//! Offline run of the wrench estimator over a flight log (homework exercise 4;
//! docs/estimator.md §7; `rotorpilot estimate`). Pure: the log arrives as text, the estimates
//! leave as values.
//!
//! The log is CSV with a header row and the columns [`REQUIRED_COLUMNS`] in any order (extra
//! columns are ignored): time [s], commanded thrust [N, positive], commanded body torques FRD
//! [N·m], world NED velocity [m/s], ZYX Euler angles [rad] and their rates [rad/s]. Each row
//! feeds one [`WrenchObserver::update`] (docs/estimator.md §4).

use thiserror::Error;

use super::{WrenchEstimate, WrenchObserver};
use crate::math::Vec3;

/// Columns a log must have.
pub const REQUIRED_COLUMNS: [&str; 14] = [
    "t",
    "thrust",
    "tau_x",
    "tau_y",
    "tau_z",
    "vx",
    "vy",
    "vz",
    "phi",
    "theta",
    "psi",
    "phi_dot",
    "theta_dot",
    "psi_dot",
];

/// Relative tolerance on the sample time between rows [-].
const SAMPLE_TIME_TOLERANCE: f64 = 0.01;

/// A log that cannot be used: the file, the line (1-based, the header is line 1), the column and why.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{origin}: {}: {reason}", self.place())]
pub struct LogError {
    /// File the log came from.
    pub origin: String,
    /// Line number, 1-based (0 for a ULog file, which has none).
    pub line: usize,
    /// Column name, when one is at fault.
    pub column: Option<String>,
    /// What is wrong.
    pub reason: String,
}

impl LogError {
    /// Where in the file: `line L, column C`, `line L` or, for a ULog file, the topic field.
    fn place(&self) -> String {
        match (self.line, &self.column) {
            (0, Some(c)) => c.clone(),
            (0, None) => "data".into(),
            (l, Some(c)) => format!("line {l}, column {c}"),
            (l, None) => format!("line {l}"),
        }
    }
}

/// One row of the log.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LogSample {
    /// Time [s].
    pub t_s: f64,
    /// Commanded collective thrust [N].
    pub thrust_n: f64,
    /// Commanded body torque, FRD [N·m].
    pub torque_b: Vec3,
    /// Velocity, world NED [m/s].
    pub vel_w: Vec3,
    /// Roll, pitch, yaw [rad].
    pub eta: Vec3,
    /// Euler-angle rates [rad/s].
    pub eta_dot: Vec3,
}

/// Estimate after one row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReplayRow {
    /// Time of the row [s].
    pub t_s: f64,
    /// Estimate (force world NED, torque body FRD, mass).
    pub estimate: WrenchEstimate,
}

/// Columns of a `run.csv` (`rotorpilot sim --csv`): applied thrust and torques (empty while the
/// motors are off: no wrench), world velocity, ZYX Euler angles and body rates.
pub const RUN_CSV_COLUMNS: [&str; 14] = [
    "t", "thrust", "tau_x", "tau_y", "tau_z", "vx", "vy", "vz", "roll", "pitch", "yaw", "p", "q", "r",
];

/// Below this |cos θ| Euler-angle rates are not defined (θ near ±90°).
const COS_THETA_MIN: f64 = 1e-3;

/// η̇ = Q(η)⁻¹ ω_b (docs/model.md §3, eq. (3.4)); `None` near θ = ±90°.
pub fn euler_rates(eta: &Vec3, omega_b: &Vec3) -> Option<Vec3> {
    crate::rpy::q_inverse(eta, COS_THETA_MIN).map(|q_inv| q_inv * omega_b)
}

/// Why `sample` cannot follow `prev` (the time step must be `ts_s` [s]) or is not a sample.
pub fn check_sample(prev: Option<&LogSample>, sample: &LogSample, ts_s: f64) -> Result<(), (&'static str, String)> {
    if let Some(prev) = prev.map(|s| s.t_s) {
        let step = sample.t_s - prev;
        if step <= 0.0 {
            return Err((
                "t",
                format!("time {} s does not increase (previous sample {prev} s)", sample.t_s),
            ));
        }
        if (step - ts_s).abs() > SAMPLE_TIME_TOLERANCE * ts_s {
            return Err(("t", format!("sample time {step} s differs from the expected {ts_s} s")));
        }
    }
    if sample.thrust_n < 0.0 {
        return Err(("thrust", format!("thrust {} N must not be negative", sample.thrust_n)));
    }
    Ok(())
}

/// Parses `text` (from `origin`), checking every value and that t advances by `ts_s` [s]. The
/// columns are either [`REQUIRED_COLUMNS`] (the homework's log) or [`RUN_CSV_COLUMNS`] (a
/// `run.csv`, whose Euler rates are computed from the body rates).
pub fn parse_log(text: &str, origin: &str, ts_s: f64) -> Result<Vec<LogSample>, LogError> {
    let err = |line: usize, column: Option<&str>, reason: String| LogError {
        origin: origin.to_string(),
        line,
        column: column.map(str::to_string),
        reason,
    };
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty());
    let Some((h, header)) = lines.next() else {
        return Err(err(1, None, "empty file: expected a header row".into()));
    };
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let has = |cols: &[&str]| cols.iter().all(|c| names.contains(c));
    let run_csv = !has(&REQUIRED_COLUMNS) && has(&RUN_CSV_COLUMNS);
    let wanted = if run_csv { RUN_CSV_COLUMNS } else { REQUIRED_COLUMNS };
    let mut index = [0usize; REQUIRED_COLUMNS.len()];
    for (slot, name) in index.iter_mut().zip(wanted) {
        *slot = names.iter().position(|n| *n == name).ok_or_else(|| {
            err(
                h + 1,
                Some(name),
                format!(
                    "missing column (header has: {}; a run.csv needs {})",
                    names.join(","),
                    RUN_CSV_COLUMNS.join(",")
                ),
            )
        })?;
    }
    let mut samples: Vec<LogSample> = Vec::new();
    for (i, line) in lines {
        let line_no = i + 1;
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != names.len() {
            return Err(err(
                line_no,
                None,
                format!("{} fields, the header has {}", fields.len(), names.len()),
            ));
        }
        let mut v = [0.0; REQUIRED_COLUMNS.len()];
        for (k, ((value, &col), name)) in v.iter_mut().zip(&index).zip(wanted).enumerate() {
            let text = fields[col];
            *value = match text.parse::<f64>() {
                Ok(x) if x.is_finite() => x,
                // A run.csv leaves the wrench empty while the motors are off.
                _ if run_csv && (1..=4).contains(&k) && text.is_empty() => 0.0,
                Ok(_) => return Err(err(line_no, Some(name), format!("{text:?} is not a finite number"))),
                Err(_) => return Err(err(line_no, Some(name), format!("{text:?} is not a number"))),
            };
        }
        let eta = Vec3::new(v[8], v[9], v[10]);
        let rates = Vec3::new(v[11], v[12], v[13]);
        let eta_dot = if run_csv {
            euler_rates(&eta, &rates).ok_or_else(|| {
                err(
                    line_no,
                    Some("pitch"),
                    format!("pitch {} rad: Euler rates undefined", eta.y),
                )
            })?
        } else {
            rates
        };
        let sample = LogSample {
            t_s: v[0],
            thrust_n: v[1],
            torque_b: Vec3::new(v[2], v[3], v[4]),
            vel_w: Vec3::new(v[5], v[6], v[7]),
            eta,
            eta_dot,
        };
        check_sample(samples.last(), &sample, ts_s).map_err(|(col, why)| err(line_no, Some(col), why))?;
        samples.push(sample);
    }
    if samples.is_empty() {
        return Err(err(h + 1, None, "no data rows after the header".into()));
    }
    Ok(samples)
}

/// Runs `observer` over `samples`, one update per row.
pub fn replay(samples: &[LogSample], mut observer: WrenchObserver) -> Vec<ReplayRow> {
    samples
        .iter()
        .map(|s| ReplayRow {
            t_s: s.t_s,
            estimate: observer.update(&super::ObserverInput {
                vel_w: s.vel_w,
                eta: s.eta,
                eta_dot: s.eta_dot,
                thrust_n: s.thrust_n,
                torque_b: s.torque_b,
            }),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::GRAVITY_M_S2;
    use crate::wrench_estimator::ChebyshevDesign;

    const HEADER: &str = "t,thrust,tau_x,tau_y,tau_z,vx,vy,vz,phi,theta,psi,phi_dot,theta_dot,psi_dot";

    /// A 1.7 kg vehicle held still by a thrust equal to its weight while a 0.2 N·m yaw torque
    /// spins it up; the estimator believes 1.5 kg.
    fn hover_log(seconds: f64) -> String {
        let mut text = String::from(HEADER);
        let n = (seconds / 1e-3) as usize;
        for k in 0..n {
            let t = k as f64 * 1e-3;
            let yaw_rate = 0.2 / 2.4832 * t;
            text.push_str(&format!(
                "\n{t},{},0,0,0,0,0,0,0,0,0,0,0,{yaw_rate}",
                1.7 * GRAVITY_M_S2
            ));
        }
        text
    }

    fn observer() -> WrenchObserver {
        let gains = ChebyshevDesign {
            order: 1,
            ripple_db: 3.0,
            passband_rad_s: 2.0,
        }
        .gains(1e-3)
        .unwrap();
        WrenchObserver::new(1.5, Vec3::new(1.2416, 1.2416, 2.4832), gains, 1e-3).unwrap()
    }

    #[test]
    fn hover_log_gives_the_unmodelled_weight_and_the_yaw_torque() {
        let samples = parse_log(&hover_log(20.0), "log.csv", 1e-3).unwrap();
        assert_eq!(samples.len(), 20_000);
        let last = replay(&samples, observer()).last().copied().unwrap().estimate;
        // Held still: f̂ → −β_lin = u_T e3 − m_e g e3 = (1.7 − 1.5) g upward thrust unexplained.
        assert!((last.force_w.z - 0.2 * GRAVITY_M_S2).abs() < 1e-6, "{}", last.force_w);
        assert!((last.mass_kg - 1.7).abs() < 1e-6);
        assert!((last.torque_b.z - 0.2).abs() < 1e-6, "{}", last.torque_b);
    }

    #[test]
    fn columns_may_come_in_any_order_with_extras() {
        let text = "psi_dot,extra,t,thrust,tau_x,tau_y,tau_z,vx,vy,vz,phi,theta,psi,phi_dot,theta_dot\n\
                    0.5,9,0,14.7,0,0,0,1,2,3,0,0,0,0,0\n0.5,9,0.001,14.7,0,0,0,1,2,3,0,0,0,0,0";
        let s = parse_log(text, "x.csv", 1e-3).unwrap();
        assert_eq!(s[1].eta_dot.z, 0.5);
        assert_eq!(s[1].vel_w, Vec3::new(1.0, 2.0, 3.0));
    }

    #[test]
    fn bad_logs_name_line_and_column() {
        let good = hover_log(0.005);
        let cases = [
            (
                good.replace(",psi_dot", ""),
                "log.csv: line 1, column psi_dot: missing column",
            ),
            (
                good.replacen(",0,0,0,0,0,0,0,0,0,0,0,0", ",0,0,0,0,0,NaN,0,0,0,0,0,0", 1),
                "line 2, column vz: \"NaN\" is not a finite number",
            ),
            (
                good.replace("\n0.003,", "\nx,"),
                "line 5, column t: \"x\" is not a number",
            ),
            (
                good.replace("\n0.003,", "\n0.001,"),
                "line 5, column t: time 0.001 s does not increase",
            ),
            (good.replace("\n0.003,", "\n0.0035,"), "line 5, column t: sample time"),
            (format!("{good}\n1,2"), "line 7: 2 fields, the header has 14"),
            (HEADER.to_string(), "line 1: no data rows"),
            (String::new(), "line 1: empty file"),
        ];
        for (text, expected) in cases {
            let e = parse_log(&text, "log.csv", 1e-3).unwrap_err().to_string();
            assert!(e.contains(expected), "expected {expected:?} in {e:?}");
        }
    }
}
