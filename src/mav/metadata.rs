//! Component metadata (the MAVLink component information protocol) as PX4 serves it: the
//! general metadata file, whose MAVLink FTP URI and CRC COMPONENT_METADATA (397) and the older
//! COMPONENT_INFORMATION (395) carry (only when asked for with REQUEST_MESSAGE, never streamed),
//! lists the parameter metadata file (type 1) with its URI and CRC; QGroundControl downloads both
//! over MAVLink FTP and shows every parameter with its description, unit, range, default and
//! group. The parameter file is generated from the parameter rows (QGroundControl's
//! `CompInfoParam` format, version 1).
//!
//! Both files are served `.xz`-compressed at PX4's paths (`/etc/extras/component_general.json.xz`,
//! `/etc/extras/parameters.json.xz`; QGroundControl inflates a `.xz` name), compressed with
//! PX4's lzma preset 9 (`generate_component_general.py`). The CRCs are PX4's: [`crc32_part`]
//! from 0; COMPONENT_METADATA's `file_crc` over the uncompressed general JSON
//! (`generate_crc.py`), the general file's `fileCrc` over the `.xz` file it names. Pure.

#[allow(deprecated)]
use mavlink::dialects::ardupilotmega::COMPONENT_INFORMATION_DATA;
use mavlink::dialects::ardupilotmega::{MavMessage, COMPONENT_METADATA_DATA};
use serde_json::{json, Map, Value};

use super::crc32::crc32_part;
use super::ftp::{PublishError, Vfs};
use crate::params::{ParamTable, ParamType};

/// Where the general metadata file is served.
pub const GENERAL_PATH: &str = "/etc/extras/component_general.json.xz";
/// Where the parameter metadata file is served.
pub const PARAMETERS_PATH: &str = "/etc/extras/parameters.json.xz";
/// PX4's xz preset for the metadata files.
const XZ_PRESET: u32 = 9;

/// Why the metadata files could not be published.
#[derive(Debug, thiserror::Error)]
pub enum MetadataError {
    /// The file system refused the path.
    #[error(transparent)]
    Publish(#[from] PublishError),
    /// The xz encoder failed.
    #[error("xz compression failed: {0}")]
    Compress(#[from] std::io::Error),
}

/// `data` as an `.xz` file: one LZMA2 block with a CRC-64 check (what Python's
/// `lzma.open(..., preset=9)` writes), preset 9 with the dictionary cut to what `data` needs (at
/// least 4 KiB), so neither end reserves preset 9's 64 MiB for a file of some kilobytes.
pub fn xz(data: &[u8]) -> Result<Vec<u8>, MetadataError> {
    use lzma_rust2::{XzOptions, XzWriter};
    use std::io::Write;
    let mut options = XzOptions::with_preset(XZ_PRESET);
    let needed = u32::try_from(data.len())
        .unwrap_or(u32::MAX)
        .max(lzma_rust2::DICT_SIZE_MIN);
    options.lzma_options.dict_size = options.lzma_options.dict_size.min(needed.next_power_of_two());
    let mut writer = XzWriter::new(Vec::new(), options)?;
    writer.write_all(data)?;
    Ok(writer.finish()?)
}

/// COMP_METADATA_TYPE_PARAMETER.
const TYPE_PARAMETER: u32 = 1;

/// The MAVLink FTP URI of the served `path` (`mftp://etc/...`; QGroundControl keeps the slash
/// after the scheme, so the vehicle is asked for `/etc/...`).
pub fn uri(path: &str) -> String {
    format!("mftp://{}", path.trim_start_matches('/'))
}

/// The parameter metadata JSON of `table`: version 1 and one object per parameter with
/// `name`, `type` (`Int32` / `Float`), `shortDesc`, `longDesc`, `units` (when it has one),
/// `min`, `max`, `default` (the airframe's value), `group` (what it acts on), `category`, and
/// `values` (code and meaning) for an INT32 choice.
pub fn parameter_json(table: &ParamTable) -> Vec<u8> {
    let number = |kind: ParamType, v: f64| match kind {
        ParamType::Int32 => json!(v as i64),
        ParamType::Real32 => json!(v),
    };
    let parameters: Vec<Value> = (0..table.len())
        .filter_map(|i| {
            let (def, value) = table.get(i)?;
            let default = table.default_value(i).unwrap_or(value);
            let scope = def.scope.to_string();
            let mut group = scope.clone();
            if let Some(first) = group.get_mut(..1) {
                first.make_ascii_uppercase();
            }
            let mut p = Map::new();
            p.insert("name".into(), json!(def.name));
            let kind = match def.kind {
                ParamType::Int32 => "Int32",
                ParamType::Real32 => "Float",
            };
            p.insert("type".into(), json!(kind));
            p.insert("shortDesc".into(), json!(def.description));
            p.insert(
                "longDesc".into(),
                json!(format!("{} (acts on the {scope}).", def.description)),
            );
            if !def.unit.is_empty() {
                p.insert("units".into(), json!(def.unit));
            }
            p.insert("min".into(), number(def.kind, def.min));
            p.insert("max".into(), number(def.kind, def.max));
            p.insert("default".into(), number(def.kind, default));
            p.insert("group".into(), json!(group));
            p.insert("category".into(), json!("Standard"));
            if def.kind == ParamType::Real32 {
                p.insert("decimalPlaces".into(), json!(3));
            }
            if let Some(codes) = def.choices {
                let values: Vec<Value> = codes()
                    .into_iter()
                    .map(|(value, description)| json!({ "value": value, "description": description }))
                    .collect();
                p.insert("values".into(), Value::Array(values));
            }
            Some(Value::Object(p))
        })
        .collect();
    json!({ "version": 1, "parameters": parameters })
        .to_string()
        .into_bytes()
}

/// The general metadata JSON: version 1 and the parameter metadata type with its URI and the
/// CRC of `parameters_xz`, the served parameter file (PX4's `generate_component_general.py`
/// layout; keys sorted, as its `json.dump(sort_keys=True)` writes them).
pub fn general_json(parameters_xz: &[u8]) -> Vec<u8> {
    let types = json!([{
        "type": TYPE_PARAMETER,
        "uri": uri(PARAMETERS_PATH),
        "fileCrc": crc32_part(parameters_xz, 0),
    }]);
    json!({ "version": 1, "metadataTypes": types }).to_string().into_bytes()
}

/// The metadata files of one parameter table, compressed and ready to publish: built once, a
/// caller that starts many machines with one table (the fuzz target) publishes copies.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MetadataFiles {
    parameters_xz: Vec<u8>,
    general_xz: Vec<u8>,
    general_crc: u32,
}

impl MetadataFiles {
    /// Both `.xz` files of `table`, and the CRC of the uncompressed general JSON
    /// (COMPONENT_METADATA's `file_crc`).
    pub fn new(table: &ParamTable) -> Result<Self, MetadataError> {
        let parameters_xz = xz(&parameter_json(table))?;
        let general = general_json(&parameters_xz);
        Ok(Self {
            general_crc: crc32_part(&general, 0),
            general_xz: xz(&general)?,
            parameters_xz,
        })
    }

    /// Publishes both files in `fs`; returns the general file's CRC.
    pub fn publish(self, fs: &mut Vfs) -> Result<u32, MetadataError> {
        fs.publish(PARAMETERS_PATH, self.parameters_xz)?;
        fs.publish(GENERAL_PATH, self.general_xz)?;
        Ok(self.general_crc)
    }
}

/// Publishes both `.xz` files of `table` in `fs`; returns the CRC of the uncompressed general
/// JSON (COMPONENT_METADATA's `file_crc`).
pub fn install(fs: &mut Vfs, table: &ParamTable) -> Result<u32, MetadataError> {
    MetadataFiles::new(table)?.publish(fs)
}

/// COMPONENT_METADATA: the general file's URI and `general_crc`, at `time_boot_ms` [ms].
pub fn component_metadata(general_crc: u32, time_boot_ms: u32) -> MavMessage {
    MavMessage::COMPONENT_METADATA(COMPONENT_METADATA_DATA {
        time_boot_ms,
        file_crc: general_crc,
        uri: uri(GENERAL_PATH).as_str().into(),
    })
}

/// COMPONENT_INFORMATION (deprecated; PX4 still answers it): the same URI and CRC, no
/// peripherals file.
#[allow(deprecated)]
pub fn component_information(general_crc: u32, time_boot_ms: u32) -> MavMessage {
    MavMessage::COMPONENT_INFORMATION(COMPONENT_INFORMATION_DATA {
        time_boot_ms,
        general_metadata_file_crc: general_crc,
        general_metadata_uri: uri(GENERAL_PATH).as_str().into(),
        ..Default::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::{ControllerGains, ControllerKind};
    use crate::params::VehicleSettings;

    fn table() -> ParamTable {
        ParamTable::new(&VehicleSettings::new(
            ControllerKind::Geometric,
            ControllerGains::default(),
            None,
        ))
    }

    #[test]
    fn every_parameter_is_described_with_its_unit_range_and_default() {
        let mut t = table();
        t.set("MIS_TAKEOFF_ALT", 7.0, 1e-3).unwrap();
        let doc: Value = serde_json::from_slice(&parameter_json(&t)).unwrap();
        assert_eq!(doc["version"], 1);
        let params = doc["parameters"].as_array().unwrap();
        assert_eq!(params.len(), t.len());
        for (p, (def, _)) in params.iter().zip((0..t.len()).filter_map(|i| t.get(i))) {
            assert_eq!(p["name"], def.name);
            let (min, max, default) = (
                p["min"].as_f64().unwrap(),
                p["max"].as_f64().unwrap(),
                p["default"].as_f64().unwrap(),
            );
            assert!(
                min <= default && default <= max,
                "{}: {default} outside [{min}, {max}]",
                def.name
            );
            assert_eq!(p.get("units").is_some(), !def.unit.is_empty(), "{}", def.name);
        }
        let alt = params.iter().find(|p| p["name"] == "MIS_TAKEOFF_ALT").unwrap();
        assert_eq!(alt["default"], 2.5, "the airframe's default, not the value set");
        assert_eq!(
            (alt["type"].as_str(), alt["units"].as_str()),
            (Some("Float"), Some("m"))
        );
        let kp = params.iter().find(|p| p["name"] == "RP_GEO_KP_X").unwrap();
        assert_eq!(
            (kp["units"].as_str(), kp["group"].as_str()),
            (Some("N/m"), Some("Controller"))
        );
        let ctrl = params.iter().find(|p| p["name"] == "RP_CTRL").unwrap();
        assert_eq!(ctrl["type"], "Int32");
        let dll = params.iter().find(|p| p["name"] == "NAV_DLL_ACT").unwrap();
        assert!(dll["values"].as_array().is_some_and(|v| v.len() >= 3), "{dll}");
    }

    /// `xz` inflated again by the crate's own reader.
    fn unxz(xz: &[u8]) -> Vec<u8> {
        use std::io::Read;
        let mut out = Vec::new();
        lzma_rust2::XzReader::new(xz, false).read_to_end(&mut out).unwrap();
        out
    }

    #[test]
    fn the_general_file_points_at_the_parameters_with_their_crc() {
        let mut fs = Vfs::default();
        let crc = install(&mut fs, &table()).unwrap();
        let general_xz = fs.read(GENERAL_PATH).unwrap();
        assert_eq!(&general_xz[..6], b"\xFD7zXZ\0", "an .xz file");
        let general = unxz(general_xz);
        assert_eq!(crc, crc32_part(&general, 0), "the CRC of the uncompressed JSON");
        let doc: Value = serde_json::from_slice(&general).unwrap();
        assert_eq!(doc["version"], 1);
        let t = &doc["metadataTypes"][0];
        assert_eq!(
            (t["type"].as_u64(), t["uri"].as_str()),
            (Some(1), Some("mftp://etc/extras/parameters.json.xz"))
        );
        let params_xz = fs.read(PARAMETERS_PATH).unwrap();
        assert_eq!(
            t["fileCrc"].as_u64(),
            Some(u64::from(crc32_part(params_xz, 0))),
            "the CRC of the served file"
        );
        let params = unxz(params_xz);
        assert_eq!(params, parameter_json(&table()));
        assert!(
            params_xz.len() * 4 < params.len(),
            "compressed: {} of {}",
            params_xz.len(),
            params.len()
        );
        let MavMessage::COMPONENT_METADATA(m) = component_metadata(crc, 5) else {
            panic!()
        };
        assert_eq!(
            (m.file_crc, m.uri.to_str().unwrap()),
            (crc, "mftp://etc/extras/component_general.json.xz")
        );
    }

    #[test]
    fn xz_round_trips_empty_and_larger_than_the_smallest_dictionary() {
        assert_eq!(unxz(&xz(b"").unwrap()), b"");
        let data: Vec<u8> = (0..20_000u32).flat_map(|k| (k * 7919 % 251).to_le_bytes()).collect();
        assert_eq!(unxz(&xz(&data).unwrap()), data);
    }
}
