//! ArduCopter's parameters for the settings the vehicle has (docs/ardupilot.md §5): each Copter
//! name is one underlying setting of the one parameter declaration (`src/params/`), in Copter's
//! unit (a pure scale of the setting's), stored as Copter stores it, with Copter's default where
//! it applies. A vehicle presented as ArduCopter starts from these defaults where they differ
//! from PX4's; [`CopterParamView`](super::copter_param_face::CopterParamView) shows the table
//! under these names. Pure.
//!
//! Left out on purpose: Copter parameters without a setting here (`SYSID_THISMAV`: the system
//! id is fixed at start; `ARMING_CHECK`, `FENCE_ENABLE`, `RTL_ALT_FINAL`, the `SRn_*` stream
//! rates, which are the link's, not settings), enums that do not map one to one
//! (`FS_GCS_ENABLE` against `NAV_DLL_ACT`, `FENCE_ACTION` against `GF_ACTION`), a second name
//! for a setting that has one (`LAND_SPEED_HIGH` is `WPNAV_SPEED_DN`'s `MPC_Z_V_AUTO_DN`), and
//! constants of the emulator (`CIRCLE_RADIUS`, `CIRCLE_RATE`).

use mavlink::dialects::ardupilotmega::MavParamType;

use crate::mav::ftp::PackedValue;

/// How ArduCopter stores a parameter (AP_Param's scalar types): the `param_type` of its
/// PARAM_VALUE and the type of its `@PARAM/param.pck` entry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CopterType {
    /// AP_Int8.
    Int8,
    /// AP_Int16.
    Int16,
    /// AP_Int32.
    Int32,
    /// AP_Float.
    Float,
}

impl CopterType {
    /// MAV_PARAM_TYPE of the PARAM_VALUE (INT8 2, INT16 4, INT32 6, REAL32 9).
    pub fn mav_type(self) -> MavParamType {
        match self {
            Self::Int8 => MavParamType::MAV_PARAM_TYPE_INT8,
            Self::Int16 => MavParamType::MAV_PARAM_TYPE_INT16,
            Self::Int32 => MavParamType::MAV_PARAM_TYPE_INT32,
            Self::Float => MavParamType::MAV_PARAM_TYPE_REAL32,
        }
    }

    /// True for the integer types.
    pub fn is_integer(self) -> bool {
        self != Self::Float
    }

    /// `value` (Copter's unit) as this type stores it: an integer type's nearest integer
    /// (saturated to the type), a float rounded to f32.
    pub fn stored(self, value: f64) -> PackedValue {
        let whole = value.round();
        match self {
            Self::Int8 => PackedValue::Int8(whole as i8),
            Self::Int16 => PackedValue::Int16(whole as i16),
            Self::Int32 => PackedValue::Int32(whole as i32),
            Self::Float => PackedValue::Float(value as f32),
        }
    }

    /// The number a PARAM_SET's float `value` sets, as ArduPilot's `set_float` takes it: an
    /// integer type truncates towards zero after a nudge of 0.01 away from it (so 4.999 sets
    /// 5, 4.5 sets 4), a float is taken as it is.
    pub fn from_set(self, value: f64) -> f64 {
        if self.is_integer() {
            (value + 0.01_f64.copysign(value)).trunc()
        } else {
            value
        }
    }
}

/// One Copter parameter: its name, the setting it is, and how its unit relates to the setting's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CopterParam {
    /// Copter's name (4.5/4.6 spelling, as DroneKit and MAVProxy scripts use it).
    pub name: &'static str,
    /// The underlying setting's (PX4) name in the parameter declaration.
    pub setting: &'static str,
    /// Copter units per unit of the setting (100 for cm against m).
    pub scale: f64,
    /// How Copter stores it.
    pub kind: CopterType,
    /// Copter's default, in Copter's unit, when a vehicle presented as ArduCopter starts from it
    /// (`None`: the setting keeps its own default, the airframe's or PX4's).
    pub default: Option<f64>,
}

const fn param(
    name: &'static str,
    setting: &'static str,
    scale: f64,
    kind: CopterType,
    default: Option<f64>,
) -> CopterParam {
    CopterParam {
        name,
        setting,
        scale,
        kind,
        default,
    }
}

use CopterType::{Float, Int16, Int32, Int8};

/// The Copter parameters the vehicle has (ArduCopter `Parameters.cpp`, `AC_WPNav.cpp`,
/// `AC_Fence.cpp`, `AP_BattMonitor_Params.cpp`, `config.h`).
pub const COPTER_PARAMS: [CopterParam; 14] = [
    param("WPNAV_SPEED", "MPC_XY_CRUISE", 100.0, Float, Some(1000.0)),
    param("WPNAV_SPEED_UP", "MPC_Z_V_AUTO_UP", 100.0, Float, Some(250.0)),
    param("WPNAV_SPEED_DN", "MPC_Z_V_AUTO_DN", 100.0, Float, Some(150.0)),
    param("WPNAV_RADIUS", "NAV_ACC_RAD", 100.0, Float, Some(200.0)),
    param("WPNAV_ACCEL", "MPC_ACC_HOR", 100.0, Float, Some(250.0)),
    param("RTL_ALT", "RTL_RETURN_ALT", 100.0, Int32, Some(1500.0)),
    param("LAND_SPEED", "MPC_LAND_SPEED", 100.0, Int16, Some(50.0)),
    param("PILOT_SPEED_UP", "MPC_Z_VEL_MAX_UP", 100.0, Int16, Some(250.0)),
    param("ANGLE_MAX", "MPC_TILTMAX_AIR", 100.0, Int16, Some(3000.0)),
    param("DISARM_DELAY", "COM_DISARM_PRFLT", 1.0, Int8, Some(10.0)),
    param("GUID_TIMEOUT", "COM_OF_LOSS_T", 1.0, Float, Some(3.0)),
    // Copter's fence is off until FENCE_ENABLE (not emulated); here 0 is "no limit" and a
    // limit set is flown at once, so Copter's 100 m and 300 m are not applied.
    param("FENCE_ALT_MAX", "GF_MAX_VER_DIST", 1.0, Float, None),
    param("FENCE_RADIUS", "GF_MAX_HOR_DIST", 1.0, Float, None),
    // The pack is the airframe's.
    param("BATT_CAPACITY", "BAT1_CAPACITY", 1.0, Int32, None),
];

/// The Copter parameter named `name` (Copter's name).
pub fn by_name(name: &str) -> Option<&'static CopterParam> {
    COPTER_PARAMS.iter().find(|p| p.name == name)
}

/// The Copter parameter that is setting `setting` (its PX4 name).
pub fn by_setting(setting: &str) -> Option<&'static CopterParam> {
    COPTER_PARAMS.iter().find(|p| p.setting == setting)
}

/// Settings without a Copter name that ArduCopter's behaviour fixes: (why, setting, value).
const BEHAVIOUR: [(&str, &str, f64); 1] = [
    // Copter's RC never takes over GUIDED, AUTO or RTL (docs/ardupilot.md §8).
    ("ArduCopter has no stick take-over", "COM_RC_OVERRIDE", 0.0),
];

/// Copter's defaults as settings: (where they come from, setting name, value in the setting's
/// unit), to apply to a vehicle presented as ArduCopter before any user parameter.
pub fn copter_defaults() -> impl Iterator<Item = (String, &'static str, f64)> {
    let named = COPTER_PARAMS.iter().filter_map(|p| {
        let default = p.default?;
        Some((format!("ArduCopter's {} default", p.name), p.setting, default / p.scale))
    });
    named.chain(
        BEHAVIOUR
            .iter()
            .map(|(why, setting, value)| (why.to_string(), *setting, *value)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::{ControllerGains, ControllerKind};
    use crate::params::{ParamTable, ParamType, VehicleSettings};

    fn table() -> ParamTable {
        let settings = VehicleSettings::new(ControllerKind::Geometric, ControllerGains::default(), None);
        ParamTable::new(&settings)
    }

    #[test]
    fn every_copter_parameter_is_a_setting_and_its_default_is_valid() {
        let mut table = table();
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
        assert_eq!(get("MPC_TILTMAX_AIR"), 30.0, "ANGLE_MAX 3000 cdeg");
        assert_eq!(get("COM_RC_OVERRIDE"), 0.0, "no stick take-over");
    }

    #[test]
    fn names_and_settings_are_one_to_one_and_fit_their_types() {
        let table = table();
        for (i, p) in COPTER_PARAMS.iter().enumerate() {
            assert!(p.name.len() <= 16, "{}", p.name);
            assert!(p.scale > 0.0, "{}", p.name);
            let Some((def, _)) = table.index_of(p.setting).and_then(|k| table.get(k)) else {
                panic!("{}: no setting {}", p.name, p.setting);
            };
            for other in &COPTER_PARAMS[i + 1..] {
                assert_ne!(p.name, other.name);
                assert_ne!(p.setting, other.setting, "{} and {}", p.name, other.name);
            }
            assert!(table.index_of(p.name).is_none(), "{} is also a setting's name", p.name);
            // An integer type holds the whole range of the setting in Copter's unit.
            let limit = match p.kind {
                Int8 => f64::from(i8::MAX),
                Int16 => f64::from(i16::MAX),
                Int32 => f64::from(i32::MAX),
                Float => f64::INFINITY,
            };
            assert!(def.max * p.scale <= limit, "{}", p.name);
            assert!(def.kind == ParamType::Real32 || p.scale == 1.0, "{}", p.name);
            assert_eq!(by_name(p.name), Some(p));
            assert_eq!(by_setting(p.setting), Some(p));
        }
        assert_eq!(by_name("MPC_XY_CRUISE"), None);
        assert_eq!(by_setting("WPNAV_SPEED"), None);
    }

    #[test]
    fn stored_values_and_sets_as_copter_casts_them() {
        assert_eq!(Int16.stored(1234.4), PackedValue::Int16(1234));
        assert_eq!(Int8.stored(300.0), PackedValue::Int8(127), "saturated");
        assert_eq!(Int32.stored(1500.0000001), PackedValue::Int32(1500));
        assert_eq!(Float.stored(0.1), PackedValue::Float(0.1));
        assert_eq!(Int16.from_set(4.999), 5.0);
        assert_eq!(Int16.from_set(4.5), 4.0);
        assert_eq!(Int16.from_set(-4.995), -5.0);
        assert_eq!(Float.from_set(4.5), 4.5);
        assert_eq!(Int8.mav_type(), MavParamType::MAV_PARAM_TYPE_INT8);
        assert_eq!(Float.mav_type(), MavParamType::MAV_PARAM_TYPE_REAL32);
    }
}
