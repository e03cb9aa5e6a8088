//! Home and the uploaded plans in the commander ([`Plans`]), as PX4's navigator uses them:
//! which zones of an uploaded fence count (`Geofence::_updateFence`), the arming refusal outside
//! the fence (the commander's geofence pre-arm check) and where a return goes (`RTL_TYPE`,
//! `RTL::findRtlDestination`). The breach failsafe itself runs with the others
//! ([`super::reactions::FailsafeState`]).

use super::FailsafeCause;
use crate::control::VehicleState;
use crate::guidance::{Geofence, RallyPoints, RallyRule};
use crate::math::Vec3;

use super::failsafe::fence_breach;
use super::{Event, FailsafeParams, GeofenceAction, RtlType};

/// Announced for each uploaded zone home breaks (PX4's wording).
pub const ZONE_WITHOUT_HOME: &str = "Geofence invalid, doesn't contain Home position";
/// Announced for each uploaded zone the vehicle in flight breaks (PX4's wording).
pub const ZONE_WITHOUT_VEHICLE: &str = "Geofence invalid, doesn't contain current vehicle position";

/// Home, the fence and the rally points.
#[derive(Debug, Clone, PartialEq, Default)]
pub(super) struct Plans {
    /// The local NED point a return goes back to [m].
    home_w: Vec3,
    /// The uploaded fence's zones that count (PX4 leaves out those home breaks).
    geofence: Geofence,
    /// The uploaded rally points.
    rally: RallyPoints,
}

impl Plans {
    /// Home [m].
    pub fn home_w(&self) -> Vec3 {
        self.home_w
    }

    /// Moves home to `home_w` [m].
    pub fn set_home(&mut self, home_w: Vec3) {
        self.home_w = home_w;
    }

    /// The fence's zones in force.
    pub fn geofence(&self) -> &Geofence {
        &self.geofence
    }

    /// A new uploaded fence with the vehicle in `x`: a zone home breaks is left out, and so is,
    /// when `check_here` (in flight with `GF_ACTION` set), a zone the vehicle breaks now; the
    /// announcements of the zones left out.
    pub fn set_geofence(&mut self, fence: Geofence, x: &VehicleState, check_here: bool) -> Vec<Event> {
        let home = [self.home_w.x, self.home_w.y];
        let here = [x.pos_w.x, x.pos_w.y];
        let mut left_out = Vec::new();
        let mut zones = Vec::with_capacity(fence.zones.len());
        for zone in fence.zones {
            if !zone.allows(home) {
                left_out.push(Event::Failsafe(FailsafeCause::Other, ZONE_WITHOUT_HOME.into()));
            } else if check_here && !zone.allows(here) {
                left_out.push(Event::Failsafe(FailsafeCause::Other, ZONE_WITHOUT_VEHICLE.into()));
            } else {
                zones.push(zone);
            }
        }
        self.geofence = Geofence { zones };
        left_out
    }

    /// New rally points.
    pub fn set_rally_points(&mut self, rally: RallyPoints) {
        self.rally = rally;
    }

    /// The geofence breach at the vehicle's position, if any (distance limits and the zones in
    /// force); `None` also while `GF_ACTION` is 0, which switches the geofence off (PX4's pre-arm
    /// check only looks while it is set).
    pub fn arming_fence_breach(&self, p: &FailsafeParams, x: &VehicleState) -> Option<String> {
        if p.geofence_action == GeofenceAction::Disabled {
            return None;
        }
        let rel = x.pos_w - self.home_w;
        fence_breach(p, [rel.x, rel.y, rel.z], self.geofence.breach(&x.pos_w))
    }

    /// Where a return from `from_w` [m] goes (horizontally, local NED) under `RTL_TYPE`
    /// `rtl_type`: home, or a rally point closer by more than 2 m and (while home is a choice)
    /// over 10 m from home; type 1 prefers any rally point to home; type 5 knows only rally
    /// points and, without one, lands where it is; type 6, without a battery time remaining, is
    /// type 0.
    /// Rally points uploaded under ArduCopter's rule choose as ArduCopter does instead
    /// ([`RallyRule::Copter`]: `RTL_TYPE` is PX4's).
    pub fn rtl_destination(&self, from_w: &Vec3, rtl_type: RtlType) -> Vec3 {
        let home = self.home_w;
        if let RallyRule::Copter { limit_m, include_home } = self.rally.rule {
            return self
                .rally
                .copter_choice(from_w, &home, limit_m, include_home)
                .unwrap_or(home);
        }
        let rally = match rtl_type {
            RtlType::HomeOrRally | RtlType::Closest | RtlType::PrioritizeHome => {
                let to_home = (from_w.xy() - home.xy()).norm();
                self.rally.closest(from_w, to_home, Some(&home))
            }
            RtlType::RallyFirst => self.rally.closest(from_w, f64::INFINITY, Some(&home)),
            RtlType::RallyOnly => return self.rally.closest(from_w, f64::INFINITY, None).unwrap_or(*from_w),
        };
        rally.unwrap_or(home)
    }
}

#[cfg(test)]
mod tests {
    use super::super::script::{Script, GROUND_Z_M};
    use super::super::{CommanderParams, FlightMode, Outcome, Request};
    use super::*;
    use crate::guidance::geofence::{Shape, Zone};

    fn circle(center: [f64; 2], radius_m: f64, inclusion: bool) -> Zone {
        Zone {
            inclusion,
            shape: Shape::Circle { center, radius_m },
        }
    }

    fn fenced(action: GeofenceAction) -> Script {
        let mut s = Script::new(CommanderParams {
            failsafe: FailsafeParams {
                geofence_action: action,
                ..Default::default()
            },
            ..Default::default()
        });
        let fence = Geofence {
            zones: vec![circle([0.0, 0.0], 15.0, true), circle([-8.0, 0.0], 3.0, false)],
        };
        assert_eq!(s.request(Request::SetGeofence(fence)), Outcome::Accepted);
        s
    }

    fn to(north_m: f64, east_m: f64) -> Request {
        Request::Reposition {
            north_m: Some(north_m),
            east_m: Some(east_m),
            down_m: None,
            yaw_rad: None,
            speed_m_s: None,
            change_mode: true,
        }
    }

    fn failsafes(s: &Script) -> Vec<String> {
        let texts = s.events.iter().filter_map(|e| match e {
            Event::Failsafe(_, t) => Some(t.clone()),
            _ => None,
        });
        texts.collect()
    }

    #[test]
    fn leaving_an_inclusion_zone_runs_gf_action_once() {
        let mut s = fenced(GeofenceAction::Return);
        s.airborne(3.0);
        assert_eq!(s.request(to(40.0, 0.0)), Outcome::Accepted);
        assert!(s.fly_until(30.0, |s| s.c.mode() == FlightMode::ReturnToLaunch));
        assert!(s.x.pos_w.x > 15.0 && s.x.pos_w.x < 16.0, "{:?}", s.x.pos_w);
        assert_eq!(failsafes(&s), vec!["Geofence breached (outside inclusion zone 1)"]);
        assert!(s.until_disarmed(200.0), "returned home and landed");
        assert!(s.x.pos_w.xy().norm() < 1e-6);
        assert_eq!(failsafes(&s).len(), 1, "once per breach");
    }

    #[test]
    fn entering_an_exclusion_zone_holds() {
        let mut s = fenced(GeofenceAction::Hold);
        s.airborne(3.0);
        assert_eq!(s.request(to(-20.0, 0.0)), Outcome::Accepted);
        assert!(s.fly_until(30.0, |s| s.c.geofence_breached()));
        let at = s.x.pos_w;
        assert!((at.x + 5.0).abs() < 0.1, "at the keep-out circle: {at:?}");
        s.fly(5.0);
        assert!((s.x.pos_w - at).norm() < 1e-9, "holds where it breached");
        assert_eq!(failsafes(&s), vec!["Geofence breached (inside exclusion zone 2)"]);
    }

    #[test]
    fn arming_outside_the_fence_is_refused_unless_forced() {
        let mut s = fenced(GeofenceAction::Warn);
        s.airborne(3.0);
        assert_eq!(s.request(to(25.0, 0.0)), Outcome::Accepted);
        s.fly(15.0);
        assert_eq!(failsafes(&s).len(), 1, "warned only");
        assert_eq!(s.request(Request::Land), Outcome::Accepted);
        assert!(s.until_disarmed(60.0));
        let refused = Outcome::TemporarilyRejected("Arming denied: vehicle outside geofence".into());
        assert_eq!(s.request(Request::Arm { force: false }), refused);
        assert_eq!(s.request(Request::Arm { force: true }), Outcome::Accepted);
        // With GF_ACTION 0 the fence is off.
        let mut off = fenced(GeofenceAction::Disabled);
        off.x.pos_w = Vec3::new(25.0, 0.0, GROUND_Z_M);
        assert_eq!(off.request(Request::Arm { force: false }), Outcome::Accepted);
    }

    #[test]
    fn zones_that_home_or_the_flying_vehicle_break_are_left_out() {
        let mut s = fenced(GeofenceAction::Hold);
        let far = Geofence {
            zones: vec![circle([100.0, 0.0], 10.0, true), circle([0.0, 0.0], 5.0, false)],
        };
        assert_eq!(s.request(Request::SetGeofence(far)), Outcome::Accepted);
        assert!(s.c.plans.geofence.is_empty());
        assert_eq!(
            failsafes(&{
                s.step();
                s
            }),
            vec![ZONE_WITHOUT_HOME, ZONE_WITHOUT_HOME]
        );
        let mut s = fenced(GeofenceAction::Hold);
        s.airborne(3.0);
        assert_eq!(s.request(to(10.0, 0.0)), Outcome::Accepted);
        s.fly(10.0);
        let here_out = Geofence {
            zones: vec![circle([0.0, 0.0], 5.0, true), circle([0.0, 0.0], 50.0, true)],
        };
        assert_eq!(s.request(Request::SetGeofence(here_out)), Outcome::Accepted);
        assert_eq!(s.c.plans.geofence.zones, vec![circle([0.0, 0.0], 50.0, true)]);
        s.step();
        assert_eq!(failsafes(&s), vec![ZONE_WITHOUT_VEHICLE]);
    }

    #[test]
    fn rtl_type_picks_home_or_a_rally_point() {
        let mut s = Script::new(CommanderParams::default());
        let rally = RallyPoints {
            points_w: vec![Vec3::new(40.0, 0.0, -5.0), Vec3::new(0.0, 5.0, 0.0)],
            ..Default::default()
        };
        assert_eq!(s.request(Request::SetRallyPoints(rally)), Outcome::Accepted);
        let dest = |s: &mut Script, t: RtlType, from: Vec3| {
            s.c.params.rtl_type = t;
            s.c.plans.rtl_destination(&from, s.c.params.rtl_type)
        };
        let near_rally = Vec3::new(30.0, 0.0, -3.0);
        let near_home = Vec3::new(8.0, 0.0, -3.0);
        assert_eq!(
            dest(&mut s, RtlType::HomeOrRally, near_rally),
            Vec3::new(40.0, 0.0, -5.0)
        );
        assert_eq!(dest(&mut s, RtlType::HomeOrRally, near_home), Vec3::zeros());
        assert_eq!(dest(&mut s, RtlType::Closest, near_home), Vec3::zeros());
        // No battery time remaining: type 6 chooses as type 0.
        assert_eq!(dest(&mut s, RtlType::PrioritizeHome, near_home), Vec3::zeros());
        assert_eq!(
            dest(&mut s, RtlType::PrioritizeHome, near_rally),
            Vec3::new(40.0, 0.0, -5.0)
        );
        assert_eq!(dest(&mut s, RtlType::RallyFirst, near_home), Vec3::new(40.0, 0.0, -5.0));
        assert_eq!(
            dest(&mut s, RtlType::RallyOnly, near_home),
            Vec3::new(0.0, 5.0, 0.0),
            "the point by home counts"
        );
        s.request(Request::SetRallyPoints(RallyPoints::default()));
        assert_eq!(dest(&mut s, RtlType::RallyOnly, near_home), near_home, "lands here");
        assert_eq!(dest(&mut s, RtlType::RallyFirst, near_home), Vec3::zeros());
    }

    #[test]
    fn a_fence_keeps_the_zones_home_and_a_checked_vehicle_are_inside() {
        let mut plans = Plans::default();
        plans.set_home(Vec3::new(0.0, 0.0, 0.0));
        let x = crate::control::VehicleState {
            t_s: 0.0,
            pos_w: Vec3::new(20.0, 0.0, -5.0),
            vel_w: Vec3::zeros(),
            r_wb: crate::math::Mat3::identity(),
            omega_b: Vec3::zeros(),
        };
        let fence = || Geofence {
            zones: vec![
                circle([0.0, 0.0], 50.0, true),
                circle([100.0, 0.0], 5.0, true),
                circle([0.0, 0.0], 10.0, true),
            ],
        };
        let notices = plans.set_geofence(fence(), &x, false);
        assert_eq!(
            notices,
            vec![Event::Failsafe(FailsafeCause::Other, ZONE_WITHOUT_HOME.into())]
        );
        assert_eq!(plans.geofence().zones.len(), 2);
        let notices = plans.set_geofence(fence(), &x, true);
        assert_eq!(
            notices,
            vec![
                Event::Failsafe(FailsafeCause::Other, ZONE_WITHOUT_HOME.into()),
                Event::Failsafe(FailsafeCause::Other, ZONE_WITHOUT_VEHICLE.into())
            ]
        );
        assert_eq!(plans.geofence().zones, vec![circle([0.0, 0.0], 50.0, true)]);
        let p = FailsafeParams {
            geofence_action: GeofenceAction::Hold,
            ..Default::default()
        };
        assert_eq!(plans.arming_fence_breach(&p, &x), None);
        let outside = crate::control::VehicleState {
            pos_w: Vec3::new(60.0, 0.0, -5.0),
            ..x
        };
        assert!(plans.arming_fence_breach(&p, &outside).is_some());
        let off = FailsafeParams {
            geofence_action: GeofenceAction::Disabled,
            ..Default::default()
        };
        assert_eq!(plans.arming_fence_breach(&off, &outside), None, "GF_ACTION 0: off");
        let switched_off = FailsafeParams {
            geofence_enabled: false,
            ..p
        };
        assert_eq!(
            plans.arming_fence_breach(&switched_off, &outside),
            None,
            "RP_GF_ENABLE 0: off"
        );
    }
}
