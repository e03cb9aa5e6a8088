//! The one parameter table as ArduCopter shows it (docs/ardupilot.md §5.1): a view, never a
//! second table of values. Index `i` is the table's parameter `i`; a setting that
//! [`COPTER_PARAMS`](super::copter_params::COPTER_PARAMS) names is shown under its Copter name,
//! in Copter's unit (value × scale) and storage type, and is not found under its PX4 name; the
//! others keep their own names and types. PARAM_VALUE carries the value as a number cast to
//! float (ArduPilot's `cast_to_float`: an INT32 of 1 is 1.0, not PX4's bytes), and a PARAM_SET's
//! float is the number, converted back (÷ scale) to the setting. Before a parameter list
//! ArduCopter says its banner ([`banner`]). Pure.

use mavlink::dialects::ardupilotmega::{MavMessage, MavParamType, MavType, PARAM_SET_DATA, PARAM_VALUE_DATA};

use super::copter_params::{by_name, by_setting, CopterType};
use crate::mav::ftp::{PackedParam, PackedValue};
use crate::mav::param_encoding::{name_of, param_id, wire_value};
use crate::params::{ParamTable, ParamType};

/// The ArduCopter release the emulator presents itself as (major, minor, patch: 4.5.7, the last
/// 4.5), in the banner and AUTOPILOT_VERSION.
pub const COPTER_RELEASE: (u8, u8, u8) = (4, 5, 7);

/// The firmware line of the banner: [`COPTER_RELEASE`], with `rotorpilot` where a build would
/// show its git hash.
pub const COPTER_VERSION: &str = "ArduCopter V4.5.7 (rotorpilot)";

/// The STATUSTEXTs (INFO) ArduCopter sends before a parameter list: its firmware line
/// ([`COPTER_VERSION`]) and its frame, the class from the rotor count (`mav_type`) and type X
/// (`Frame: QUAD/X`).
pub fn banner(mav_type: MavType) -> [String; 2] {
    let class = match mav_type {
        MavType::MAV_TYPE_QUADROTOR => "QUAD",
        MavType::MAV_TYPE_HEXAROTOR => "HEXA",
        MavType::MAV_TYPE_OCTOROTOR => "OCTA",
        MavType::MAV_TYPE_DECAROTOR => "DECA",
        MavType::MAV_TYPE_DODECAROTOR => "DODECAHEXA",
        _ => "UNKNOWN",
    };
    [COPTER_VERSION.to_string(), format!("Frame: {class}/X")]
}

/// Name and value of a PARAM_SET as ArduCopter reads it: the float is the number, whatever the
/// `param_type`.
pub fn copter_param_set(set: &PARAM_SET_DATA) -> (String, f64) {
    (name_of(&set.param_id), f64::from(set.param_value))
}

/// One parameter as ArduCopter shows it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CopterValue {
    /// Copter's name, or the setting's own.
    pub name: &'static str,
    /// The value as Copter stores it, in Copter's unit.
    pub value: PackedValue,
    /// Its default, of the same type: Copter's where the personality applies it, else the
    /// airframe's.
    pub default: PackedValue,
}

/// The MAV_PARAM_TYPE of a stored value.
fn mav_type_of(value: PackedValue) -> MavParamType {
    match value {
        PackedValue::Int8(_) => CopterType::Int8.mav_type(),
        PackedValue::Int16(_) => CopterType::Int16.mav_type(),
        PackedValue::Int32(_) => CopterType::Int32.mav_type(),
        PackedValue::Float(_) => CopterType::Float.mav_type(),
    }
}

/// The parameter table under ArduCopter's names, units and types (borrowed, not copied).
#[derive(Debug, Clone, Copy)]
pub struct CopterParamView<'a> {
    table: &'a ParamTable,
}

impl<'a> CopterParamView<'a> {
    /// The view of `table`.
    pub fn new(table: &'a ParamTable) -> Self {
        Self { table }
    }

    /// Number of parameters: the table's.
    pub fn len(&self) -> usize {
        self.table.len()
    }

    /// True when the table is empty (never, in practice).
    pub fn is_empty(&self) -> bool {
        self.table.is_empty()
    }

    /// The parameter at `index` as Copter shows it, or `None` past the end.
    pub fn get(&self, index: usize) -> Option<CopterValue> {
        let (def, value) = self.table.get(index)?;
        let default = self.table.default_value(index).unwrap_or(value);
        Some(match by_setting(def.name) {
            Some(p) => CopterValue {
                name: p.name,
                value: p.kind.stored(value * p.scale),
                default: p.kind.stored(p.default.unwrap_or(default * p.scale)),
            },
            None => CopterValue {
                name: def.name,
                value: wire_value(def.kind, value),
                default: wire_value(def.kind, default),
            },
        })
    }

    /// Index of the parameter Copter calls `name`: a Copter name's setting, or a setting without
    /// a Copter name by its own; `None` for anything else, the PX4 name of a setting that has a
    /// Copter name included.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        match by_name(name) {
            Some(p) => self.table.index_of(p.setting),
            None if by_setting(name).is_some() => None,
            None => self.table.index_of(name),
        }
    }

    /// PARAM_VALUE of the parameter at `index` with `param_index` in the message (the index in a
    /// list and a read by index, 65535 (−1) in an answer by name and an announced change, as
    /// ArduCopter sends them); `None` past the end.
    pub fn param_value(&self, index: usize, param_index: u16) -> Option<MavMessage> {
        let v = self.get(index)?;
        Some(MavMessage::PARAM_VALUE(PARAM_VALUE_DATA {
            param_value: v.value.as_f64() as f32,
            param_count: self.len() as u16,
            param_index,
            param_id: param_id(v.name),
            param_type: mav_type_of(v.value),
        }))
    }

    /// What a PARAM_SET of `name` to `value` (the float as sent, in Copter's unit) asks of the
    /// table: the setting and its value (÷ scale), an integer type's value cast as Copter casts
    /// it ([`CopterType::from_set`]); `None` for a name Copter does not have; a refusal, in
    /// Copter's unit, for a value the setting cannot take (`WPNAV_SPEED: 5000 outside [50,
    /// 3000]`).
    pub fn setting_for(&self, name: &str, value: f64) -> Option<Result<(&'static str, f64), String>> {
        let (def, _) = self.table.get(self.index_of(name)?)?;
        let (scale, kind) = match by_name(name) {
            Some(p) => (p.scale, p.kind),
            None if def.kind == ParamType::Int32 => (1.0, CopterType::Int32),
            None => (1.0, CopterType::Float),
        };
        let copter = kind.from_set(value);
        let setting = copter / scale;
        Some(match def.check(setting) {
            Ok(()) => Ok((def.name, setting)),
            Err(_) if !copter.is_finite() => Err(format!("{name}: {value} is not a number")),
            Err(_) if setting < def.min || setting > def.max => Err(format!(
                "{name}: {copter} outside [{}, {}]",
                (def.min * scale) as f32,
                (def.max * scale) as f32
            )),
            Err(reason) => Err(format!("{name}: {reason}")),
        })
    }

    /// Every parameter as `@PARAM/param.pck` packs it for ArduCopter: Copter's names, units,
    /// storage types and defaults, in index order.
    pub fn packed(&self) -> Vec<PackedParam> {
        (0..self.len())
            .filter_map(|i| self.get(i))
            .map(|v| PackedParam {
                name: v.name.to_string(),
                value: v.value,
                default: v.default,
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::{ControllerGains, ControllerKind};
    use crate::mav::ardupilot::copter_params::{copter_defaults, COPTER_PARAMS};
    use crate::params::VehicleSettings;

    fn table() -> ParamTable {
        ParamTable::new(&VehicleSettings::new(
            ControllerKind::Geometric,
            ControllerGains::default(),
            None,
        ))
    }

    fn value(view: &CopterParamView, name: &str) -> PARAM_VALUE_DATA {
        let i = view.index_of(name).unwrap_or(usize::MAX);
        match view.param_value(i, i as u16) {
            Some(MavMessage::PARAM_VALUE(v)) => v,
            other => panic!("{name}: {other:?}"),
        }
    }

    #[test]
    fn every_name_scale_and_type_round_trips() {
        let mut t = table();
        t.set("MPC_XY_CRUISE", 10.0, 1e-3).unwrap();
        let view = CopterParamView::new(&t);
        assert_eq!(view.len(), t.len());
        let v = value(&view, "WPNAV_SPEED");
        assert_eq!((name_of(&v.param_id).as_str(), v.param_value), ("WPNAV_SPEED", 1000.0));
        assert_eq!(v.param_type, MavParamType::MAV_PARAM_TYPE_REAL32);
        assert_eq!(v.param_index as usize, t.index_of("MPC_XY_CRUISE").unwrap());
        assert_eq!(view.index_of("MPC_XY_CRUISE"), None, "not under its PX4 name");
        assert_eq!(view.setting_for("MPC_XY_CRUISE", 5.0), None);
        assert_eq!(view.setting_for("WPNAV_SPEED", 500.0), Some(Ok(("MPC_XY_CRUISE", 5.0))));
        for p in &COPTER_PARAMS {
            let i = view.index_of(p.name).unwrap();
            let shown = view.get(i).unwrap();
            assert_eq!(shown.name, p.name);
            let (def, setting) = t.get(i).unwrap();
            assert_eq!(def.name, p.setting);
            let back = view.setting_for(p.name, shown.value.as_f64()).unwrap().unwrap();
            let tolerance = if p.kind.is_integer() {
                0.5 / p.scale
            } else {
                1e-6 * setting.abs()
            };
            assert!(
                (back.1 - setting).abs() <= tolerance,
                "{}: {back:?} vs {setting}",
                p.name
            );
            assert_eq!(mav_type_of(shown.value), p.kind.mav_type(), "{}", p.name);
        }
        // Settings without a Copter name keep their own name and type.
        let ctrl = value(&view, "RP_CTRL");
        assert_eq!(ctrl.param_type, MavParamType::MAV_PARAM_TYPE_INT32);
    }

    #[test]
    fn integers_travel_as_numbers_cast_to_float() {
        let mut t = table();
        t.set("RP_CTRL", 1.0, 1e-3).unwrap();
        t.set("COM_DISARM_PRFLT", 7.0, 1e-3).unwrap();
        t.set("MPC_TILTMAX_AIR", 45.0, 1e-3).unwrap();
        let view = CopterParamView::new(&t);
        let ctrl = value(&view, "RP_CTRL");
        assert_eq!(ctrl.param_value, 1.0, "1.0, not the denormal of PX4's bytes");
        assert_ne!(ctrl.param_value.to_bits(), 1);
        let delay = value(&view, "DISARM_DELAY");
        assert_eq!(
            (delay.param_value, delay.param_type),
            (7.0, MavParamType::MAV_PARAM_TYPE_INT8)
        );
        let angle = value(&view, "ANGLE_MAX");
        assert_eq!(
            (angle.param_value, angle.param_type),
            (4500.0, MavParamType::MAV_PARAM_TYPE_INT16)
        );
        // A PARAM_SET's float is the number whatever its type.
        let set = PARAM_SET_DATA {
            param_value: 1.0,
            target_system: 1,
            target_component: 1,
            param_id: param_id("RP_CTRL"),
            param_type: MavParamType::MAV_PARAM_TYPE_INT32,
        };
        assert_eq!(copter_param_set(&set), ("RP_CTRL".to_string(), 1.0));
        assert_eq!(view.setting_for("RP_CTRL", 1.0), Some(Ok(("RP_CTRL", 1.0))));
        assert_eq!(
            view.setting_for("LAND_SPEED", 49.999),
            Some(Ok(("MPC_LAND_SPEED", 0.5)))
        );
    }

    #[test]
    fn unknown_names_and_refused_values() {
        let t = table();
        let view = CopterParamView::new(&t);
        for unknown in [
            "NOPE",
            "SYSID_THISMAV",
            "SR0_EXTRA1",
            "_HASH_CHECK",
            "RTL_RETURN_ALT",
            "",
        ] {
            assert_eq!(view.index_of(unknown), None, "{unknown}");
            assert_eq!(view.setting_for(unknown, 1.0), None, "{unknown}");
        }
        assert!(view.param_value(t.len(), 0).is_none());
        assert_eq!(
            view.setting_for("WPNAV_SPEED", 5000.0),
            Some(Err("WPNAV_SPEED: 5000 outside [50, 3000]".into()))
        );
        assert_eq!(
            view.setting_for("WPNAV_RADIUS", 1.0),
            Some(Err("WPNAV_RADIUS: 1 outside [5, 20000]".into()))
        );
        assert_eq!(view.setting_for("WPNAV_RADIUS", 5.0), Some(Ok(("NAV_ACC_RAD", 0.05))));
        assert_eq!(
            view.setting_for("RTL_ALT", f64::NAN),
            Some(Err("RTL_ALT: NaN is not a number".into()))
        );
    }

    #[test]
    fn the_packed_file_carries_copter_names_types_and_defaults() {
        let mut t = table();
        for (_, setting, v) in copter_defaults() {
            t.set(setting, v, 1e-3).unwrap();
        }
        let packed = CopterParamView::new(&t).packed();
        assert_eq!(packed.len(), t.len());
        let find = |name: &str| packed.iter().find(|p| p.name == name).cloned().unwrap();
        let speed = find("WPNAV_SPEED");
        assert_eq!(
            (speed.value, speed.default),
            (PackedValue::Float(1000.0), PackedValue::Float(1000.0))
        );
        let delay = find("DISARM_DELAY");
        assert_eq!(
            (delay.value, delay.default),
            (PackedValue::Int8(10), PackedValue::Int8(10))
        );
        let fence = find("FENCE_RADIUS");
        assert_eq!(fence.default, PackedValue::Float(0.0), "the setting's own default");
        assert!(packed.iter().all(|p| p.name != "MPC_XY_CRUISE"));
    }

    #[test]
    fn the_banner_names_the_firmware_and_the_frame() {
        assert_eq!(
            banner(MavType::MAV_TYPE_QUADROTOR),
            [COPTER_VERSION.to_string(), "Frame: QUAD/X".to_string()]
        );
        let (major, minor, patch) = COPTER_RELEASE;
        assert_eq!(
            COPTER_VERSION,
            format!("ArduCopter V{major}.{minor}.{patch} (rotorpilot)")
        );
        assert_eq!(banner(MavType::MAV_TYPE_HEXAROTOR)[1], "Frame: HEXA/X");
        assert_eq!(banner(MavType::MAV_TYPE_OCTOROTOR)[1], "Frame: OCTA/X");
    }
}
