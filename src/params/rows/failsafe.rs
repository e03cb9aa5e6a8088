//! What the vehicle does when something goes wrong: offboard and GCS link loss, geofence
//! breach, battery levels (with the pack the gauge counts against), and PX4's switch that allows
//! failure injection.

use crate::commander::{GeofenceAction, LinkLossAction, LowBatteryAction, OffboardLossAction};
use crate::params::ParamDef;

/// Offboard and GCS link loss (indices 53–55).
pub(super) static LINK_LOSS: &[ParamDef] = &[
    row!(
        "COM_OF_LOSS_T",
        Real32,
        [0.0, 60.0],
        "s",
        Commander,
        "Offboard setpoints older than this are lost (COM_OBL_RC_ACT runs); OFFBOARD needs fresher ones",
        value commander.offboard_loss_s
    ),
    row!(
        "NAV_DLL_ACT",
        Int32,
        [0.0, 6.0],
        "",
        Failsafe,
        "What GCS link loss does in flight, once per loss, with a critical STATUSTEXT",
        action LinkLossAction commander.link_loss_action
    ),
    row!(
        "COM_DL_LOSS_T",
        Int32,
        [5.0, 300.0],
        "s",
        Failsafe,
        "GCS heartbeat silence (in wall and in simulated time) that counts as link loss, once a GCS heartbeat was seen",
        value commander.link_loss_s
    ),
];

/// Geofence, battery, failure injection, offboard-loss action (indices 60–70).
pub(super) static FAILSAFES: &[ParamDef] = &[
    row!(
        "GF_ACTION",
        Int32,
        [0.0, 5.0],
        "",
        Failsafe,
        "What a geofence breach in flight does; fires once per breach",
        action GeofenceAction commander.failsafe.geofence_action
    ),
    row!(
        "GF_MAX_HOR_DIST",
        Real32,
        [0.0, 1e4],
        "m",
        Failsafe,
        "Geofence: largest horizontal distance from home (0: no limit)",
        value commander.failsafe.geofence_max_hor_m
    ),
    row!(
        "GF_MAX_VER_DIST",
        Real32,
        [0.0, 1e4],
        "m",
        Failsafe,
        "Geofence: largest height above home (0: no limit)",
        value commander.failsafe.geofence_max_ver_m
    ),
    row!(
        "COM_LOW_BAT_ACT",
        Int32,
        [0.0, 3.0],
        "",
        Failsafe,
        "What the critical battery level does; the emergency level lands unless this is 0",
        action LowBatteryAction commander.failsafe.low_battery_action
    ),
    row!(
        "BAT_LOW_THR",
        Real32,
        [0.12, 0.5],
        "",
        Failsafe,
        "Low battery level, as the fraction remaining: a warning (thresholds must fall from low to emergency)",
        value commander.failsafe.battery_low
    ),
    row!(
        "BAT_CRIT_THR",
        Real32,
        [0.05, 0.25],
        "",
        Failsafe,
        "Critical battery level, as the fraction remaining: COM_LOW_BAT_ACT runs",
        value commander.failsafe.battery_critical
    ),
    row!(
        "BAT_EMERGEN_THR",
        Real32,
        [0.03, 0.1],
        "",
        Failsafe,
        "Emergency battery level, as the fraction remaining: lands unless COM_LOW_BAT_ACT is 0",
        value commander.failsafe.battery_emergency
    ),
    row!(
        "BAT1_CAPACITY",
        Real32,
        [1.0, 1e5],
        "mAh",
        Battery,
        "Capacity of the pack the gauge counts against (energy = mAh × cells × 3.7 V)",
        value commander.battery.capacity_mah
    ),
    row!(
        "BAT1_N_CELLS",
        Int32,
        [1.0, 14.0],
        "",
        Battery,
        "Cells in series in the pack",
        |s| f64::from(s.commander.battery.cells),
        |s, v| {
            s.commander.battery.cells = v as u32;
            Ok(())
        }
    ),
    row!(
        "SYS_FAILURE_EN",
        Int32,
        [0.0, 1.0],
        "",
        Commander,
        "1 allows MAV_CMD_INJECT_FAILURE (PX4's switch; 1 as PX4 SITL boots, the firmware's default is 0)",
        flag commander.failure_injection
    ),
    row!(
        "COM_OBL_RC_ACT",
        Int32,
        [0.0, 7.0],
        "",
        Failsafe,
        "What offboard setpoint loss does; without RC the stick modes (0–2) all hold position in POSCTL, as PX4 without sticks",
        action OffboardLossAction commander.offboard_loss_action
    ),
];

/// What the loss of the position estimate does (appended after the wind).
pub(super) static NAVIGATION_LOSS: &[ParamDef] = &[row!(
    "COM_POSCTL_NAVL",
    Int32,
    [0.0, 1.0],
    "",
    Failsafe,
    "Position lost in POSCTL: 0 Altitude mode (with sticks), 1 land; the AUTO modes and OFFBOARD always descend",
    flag commander.position_loss_lands
)];

/// The hold before a failsafe's return or landing (appended after the logger's).
pub(super) static DELAY: &[ParamDef] = &[row!(
    "COM_FAIL_ACT_T",
    Real32,
    [0.0, 25.0],
    "s",
    Failsafe,
    "Hold before a failsafe's return or landing, for the pilot to react (0: none)",
    value commander.fail_action_delay_s
)];
