//! Geofence and battery failsafes (docs/mavlink.md §11.2, PX4 names and semantics). Pure: the
//! commander feeds the position relative to home, the uploaded fence's verdict on it and the
//! battery's remaining fraction each tick and gets back the failsafes that have just triggered,
//! each with the action to take.

use super::{GeofenceAction, LowBatteryAction};
use crate::guidance::geofence::ZoneBreach;
use crate::guidance::Geofence;
use crate::math::Vec3;

/// A breach ends only once the vehicle is this far inside every limit again [m], so that a
/// vehicle holding where it crossed a limit does not announce a new breach each time it
/// wavers across it.
pub const FENCE_CLEAR_MARGIN_M: f64 = 1.0;

/// Failsafe settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FailsafeParams {
    /// The geofence is on (`RP_GF_ENABLE` 1, the default): its limits and uploaded zones are
    /// checked before arming and acted on in flight; 0 switches all of it off (ArduCopter's
    /// `FENCE_ENABLE` 0).
    pub geofence_enabled: bool,
    /// Geofence breach action (`GF_ACTION`: 0 none, 1 warning, 2 hold, 3 return, 4 terminate,
    /// 5 land; default 2).
    pub geofence_action: GeofenceAction,
    /// Largest horizontal distance from home [m] (`GF_MAX_HOR_DIST`; 0 = no limit).
    pub geofence_max_hor_m: f64,
    /// Largest height above home [m] (`GF_MAX_VER_DIST`; 0 = no limit).
    pub geofence_max_ver_m: f64,
    /// Action at the critical battery level (`COM_LOW_BAT_ACT`: 0 warning, 2 land, 3 return
    /// then land at the emergency level; default 0).
    pub low_battery_action: LowBatteryAction,
    /// Low battery level, fraction remaining (`BAT_LOW_THR`, 0.15): a warning.
    pub battery_low: f64,
    /// Critical battery level (`BAT_CRIT_THR`, 0.07): `COM_LOW_BAT_ACT`.
    pub battery_critical: f64,
    /// Emergency battery level (`BAT_EMERGEN_THR`, 0.05): land whatever the action.
    pub battery_emergency: f64,
}

impl Default for FailsafeParams {
    fn default() -> Self {
        Self {
            geofence_enabled: true,
            geofence_action: GeofenceAction::Hold,
            geofence_max_hor_m: 0.0,
            geofence_max_ver_m: 0.0,
            low_battery_action: LowBatteryAction::Warn,
            battery_low: 0.15,
            battery_critical: 0.07,
            battery_emergency: 0.05,
        }
    }
}

/// What a failsafe makes the vehicle do.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FailsafeAction {
    /// Announce only.
    Warn,
    /// Hold position (AUTO.LOITER).
    Hold,
    /// Return to launch.
    Return,
    /// Land here.
    Land,
    /// Stop the motors (flight termination).
    Terminate,
}

/// What a failsafe's announcement is about, for a face that words failsafes its own way
/// (docs/ardupilot.md §2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FailsafeCause {
    /// The battery fell to this level.
    Battery(BatteryLevel),
    /// The geofence breached: which limits.
    Geofence(FenceLimits),
    /// The ground station's link lost (`NAV_DLL_ACT`).
    GcsLink,
    /// The position estimate lost.
    PositionLost,
    /// The position estimate valid again.
    PositionRegained,
    /// The position-loss failsafe switched to this mode (ALTCTL, or the landing).
    PositionAction(super::FlightMode),
    /// Anything else (a motor, the sticks, a fence plan the vehicle cannot use).
    Other,
}

/// Which geofence limits a breach crossed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FenceLimits {
    /// Higher than `GF_MAX_VER_DIST` above home.
    pub height: bool,
    /// Farther than `GF_MAX_HOR_DIST` from home.
    pub distance: bool,
    /// Outside an uploaded inclusion zone or inside an exclusion zone.
    pub zone: bool,
}

impl FenceLimits {
    /// The limits the vehicle at `rel_home_w` [m] from home (NED) crosses under `p`, with the
    /// uploaded fence's verdict `zone`.
    pub fn crossed(p: &FailsafeParams, rel_home_w: [f64; 3], zone: bool) -> Self {
        Self {
            height: p.geofence_max_ver_m > 0.0 && -rel_home_w[2] > p.geofence_max_ver_m,
            distance: p.geofence_max_hor_m > 0.0 && rel_home_w[0].hypot(rel_home_w[1]) > p.geofence_max_hor_m,
            zone,
        }
    }
}

/// A failsafe that has just triggered.
#[derive(Debug, Clone, PartialEq)]
pub struct Failsafe {
    /// What to do.
    pub action: FailsafeAction,
    /// What it is about.
    pub cause: FailsafeCause,
    /// The announcement (STATUSTEXT).
    pub text: String,
}

/// Battery state by threshold.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Default)]
pub enum BatteryLevel {
    /// Above `BAT_LOW_THR`.
    #[default]
    Ok,
    /// At or below `BAT_LOW_THR`.
    Low,
    /// At or below `BAT_CRIT_THR`.
    Critical,
    /// At or below `BAT_EMERGEN_THR`.
    Emergency,
}

/// Remembers which failsafes have fired, so each fires once per breach (a new breach after
/// the vehicle came back inside the fence, by [`FENCE_CLEAR_MARGIN_M`], fires again; battery
/// levels only go down).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FailsafeMonitor {
    fence_breached: bool,
    battery: BatteryLevel,
}

impl FailsafeMonitor {
    /// The battery level last seen.
    pub fn battery_level(&self) -> BatteryLevel {
        self.battery
    }

    /// True from a check that found the vehicle outside the geofence (`GF_MAX_HOR_DIST` /
    /// `GF_MAX_VER_DIST`, the uploaded zones) until one found it [`FENCE_CLEAR_MARGIN_M`] inside
    /// again: what SYS_STATUS reports as an unhealthy geofence.
    pub fn geofence_breached(&self) -> bool {
        self.fence_breached
    }

    /// Failsafes triggered by being at `rel_home_w` [m] from home (NED) with `battery_fraction`
    /// [0, 1] remaining. Only checked in flight: the caller passes `in_air`.
    pub fn check(
        &mut self,
        p: &FailsafeParams,
        rel_home_w: [f64; 3],
        battery_fraction: f64,
        in_air: bool,
    ) -> Vec<Failsafe> {
        let pos_w = Vec3::from(rel_home_w);
        self.check_with_fence(p, rel_home_w, &Geofence::default(), &pos_w, battery_fraction, in_air)
    }

    /// [`check`](Self::check) with the uploaded `fence` too, the vehicle at `pos_w` (local NED
    /// [m], the frame of the fence's zones).
    pub fn check_with_fence(
        &mut self,
        p: &FailsafeParams,
        rel_home_w: [f64; 3],
        fence: &Geofence,
        pos_w: &Vec3,
        battery_fraction: f64,
        in_air: bool,
    ) -> Vec<Failsafe> {
        let mut out = Vec::new();
        let level = battery_level(p, battery_fraction);
        if level > self.battery {
            self.battery = level;
            if in_air {
                out.extend(battery_failsafe(p, level, battery_fraction));
            }
        }
        let zone = fence.breach(pos_w);
        let limits = FenceLimits::crossed(p, rel_home_w, zone.is_some());
        let breach = fence_breach(p, rel_home_w, zone);
        let outside = breach.is_some();
        let action = fence_failsafe(p.geofence_action).filter(|_| outside && !self.fence_breached && in_air);
        if let (Some(action), Some(text)) = (action, breach) {
            let cause = FailsafeCause::Geofence(limits);
            out.push(Failsafe { action, cause, text });
        }
        if outside {
            self.fence_breached = true;
        } else if well_inside(p, rel_home_w, fence, pos_w) {
            self.fence_breached = false;
        }
        out
    }
}

/// Inside every limit by [`FENCE_CLEAR_MARGIN_M`]: below the distance limits by the margin, and
/// every point at the margin around `pos_w` (eight directions) inside the fence.
fn well_inside(p: &FailsafeParams, rel_home_w: [f64; 3], fence: &Geofence, pos_w: &Vec3) -> bool {
    if !p.geofence_enabled {
        return true;
    }
    let m = FENCE_CLEAR_MARGIN_M;
    let horizontal = rel_home_w[0].hypot(rel_home_w[1]);
    let height = -rel_home_w[2];
    let near_limit = (p.geofence_max_hor_m > 0.0 && horizontal + m > p.geofence_max_hor_m)
        || (p.geofence_max_ver_m > 0.0 && height + m > p.geofence_max_ver_m);
    let around = (0..8).map(|k| f64::from(k) * std::f64::consts::FRAC_PI_4);
    !near_limit
        && around
            .map(|a| pos_w + Vec3::new(m * a.cos(), m * a.sin(), 0.0))
            .all(|q| fence.contains(&q))
}

/// The announcement of a geofence breach at `rel_home_w` [m] from home (NED) with the uploaded
/// fence's verdict `zone`, or `None` inside every limit or with the fence off (`RP_GF_ENABLE` 0): `GF_MAX_HOR_DIST` and `GF_MAX_VER_DIST`
/// first (0 = no limit), then the zones (PX4 `Geofence::checkPointAgainstAllGeofences`).
pub fn fence_breach(p: &FailsafeParams, rel_home_w: [f64; 3], zone: Option<ZoneBreach>) -> Option<String> {
    if !p.geofence_enabled {
        return None;
    }
    let horizontal = rel_home_w[0].hypot(rel_home_w[1]);
    let height = -rel_home_w[2];
    if (p.geofence_max_hor_m > 0.0 && horizontal > p.geofence_max_hor_m)
        || (p.geofence_max_ver_m > 0.0 && height > p.geofence_max_ver_m)
    {
        return Some(format!(
            "Geofence breached ({horizontal:.1} m from home, {height:.1} m up; limits {} m / {} m)",
            p.geofence_max_hor_m, p.geofence_max_ver_m
        ));
    }
    zone.map(|z| format!("Geofence breached ({z})"))
}

/// What a breach does under `GF_ACTION` (`None`: nothing, not even an announcement).
fn fence_failsafe(action: GeofenceAction) -> Option<FailsafeAction> {
    match action {
        GeofenceAction::Disabled => None,
        GeofenceAction::Warn => Some(FailsafeAction::Warn),
        GeofenceAction::Hold => Some(FailsafeAction::Hold),
        GeofenceAction::Return => Some(FailsafeAction::Return),
        GeofenceAction::Terminate => Some(FailsafeAction::Terminate),
        GeofenceAction::Land => Some(FailsafeAction::Land),
    }
}

/// The level of `fraction` against the thresholds.
pub fn battery_level(p: &FailsafeParams, fraction: f64) -> BatteryLevel {
    if fraction <= p.battery_emergency {
        BatteryLevel::Emergency
    } else if fraction <= p.battery_critical {
        BatteryLevel::Critical
    } else if fraction <= p.battery_low {
        BatteryLevel::Low
    } else {
        BatteryLevel::Ok
    }
}

fn battery_failsafe(p: &FailsafeParams, level: BatteryLevel, fraction: f64) -> Option<Failsafe> {
    let percent = (fraction * 100.0).max(0.0);
    let (action, text) = match level {
        BatteryLevel::Ok => return None,
        BatteryLevel::Low => (FailsafeAction::Warn, format!("Low battery: {percent:.0}% remaining")),
        BatteryLevel::Critical => match p.low_battery_action {
            LowBatteryAction::Land => (
                FailsafeAction::Land,
                format!("Critical battery ({percent:.0}%): landing"),
            ),
            LowBatteryAction::Return => (
                FailsafeAction::Return,
                format!("Critical battery ({percent:.0}%): returning"),
            ),
            LowBatteryAction::Warn => (
                FailsafeAction::Warn,
                format!("Critical battery: {percent:.0}% remaining"),
            ),
        },
        BatteryLevel::Emergency => match p.low_battery_action {
            LowBatteryAction::Warn => (
                FailsafeAction::Warn,
                format!("Emergency battery: {percent:.0}% remaining"),
            ),
            LowBatteryAction::Land | LowBatteryAction::Return => (
                FailsafeAction::Land,
                format!("Emergency battery ({percent:.0}%): landing"),
            ),
        },
    };
    Some(Failsafe {
        action,
        cause: FailsafeCause::Battery(level),
        text,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fence(action: GeofenceAction) -> FailsafeParams {
        FailsafeParams {
            geofence_action: action,
            geofence_max_hor_m: 10.0,
            geofence_max_ver_m: 5.0,
            ..Default::default()
        }
    }

    #[test]
    fn fence_fires_once_per_breach_and_only_in_the_air() {
        let p = fence(GeofenceAction::Return);
        let mut m = FailsafeMonitor::default();
        assert!(m.check(&p, [9.0, 0.0, -4.0], 1.0, true).is_empty());
        let fired = m.check(&p, [8.0, 8.0, -4.0], 1.0, true);
        assert_eq!(fired.len(), 1);
        assert_eq!(fired[0].action, FailsafeAction::Return);
        assert!(fired[0].text.contains("11.3 m from home"), "{}", fired[0].text);
        assert!(m.check(&p, [8.0, 8.0, -4.0], 1.0, true).is_empty(), "once per breach");
        assert!(m.check(&p, [1.0, 0.0, -4.0], 1.0, true).is_empty());
        assert_eq!(
            m.check(&p, [0.0, 0.0, -6.0], 1.0, true)[0].action,
            FailsafeAction::Return,
            "too high"
        );
        let mut ground = FailsafeMonitor::default();
        assert!(ground.check(&p, [20.0, 0.0, 0.0], 1.0, false).is_empty());
    }

    #[test]
    fn a_fence_switched_off_is_neither_breached_nor_acted_on() {
        let off = FailsafeParams {
            geofence_enabled: false,
            ..fence(GeofenceAction::Return)
        };
        assert_eq!(fence_breach(&off, [20.0, 0.0, -9.0], None), None);
        let mut m = FailsafeMonitor::default();
        assert_eq!(
            m.check(&fence(GeofenceAction::Return), [20.0, 0.0, -4.0], 1.0, true)
                .len(),
            1
        );
        assert!(m.geofence_breached());
        assert!(m.check(&off, [20.0, 0.0, -4.0], 1.0, true).is_empty(), "RP_GF_ENABLE 0");
        assert!(!m.geofence_breached(), "switched off: no breach reported");
    }

    #[test]
    fn fence_actions_follow_gf_action_and_zero_limits_are_off() {
        let at = |action| FailsafeMonitor::default().check(&fence(action), [11.0, 0.0, 0.0], 1.0, true);
        assert_eq!(at(GeofenceAction::Warn)[0].action, FailsafeAction::Warn);
        assert_eq!(at(GeofenceAction::Hold)[0].action, FailsafeAction::Hold);
        assert_eq!(at(GeofenceAction::Terminate)[0].action, FailsafeAction::Terminate);
        assert_eq!(at(GeofenceAction::Land)[0].action, FailsafeAction::Land);
        assert!(at(GeofenceAction::Disabled).is_empty());
        let off = FailsafeParams::default();
        assert!(FailsafeMonitor::default()
            .check(&off, [1e4, 0.0, -1e3], 1.0, true)
            .is_empty());
    }

    #[test]
    fn an_uploaded_zone_breach_fires_once_until_well_inside_again() {
        use crate::guidance::geofence::{Shape, Zone};
        let p = fence(GeofenceAction::Land);
        let zones = Geofence {
            zones: vec![
                Zone {
                    inclusion: true,
                    shape: Shape::Circle {
                        center: [0.0, 0.0],
                        radius_m: 6.0,
                    },
                },
                Zone {
                    inclusion: false,
                    shape: Shape::Circle {
                        center: [-4.0, 0.0],
                        radius_m: 1.0,
                    },
                },
            ],
        };
        let mut m = FailsafeMonitor::default();
        let mut at = |n: f64| {
            let pos = Vec3::new(n, 0.0, -2.0);
            m.check_with_fence(&p, [n, 0.0, -2.0], &zones, &pos, 1.0, true)
        };
        let fired = at(6.1);
        assert_eq!(fired.len(), 1);
        assert_eq!(
            (fired[0].action, fired[0].text.as_str()),
            (FailsafeAction::Land, "Geofence breached (outside inclusion zone 1)")
        );
        // Wavering across the edge: the same breach; back 1 m inside ends it.
        for n in [5.9, 6.1, 5.5, 6.05] {
            assert!(at(n).is_empty(), "{n}");
        }
        assert!(at(4.9).is_empty());
        assert_eq!(at(6.2).len(), 1, "a new breach");
        assert!(at(0.0).is_empty());
        assert_eq!(at(-4.5)[0].text, "Geofence breached (inside exclusion zone 2)");
        assert!(m.geofence_breached());
    }

    #[test]
    fn battery_levels_fire_in_order_with_com_low_bat_act() {
        let p = FailsafeParams {
            low_battery_action: LowBatteryAction::Return,
            ..Default::default()
        };
        let mut m = FailsafeMonitor::default();
        let mut actions = Vec::new();
        for percent in (0..=100).rev() {
            for f in m.check(&p, [0.0; 3], f64::from(percent) / 100.0, true) {
                actions.push((percent, f.action));
            }
        }
        assert_eq!(
            actions,
            vec![
                (15, FailsafeAction::Warn),
                (7, FailsafeAction::Return),
                (5, FailsafeAction::Land)
            ]
        );
        assert_eq!(m.battery_level(), BatteryLevel::Emergency);
        // A battery that recovers (noise) does not re-arm the failsafes.
        assert!(m.check(&p, [0.0; 3], 0.5, true).is_empty());
        let warn_only = FailsafeParams::default();
        let mut m = FailsafeMonitor::default();
        let fired = m.check(&warn_only, [0.0; 3], 0.06, true);
        assert_eq!(
            (fired[0].action, fired[0].text.as_str()),
            (FailsafeAction::Warn, "Critical battery: 6% remaining")
        );
    }
}
