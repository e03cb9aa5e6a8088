//! Tests of [`CopterParamView`](super::CopterParamView): names, units, types and codes both
//! ways, what the link holds, refusals, the packed file, `--params` lines and the banner.

use super::*;
use crate::control::{ControllerGains, ControllerKind};
use crate::mav::ardupilot::copter_params::{copter_defaults, COPTER_PARAMS};
use crate::mav::ardupilot::copter_streams::{CopterGroup, GROUP_COUNT};
use crate::params::VehicleSettings;

fn table() -> ParamTable {
    ParamTable::new(&VehicleSettings::new(
        ControllerKind::Geometric,
        ControllerGains::default(),
        None,
    ))
}

/// A vehicle with system id 1 and one link whose groups are all off.
static LINK: LinkParams = LinkParams {
    system_id: 1,
    stream_rates: Vec::new(),
};

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
    let view = CopterParamView::new(&t, &LINK);
    assert_eq!(view.len(), t.len() + 1, "the table, then SYSID_THISMAV");
    let v = value(&view, "WPNAV_SPEED");
    assert_eq!((name_of(&v.param_id).as_str(), v.param_value), ("WPNAV_SPEED", 1000.0));
    assert_eq!(v.param_type, MavParamType::MAV_PARAM_TYPE_REAL32);
    assert_eq!(v.param_index as usize, t.index_of("MPC_XY_CRUISE").unwrap());
    assert_eq!(view.index_of("MPC_XY_CRUISE"), None, "not under its PX4 name");
    assert_eq!(view.setting_for("MPC_XY_CRUISE", 5.0), None);
    assert_eq!(
        view.setting_for("WPNAV_SPEED", 500.0),
        Some(Ok(CopterSet::Setting("MPC_XY_CRUISE", 5.0)))
    );
    for p in &COPTER_PARAMS {
        let i = view.index_of(p.name).unwrap();
        let shown = view.get(i).unwrap();
        assert_eq!(shown.name, p.name);
        let (def, setting) = t.get(i).unwrap();
        assert_eq!(def.name, p.setting);
        let Some(Ok(CopterSet::Setting(name, back))) = view.setting_for(p.name, shown.value.as_f64()) else {
            panic!("{}: not set back", p.name);
        };
        let tolerance = match (p.conv, p.kind.is_integer()) {
            (Conversion::Scale(scale), true) => 0.5 / scale,
            (Conversion::Scale(_), false) => 1e-6 * setting.abs(),
            (Conversion::Codes(_), _) => 0.0,
        };
        assert_eq!(name, p.setting);
        assert!((back - setting).abs() <= tolerance, "{}: {back} vs {setting}", p.name);
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
    let view = CopterParamView::new(&t, &LINK);
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
    assert_eq!(
        view.setting_for("RP_CTRL", 1.0),
        Some(Ok(CopterSet::Setting("RP_CTRL", 1.0)))
    );
    assert_eq!(
        view.setting_for("LAND_SPEED", 49.999),
        Some(Ok(CopterSet::Setting("MPC_LAND_SPEED", 0.5)))
    );
}

#[test]
fn unknown_names_and_refused_values() {
    let t = table();
    let view = CopterParamView::new(&t, &LINK);
    for unknown in ["NOPE", "SR0_EXTRA1", "_HASH_CHECK", "RTL_RETURN_ALT", ""] {
        assert_eq!(view.index_of(unknown), None, "{unknown}");
        assert_eq!(view.setting_for(unknown, 1.0), None, "{unknown}");
    }
    assert!(view.param_value(t.len() + 1, 0).is_none());
    assert_eq!(
        view.setting_for("WPNAV_SPEED", 5000.0),
        Some(Err("WPNAV_SPEED: 5000 outside [50, 3000]".into()))
    );
    assert_eq!(
        view.setting_for("WPNAV_RADIUS", 1.0),
        Some(Err("WPNAV_RADIUS: 1 outside [5, 20000]".into()))
    );
    assert_eq!(
        view.setting_for("WPNAV_RADIUS", 5.0),
        Some(Ok(CopterSet::Setting("NAV_ACC_RAD", 0.05)))
    );
    assert_eq!(
        view.setting_for("RTL_ALT", f64::NAN),
        Some(Err("RTL_ALT: NaN is not a number".into()))
    );
    // Copter codes without a behaviour here are refused with the codes allowed.
    for (name, value, why) in [
        ("FS_GCS_ENABLE", 3.0, "FS_GCS_ENABLE: 3 not emulated (0, 1, 5 or 7)"),
        ("FENCE_ACTION", 5.0, "FENCE_ACTION: 5 not emulated (0, 1, 2 or 4)"),
        ("ARMING_CHECK", 65470.0, "ARMING_CHECK: 65470 not emulated (0 or 1)"),
        ("BATT_FS_CRT_ACT", 5.0, "BATT_FS_CRT_ACT: 5 not emulated (0, 1 or 2)"),
    ] {
        assert_eq!(view.setting_for(name, value), Some(Err(why.into())), "{name}");
        assert!(why.len() <= 50, "{why}: a STATUSTEXT holds 50 bytes");
    }
    assert_eq!(
        view.setting_for("FS_GCS_ENABLE", 1.0),
        Some(Ok(CopterSet::Setting("NAV_DLL_ACT", 2.0)))
    );
    assert_eq!(
        view.setting_for("FS_GCS_TIMEOUT", 2.0),
        Some(Err("FS_GCS_TIMEOUT: 2 outside [5, 300]".into()))
    );
}

#[test]
fn codes_show_as_copter_and_what_copter_lacks_as_minus_one() {
    let mut t = table();
    t.set("NAV_DLL_ACT", 3.0, 1e-3).unwrap();
    t.set("GF_ACTION", 4.0, 1e-3).unwrap();
    let view = CopterParamView::new(&t, &LINK);
    let fs = value(&view, "FS_GCS_ENABLE");
    assert_eq!(
        (fs.param_value, fs.param_type),
        (5.0, MavParamType::MAV_PARAM_TYPE_INT8)
    );
    assert_eq!(value(&view, "FENCE_ACTION").param_value, -1.0, "PX4's terminate");
    let checks = value(&view, "ARMING_CHECK");
    assert_eq!(
        (checks.param_value, checks.param_type),
        (1.0, MavParamType::MAV_PARAM_TYPE_INT32)
    );
}

#[test]
fn what_the_link_holds_follows_the_table() {
    let t = table();
    let mut rates = [0; GROUP_COUNT];
    rates[CopterGroup::Position.index()] = 4;
    let link = LinkParams {
        system_id: 3,
        stream_rates: vec![rates, [0; GROUP_COUNT]],
    };
    let view = CopterParamView::new(&t, &link);
    assert_eq!(view.len(), t.len() + 21);
    assert_eq!(view.index_of("SYSID_THISMAV"), Some(t.len()));
    let sysid = value(&view, "SYSID_THISMAV");
    assert_eq!(
        (sysid.param_value, sysid.param_type, sysid.param_index as usize),
        (3.0, MavParamType::MAV_PARAM_TYPE_INT16, t.len())
    );
    assert_eq!(value(&view, "SR0_POSITION").param_value, 4.0);
    assert_eq!(value(&view, "SR1_POSITION").param_value, 0.0);
    assert_eq!(view.index_of("SR2_POSITION"), None);
    assert_eq!(
        view.setting_for("SR0_POSITION", 2.0),
        Some(Ok(CopterSet::Link(LinkSet::StreamRate {
            link: 0,
            group: CopterGroup::Position,
            rate_hz: 2
        })))
    );
    assert_eq!(
        view.setting_for("SYSID_THISMAV", 4.0),
        Some(Err("SYSID_THISMAV: fixed at start (--sysid)".into()))
    );
    let packed = view.packed();
    assert_eq!(packed.len(), view.len());
    assert_eq!(packed[t.len()].default, PackedValue::Int16(1), "Copter's default id");
}

#[test]
fn the_packed_file_carries_copter_names_types_and_defaults() {
    let mut t = table();
    for (_, setting, v) in copter_defaults() {
        t.set(setting, v, 1e-3).unwrap();
    }
    let packed = CopterParamView::new(&t, &LINK).packed();
    assert_eq!(packed.len(), t.len() + 1);
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
    assert_eq!(fence.default, PackedValue::Float(300.0), "Copter's default");
    let capacity = find("BATT_CAPACITY");
    assert_eq!(capacity.default, capacity.value, "the airframe's pack");
    assert!(packed.iter().all(|p| p.name != "MPC_XY_CRUISE"));
}

#[test]
fn a_params_file_takes_copter_names_and_refuses_the_links() {
    let t = table();
    assert_eq!(
        copter_file_param(&t, "FENCE_ENABLE", 1.0),
        Ok(Some(("RP_GF_ENABLE", 1.0)))
    );
    assert_eq!(
        copter_file_param(&t, "WPNAV_SPEED", 500.0),
        Ok(Some(("MPC_XY_CRUISE", 5.0)))
    );
    assert_eq!(
        copter_file_param(&t, "MPC_XY_CRUISE", 5.0),
        Ok(None),
        "a setting's own name"
    );
    assert_eq!(
        copter_file_param(&t, "FS_GCS_ENABLE", 4.0),
        Err("FS_GCS_ENABLE: 4 not emulated (0, 1, 5 or 7)".into())
    );
    assert!(copter_file_param(&t, "SR0_POSITION", 4.0).is_err());
    assert!(copter_file_param(&t, "SYSID_THISMAV", 1.0).is_err());
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
