//! When `rotorpilot run` writes a ULog flight log: PX4's `SDLOG_MODE` ([`LogMode`]) and, tick by
//! tick, whether a log should be open ([`LogSchedule`]), as PX4's logger module decides it
//! (`src/modules/logger/logger.cpp`: a log from boot is started before the first arming, a
//! transition of the arming state starts or stops one). Pure.

use thiserror::Error;

/// `SDLOG_MODE`: when the logger writes a ULog file (PX4's codes; −1, which older PX4 had for
/// "disabled", writes none). PX4's 3 (while the RC channel AUX1 is above 30 %) is refused: this
/// vehicle has no RC channels, so it could never log.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum LogMode {
    /// No flight logs.
    Disabled = -1,
    /// From arming until disarming, one file per flight (PX4's firmware default).
    #[default]
    WhileArmed = 0,
    /// From boot until the first disarming, then from each arming until its disarming (PX4
    /// SITL's `rcS` sets this).
    BootUntilDisarm = 1,
    /// From boot until the process stops: one file.
    BootUntilShutdown = 2,
    /// From the first arming until the process stops: one file.
    ArmUntilShutdown = 4,
}

/// A code that is no `SDLOG_MODE`.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum UnknownLogMode {
    /// PX4's 3: logging while AUX1 is above 30 %.
    #[error(
        "3 (log while RC AUX1 > 30 %) needs an RC AUX1 channel, which this vehicle has not (choose {choices})",
        choices = LogMode::choices()
    )]
    Aux1,
    /// Any other code.
    #[error("{0} is not a SDLOG_MODE (choose {choices})", choices = LogMode::choices())]
    Other(i32),
}

impl LogMode {
    /// The parameter.
    pub const PARAM: &'static str = "SDLOG_MODE";
    /// Every mode, by code.
    pub const ALL: &'static [Self] = &[
        Self::Disabled,
        Self::WhileArmed,
        Self::BootUntilDisarm,
        Self::BootUntilShutdown,
        Self::ArmUntilShutdown,
    ];

    /// The mode in a few words.
    pub fn label(self) -> &'static str {
        match self {
            Self::Disabled => "disabled",
            Self::WhileArmed => "when armed until disarm",
            Self::BootUntilDisarm => "from boot until disarm",
            Self::BootUntilShutdown => "from boot until shutdown",
            Self::ArmUntilShutdown => "from 1st armed until shutdown",
        }
    }

    /// Every code with its meaning, by code.
    pub fn codes() -> Vec<(i32, &'static str)> {
        Self::ALL.iter().map(|m| (i32::from(*m), m.label())).collect()
    }

    /// Every code with its meaning: `-1 disabled, 0 when armed until disarm, ...`.
    pub fn choices() -> String {
        let all: Vec<String> = Self::codes().iter().map(|(c, l)| format!("{c} {l}")).collect();
        all.join(", ")
    }
}

impl TryFrom<i32> for LogMode {
    type Error = UnknownLogMode;

    fn try_from(code: i32) -> Result<Self, UnknownLogMode> {
        match code {
            3 => Err(UnknownLogMode::Aux1),
            _ => Self::ALL
                .iter()
                .copied()
                .find(|m| i32::from(*m) == code)
                .ok_or(UnknownLogMode::Other(code)),
        }
    }
}

impl From<LogMode> for i32 {
    fn from(mode: LogMode) -> i32 {
        mode as i32
    }
}

impl From<LogMode> for f64 {
    fn from(mode: LogMode) -> f64 {
        f64::from(mode as i32)
    }
}

/// Whether a flight log should be open, from the mode read at boot and the arming state of each
/// tick. A log that should be open and is not (its file could not be opened) is asked for again
/// at the next tick.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LogSchedule {
    mode: LogMode,
    /// Armed at least once since boot.
    armed_once: bool,
    /// Disarmed at least once after an arming.
    disarmed_once: bool,
    /// Armed at the last tick.
    was_armed: bool,
}

impl LogSchedule {
    /// The schedule of `mode`, at boot.
    pub fn new(mode: LogMode) -> Self {
        Self {
            mode,
            armed_once: false,
            disarmed_once: false,
            was_armed: false,
        }
    }

    /// The mode.
    pub fn mode(&self) -> LogMode {
        self.mode
    }

    /// True when a log should be open at a tick whose vehicle is `armed`.
    pub fn wants_log(&mut self, armed: bool) -> bool {
        self.armed_once |= armed;
        self.disarmed_once |= self.was_armed && !armed;
        self.was_armed = armed;
        match self.mode {
            LogMode::Disabled => false,
            LogMode::WhileArmed => armed,
            LogMode::BootUntilDisarm => armed || !self.disarmed_once,
            LogMode::BootUntilShutdown => true,
            LogMode::ArmUntilShutdown => self.armed_once,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The logs `mode` writes over `armed` (one entry per tick): (first tick, last tick) of each.
    fn logs(mode: LogMode, armed: &[bool]) -> Vec<(usize, usize)> {
        let mut schedule = LogSchedule::new(mode);
        let mut out: Vec<(usize, usize)> = Vec::new();
        let mut open = false;
        for (k, a) in armed.iter().enumerate() {
            let want = schedule.wants_log(*a);
            match (open, want) {
                (false, true) => out.push((k, k)),
                (true, true) => {
                    if let Some(last) = out.last_mut() {
                        last.1 = k;
                    }
                }
                _ => {}
            }
            open = want;
        }
        out
    }

    /// Disarmed, armed (two ticks), disarmed, armed, disarmed (two ticks).
    const FLIGHTS: [bool; 8] = [false, true, true, false, true, false, false, false];

    #[test]
    fn while_armed_logs_each_flight_in_its_own_file() {
        assert_eq!(logs(LogMode::WhileArmed, &FLIGHTS), vec![(1, 2), (4, 4)]);
        assert!(logs(LogMode::WhileArmed, &[false; 5]).is_empty(), "no flight, no log");
    }

    #[test]
    fn boot_until_disarm_starts_at_boot_and_then_logs_each_flight() {
        // The boot log runs through the first flight; the second flight has its own file.
        assert_eq!(logs(LogMode::BootUntilDisarm, &FLIGHTS), vec![(0, 2), (4, 4)]);
        assert_eq!(logs(LogMode::BootUntilDisarm, &[false; 5]), vec![(0, 4)]);
    }

    #[test]
    fn shutdown_modes_keep_one_file_and_disabled_writes_none() {
        assert_eq!(logs(LogMode::BootUntilShutdown, &FLIGHTS), vec![(0, 7)]);
        assert_eq!(logs(LogMode::ArmUntilShutdown, &FLIGHTS), vec![(1, 7)]);
        assert!(logs(LogMode::ArmUntilShutdown, &[false; 5]).is_empty());
        assert!(logs(LogMode::Disabled, &FLIGHTS).is_empty());
    }

    #[test]
    fn codes_are_px4s_and_aux1_is_refused_with_the_reason() {
        for mode in LogMode::ALL {
            assert_eq!(LogMode::try_from(i32::from(*mode)), Ok(*mode));
        }
        assert_eq!(LogMode::default(), LogMode::WhileArmed);
        let aux = LogMode::try_from(3).unwrap_err().to_string();
        assert!(aux.contains("AUX1") && aux.contains("-1 disabled"), "{aux}");
        assert!(LogMode::try_from(5)
            .unwrap_err()
            .to_string()
            .contains("5 is not a SDLOG_MODE"));
    }
}
