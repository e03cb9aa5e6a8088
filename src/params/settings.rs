//! The settings the parameter table describes, as the flight software uses them, and the checks
//! that only make sense on all of them together. Pure.

use crate::allocation::Airmode;
use crate::commander::CommanderParams;
use crate::control::{ControllerGains, ControllerKind};
use crate::flight::MotorFailureParams;
use crate::nav_filter::NavParams;
use crate::ulog::LogMode;
use crate::wrench_estimator::ChebyshevDesign;

/// The settings the table describes, as the flight software uses them.
#[derive(Debug, Clone, PartialEq)]
pub struct VehicleSettings {
    /// Commander settings.
    pub commander: CommanderParams,
    /// Control law.
    pub controller: ControllerKind,
    /// Compensation of the estimated wrench.
    pub compensation: bool,
    /// Controller gains.
    pub gains: ControllerGains,
    /// Estimator design; `None` when off (order 0).
    pub estimator: Option<ChebyshevDesign>,
    /// The plant's ground effect (as its airframe file configures it) switched on.
    pub ground_effect: bool,
    /// The plant's ceiling effect switched on.
    pub ceiling_effect: bool,
    /// The navigation filter's settings (EKF2_*).
    pub nav: NavParams,
    /// The simulated wind the parameters set (the airframe's or scenario's wind blows until one
    /// of them changes).
    pub wind: WindParams,
    /// When `run` writes flight logs (`SDLOG_MODE`, read at start).
    pub log_mode: LogMode,
    /// How the allocation may raise the collective for torque (`MC_AIRMODE_LIM`,
    /// `MC_AIRMODE_YAW`; off as PX4's default).
    pub airmode: Airmode,
    /// How motor failures are detected and handled (`FD_ACT_*`, `CA_FAILURE_MODE`,
    /// `SYS_FAIL_MOT_OFF`).
    pub motors: MotorFailureParams,
}

/// The simulated wind as parameters set it (PX4 SIH's `SIH_WIND_N`/`SIH_WIND_E`, and the
/// Dryden intensity).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WindParams {
    /// Mean wind toward north [m/s].
    pub north_m_s: f64,
    /// Mean wind toward east [m/s].
    pub east_m_s: f64,
    /// Dryden turbulence intensity W20 [m/s]; 0: none (docs/model.md §5.3).
    pub turbulence_w20_m_s: f64,
}

impl VehicleSettings {
    /// `controller` with `gains` and the wrench `estimator`; everything else at its default
    /// (PX4's commander defaults, no compensation, ground and ceiling effect on, flight logs
    /// from arming to disarming, air mode off, motor failures detected and allocated around).
    pub fn new(controller: ControllerKind, gains: ControllerGains, estimator: Option<ChebyshevDesign>) -> Self {
        Self {
            commander: CommanderParams::default(),
            controller,
            compensation: false,
            gains,
            estimator,
            ground_effect: true,
            ceiling_effect: true,
            wind: WindParams::default(),
            nav: NavParams::default(),
            log_mode: LogMode::default(),
            airmode: Airmode::DISABLED,
            motors: MotorFailureParams::default(),
        }
    }

    /// The checks across parameters: every gain positive ([`ControllerGains::validate`]),
    /// battery thresholds falling (`BAT_LOW_THR` > `BAT_CRIT_THR` > `BAT_EMERGEN_THR`), and the
    /// estimator design realisable and stable at step `ts_s` [s]. The reason names what is wrong.
    pub fn validate(&self, ts_s: f64) -> Result<(), String> {
        self.gains.validate()?;
        let f = &self.commander.failsafe;
        if !(f.battery_emergency < f.battery_critical && f.battery_critical < f.battery_low) {
            return Err(format!(
                "battery thresholds must fall: BAT_LOW_THR {} > BAT_CRIT_THR {} > BAT_EMERGEN_THR {}",
                f.battery_low, f.battery_critical, f.battery_emergency
            ));
        }
        self.nav.validate().map_err(|e| e.to_string())?;
        if let Some(design) = self.estimator {
            design.gains(ts_s).map_err(|e| e.to_string())?;
        }
        Ok(())
    }
}
