//! ArduCopter's failsafes as its ground stations see them (docs/ardupilot.md §2): the texts
//! Copter says where the commander announces a failsafe in PX4's words (`events.cpp`,
//! `ekf_check.cpp`, `fence.cpp`, `AP_BattMonitor`), and whether a failsafe is active, which
//! Copter's HEARTBEAT shows as CRITICAL (`any_failsafe_triggered`: the GCS, battery and EKF
//! failsafes; a fence breach is not one). Pure: the commander's events, the link's verdict on
//! the ground station and the vehicle's state in, texts out.

use mavlink::dialects::ardupilotmega::MavSeverity;

use crate::commander::{BatteryLevel, Event, FailsafeCause, FenceLimits, FlightMode};
use crate::telemetry::Snapshot;

use super::copter_modes::ModeShown;

const WARNING: MavSeverity = MavSeverity::MAV_SEVERITY_WARNING;
const NOTICE: MavSeverity = MavSeverity::MAV_SEVERITY_NOTICE;
const CRITICAL: MavSeverity = MavSeverity::MAV_SEVERITY_CRITICAL;

/// One STATUSTEXT to say: its severity and text.
pub type Spoken = (MavSeverity, String);

/// The failsafes Copter has announced and which of them are still active.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CopterFailsafes {
    /// The GCS failsafe (`failsafe.gcs`): from the ground station's loss until it is heard again.
    gcs: bool,
    /// A battery failsafe fired (`has_failsafed`): until the vehicle restarts.
    battery: bool,
    /// The EKF failsafe (`failsafe.ekf`): from the position's loss until it is valid again.
    ekf: bool,
    /// A fence breach was announced and has not been cleared.
    fence: bool,
}

impl CopterFailsafes {
    /// Whether a failsafe is active (the HEARTBEAT's CRITICAL).
    pub fn active(&self) -> bool {
        self.gcs || self.battery || self.ekf
    }

    /// What Copter says for the commander's `event` with the vehicle in `state`: `Some` of its
    /// texts (none: it says nothing) for a failsafe Copter
    /// words itself, `None` for every other event.
    pub fn handle_event(&mut self, event: &Event, state: &Snapshot) -> Option<Vec<Spoken>> {
        let Event::Failsafe(cause, _) = event else {
            return None;
        };
        let said = match *cause {
            FailsafeCause::Battery(level) => {
                self.battery = true;
                let b = &state.battery;
                let volts = b.cell_v * f64::from(b.cells);
                let level = match level {
                    BatteryLevel::Low => Some("low"),
                    BatteryLevel::Critical => Some("critical"),
                    // Copter has two levels; the commander's third only lands.
                    BatteryLevel::Emergency | BatteryLevel::Ok => None,
                };
                let detail = level.map(|level| {
                    let used = b.consumed_mah;
                    (WARNING, format!("Battery 1 is {level} {volts:.2}V used {used:.0} mAh"))
                });
                detail
                    .into_iter()
                    .chain([(WARNING, "Battery Failsafe".to_string())])
                    .collect()
            }
            FailsafeCause::Geofence(limits) => {
                self.fence = true;
                vec![(NOTICE, format!("{} breached", fence_names(limits)))]
            }
            // The link announces the GCS failsafe itself ([`Self::handle_gcs`]).
            FailsafeCause::GcsLink => Vec::new(),
            FailsafeCause::PositionLost => {
                self.ekf = true;
                vec![(CRITICAL, "EKF variance".to_string())]
            }
            FailsafeCause::PositionAction(mode) => {
                let name = copter_name(mode);
                vec![(CRITICAL, format!("EKF Failsafe: changed to {name} Mode"))]
            }
            FailsafeCause::PositionRegained if self.ekf => {
                self.ekf = false;
                vec![(CRITICAL, "EKF Failsafe Cleared".to_string())]
            }
            FailsafeCause::PositionRegained => Vec::new(),
            FailsafeCause::Other => return None,
        };
        Some(said)
    }

    /// The link's verdict on the ground station: `lost` while its heartbeat has been silent for
    /// `COM_DL_LOSS_T` with `NAV_DLL_ACT` set (Copter's `FS_GCS_ENABLE`); "GCS Failsafe" when
    /// it is lost, "GCS Failsafe Cleared" when it is heard again (armed or not, as Copter).
    pub fn handle_gcs(&mut self, lost: bool) -> Option<Spoken> {
        if lost == self.gcs {
            return None;
        }
        self.gcs = lost;
        Some(if lost {
            (WARNING, "GCS Failsafe".to_string())
        } else {
            (WARNING, "GCS Failsafe Cleared".to_string())
        })
    }

    /// The vehicle's latest `state`: "Fence breach cleared" once a breach announced is over.
    pub fn handle_state(&mut self, state: &Snapshot) -> Option<Spoken> {
        if !self.fence || state.geofence_breached {
            return None;
        }
        self.fence = false;
        Some((NOTICE, "Fence breach cleared".to_string()))
    }
}

/// Copter's name of the mode that flies the commander's `mode` (LAND, ALT_HOLD …).
fn copter_name(mode: FlightMode) -> &'static str {
    let number = ModeShown::default().number(mode);
    super::copter_modes::CopterMode::by_number(u32::from(number)).map_or("UNKNOWN", |m| m.name)
}

/// Copter's names of the fences `limits` crosses (`AC_Fence::get_fence_names`): Max Alt, Circle
/// (the horizontal distance) and Polygon (the uploaded zones), "X fence", "X and Y fences",
/// "X, Y and Z fences".
fn fence_names(limits: FenceLimits) -> String {
    let names: Vec<&str> = [
        (limits.height, "Max Alt"),
        (limits.distance, "Circle"),
        (limits.zone, "Polygon"),
    ]
    .into_iter()
    .filter_map(|(crossed, name)| crossed.then_some(name))
    .collect();
    let list = match names.as_slice() {
        [] => return "Polygon fence".to_string(),
        [one] => return format!("{one} fence"),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    };
    format!("{list} fences")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::guidance::Home;

    fn texts(said: Option<Vec<Spoken>>) -> Vec<String> {
        said.unwrap_or_default().into_iter().map(|(_, t)| t).collect()
    }

    #[test]
    fn the_battery_failsafe_is_said_as_copter_says_it_and_stays_active() {
        let mut f = CopterFailsafes::default();
        let mut s = Snapshot::initial(Home::default());
        s.battery.cell_v = 3.6;
        s.battery.consumed_mah = 4321.4;
        let low = Event::Failsafe(FailsafeCause::Battery(BatteryLevel::Low), "Low battery".into());
        assert_eq!(
            texts(f.handle_event(&low, &s)),
            ["Battery 1 is low 10.80V used 4321 mAh", "Battery Failsafe"]
        );
        assert!(f.active());
        let emergency = Event::Failsafe(FailsafeCause::Battery(BatteryLevel::Emergency), "x".into());
        assert_eq!(texts(f.handle_event(&emergency, &s)), ["Battery Failsafe"]);
    }

    #[test]
    fn the_gcs_failsafe_lasts_until_the_ground_station_is_heard_again() {
        let mut f = CopterFailsafes::default();
        assert_eq!(f.handle_gcs(false), None);
        assert_eq!(f.handle_gcs(true), Some((WARNING, "GCS Failsafe".into())));
        assert!(f.active());
        assert_eq!(f.handle_gcs(true), None, "once");
        let commander = Event::Failsafe(FailsafeCause::GcsLink, "GCS link lost: returning".into());
        let s = Snapshot::initial(Home::default());
        assert_eq!(f.handle_event(&commander, &s), Some(Vec::new()), "PX4's words not said");
        assert_eq!(f.handle_gcs(false), Some((WARNING, "GCS Failsafe Cleared".into())));
        assert!(!f.active());
    }

    #[test]
    fn the_ekf_failsafe_names_the_mode_and_clears() {
        let mut f = CopterFailsafes::default();
        let s = Snapshot::initial(Home::default());
        let lost = Event::Failsafe(FailsafeCause::PositionLost, "Position estimate lost".into());
        let land = Event::Failsafe(FailsafeCause::PositionAction(FlightMode::Land), "x".into());
        let alt = Event::Failsafe(FailsafeCause::PositionAction(FlightMode::Altitude), "x".into());
        let back = Event::Failsafe(FailsafeCause::PositionRegained, "x".into());
        assert_eq!(texts(f.handle_event(&lost, &s)), ["EKF variance"]);
        assert!(f.active());
        assert_eq!(texts(f.handle_event(&land, &s)), ["EKF Failsafe: changed to LAND Mode"]);
        assert_eq!(
            texts(f.handle_event(&alt, &s)),
            ["EKF Failsafe: changed to ALT_HOLD Mode"]
        );
        assert_eq!(texts(f.handle_event(&back, &s)), ["EKF Failsafe Cleared"]);
        assert!(!f.active());
        assert_eq!(f.handle_event(&back, &s), Some(Vec::new()), "cleared once");
        let other = Event::Failsafe(FailsafeCause::Other, "Motor 1 failed".into());
        assert_eq!(f.handle_event(&other, &s), None, "said in the commander's words");
    }

    #[test]
    fn fence_breaches_name_copters_fences_and_are_cleared_without_critical() {
        let mut f = CopterFailsafes::default();
        let mut s = Snapshot::initial(Home::default());
        let limits = |height, distance, zone| FenceLimits { height, distance, zone };
        let breach = |l| Event::Failsafe(FailsafeCause::Geofence(l), "Geofence breached".into());
        assert_eq!(
            texts(f.handle_event(&breach(limits(false, true, false)), &s)),
            ["Circle fence breached"]
        );
        assert!(!f.active(), "Copter's HEARTBEAT does not count a breach");
        assert_eq!(fence_names(limits(true, true, false)), "Max Alt and Circle fences");
        assert_eq!(
            fence_names(limits(true, true, true)),
            "Max Alt, Circle and Polygon fences"
        );
        s.geofence_breached = true;
        assert_eq!(f.handle_state(&s), None);
        s.geofence_breached = false;
        assert_eq!(f.handle_state(&s), Some((NOTICE, "Fence breach cleared".into())));
        assert_eq!(f.handle_state(&s), None);
    }
}
