//! Where `rotorpilot run` keeps each vehicle's logs, and the log set-up of one vehicle: its log
//! directory (served to log downloads), the writer thread of its files, the flight logs of the
//! vehicle (as `SDLOG_MODE` says) and the logger's announcement of each new one.
//!
//! - `--log DIR` ([`LogPlace::Chosen`]): the flight logs and `DIR/flight.tlog`, in `DIR` or, with
//!   several vehicles, `DIR/vehicle-SYSID`; created at start, so a bad directory stops the start.
//! - Without `--log` ([`LogPlace::Default`]): the flight logs only (PX4 SITL writes ULog files,
//!   not tlogs: a ground station keeps those), in the per-user state directory
//!   ([`default_log_root`]) under `instance-K`, K the vehicle's PX4 instance (`--port-base` + its
//!   index), so the processes that share a machine keep apart, as PX4 SITL's instances keep
//!   `rootfs/K`; created when the first log begins, so a run that never logs leaves nothing.
//!
//! Runtime layer: files, threads.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};

use super::config::RuntimeError;
use super::flight_log::{self, Announce, LogSender, LogWriter};
use super::log_store::LogDir;
use super::vehicle::Vehicle;
use crate::ulog::{LogMode, Profile};

/// Where `run` keeps the logs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LogPlace {
    /// `--log DIR`: flight logs and tlog in DIR (per vehicle `DIR/vehicle-SYSID` when several).
    Chosen(PathBuf),
    /// The per-user default: flight logs in `root/instance-K`, K = `first_instance` + the
    /// vehicle's index.
    Default {
        /// The per-user directory ([`default_log_root`]).
        root: PathBuf,
        /// PX4 instance of the first vehicle (`--port-base`).
        first_instance: usize,
    },
}

/// The per-user log directory: `$XDG_STATE_HOME/rotorpilot` when that is an absolute path (the
/// XDG Base Directory specification ignores a relative one), else `$HOME/.local/state/rotorpilot`;
/// `None` without either.
pub fn default_log_root(xdg_state_home: Option<&OsStr>, home: Option<&OsStr>) -> Option<PathBuf> {
    let xdg = xdg_state_home.map(Path::new).filter(|p| p.is_absolute());
    let state = match xdg {
        Some(dir) => dir.to_path_buf(),
        None => Path::new(home.filter(|h| !h.is_empty())?).join(".local/state"),
    };
    Some(state.join("rotorpilot"))
}

impl LogPlace {
    /// The directory of vehicle `index` (system id `sysid`) of `count`.
    pub fn vehicle_dir(&self, index: usize, sysid: u8, count: usize) -> PathBuf {
        match self {
            Self::Chosen(dir) if count > 1 => dir.join(format!("vehicle-{sysid}")),
            Self::Chosen(dir) => dir.clone(),
            Self::Default { root, first_instance } => root.join(format!("instance-{}", first_instance + index)),
        }
    }

    /// True when the tlog is written (`--log` only).
    pub fn tlog(&self) -> bool {
        matches!(self, Self::Chosen(_))
    }
}

/// The logs of one vehicle.
pub(super) struct VehicleLog {
    /// Its log directory.
    pub dir: PathBuf,
    /// Its flight logs, served to log downloads.
    pub store: LogDir,
    /// The writer thread, when anything is written; its sender for the tlog too when there is one.
    pub writer: Option<(LogSender, LogWriter)>,
    /// The tlog is written.
    pub tlog: bool,
}

/// Sets up the logs of vehicle `index` (system id `sysid`) of `count` at `place`: its flight
/// logs with `profile` as the vehicle's `SDLOG_MODE` says (none at −1; the directory is served
/// all the same, as PX4 lists its SD card whatever the mode), each announced through `announce`.
pub(super) fn open(
    place: &LogPlace,
    (index, sysid, count): (usize, u8, usize),
    vehicle: &mut Vehicle,
    profile: Profile,
    announce: Announce,
) -> Result<VehicleLog, RuntimeError> {
    let dir = place.vehicle_dir(index, sysid, count);
    let log_error = |source| RuntimeError::Log {
        dir: dir.display().to_string(),
        source,
    };
    let store = match place {
        LogPlace::Chosen(_) => LogDir::open(&dir.join("log")).map_err(log_error)?,
        LogPlace::Default { .. } => LogDir::at(&dir.join("log")),
    };
    let tlog = place.tlog();
    let flights = vehicle.params().current().log_mode != LogMode::Disabled;
    let writer = if tlog || flights {
        let tlog_path = tlog.then(|| dir.join("flight.tlog"));
        let (sender, writer) = flight_log::start(tlog_path, Some(store.clone()), Some(announce)).map_err(log_error)?;
        if flights {
            vehicle.set_log(sender.clone(), profile);
        }
        Some((sender, writer))
    } else {
        None
    };
    Ok(VehicleLog {
        dir,
        store,
        writer,
        tlog,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_root_follows_xdg_then_home() {
        let os = |s: &'static str| Some(OsStr::new(s));
        assert_eq!(
            default_log_root(os("/state"), os("/home/me")),
            Some(PathBuf::from("/state/rotorpilot"))
        );
        let home = Some(PathBuf::from("/home/me/.local/state/rotorpilot"));
        assert_eq!(default_log_root(None, os("/home/me")), home);
        assert_eq!(default_log_root(os(""), os("/home/me")), home, "empty: unset");
        assert_eq!(default_log_root(os("state"), os("/home/me")), home, "relative: ignored");
        assert_eq!(default_log_root(None, None), None);
        assert_eq!(default_log_root(None, os("")), None);
    }

    #[test]
    fn vehicles_get_their_own_directories() {
        let chosen = LogPlace::Chosen(PathBuf::from("/logs"));
        assert_eq!(chosen.vehicle_dir(0, 1, 1), PathBuf::from("/logs"));
        assert_eq!(chosen.vehicle_dir(2, 7, 3), PathBuf::from("/logs/vehicle-7"));
        let default = LogPlace::Default {
            root: PathBuf::from("/s/rotorpilot"),
            first_instance: 50,
        };
        assert_eq!(default.vehicle_dir(0, 1, 1), PathBuf::from("/s/rotorpilot/instance-50"));
        assert_eq!(
            default.vehicle_dir(3, 54, 4),
            PathBuf::from("/s/rotorpilot/instance-53")
        );
        assert!(chosen.tlog() && !default.tlog());
    }
}
