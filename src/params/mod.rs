//! The parameter table (docs/mavlink.md §8): PX4 names where they exist, `RP_` names for the
//! emulator's own settings (controller, every gain, estimator, compensation). Each parameter is
//! declared once, as a row of [`rows`]: name, type, range, unit, meaning, and how it reads and
//! writes [`VehicleSettings`]. The table is built once per vehicle from its settings (the
//! airframe's default gains); values are validated as a whole before they change, so a refused
//! set leaves everything as it was. Pure.
//!
//! # Layout
//! - `def.rs`: [`ParamDef`] (one row), [`ParamType`], [`Scope`].
//! - `settings.rs`: [`VehicleSettings`] and the checks across parameters.
//! - `rows/`: every row, grouped by what it acts on, in wire order.
//! - `markdown.rs`: the parameter table of docs/parameters.md, generated from the rows.
//! - `file.rs`: `--params FILE` parsing.

mod def;
mod file;
mod markdown;
mod rows;
mod settings;

use thiserror::Error;

pub use def::{Codes, ParamDef, ParamType, Scope};
pub use file::{parse_param_file, ParamFileError};
pub use markdown::markdown_table;
pub use rows::rows;
pub use settings::{VehicleSettings, WindParams};

/// A refused parameter set.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ParamError {
    /// No parameter of that name.
    #[error("{0}: no such parameter{1}")]
    Unknown(String, String),
    /// Value outside the parameter's range or of the wrong kind.
    #[error("{name}: {reason}")]
    Invalid {
        /// Parameter name.
        name: String,
        /// Why.
        reason: String,
    },
}

/// Every parameter's value, with the settings they describe.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamTable {
    defs: Vec<&'static ParamDef>,
    values: Vec<f64>,
    /// What decoding starts from: the settings the table was built with.
    base: VehicleSettings,
    /// The settings the values describe.
    settings: VehicleSettings,
}

impl ParamTable {
    /// The table with `settings` as the values (every row's getter).
    pub fn new(settings: &VehicleSettings) -> Self {
        let defs: Vec<&'static ParamDef> = rows().collect();
        let values = defs.iter().map(|d| (d.get)(settings)).collect();
        Self {
            defs,
            values,
            base: settings.clone(),
            settings: settings.clone(),
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
        Some((*self.defs.get(index)?, *self.values.get(index)?))
    }

    /// The value at `index` in the settings the table was built with (the airframe's
    /// defaults, before any `--params` file or PARAM_SET).
    pub fn default_value(&self, index: usize) -> Option<f64> {
        Some((self.defs.get(index)?.get)(&self.base))
    }

    /// Index of `name`.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.defs.iter().position(|d| d.name == name)
    }

    /// The settings the current values describe.
    pub fn settings(&self) -> VehicleSettings {
        self.settings.clone()
    }

    /// The settings the current values describe, borrowed.
    pub fn current(&self) -> &VehicleSettings {
        &self.settings
    }

    /// Sets `name` to `value`; refused (nothing changed) when not a finite number, not an
    /// integer for an INT32 parameter, out of range, a code its choice lacks, or when the
    /// resulting settings are invalid ([`VehicleSettings::validate`] at step `ts_s` [s]: a gain
    /// ≤ 0, battery thresholds not falling, an unstable estimator design). Returns the index.
    pub fn set(&mut self, name: &str, value: f64, ts_s: f64) -> Result<usize, ParamError> {
        let index = self.index_of(name).ok_or_else(|| {
            let hint = crate::suggest::did_you_mean(name, self.defs.iter().map(|d| d.name));
            ParamError::Unknown(name.to_string(), hint)
        })?;
        let invalid = |reason: String| ParamError::Invalid {
            name: name.to_string(),
            reason,
        };
        self.defs[index].check(value).map_err(invalid)?;
        let mut values = self.values.clone();
        values[index] = value;
        let settings = self.decode(&values)?;
        settings.validate(ts_s).map_err(invalid)?;
        self.values = values;
        self.settings = settings;
        Ok(index)
    }

    /// The settings `values` describe: every row's setter applied in wire order to the settings
    /// the table was built with; the first refusal names its parameter.
    fn decode(&self, values: &[f64]) -> Result<VehicleSettings, ParamError> {
        let mut s = self.base.clone();
        for (def, v) in self.defs.iter().zip(values) {
            (def.set)(&mut s, *v).map_err(|reason| ParamError::Invalid {
                name: def.name.to_string(),
                reason,
            })?;
        }
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::{ControllerGains, ControllerKind};
    use crate::wrench_estimator::ChebyshevDesign;

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
        assert_eq!(t.decode(&t.values), Ok(s.clone()));
        assert_eq!(
            ParamTable::new(&settings()).decode(&t.values),
            Ok(s),
            "decoding from other settings"
        );
        assert_eq!(t.len(), rows().count());
        assert!(
            rows().all(|r| r.name.len() <= 16),
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
        assert_eq!(t, before, "refused sets change nothing");
        t.set("RP_EST_ORDER", 13.0, 1e-3).unwrap();
        let e = t.set("RP_EST_WP", 20.0, 1e-3).unwrap_err().to_string();
        assert!(e.contains("largest stable passband edge"), "{e}");
        assert_eq!(
            t.set("NOPE", 1.0, 1e-3),
            Err(ParamError::Unknown("NOPE".into(), String::new()))
        );
        let typo = t.set("MPC_XY_VEL_MX", 1.0, 1e-3).unwrap_err().to_string();
        assert_eq!(typo, "MPC_XY_VEL_MX: no such parameter; did you mean MPC_XY_VEL_MAX?");
        assert_eq!(t.settings().estimator.map(|d| d.order), Some(13));
        t.set("RP_EST_ORDER", 0.0, 1e-3).unwrap();
        assert_eq!(t.settings().estimator, None);
        let e = t.set("BAT_CRIT_THR", 0.2, 1e-3).unwrap_err().to_string();
        assert!(e.starts_with("BAT_CRIT_THR: battery thresholds must fall"), "{e}");
        t.set("BAT_CRIT_THR", 0.1, 1e-3).unwrap();
        assert_eq!(t.settings().commander.failsafe.battery_critical, 0.1);
        assert_eq!(before.settings().controller, ControllerKind::Hierarchical);
    }

    #[test]
    fn the_estimator_keeps_its_design_while_off() {
        let mut t = ParamTable::new(&settings());
        t.set("RP_EST_RIPPLE", 1.0, 1e-3).unwrap();
        t.set("RP_EST_WP", 4.0, 1e-3).unwrap();
        assert_eq!(t.settings().estimator, None);
        t.set("RP_EST_ORDER", 2.0, 1e-3).unwrap();
        let design = ChebyshevDesign {
            order: 2,
            ripple_db: 1.0,
            passband_rad_s: 4.0,
        };
        assert_eq!(t.settings().estimator, Some(design));
    }

    #[test]
    fn failsafe_codes_without_an_action_are_refused() {
        use crate::commander::{LinkLossAction, LowBatteryAction};
        let mut t = ParamTable::new(&settings());
        let before = t.clone();
        let e = t.set("NAV_DLL_ACT", 4.0, 1e-3).unwrap_err().to_string();
        assert!(
            e.starts_with("NAV_DLL_ACT: 4 is not a NAV_DLL_ACT action (choose 0 disabled"),
            "{e}"
        );
        let e = t.set("COM_LOW_BAT_ACT", 1.0, 1e-3).unwrap_err().to_string();
        assert!(
            e.starts_with("COM_LOW_BAT_ACT: 1 is not a COM_LOW_BAT_ACT action"),
            "{e}"
        );
        assert_eq!(t, before);
        t.set("NAV_DLL_ACT", 5.0, 1e-3).unwrap();
        t.set("COM_LOW_BAT_ACT", 2.0, 1e-3).unwrap();
        let c = t.settings().commander;
        assert_eq!(c.link_loss_action, LinkLossAction::Terminate);
        assert_eq!(c.failsafe.low_battery_action, LowBatteryAction::Land);
    }
}
