//! The fixed parameter list: names, types, ranges, and how each maps to a setting.

use crate::commander::{BatteryParams, CommanderParams, FailsafeParams, LandDetectorParams};
use crate::control::{ControllerGains, ControllerKind};
use crate::estimation::{ChebyshevDesign, MAX_ORDER};
use crate::navigation::MotionLimits;

use super::{vec3, ParamDef, ParamType, VehicleSettings};

/// Every parameter name, in index order.
pub const PARAM_NAMES: [&str; 82] = [
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
];

fn def(name: &'static str, kind: ParamType, min: f64, max: f64) -> ParamDef {
    ParamDef { name, kind, min, max }
}

/// Definitions and values for `s`, in [`PARAM_NAMES`] order. Units: metres, m/s, seconds,
/// degrees (MPC_TILTMAX_AIR, MPC_YAWRAUTO_MAX, MC_YAWRATE_MAX, LNDMC_ROT_MAX), rad/s (RP_EST_WP), dB, and the gain units of `control::gains`.
pub(super) fn encode(s: &VehicleSettings) -> Vec<(ParamDef, f64)> {
    use ParamType::{Int32, Real32};
    let c = &s.commander;
    let g = &s.gains;
    let est = s.estimator;
    let mut out = vec![
        (def(PARAM_NAMES[0], Real32, 0.5, 1000.0), c.takeoff_alt_m),
        (def(PARAM_NAMES[1], Real32, 0.5, 20.0), c.motion.up_m_s),
        (def(PARAM_NAMES[2], Real32, 0.1, 5.0), c.land_speed_m_s),
        (def(PARAM_NAMES[3], Real32, 0.5, 30.0), c.cruise_speed_m_s),
        (def(PARAM_NAMES[4], Real32, 1.0, 500.0), c.rtl_return_alt_m),
        (def(PARAM_NAMES[5], Real32, -1.0, 20.0), c.disarm_land_s),
        (def(PARAM_NAMES[6], Real32, -1.0, 60.0), c.disarm_preflight_s),
        (def(PARAM_NAMES[7], Int32, 0.0, 2.0), kind_index(s.controller)),
        (
            def(PARAM_NAMES[8], Int32, 0.0, 1.0),
            f64::from(u8::from(s.compensation)),
        ),
        (
            def(PARAM_NAMES[9], Int32, 0.0, MAX_ORDER as f64),
            est.map_or(0.0, |d| d.order as f64),
        ),
        (
            def(PARAM_NAMES[10], Real32, 0.01, 20.0),
            est.map_or(3.0, |d| d.ripple_db),
        ),
        (
            def(PARAM_NAMES[11], Real32, 0.01, 1000.0),
            est.map_or(2.0, |d| d.passband_rad_s),
        ),
        (
            def(PARAM_NAMES[12], Real32, 1.0, 79.0),
            g.limits.tilt_max_rad.to_degrees(),
        ),
        (def(PARAM_NAMES[13], Real32, 0.001, 1.0), g.limits.derivative_tau_s),
    ];
    let vectors = [
        g.geometric.kp,
        g.geometric.kv,
        g.geometric.kr,
        g.geometric.komega,
        g.hierarchical.kp,
        g.hierarchical.kd,
        g.hierarchical.k_eta,
        g.hierarchical.k_eta_dot,
    ];
    let mut k = 14;
    for v in &vectors {
        for x in v.iter() {
            out.push((def(PARAM_NAMES[k], Real32, 0.0, 1e6), *x));
            k += 1;
        }
    }
    out.push((def(PARAM_NAMES[k], Real32, 0.0, 1e3), g.passivity.sigma));
    k += 1;
    for v in [g.passivity.d_a, g.passivity.k_a, g.passivity.d_o, g.passivity.k_o] {
        for x in v.iter() {
            out.push((def(PARAM_NAMES[k], Real32, 0.0, 1e6), *x));
            k += 1;
        }
    }
    out.push((def(PARAM_NAMES[k], Real32, 0.01, 9.0), g.limits.eps_z_m_s2));
    out.push((def(PARAM_NAMES[k + 1], Real32, 1e-6, 10.0), g.limits.eps_a_n));
    out.push((def(PARAM_NAMES[k + 2], Real32, 0.0, 60.0), c.offboard_loss_s));
    out.push((def(PARAM_NAMES[k + 3], Int32, 0.0, 6.0), f64::from(c.link_loss_action)));
    out.push((def(PARAM_NAMES[k + 4], Int32, 5.0, 300.0), c.link_loss_s));
    out.push((
        def(PARAM_NAMES[k + 5], Int32, 0.0, 1.0),
        f64::from(u8::from(s.ground_effect)),
    ));
    out.push((
        def(PARAM_NAMES[k + 6], Int32, 0.0, 1.0),
        f64::from(u8::from(s.ceiling_effect)),
    ));
    out.push((def(PARAM_NAMES[k + 7], Real32, 0.5, 50.0), c.motion.horizontal_m_s));
    out.push((def(PARAM_NAMES[k + 8], Real32, 0.1, 10.0), c.motion.down_m_s));
    let f = &c.failsafe;
    out.push((def(PARAM_NAMES[k + 9], Int32, 0.0, 5.0), f64::from(f.geofence_action)));
    out.push((def(PARAM_NAMES[k + 10], Real32, 0.0, 1e4), f.geofence_max_hor_m));
    out.push((def(PARAM_NAMES[k + 11], Real32, 0.0, 1e4), f.geofence_max_ver_m));
    out.push((
        def(PARAM_NAMES[k + 12], Int32, 0.0, 3.0),
        f64::from(f.low_battery_action),
    ));
    out.push((def(PARAM_NAMES[k + 13], Real32, 0.12, 0.5), f.battery_low));
    out.push((def(PARAM_NAMES[k + 14], Real32, 0.05, 0.25), f.battery_critical));
    out.push((def(PARAM_NAMES[k + 15], Real32, 0.03, 0.1), f.battery_emergency));
    out.push((def(PARAM_NAMES[k + 16], Real32, 1.0, 1e5), c.battery.capacity_mah));
    out.push((def(PARAM_NAMES[k + 17], Int32, 1.0, 14.0), f64::from(c.battery.cells)));
    out.push((
        def(PARAM_NAMES[k + 18], Int32, 0.0, 1.0),
        f64::from(u8::from(c.failure_injection)),
    ));
    out.push((
        def(PARAM_NAMES[k + 19], Int32, 0.0, 7.0),
        f64::from(c.offboard_loss_action),
    ));
    let m = &c.motion;
    let l = &c.land_detector;
    out.push((def(PARAM_NAMES[k + 20], Real32, 0.5, 15.0), m.acc_horizontal_m_s2));
    out.push((def(PARAM_NAMES[k + 21], Real32, 1.0, 15.0), m.acc_up_m_s2));
    out.push((def(PARAM_NAMES[k + 22], Real32, 1.0, 15.0), m.acc_down_m_s2));
    out.push((
        def(PARAM_NAMES[k + 23], Real32, 5.0, 360.0),
        m.yaw_rate_auto_rad_s.to_degrees(),
    ));
    out.push((
        def(PARAM_NAMES[k + 24], Real32, 5.0, 1800.0),
        m.yaw_rate_max_rad_s.to_degrees(),
    ));
    out.push((def(PARAM_NAMES[k + 25], Real32, 0.05, 1.0), l.z_vel_max_m_s));
    out.push((def(PARAM_NAMES[k + 26], Real32, 0.1, 5.0), l.xy_vel_max_m_s));
    out.push((
        def(PARAM_NAMES[k + 27], Real32, 5.0, 360.0),
        l.rot_max_rad_s.to_degrees(),
    ));
    out.push((def(PARAM_NAMES[k + 28], Real32, 0.1, 10.0), l.trigger_time_s));
    out.push((def(PARAM_NAMES[k + 29], Real32, 0.0, 122.0), c.land_alt1_m));
    out.push((def(PARAM_NAMES[k + 30], Real32, 0.0, 122.0), c.land_alt2_m));
    out
}

fn kind_index(k: ControllerKind) -> f64 {
    match k {
        ControllerKind::Geometric => 0.0,
        ControllerKind::Hierarchical => 1.0,
        ControllerKind::Passivity => 2.0,
    }
}

/// Settings from values in [`PARAM_NAMES`] order.
pub(super) fn decode(v: &[f64]) -> VehicleSettings {
    let mut gains = ControllerGains::default();
    gains.limits.tilt_max_rad = v[12].to_radians();
    gains.limits.derivative_tau_s = v[13];
    gains.geometric.kp = vec3(&v[14..]);
    gains.geometric.kv = vec3(&v[17..]);
    gains.geometric.kr = vec3(&v[20..]);
    gains.geometric.komega = vec3(&v[23..]);
    gains.hierarchical.kp = vec3(&v[26..]);
    gains.hierarchical.kd = vec3(&v[29..]);
    gains.hierarchical.k_eta = vec3(&v[32..]);
    gains.hierarchical.k_eta_dot = vec3(&v[35..]);
    gains.passivity.sigma = v[38];
    gains.passivity.d_a = vec3(&v[39..]);
    gains.passivity.k_a = vec3(&v[42..]);
    gains.passivity.d_o = vec3(&v[45..]);
    gains.passivity.k_o = vec3(&v[48..]);
    gains.limits.eps_z_m_s2 = v[51];
    gains.limits.eps_a_n = v[52];
    let order = v[9] as usize;
    VehicleSettings {
        commander: CommanderParams {
            takeoff_alt_m: v[0],
            land_speed_m_s: v[2],
            land_alt1_m: v[80],
            land_alt2_m: v[81],
            cruise_speed_m_s: v[3],
            rtl_return_alt_m: v[4],
            disarm_land_s: v[5],
            disarm_preflight_s: v[6],
            offboard_loss_s: v[53],
            link_loss_action: v[54] as i32,
            link_loss_s: v[55],
            motion: MotionLimits {
                horizontal_m_s: v[58],
                up_m_s: v[1],
                down_m_s: v[59],
                acc_horizontal_m_s2: v[71],
                acc_up_m_s2: v[72],
                acc_down_m_s2: v[73],
                yaw_rate_auto_rad_s: v[74].to_radians(),
                yaw_rate_max_rad_s: v[75].to_radians(),
            },
            land_detector: LandDetectorParams {
                z_vel_max_m_s: v[76],
                xy_vel_max_m_s: v[77],
                rot_max_rad_s: v[78].to_radians(),
                trigger_time_s: v[79],
            },
            failsafe: FailsafeParams {
                geofence_action: v[60] as i32,
                geofence_max_hor_m: v[61],
                geofence_max_ver_m: v[62],
                low_battery_action: v[63] as i32,
                battery_low: v[64],
                battery_critical: v[65],
                battery_emergency: v[66],
            },
            battery: BatteryParams {
                capacity_mah: v[67],
                cells: v[68] as u32,
            },
            failure_injection: v[69] != 0.0,
            offboard_loss_action: v[70] as i32,
        },
        controller: match v[7] as i64 {
            1 => ControllerKind::Hierarchical,
            2 => ControllerKind::Passivity,
            _ => ControllerKind::Geometric,
        },
        compensation: v[8] != 0.0,
        ground_effect: v[56] != 0.0,
        ceiling_effect: v[57] != 0.0,
        gains,
        estimator: (order > 0).then_some(ChebyshevDesign {
            order,
            ripple_db: v[10],
            passband_rad_s: v[11],
        }),
    }
}
