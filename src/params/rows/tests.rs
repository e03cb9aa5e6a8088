use super::*;
use crate::control::{ControllerGains, ControllerKind};
use crate::params::{ParamType, VehicleSettings};
use crate::wrench_estimator::ChebyshevDesign;

/// The wire order before the rows were declared: index `i` must stay parameter `i`.
const WIRE_ORDER: [&str; 155] = [
    "MIS_TAKEOFF_ALT",
    "MPC_Z_VEL_MAX_UP",
    "MPC_LAND_SPEED",
    "MPC_XY_CRUISE",
    "RTL_RETURN_ALT",
    "COM_DISARM_LAND",
    "COM_DISARM_PRFLT",
    "RP_CTRL",
    "RP_COMP",
    "RP_EST_ORDER",
    "RP_EST_RIPPLE",
    "RP_EST_WP",
    "MPC_TILTMAX_AIR",
    "RP_DERIV_TAU",
    "RP_GEO_KP_X",
    "RP_GEO_KP_Y",
    "RP_GEO_KP_Z",
    "RP_GEO_KV_X",
    "RP_GEO_KV_Y",
    "RP_GEO_KV_Z",
    "RP_GEO_KR_X",
    "RP_GEO_KR_Y",
    "RP_GEO_KR_Z",
    "RP_GEO_KW_X",
    "RP_GEO_KW_Y",
    "RP_GEO_KW_Z",
    "RP_HIE_KP_X",
    "RP_HIE_KP_Y",
    "RP_HIE_KP_Z",
    "RP_HIE_KD_X",
    "RP_HIE_KD_Y",
    "RP_HIE_KD_Z",
    "RP_HIE_KETA_R",
    "RP_HIE_KETA_P",
    "RP_HIE_KETA_Y",
    "RP_HIE_KETAD_R",
    "RP_HIE_KETAD_P",
    "RP_HIE_KETAD_Y",
    "RP_PAS_SIGMA",
    "RP_PAS_DA_R",
    "RP_PAS_DA_P",
    "RP_PAS_DA_Y",
    "RP_PAS_KA_R",
    "RP_PAS_KA_P",
    "RP_PAS_KA_Y",
    "RP_PAS_DO_X",
    "RP_PAS_DO_Y",
    "RP_PAS_DO_Z",
    "RP_PAS_KO_X",
    "RP_PAS_KO_Y",
    "RP_PAS_KO_Z",
    "RP_EPS_Z",
    "RP_EPS_A",
    "COM_OF_LOSS_T",
    "NAV_DLL_ACT",
    "COM_DL_LOSS_T",
    "RP_GND_EFFECT",
    "RP_CEIL_EFFECT",
    "MPC_XY_VEL_MAX",
    "MPC_Z_VEL_MAX_DN",
    "GF_ACTION",
    "GF_MAX_HOR_DIST",
    "GF_MAX_VER_DIST",
    "COM_LOW_BAT_ACT",
    "BAT_LOW_THR",
    "BAT_CRIT_THR",
    "BAT_EMERGEN_THR",
    "BAT1_CAPACITY",
    "BAT1_N_CELLS",
    "SYS_FAILURE_EN",
    "COM_OBL_RC_ACT",
    "MPC_ACC_HOR",
    "MPC_ACC_UP_MAX",
    "MPC_ACC_DOWN_MAX",
    "MPC_YAWRAUTO_MAX",
    "MC_YAWRATE_MAX",
    "LNDMC_Z_VEL_MAX",
    "LNDMC_XY_VEL_MAX",
    "LNDMC_ROT_MAX",
    "LNDMC_TRIG_TIME",
    "MPC_LAND_ALT1",
    "MPC_LAND_ALT2",
    "RTL_TYPE",
    "COM_RC_IN_MODE",
    "COM_RC_LOSS_T",
    "NAV_RCL_ACT",
    "COM_RCL_EXCEPT",
    "COM_RC_OVERRIDE",
    "COM_RC_STICK_OV",
    "MPC_HOLD_DZ",
    "MPC_XY_MAN_EXPO",
    "MPC_Z_MAN_EXPO",
    "MPC_YAW_EXPO",
    "MPC_VEL_MANUAL",
    "MPC_MAN_TILT_MAX",
    "MPC_MAN_Y_MAX",
    "MC_ACRO_R_MAX",
    "MC_ACRO_P_MAX",
    "MC_ACRO_Y_MAX",
    "MPC_MANTHR_MIN",
    "MPC_THR_HOVER",
    "FLW_TGT_HT",
    "FLW_TGT_DST",
    "FLW_TGT_FA",
    "FLW_TGT_ALT_M",
    "FLW_TGT_MAX_VEL",
    "FLW_TGT_RS",
    "SIH_WIND_N",
    "SIH_WIND_E",
    "RP_WIND_TURB",
    "COM_POSCTL_NAVL",
    "EKF2_HGT_REF",
    "EKF2_GPS_DELAY",
    "EKF2_NOAID_TOUT",
    "EKF2_MAG_DECL",
    "EKF2_GPS_P_GATE",
    "EKF2_GPS_V_GATE",
    "EKF2_BARO_GATE",
    "EKF2_MAG_GATE",
    "EKF2_GPS_P_NOISE",
    "EKF2_GPS_V_NOISE",
    "EKF2_BARO_NOISE",
    "EKF2_HEAD_NOISE",
    "EKF2_ACC_NOISE",
    "EKF2_GYR_NOISE",
    "EKF2_TAU_VEL",
    "NAV_ACC_RAD",
    "NAV_MC_ALT_RAD",
    "MPC_XY_TRAJ_P",
    "SDLOG_MODE",
    "COM_FAIL_ACT_T",
    "MPC_YAWRAUTO_ACC",
    "RTL_CONE_ANG",
    "RTL_MIN_DIST",
    "COM_ACT_FAIL_ACT",
    "FD_ACT_EN",
    "FD_ACT_MOT_THR",
    "FD_ACT_MOT_TOUT",
    "CA_FAILURE_MODE",
    "SYS_FAIL_MOT_OFF",
    "MC_AIRMODE_LIM",
    "MC_AIRMODE_YAW",
    "MPC_Z_V_AUTO_UP",
    "MPC_Z_V_AUTO_DN",
    "MPC_TKO_SPEED",
    "MPC_TKO_RAMP_T",
    "RTL_APPR_FORCE",
    "EKF2_IMU_CTRL",
    "EKF2_GRAV_NOISE",
    "EKF2_GPS_CTRL",
    "EKF2_MAG_TYPE",
    "COM_ARM_WO_GPS",
    "EKF2_DECL_TYPE",
    "RP_ARM_CHECKS",
    "RP_GF_ENABLE",
];

fn settings() -> VehicleSettings {
    let design = ChebyshevDesign {
        order: 2,
        ripple_db: 1.0,
        passband_rad_s: 4.0,
    };
    VehicleSettings::new(ControllerKind::Geometric, ControllerGains::default(), Some(design))
}

#[test]
fn names_are_unique_short_and_in_wire_order() {
    let names: Vec<&str> = rows().map(|r| r.name).collect();
    assert_eq!(names, WIRE_ORDER);
    for (i, name) in names.iter().enumerate() {
        assert!(name.len() <= 16, "{name}: MAVLink param_id holds 16 characters");
        assert!(!names[..i].contains(name), "{name} declared twice");
    }
}

#[test]
fn every_row_is_documented_on_one_line_within_its_range() {
    let s = settings();
    for r in rows() {
        assert!(r.min < r.max, "{}", r.name);
        assert!(!r.description.is_empty(), "{}", r.name);
        for text in [r.description, r.unit] {
            assert!(!text.contains(['|', '\n']), "{}: {text:?} breaks a table row", r.name);
        }
        assert_eq!(r.check((r.get)(&s)), Ok(()), "{}: default out of its range", r.name);
    }
}

/// Values across `[min, max]`, integers for INT32.
fn samples(r: &ParamDef) -> Vec<f64> {
    let raw = [0.0, 0.1, 0.25, 0.5, 0.75, 1.0].map(|f| r.min + f * (r.max - r.min));
    let mut out: Vec<f64> = match r.kind {
        ParamType::Int32 => (r.min as i64..=r.max as i64).map(|i| i as f64).collect(),
        ParamType::Real32 => raw.to_vec(),
    };
    out.dedup();
    out
}

#[test]
fn every_row_reads_back_what_it_wrote() {
    for r in rows() {
        let mut written = 0;
        for v in samples(r) {
            let mut s = settings();
            if (r.set)(&mut s, v).is_err() {
                assert!(r.choices.is_some(), "{}: {v} refused without a list of choices", r.name);
                continue;
            }
            written += 1;
            let back = (r.get)(&s);
            assert!(
                (back - v).abs() <= 1e-9 * v.abs().max(1.0),
                "{}: wrote {v}, read {back}",
                r.name
            );
        }
        assert!(written >= 2, "{}: only {written} values accepted", r.name);
    }
}

#[test]
fn choices_refuse_codes_they_lack_and_list_only_codes_in_range() {
    let s = settings();
    for r in rows().filter(|r| r.choices.is_some()) {
        assert_eq!(r.kind, ParamType::Int32, "{}", r.name);
        let listed = r.choices.map(|c| c()).unwrap_or_default();
        for v in samples(r) {
            let accepted = (r.set)(&mut s.clone(), v).is_ok();
            let named = listed.iter().any(|(c, _)| f64::from(*c) == v);
            assert_eq!(accepted, named, "{}: {v} against {listed:?}", r.name);
        }
        for (code, _) in &listed {
            assert!((r.min..=r.max).contains(&f64::from(*code)), "{}: {code}", r.name);
        }
    }
    let nav_dll_act = rows().find(|r| r.name == "NAV_DLL_ACT").map(|r| r.set);
    let e = nav_dll_act.map(|set| set(&mut settings(), 4.0));
    assert_eq!(
        e,
        Some(Err(
            "4 is not a NAV_DLL_ACT action (choose 0 disabled, 1 hold, 2 return, 3 land, 5 terminate, 6 disarm)".into()
        ))
    );
}

#[test]
fn the_estimator_order_comes_before_its_design() {
    let at = |name: &str| rows().position(|r| r.name == name);
    assert!(at("RP_EST_ORDER") < at("RP_EST_RIPPLE"));
    assert!(at("RP_EST_ORDER") < at("RP_EST_WP"));
}
