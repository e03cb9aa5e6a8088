//! The parameter table (mavlink.md §8): PX4 names where they exist, `RP_` names for the
//! emulator's own settings (controller, every gain, estimator, compensation). A fixed list,
//! built once per vehicle with the airframe's default gains; values are validated as a whole
//! before they change, so a refused set leaves everything as it was. Pure.

mod file;
mod names;

use thiserror::Error;

use crate::commander::CommanderParams;
use crate::control::{ControllerGains, ControllerKind};
use crate::estimation::ChebyshevDesign;
use crate::math::Vec3;

pub use file::{parse_param_file, ParamFileError};
pub use names::PARAM_NAMES;

/// How a parameter travels (MAV_PARAM_TYPE).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamType {
    /// 32-bit signed integer (byte-wise in the float field).
    Int32,
    /// 32-bit float.
    Real32,
}

/// A refused parameter set.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ParamError {
    /// No parameter of that name.
    #[error("{0}: no such parameter")]
    Unknown(String),
    /// Value outside the parameter's range or of the wrong kind.
    #[error("{name}: {reason}")]
    Invalid {
        /// Parameter name.
        name: String,
        /// Why.
        reason: String,
    },
}

/// One parameter's definition.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamDef {
    /// Name (≤ 16 characters).
    pub name: &'static str,
    /// Wire type.
    pub kind: ParamType,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
}

/// Every parameter's value.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamTable {
    defs: Vec<ParamDef>,
    values: Vec<f64>,
}

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
}

impl VehicleSettings {
    /// `controller` with `gains` and the wrench `estimator`; everything else at its default
    /// (PX4's commander defaults, no compensation, ground and ceiling effect on).
    pub fn new(controller: ControllerKind, gains: ControllerGains, estimator: Option<ChebyshevDesign>) -> Self {
        Self {
            commander: CommanderParams::default(),
            controller,
            compensation: false,
            gains,
            estimator,
            ground_effect: true,
            ceiling_effect: true,
        }
    }
}

impl ParamTable {
    /// The table with `settings` as the values.
    pub fn new(settings: &VehicleSettings) -> Self {
        let pairs = names::encode(settings);
        Self {
            defs: pairs.iter().map(|(d, _)| d.clone()).collect(),
            values: pairs.iter().map(|(_, v)| *v).collect(),
        }
    }

    /// Number of parameters.
    pub fn len(&self) -> usize {
        self.defs.len()
    }

    /// True when the table is empty (never, in practice).
    pub fn is_empty(&self) -> bool {
        self.defs.is_empty()
    }

    /// Definition and value at `index`.
    pub fn get(&self, index: usize) -> Option<(&ParamDef, f64)> {
        Some((self.defs.get(index)?, *self.values.get(index)?))
    }

    /// Index of `name`.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.defs.iter().position(|d| d.name == name)
    }

    /// The settings the current values describe.
    pub fn settings(&self) -> VehicleSettings {
        names::decode(&self.values)
    }

    /// Sets `name` to `value`; refused (nothing changed) when out of range, not an integer for an
    /// INT32 parameter, or when the resulting settings are invalid (a gain ≤ 0, an unstable
    /// estimator design at `ts_s`). Returns the parameter's index.
    pub fn set(&mut self, name: &str, value: f64, ts_s: f64) -> Result<usize, ParamError> {
        let index = self
            .index_of(name)
            .ok_or_else(|| ParamError::Unknown(name.to_string()))?;
        let def = &self.defs[index];
        let invalid = |reason: String| ParamError::Invalid {
            name: name.to_string(),
            reason,
        };
        if !value.is_finite() {
            return Err(invalid(format!("{value} is not a number")));
        }
        if def.kind == ParamType::Int32 && value.fract() != 0.0 {
            return Err(invalid(format!("{value} is not an integer")));
        }
        if value < def.min || value > def.max {
            return Err(invalid(format!("{value} outside [{}, {}]", def.min, def.max)));
        }
        let mut values = self.values.clone();
        values[index] = value;
        let s = names::decode(&values);
        s.gains.validate().map_err(invalid)?;
        let f = &s.commander.failsafe;
        if !(f.battery_emergency < f.battery_critical && f.battery_critical < f.battery_low) {
            return Err(invalid(format!(
                "battery thresholds must fall: BAT_LOW_THR {} > BAT_CRIT_THR {} > BAT_EMERGEN_THR {}",
                f.battery_low, f.battery_critical, f.battery_emergency
            )));
        }
        if let Some(design) = s.estimator {
            design.gains(ts_s).map_err(|e| invalid(e.to_string()))?;
        }
        self.values = values;
        Ok(index)
    }
}

/// A 3-vector from three consecutive values.
fn vec3(v: &[f64]) -> Vec3 {
    Vec3::new(v[0], v[1], v[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn settings() -> VehicleSettings {
        VehicleSettings::new(ControllerKind::Geometric, ControllerGains::default(), None)
    }

    #[test]
    fn round_trip_of_every_setting() {
        let mut s = settings();
        s.controller = ControllerKind::Passivity;
        s.compensation = true;
        s.estimator = Some(ChebyshevDesign {
            order: 3,
            ripple_db: 1.0,
            passband_rad_s: 5.0,
        });
        s.gains.passivity.k_a.y = 77.0;
        s.commander.takeoff_alt_m = 4.0;
        let t = ParamTable::new(&s);
        assert_eq!(t.settings(), s);
        assert_eq!(t.len(), PARAM_NAMES.len());
        assert!(
            PARAM_NAMES.iter().all(|n| n.len() <= 16),
            "MAVLink param_id holds 16 characters"
        );
    }

    #[test]
    fn sets_are_checked_and_refusals_change_nothing() {
        let mut t = ParamTable::new(&settings());
        let i = t.set("MIS_TAKEOFF_ALT", 5.0, 1e-3).unwrap();
        assert_eq!(t.get(i).unwrap().1, 5.0);
        assert_eq!(t.settings().commander.takeoff_alt_m, 5.0);
        t.set("RP_CTRL", 1.0, 1e-3).unwrap();
        assert_eq!(t.settings().controller, ControllerKind::Hierarchical);
        let before = t.clone();
        assert!(matches!(t.set("RP_CTRL", 1.5, 1e-3), Err(ParamError::Invalid { .. })));
        assert!(matches!(t.set("RP_CTRL", 3.0, 1e-3), Err(ParamError::Invalid { .. })));
        assert!(matches!(
            t.set("RP_GEO_KP_X", -1.0, 1e-3),
            Err(ParamError::Invalid { .. })
        ));
        t.set("RP_EST_ORDER", 13.0, 1e-3).unwrap();
        let e = t.set("RP_EST_WP", 20.0, 1e-3).unwrap_err().to_string();
        assert!(e.contains("largest stable passband edge"), "{e}");
        assert_eq!(t.set("NOPE", 1.0, 1e-3), Err(ParamError::Unknown("NOPE".into())));
        assert_eq!(t.settings().estimator.map(|d| d.order), Some(13));
        t.set("RP_EST_ORDER", 0.0, 1e-3).unwrap();
        assert_eq!(t.settings().estimator, None);
        let e = t.set("BAT_CRIT_THR", 0.2, 1e-3).unwrap_err().to_string();
        assert!(e.starts_with("BAT_CRIT_THR: battery thresholds must fall"), "{e}");
        t.set("BAT_CRIT_THR", 0.1, 1e-3).unwrap();
        assert_eq!(t.settings().commander.failsafe.battery_critical, 0.1);
        assert_eq!(before.settings().controller, ControllerKind::Hierarchical);
    }
}
