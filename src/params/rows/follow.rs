//! Follow-me (AUTO.FOLLOW_TARGET): where around the target the vehicle flies, how high, how
//! fast, and how the target's reports are smoothed. MAVSDK's `follow_me.set_config` writes
//! these with the wire types PX4 declares (REAL32, `FLW_TGT_ALT_M` INT32).

use crate::guidance::FollowAltitude;
use crate::params::ParamDef;

/// Follow-me settings (appended after the stick rows).
pub(super) static FOLLOW: &[ParamDef] = &[
    row!(
        "FLW_TGT_HT",
        Real32,
        [8.0, 1000.0],
        "m",
        Navigation,
        "Follow-me height above home (FLW_TGT_ALT_M 0, 1) or above the target (2)",
        value commander.follow.height_m
    ),
    row!(
        "FLW_TGT_DST",
        Real32,
        [1.0, 100.0],
        "m",
        Navigation,
        "Follow-me horizontal distance to the target",
        value commander.follow.distance_m
    ),
    row!(
        "FLW_TGT_FA",
        Real32,
        [-180.0, 180.0],
        "deg",
        Navigation,
        "Follow-me position around the target from its course: 0 front, 90 right, 180 behind",
        degrees commander.follow.angle_rad
    ),
    row!(
        "FLW_TGT_ALT_M",
        Int32,
        [0.0, 2.0],
        "",
        Navigation,
        "Follow-me height reference: 0 home, 1 terrain (flat here: as 0), 2 the target's altitude",
        |s| match s.commander.follow.altitude {
            FollowAltitude::AboveHome => 0.0,
            FollowAltitude::AboveTerrain => 1.0,
            FollowAltitude::AboveTarget => 2.0,
        },
        |s, v| {
            s.commander.follow.altitude = match v as i32 {
                0 => FollowAltitude::AboveHome,
                1 => FollowAltitude::AboveTerrain,
                _ => FollowAltitude::AboveTarget,
            };
            Ok(())
        }
    ),
    row!(
        "FLW_TGT_MAX_VEL",
        Real32,
        [0.0, 20.0],
        "m/s",
        Navigation,
        "Follow-me horizontal speed cap (never above MPC_XY_VEL_MAX)",
        value commander.follow.max_speed_m_s
    ),
    row!(
        "FLW_TGT_RS",
        Real32,
        [0.0, 1.0],
        "",
        Navigation,
        "Smoothing of the target's reports: 0 takes each as it is, towards 1 smooths heavily",
        value commander.follow.responsiveness
    ),
];
