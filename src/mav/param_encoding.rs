//! Parameter protocol encoding (docs/mavlink.md §8): PARAM_VALUE with INT32 values copied byte-wise
//! into the float field, and the value of a PARAM_SET decoded by its `param_type` (a REAL32 set
//! of an INT32 parameter is accepted when it is an exact integer; the table checks that). Also
//! PX4's `_HASH_CHECK`: a PARAM_VALUE sent before a list, whose value is a CRC-32 over every
//! parameter's name and 4 value bytes in index order, so QGroundControl can load its cached
//! copy and stop the list (by a PARAM_SET of `_HASH_CHECK`). The same 4 value bytes and the
//! airframe's defaults make the parameters of `@PARAM/param.pck` ([`packed_params`]).
//!
//! A vehicle presented as ArduCopter shows the same table through
//! [`CopterParamView`]: [`Shown`] takes the personality and chooses the face (PX4's exactly as
//! above, or ArduCopter's names, units and plain numeric values, and what the link holds). Pure.

use mavlink::dialects::ardupilotmega::{
    MavMessage, MavParamError, MavParamType, PARAM_ERROR_DATA, PARAM_SET_DATA, PARAM_VALUE_DATA,
};
use mavlink::types::CharArray;
use mavlink::MavHeader;

use super::ardupilot::copter_link_params::LinkParams;
use super::ardupilot::copter_param_face::{copter_param_set, CopterParamView};
use super::crc32::crc32_part;
use super::ftp::{PackedParam, PackedValue};
use super::identity::Personality;
use crate::params::{ParamTable, ParamType};

/// `value` of a parameter of type `kind` as the wire carries it: an INT32 as its integer, a
/// REAL32 rounded to f32.
pub fn wire_value(kind: ParamType, value: f64) -> PackedValue {
    match kind {
        ParamType::Int32 => PackedValue::Int32(value as i32),
        ParamType::Real32 => PackedValue::Float(value as f32),
    }
}

/// Every parameter of `table` in wire order with its value as PARAM_VALUE carries it and its
/// default (the airframe's, [`ParamTable::default_value`]), for `@PARAM/param.pck`.
pub fn packed_params(table: &ParamTable) -> Vec<PackedParam> {
    (0..table.len())
        .filter_map(|i| {
            let (def, value) = table.get(i)?;
            let default = table.default_value(i).unwrap_or(value);
            Some(PackedParam {
                name: def.name.to_string(),
                value: wire_value(def.kind, value),
                default: wire_value(def.kind, default),
            })
        })
        .collect()
}

/// PARAM_VALUE for the parameter at `index`, or `None` past the end.
pub fn param_value(table: &ParamTable, index: usize) -> Option<MavMessage> {
    let (def, value) = table.get(index)?;
    let param_type = match def.kind {
        ParamType::Int32 => MavParamType::MAV_PARAM_TYPE_INT32,
        ParamType::Real32 => MavParamType::MAV_PARAM_TYPE_REAL32,
    };
    Some(MavMessage::PARAM_VALUE(PARAM_VALUE_DATA {
        param_value: f32::from_bits(wire_value(def.kind, value).bits()),
        param_count: table.len() as u16,
        param_index: index as u16,
        param_id: param_id(def.name),
        param_type,
    }))
}

/// The parameters as a personality shows them: PX4's table, or ArduCopter's view of the table
/// and of what the link holds (`link`, unused for PX4).
#[derive(Debug, Clone, Copy)]
pub struct Shown<'a> {
    /// Whose face.
    pub personality: Personality,
    /// The one parameter table.
    pub table: &'a ParamTable,
    /// What the link holds (`SYSID_THISMAV`, `SRn_*`), shown by ArduCopter after the table.
    pub link: &'a LinkParams,
}

impl Shown<'_> {
    /// Number of parameters shown.
    pub fn len(&self) -> usize {
        match self.personality {
            Personality::Px4 => self.table.len(),
            Personality::ArduPilot => CopterParamView::new(self.table, self.link).len(),
        }
    }

    /// True when nothing is shown (never, in practice).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// PARAM_VALUE for the parameter at `index` as sent in a list or a read by index (its own
    /// index in the message), or `None` past the end.
    pub fn param_value(&self, index: usize) -> Option<MavMessage> {
        match self.personality {
            Personality::Px4 => param_value(self.table, index),
            Personality::ArduPilot => CopterParamView::new(self.table, self.link).param_value(index, index as u16),
        }
    }

    /// PARAM_VALUE announcing the parameter at `index` after a change (PX4: as in a list;
    /// ArduCopter: index −1, sent as 65535).
    pub fn announced_value(&self, index: usize) -> Option<MavMessage> {
        match self.personality {
            Personality::Px4 => param_value(self.table, index),
            Personality::ArduPilot => CopterParamView::new(self.table, self.link).param_value(index, u16::MAX),
        }
    }

    /// The parameters of `@PARAM/param.pck` ([`packed_params`] or [`CopterParamView::packed`]).
    pub fn packed(&self) -> Vec<PackedParam> {
        match self.personality {
            Personality::Px4 => packed_params(self.table),
            Personality::ArduPilot => CopterParamView::new(self.table, self.link).packed(),
        }
    }
}

/// Name and value of a PARAM_SET as `personality` reads it ([`decode_param_set`], or
/// ArduCopter's plain float).
pub fn decode_param_set_as(personality: Personality, set: &PARAM_SET_DATA) -> (String, f64) {
    match personality {
        Personality::Px4 => decode_param_set(set),
        Personality::ArduPilot => copter_param_set(set),
    }
}

/// The name of PX4's parameter hash.
pub const HASH_CHECK: &str = "_HASH_CHECK";

/// PARAM_VALUE `_HASH_CHECK` (UINT32, index −1 sent as 65535): CRC-32 ([`crc32_part`] from 0)
/// over each parameter's name and the 4 bytes of its PARAM_VALUE value, in index order, as PX4
/// computes it and QGroundControl checks its cache.
pub fn hash_check(table: &ParamTable) -> MavMessage {
    let hash = (0..table.len())
        .filter_map(|i| match param_value(table, i)? {
            MavMessage::PARAM_VALUE(p) => Some(p),
            _ => None,
        })
        .fold(0, |crc, p| {
            let crc = crc32_part(name_of(&p.param_id).as_bytes(), crc);
            crc32_part(&p.param_value.to_bits().to_le_bytes(), crc)
        });
    MavMessage::PARAM_VALUE(PARAM_VALUE_DATA {
        param_value: f32::from_bits(hash),
        param_count: table.len() as u16,
        param_index: u16::MAX,
        param_id: param_id(HASH_CHECK),
        param_type: MavParamType::MAV_PARAM_TYPE_UINT32,
    })
}

/// PARAM_ERROR DOES_NOT_EXIST for `name`, to `sender`.
pub fn param_error_unknown(sender: &MavHeader, name: &str) -> MavMessage {
    MavMessage::PARAM_ERROR(PARAM_ERROR_DATA {
        param_index: -1,
        target_system: sender.system_id as u8,
        target_component: sender.component_id,
        param_id: param_id(name),
        error: MavParamError::MAV_PARAM_ERROR_DOES_NOT_EXIST,
    })
}

/// Name and value of a PARAM_SET: an integer type's bytes as an int32, else the float (as a
/// packed upload's values decode, [`PackedValue::as_f64`]).
pub fn decode_param_set(set: &PARAM_SET_DATA) -> (String, f64) {
    let value = match set.param_type {
        MavParamType::MAV_PARAM_TYPE_INT32
        | MavParamType::MAV_PARAM_TYPE_UINT32
        | MavParamType::MAV_PARAM_TYPE_INT16
        | MavParamType::MAV_PARAM_TYPE_UINT16
        | MavParamType::MAV_PARAM_TYPE_INT8
        | MavParamType::MAV_PARAM_TYPE_UINT8 => PackedValue::Int32(set.param_value.to_bits() as i32),
        _ => PackedValue::Float(set.param_value),
    };
    (name_of(&set.param_id), value.as_f64())
}

/// The text of a 16-byte, NUL-padded `param_id`.
pub fn name_of(id: &CharArray<16>) -> String {
    let bytes: &[u8] = &id[..];
    let end = bytes.iter().position(|b| *b == 0).unwrap_or(bytes.len());
    String::from_utf8_lossy(&bytes[..end]).into_owned()
}

/// `name` as a 16-byte, NUL-padded `param_id` (cut at 16 bytes).
pub fn param_id(name: &str) -> CharArray<16> {
    let mut bytes = [0u8; 16];
    for (b, c) in bytes.iter_mut().zip(name.bytes()) {
        *b = c;
    }
    bytes.into()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::{ControllerGains, ControllerKind};
    use crate::params::VehicleSettings;

    fn table() -> ParamTable {
        ParamTable::new(&VehicleSettings::new(
            ControllerKind::Passivity,
            ControllerGains::default(),
            None,
        ))
    }

    #[test]
    fn int32_travels_bytewise_and_real32_as_is() {
        let t = table();
        let i = t.index_of("RP_CTRL").unwrap();
        let Some(MavMessage::PARAM_VALUE(v)) = param_value(&t, i) else {
            panic!("no value");
        };
        assert_eq!(v.param_type, MavParamType::MAV_PARAM_TYPE_INT32);
        assert_eq!(v.param_value.to_bits(), 2);
        assert_eq!(name_of(&v.param_id), "RP_CTRL");
        assert_eq!((v.param_index as usize, v.param_count as usize), (i, t.len()));
        let Some(MavMessage::PARAM_VALUE(v)) = param_value(&t, 0) else {
            panic!("no value");
        };
        assert_eq!((name_of(&v.param_id).as_str(), v.param_value), ("MIS_TAKEOFF_ALT", 2.5));
        assert!(param_value(&t, t.len()).is_none());
    }

    #[test]
    fn the_packed_parameters_carry_param_value_s_bytes_and_the_airframe_defaults() {
        let mut t = table();
        t.set("MIS_TAKEOFF_ALT", 3.0, 1e-3).unwrap();
        let packed = packed_params(&t);
        assert_eq!(packed.len(), t.len());
        for (i, p) in packed.iter().enumerate() {
            let Some(MavMessage::PARAM_VALUE(v)) = param_value(&t, i) else {
                panic!("no value {i}");
            };
            assert_eq!(p.name, name_of(&v.param_id));
            assert_eq!(p.value.bits(), v.param_value.to_bits(), "{}", p.name);
            let int = v.param_type == MavParamType::MAV_PARAM_TYPE_INT32;
            assert_eq!(matches!(p.value, PackedValue::Int32(_)), int, "{}", p.name);
        }
        let alt = &packed[t.index_of("MIS_TAKEOFF_ALT").unwrap()];
        assert_eq!(
            (alt.value, alt.default),
            (PackedValue::Float(3.0), PackedValue::Float(2.5))
        );
        let ctrl = &packed[t.index_of("RP_CTRL").unwrap()];
        assert_eq!(
            (ctrl.value, ctrl.default),
            (PackedValue::Int32(2), PackedValue::Int32(2))
        );
    }

    #[test]
    fn param_set_decodes_by_type() {
        let set = |value: f32, param_type| PARAM_SET_DATA {
            param_value: value,
            target_system: 1,
            target_component: 1,
            param_id: param_id("RP_CTRL"),
            param_type,
        };
        assert_eq!(
            decode_param_set(&set(f32::from_bits(1), MavParamType::MAV_PARAM_TYPE_INT32)),
            ("RP_CTRL".to_string(), 1.0)
        );
        assert_eq!(decode_param_set(&set(2.0, MavParamType::MAV_PARAM_TYPE_REAL32)).1, 2.0);
        // A 16-character name has no terminating NUL.
        assert_eq!(name_of(&param_id("ABCDEFGHIJKLMNOP")), "ABCDEFGHIJKLMNOP");
    }

    #[test]
    fn the_hash_covers_every_name_and_value_in_index_order() {
        let mut t = table();
        let MavMessage::PARAM_VALUE(h) = hash_check(&t) else {
            panic!("no hash");
        };
        assert_eq!(name_of(&h.param_id), HASH_CHECK);
        assert_eq!((h.param_index, h.param_count as usize), (u16::MAX, t.len()));
        assert_eq!(h.param_type, MavParamType::MAV_PARAM_TYPE_UINT32);
        // The same CRC written out: name bytes, then the 4 value bytes, parameter by parameter.
        let mut bytes = Vec::new();
        for i in 0..t.len() {
            let Some(MavMessage::PARAM_VALUE(v)) = param_value(&t, i) else {
                panic!("no value {i}");
            };
            bytes.extend(name_of(&v.param_id).into_bytes());
            bytes.extend(v.param_value.to_bits().to_le_bytes());
        }
        assert_eq!(h.param_value.to_bits(), crc32_part(&bytes, 0));
        t.set("MIS_TAKEOFF_ALT", 3.0, 1e-3).unwrap();
        let MavMessage::PARAM_VALUE(changed) = hash_check(&t) else {
            panic!("no hash");
        };
        assert_ne!(changed.param_value.to_bits(), h.param_value.to_bits());
    }
}
