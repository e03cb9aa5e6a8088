//! ArduCopter's parameters for the settings the vehicle has (docs/ardupilot.md §5): each Copter
//! name is one underlying setting of the one parameter declaration (`src/params/`), in Copter's
//! unit, with Copter's default. A vehicle presented as ArduCopter starts from these defaults
//! where they differ from PX4's. Pure.

/// One Copter parameter: its name, the setting it is, and how its unit relates to the setting's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CopterParam {
    /// Copter's name (4.5/4.6 spelling, as DroneKit and MAVProxy scripts use it).
    pub name: &'static str,
    /// The underlying setting's (PX4) name in the parameter declaration.
    pub setting: &'static str,
    /// Copter units per unit of the setting (100 for cm against m).
    pub scale: f64,
    /// Copter's default, in Copter's unit.
    pub default: f64,
}

const fn param(name: &'static str, setting: &'static str, scale: f64, default: f64) -> CopterParam {
    CopterParam {
        name,
        setting,
        scale,
        default,
    }
}

/// The Copter parameters the vehicle has (ArduCopter `Parameters.cpp`, `AC_WPNav.cpp`,
/// `config.h`).
pub const COPTER_PARAMS: [CopterParam; 8] = [
    param("WPNAV_SPEED", "MPC_XY_CRUISE", 100.0, 1000.0),
    param("WPNAV_SPEED_UP", "MPC_Z_V_AUTO_UP", 100.0, 250.0),
    param("WPNAV_SPEED_DN", "MPC_Z_V_AUTO_DN", 100.0, 150.0),
    param("WPNAV_RADIUS", "NAV_ACC_RAD", 100.0, 200.0),
    param("RTL_ALT", "RTL_RETURN_ALT", 100.0, 1500.0),
    param("LAND_SPEED", "MPC_LAND_SPEED", 100.0, 50.0),
    param("DISARM_DELAY", "COM_DISARM_PRFLT", 1.0, 10.0),
    param("GUID_TIMEOUT", "COM_OF_LOSS_T", 1.0, 3.0),
];

/// Copter's defaults as settings: (where they come from, setting name, value in the setting's
/// unit), to apply to a vehicle presented as ArduCopter before any user parameter.
pub fn copter_defaults() -> impl Iterator<Item = (String, &'static str, f64)> {
    COPTER_PARAMS.iter().map(|p| {
        (
            format!("ArduCopter's {} default", p.name),
            p.setting,
            p.default / p.scale,
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::{ControllerGains, ControllerKind};
    use crate::params::{ParamTable, VehicleSettings};

    #[test]
    fn every_copter_parameter_is_a_setting_and_its_default_is_valid() {
        let settings = VehicleSettings::new(ControllerKind::Geometric, ControllerGains::default(), None);
        let mut table = ParamTable::new(&settings);
        for (origin, setting, value) in copter_defaults() {
            if let Err(e) = table.set(setting, value, 0.0) {
                panic!("{origin}: {e}");
            }
        }
        let get = |name: &str| {
            table
                .index_of(name)
                .and_then(|i| table.get(i))
                .map_or(f64::NAN, |(_, v)| v)
        };
        assert_eq!(get("MPC_XY_CRUISE"), 10.0, "WPNAV_SPEED 1000 cm/s");
        assert_eq!(get("RTL_RETURN_ALT"), 15.0, "RTL_ALT 1500 cm");
        assert_eq!(get("COM_OF_LOSS_T"), 3.0, "GUID_TIMEOUT 3 s");
    }
}
