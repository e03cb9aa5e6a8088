//! ArduCopter's parameters for the settings the vehicle has (docs/ardupilot.md §5): each Copter
//! name is one underlying setting of the one parameter declaration (`src/params/`), in Copter's
//! unit (a pure scale of the setting's) or Copter's codes (an enum table against the setting's,
//! [`Conversion`]), stored as Copter stores it, with Copter's default where it applies. A
//! vehicle presented as ArduCopter starts from these defaults where they differ from PX4's;
//! [`CopterParamView`](super::copter_param_face::CopterParamView) shows the table under these
//! names. What the link holds (`SYSID_THISMAV`, the `SRn_*` stream rates) is not a setting:
//! [`copter_link_params`](super::copter_link_params). Pure.
//!
//! Left out on purpose: Copter parameters without a setting here (`RTL_ALT_FINAL`,
//! `FENCE_TYPE`: each limit is on while not 0; `BATT_FS_LOW_ACT`: the low level only warns),
//! a second name for a setting that has one (`LAND_SPEED_HIGH` is `WPNAV_SPEED_DN`'s
//! `MPC_Z_V_AUTO_DN`), and constants of the emulator (`CIRCLE_RADIUS`, `CIRCLE_RATE`).

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

/// How a Copter value relates to its setting's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Conversion {
    /// A pure scale: Copter units per unit of the setting (100 for cm against m).
    Scale(f64),
    /// An enum of Copter's codes against the setting's: `(Copter code, setting code, Copter's
    /// meaning)`, one to one; Copter codes not listed have no behaviour here and are refused.
    Codes(&'static [(i32, i32, &'static str)]),
}

impl Conversion {
    /// The setting's `value` in Copter's unit; `None` for a setting code Copter has no code for
    /// (reachable only under the setting's own name: the shell, a `--params` file).
    pub fn to_copter(self, value: f64) -> Option<f64> {
        match self {
            Self::Scale(scale) => Some(value * scale),
            Self::Codes(codes) => codes
                .iter()
                .find(|(_, setting, _)| f64::from(*setting) == value)
                .map(|(copter, _, _)| f64::from(*copter)),
        }
    }

    /// Copter's `value` (a PARAM_SET's number, already cut to the type) as the setting's; a
    /// code without a behaviour here is refused with the codes allowed (`3 not emulated (0, 1,
    /// 5 or 7)`).
    pub fn to_setting(self, value: f64) -> Result<f64, String> {
        match self {
            Self::Scale(scale) => Ok(value / scale),
            Self::Codes(codes) => codes
                .iter()
                .find(|(copter, _, _)| f64::from(*copter) == value)
                .map(|(_, setting, _)| f64::from(*setting))
                .ok_or_else(|| format!("{value} not emulated ({})", self.allowed())),
        }
    }

    /// The Copter codes allowed, short enough for a STATUSTEXT (`0, 1, 5 or 7`); empty for a
    /// scale.
    pub fn allowed(self) -> String {
        let Self::Codes(codes) = self else {
            return String::new();
        };
        let all: Vec<String> = codes.iter().map(|(c, _, _)| c.to_string()).collect();
        match all.split_last() {
            Some((last, [])) => last.clone(),
            Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
            None => String::new(),
        }
    }

    /// The Copter codes allowed with their meanings (`0 disabled, 1 RTL`); empty for a scale.
    pub fn choices(self) -> String {
        match self {
            Self::Scale(_) => String::new(),
            Self::Codes(codes) => {
                let all: Vec<String> = codes.iter().map(|(c, _, label)| format!("{c} {label}")).collect();
                all.join(", ")
            }
        }
    }
}

/// One Copter parameter: its name, the setting it is, and how its value relates to the setting's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CopterParam {
    /// Copter's name (4.5/4.6 spelling, as DroneKit and MAVProxy scripts use it).
    pub name: &'static str,
    /// The underlying setting's name in the parameter declaration.
    pub setting: &'static str,
    /// Copter's value against the setting's.
    pub conv: Conversion,
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
        conv: Conversion::Scale(scale),
        kind,
        default,
    }
}

const fn codes(
    name: &'static str,
    setting: &'static str,
    codes: &'static [(i32, i32, &'static str)],
    default: i32,
) -> CopterParam {
    CopterParam {
        name,
        setting,
        conv: Conversion::Codes(codes),
        kind: CopterType::Int8,
        default: Some(default as f64),
    }
}

use CopterType::{Float, Int16, Int32, Int8};

/// `FS_GCS_ENABLE`'s actions that have one here against `NAV_DLL_ACT`'s codes: RTL is the
/// return, Land the landing, Brake or Land the hold.
const GCS_LOSS_ACTIONS: &[(i32, i32, &str)] = &[
    (0, 0, "disabled"),
    (1, 2, "RTL"),
    (5, 3, "land"),
    (7, 1, "brake or land"),
];

/// `FS_THR_ENABLE`'s against `NAV_RCL_ACT`'s (the codes of `NAV_DLL_ACT`): as
/// [`GCS_LOSS_ACTIONS`], but Copter's Land is 3 here (its 5 is SmartRTL or Land).
const STICK_LOSS_ACTIONS: &[(i32, i32, &str)] = &[
    (0, 0, "disabled"),
    (1, 2, "RTL"),
    (3, 3, "land"),
    (7, 1, "brake or land"),
];

/// The Copter parameters the vehicle has (ArduCopter `Parameters.cpp`, `AC_WPNav.cpp`,
/// `AC_Fence.cpp`, `AP_Arming.cpp`, `AP_BattMonitor_Params.cpp`, `config.h`, `defines.h`).
pub const COPTER_PARAMS: [CopterParam; 22] = [
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
    // ARMING_CHECK is a bitmask: 1 (all) and 0 (only the mandatory checks) have a behaviour.
    CopterParam {
        kind: Int32,
        ..codes(
            "ARMING_CHECK",
            "RP_ARM_CHECKS",
            &[(0, 0, "mandatory checks only"), (1, 1, "all")],
            1,
        )
    },
    // Copter's fence is off until enabled, then flies its 100 m and 300 m limits.
    codes(
        "FENCE_ENABLE",
        "RP_GF_ENABLE",
        &[(0, 0, "disabled"), (1, 1, "enabled")],
        0,
    ),
    codes(
        "FENCE_ACTION",
        "GF_ACTION",
        &[
            (0, 1, "report only"),
            (1, 3, "RTL or land"),
            (2, 5, "always land"),
            (4, 2, "brake or land"),
        ],
        1,
    ),
    param("FENCE_ALT_MAX", "GF_MAX_VER_DIST", 1.0, Float, Some(100.0)),
    param("FENCE_RADIUS", "GF_MAX_HOR_DIST", 1.0, Float, Some(300.0)),
    codes("FS_GCS_ENABLE", "NAV_DLL_ACT", GCS_LOSS_ACTIONS, 0),
    param("FS_GCS_TIMEOUT", "COM_DL_LOSS_T", 1.0, Float, Some(5.0)),
    codes("FS_THR_ENABLE", "NAV_RCL_ACT", STICK_LOSS_ACTIONS, 1),
    codes(
        "FS_EKF_ACTION",
        "COM_POSCTL_NAVL",
        &[(1, 1, "land"), (2, 0, "altitude hold")],
        1,
    ),
    codes(
        "BATT_FS_CRT_ACT",
        "COM_LOW_BAT_ACT",
        &[(0, 0, "none"), (1, 2, "land"), (2, 3, "RTL")],
        0,
    ),
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
const BEHAVIOUR: [(&str, &str, f64); 2] = [
    // Copter's RC never takes over GUIDED, AUTO or RTL (docs/ardupilot.md §8).
    ("ArduCopter has no stick take-over", "COM_RC_OVERRIDE", 0.0),
    // Copter's failsafes act at once, without PX4's hold before the action (docs/ardupilot.md §2).
    ("ArduCopter's failsafes act at once", "COM_FAIL_ACT_T", 0.0),
];

/// Copter's defaults as settings: (where they come from, setting name, value in the setting's
/// unit), to apply to a vehicle presented as ArduCopter before any user parameter.
pub fn copter_defaults() -> impl Iterator<Item = (String, &'static str, f64)> {
    let named = COPTER_PARAMS.iter().filter_map(|p| {
        // Every default is one of its codes (a test checks it).
        let default = p.conv.to_setting(p.default?).ok()?;
        Some((format!("ArduCopter's {} default", p.name), p.setting, default))
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
        let with_default = COPTER_PARAMS.iter().filter(|p| p.default.is_some()).count();
        assert_eq!(
            copter_defaults().count(),
            with_default + BEHAVIOUR.len(),
            "every default is a code"
        );
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
        assert_eq!(get("RP_GF_ENABLE"), 0.0, "FENCE_ENABLE 0");
        assert_eq!(get("GF_ACTION"), 3.0, "FENCE_ACTION 1: RTL");
        assert_eq!((get("GF_MAX_VER_DIST"), get("GF_MAX_HOR_DIST")), (100.0, 300.0));
        assert_eq!(get("NAV_DLL_ACT"), 0.0, "FS_GCS_ENABLE 0");
        assert_eq!(get("NAV_RCL_ACT"), 2.0, "FS_THR_ENABLE 1: RTL");
        assert_eq!(get("COM_DL_LOSS_T"), 5.0, "FS_GCS_TIMEOUT 5 s");
        assert_eq!(get("RP_ARM_CHECKS"), 1.0, "ARMING_CHECK 1");
    }

    #[test]
    fn names_and_settings_are_one_to_one_and_fit_their_types() {
        let table = table();
        for (i, p) in COPTER_PARAMS.iter().enumerate() {
            assert!(p.name.len() <= 16, "{}", p.name);
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
            match p.conv {
                Conversion::Scale(scale) => {
                    assert!(scale > 0.0, "{}", p.name);
                    assert!(def.max * scale <= limit, "{}", p.name);
                    assert!(def.kind == ParamType::Real32 || scale == 1.0, "{}", p.name);
                }
                Conversion::Codes(codes) => {
                    assert!(p.kind.is_integer(), "{}", p.name);
                    assert!(def.choices.is_some() || def.max == 1.0, "{}: codes or a flag", p.name);
                    for (k, (copter, setting, _)) in codes.iter().enumerate() {
                        assert!(f64::from(*copter).abs() <= limit, "{}", p.name);
                        assert_eq!(def.check(f64::from(*setting)), Ok(()), "{}: {setting}", p.name);
                        for (c, s, _) in &codes[k + 1..] {
                            assert!(c != copter && s != setting, "{}: one to one", p.name);
                        }
                    }
                }
            }
            assert_eq!(by_name(p.name), Some(p));
            assert_eq!(by_setting(p.setting), Some(p));
        }
        assert_eq!(by_name("MPC_XY_CRUISE"), None);
        assert_eq!(by_setting("WPNAV_SPEED"), None);
    }

    #[test]
    fn codes_convert_both_ways_and_refuse_what_has_no_behaviour() {
        let fs_gcs = by_name("FS_GCS_ENABLE")
            .map(|p| p.conv)
            .unwrap_or(Conversion::Scale(1.0));
        assert_eq!(fs_gcs.to_setting(1.0), Ok(2.0), "RTL is the return");
        assert_eq!(fs_gcs.to_setting(5.0), Ok(3.0), "land");
        assert_eq!(fs_gcs.to_copter(1.0), Some(7.0), "the hold is brake or land");
        assert_eq!(fs_gcs.to_copter(5.0), None, "PX4's terminate has no Copter code");
        assert_eq!(fs_gcs.to_setting(3.0), Err("3 not emulated (0, 1, 5 or 7)".into()));
        assert_eq!(fs_gcs.choices(), "0 disabled, 1 RTL, 5 land, 7 brake or land");
        let fs_thr = by_name("FS_THR_ENABLE")
            .map(|p| p.conv)
            .unwrap_or(Conversion::Scale(1.0));
        assert_eq!(fs_thr.to_setting(3.0), Ok(3.0), "Copter's throttle failsafe lands at 3");
        assert!(fs_thr.to_setting(5.0).is_err(), "its 5 is SmartRTL or Land");
        let speed = Conversion::Scale(100.0);
        assert_eq!((speed.to_setting(500.0), speed.to_copter(5.0)), (Ok(5.0), Some(500.0)));
        assert_eq!((speed.choices(), speed.allowed()), (String::new(), String::new()));
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
