//! The control law (`RP_CTRL`), compensation of the estimated wrench (`RP_COMP`), the tilt limit
//! (`MPC_TILTMAX_AIR`) and the guards every law shares.

use crate::control::ControllerKind;
use crate::params::{ParamDef, VehicleSettings};

/// `RP_CTRL`'s code of the law in `s`: its place in [`ControllerKind::ALL`].
fn law_code(s: &VehicleSettings) -> f64 {
    ControllerKind::ALL
        .iter()
        .position(|k| *k == s.controller)
        .map_or(0.0, |i| i as f64)
}

/// The law of `RP_CTRL` code `v`.
fn set_law(s: &mut VehicleSettings, v: f64) -> Result<(), String> {
    s.controller = *ControllerKind::ALL
        .get(v as usize)
        .ok_or_else(|| format!("{v} is not a control law"))?;
    Ok(())
}

/// `(0, "geometric")`, `(1, "hierarchical")`, `(2, "passivity")`.
fn law_codes() -> Vec<(i32, &'static str)> {
    (0..).zip(ControllerKind::ALL.iter().map(|k| k.name())).collect()
}

/// Law and compensation (indices 7–8).
pub(super) static LAW: &[ParamDef] = &[
    ParamDef {
        choices: Some(law_codes),
        ..row!(
            "RP_CTRL",
            Int32,
            [0.0, 2.0],
            "",
            Controller,
            "Control law; a switch takes effect at the next tick, its filters restarting from the current sample (bumpless)",
            law_code,
            set_law
        )
    },
    row!(
        "RP_COMP",
        Int32,
        [0.0, 1.0],
        "",
        Controller,
        "1: the law subtracts the estimated external wrench (needs RP_EST_ORDER > 0)",
        flag compensation
    ),
];

/// Tilt limit and derivative filter (indices 12–13).
pub(super) static LIMITS: &[ParamDef] = &[
    row!(
        "MPC_TILTMAX_AIR",
        Real32,
        [1.0, 79.0],
        "deg",
        Controller,
        "Largest tilt of the commanded thrust direction, in every law",
        degrees gains.limits.tilt_max_rad
    ),
    row!(
        "RP_DERIV_TAU",
        Real32,
        [0.001, 1.0],
        "s",
        Controller,
        "Time constant of the laws' filtered derivatives",
        value gains.limits.derivative_tau_s
    ),
];

/// Guards of the thrust direction (indices 51–52).
pub(super) static GUARDS: &[ParamDef] = &[
    row!(
        "RP_EPS_Z",
        Real32,
        [0.01, 9.0],
        "m/s²",
        Controller,
        "Upward acceleration the commanded acceleration always keeps (ε_z)",
        value gains.limits.eps_z_m_s2
    ),
    row!(
        "RP_EPS_A",
        Real32,
        [1e-6, 10.0],
        "N",
        Controller,
        "Below this thrust magnitude the geometric law keeps its previous thrust direction (ε_A)",
        value gains.limits.eps_a_n
    ),
];

/// Air mode (appended after the motor failures).
pub(super) static AIRMODE: &[ParamDef] = &[
    row!(
        "MC_AIRMODE_LIM",
        Real32,
        [0.0, 1.0],
        "",
        Controller,
        "How far the allocation may raise the collective above the request for roll and pitch, as a fraction of full thrust (0 off, 1 unlimited)",
        |s| s.airmode.raise_limit,
        |s, v| {
            s.airmode.raise_limit = v;
            Ok(())
        }
    ),
    row!(
        "MC_AIRMODE_YAW",
        Int32,
        [0.0, 1.0],
        "",
        Controller,
        "1: the collective also moves (within MC_AIRMODE_LIM) to fit the full yaw torque before yaw is scaled down",
        flag airmode.yaw
    ),
];
