//! The one parameter table as ArduCopter shows it (docs/ardupilot.md §5.1): a view, never a
//! second table of values. Index `i` is the table's parameter `i`; a setting that
//! [`COPTER_PARAMS`](super::copter_params::COPTER_PARAMS) names is shown under its Copter name,
//! in Copter's unit (value × scale, or Copter's code) and storage type, and is not found under
//! its PX4 name; the others keep their own names and types. After the table come the
//! parameters the link holds ([`LinkParams`]: `SYSID_THISMAV`, `SRn_*`), read from the link.
//! PARAM_VALUE carries the value as a number cast to float (ArduPilot's `cast_to_float`: an
//! INT32 of 1 is 1.0, not PX4's bytes), and a PARAM_SET's float is the number, converted back
//! (÷ scale, or the setting's code) to the setting. Before a parameter list ArduCopter says its
//! banner ([`banner`]). Pure.

use mavlink::dialects::ardupilotmega::{MavMessage, MavParamType, MavType, PARAM_SET_DATA, PARAM_VALUE_DATA};

use super::copter_link_params::{is_link_param, LinkParams, LinkSet};
use super::copter_params::{by_name, by_setting, Conversion, CopterType};
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
#[derive(Debug, Clone, PartialEq)]
pub struct CopterValue {
    /// Copter's name, or the setting's own.
    pub name: String,
    /// The value as Copter stores it, in Copter's unit.
    pub value: PackedValue,
    /// Its default, of the same type: Copter's where the personality applies it, else the
    /// airframe's.
    pub default: PackedValue,
}

/// What a PARAM_SET by Copter's name asks for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CopterSet {
    /// The vehicle sets this setting to this value (the setting's unit).
    Setting(&'static str, f64),
    /// The link changes what it holds.
    Link(LinkSet),
}

/// A `--params` line `name value` for a vehicle presented as ArduCopter (docs/ardupilot.md §5.3):
/// a Copter name as the setting and value a PARAM_SET asks for (Copter's unit and codes, the
/// same refusals, checked against `table`); `None` for any other name, a setting's own; what
/// the link holds is refused (it is set by PARAM_SET).
pub fn copter_file_param(table: &ParamTable, name: &str, value: f64) -> Result<Option<(&'static str, f64)>, String> {
    if is_link_param(name) {
        return Err(format!("{name}: the link's, set by PARAM_SET, not in a file"));
    }
    if by_name(name).is_none() {
        return Ok(None);
    }
    let link = LinkParams::default();
    match CopterParamView::new(table, &link).setting_for(name, value) {
        Some(Ok(CopterSet::Setting(setting, value))) => Ok(Some((setting, value))),
        Some(Err(why)) => Err(why),
        _ => Err(format!("{name}: no setting")),
    }
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

/// The code a setting value Copter has no code for shows as (docs/ardupilot.md §5).
const NO_COPTER_CODE: f64 = -1.0;

/// The parameter table under ArduCopter's names, units and types, then what the link holds
/// (borrowed, not copied).
#[derive(Debug, Clone, Copy)]
pub struct CopterParamView<'a> {
    table: &'a ParamTable,
    link: &'a LinkParams,
}

impl<'a> CopterParamView<'a> {
    /// The view of `table` and of what the link holds, `link`.
    pub fn new(table: &'a ParamTable, link: &'a LinkParams) -> Self {
        Self { table, link }
    }

    /// Number of parameters: the table's and the link's.
    pub fn len(&self) -> usize {
        self.table.len() + self.link.len()
    }

    /// True when there is nothing to show (never, in practice).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The parameter at `index` as Copter shows it, or `None` past the end. A setting value
    /// Copter has no code for shows as −1.
    pub fn get(&self, index: usize) -> Option<CopterValue> {
        let Some((def, value)) = self.table.get(index) else {
            let k = index - self.table.len();
            let (value, default) = self.link.value(k)?;
            let name = self.link.param(k)?.name();
            return Some(CopterValue { name, value, default });
        };
        let default = self.table.default_value(index).unwrap_or(value);
        Some(match by_setting(def.name) {
            Some(p) => {
                let shown = |v: f64| p.conv.to_copter(v).unwrap_or(NO_COPTER_CODE);
                CopterValue {
                    name: p.name.to_string(),
                    value: p.kind.stored(shown(value)),
                    default: p.kind.stored(p.default.unwrap_or_else(|| shown(default))),
                }
            }
            None => CopterValue {
                name: def.name.to_string(),
                value: wire_value(def.kind, value),
                default: wire_value(def.kind, default),
            },
        })
    }

    /// Index of the parameter Copter calls `name`: a Copter name's setting, a setting without
    /// a Copter name by its own, or what the link holds; `None` for anything else, the PX4 name
    /// of a setting that has a Copter name included.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        match by_name(name) {
            Some(p) => self.table.index_of(p.setting),
            None if by_setting(name).is_some() => None,
            None => self
                .table
                .index_of(name)
                .or_else(|| Some(self.table.len() + self.link.index_of(name)?)),
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
            param_id: param_id(&v.name),
            param_type: mav_type_of(v.value),
        }))
    }

    /// What a PARAM_SET of `name` to `value` (the float as sent, in Copter's unit) asks: the
    /// setting and its value (÷ scale, or the setting's code), an integer type's value cast as
    /// Copter casts it ([`CopterType::from_set`]), or a change of what the link holds; `None`
    /// for a name Copter does not have; a refusal, in Copter's unit, for a value the setting
    /// cannot take (`WPNAV_SPEED: 5000 outside [50, 3000]`, `FS_GCS_ENABLE: 3 not emulated (0,
    /// 1, 5 or 7)`).
    pub fn setting_for(&self, name: &str, value: f64) -> Option<Result<CopterSet, String>> {
        let index = self.index_of(name)?;
        let Some((def, _)) = self.table.get(index) else {
            return Some(self.link.set(index - self.table.len(), value)?.map(CopterSet::Link));
        };
        let (conv, kind) = match by_name(name) {
            Some(p) => (p.conv, p.kind),
            None if def.kind == ParamType::Int32 => (Conversion::Scale(1.0), CopterType::Int32),
            None => (Conversion::Scale(1.0), CopterType::Float),
        };
        let copter = kind.from_set(value);
        if !copter.is_finite() {
            return Some(Err(format!("{name}: {value} is not a number")));
        }
        let setting = match conv.to_setting(copter) {
            Ok(setting) => setting,
            Err(why) => return Some(Err(format!("{name}: {why}"))),
        };
        Some(match def.check(setting) {
            Ok(()) => Ok(CopterSet::Setting(def.name, setting)),
            Err(_) if setting < def.min || setting > def.max => {
                let limit = |v: f64| conv.to_copter(v).unwrap_or(v) as f32;
                Err(format!(
                    "{name}: {copter} outside [{}, {}]",
                    limit(def.min),
                    limit(def.max)
                ))
            }
            Err(reason) => Err(format!("{name}: {reason}")),
        })
    }

    /// Every parameter as `@PARAM/param.pck` packs it for ArduCopter: Copter's names, units,
    /// storage types and defaults, in index order.
    pub fn packed(&self) -> Vec<PackedParam> {
        (0..self.len())
            .filter_map(|i| self.get(i))
            .map(|v| PackedParam {
                name: v.name,
                value: v.value,
                default: v.default,
            })
            .collect()
    }
}

#[cfg(test)]
#[path = "copter_param_face_tests.rs"]
mod tests;
