//! AUTO.RTL's phases: climb to the return altitude (or stay higher), fly over the destination
//! `RTL_TYPE` chooses (home or a rally point) at that height, then descend and land there.
//!
//! The return altitude, as PX4's multicopter return computes it, with d the horizontal distance
//! to the destination and h heights above it:
//! ```text
//! d ≤ NAV_ACC_RAD:  h = 2 d
//! else:             h = RTL_RETURN_ALT, lowered to d / tan(RTL_CONE_ANG) when d ≤ RTL_MIN_DIST,
//!                   and at least 2 NAV_ACC_RAD
//! h_return = max(h_now, min(h, RTL_RETURN_ALT))     (RTL_CONE_ANG 0: max(h_now, RTL_RETURN_ALT))
//! ```
//! so a return asked right above home lands where it is instead of climbing 60 m first.
//!
//! With a geofence, the flight over the destination goes round its zones as PX4's navigator's
//! RTL geofence avoidance does: at the top of the climb [`fence_path::plan`] looks for the
//! shortest way keeping 2 `NAV_ACC_RAD` off every zone; its points are flown through as a
//! mission's waypoints are (the reference keeps its speed round each corner), then the
//! destination is flown to and landed on. Without a way inside the fence the return flies
//! straight, ignoring it, and says so (PX4's fallback).

use crate::control::VehicleState;
use crate::math::Vec3;

use super::{Commander, Event};
use crate::navigation::fence_path::{self, FencePath};
use crate::navigation::{Guidance, Track, TrackLeg};

/// Where a return is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum RtlPhase {
    /// Climbing to the return altitude.
    Climb,
    /// Flying over the destination.
    Return,
    /// Descending to land at the destination.
    Descend,
}

/// Announced when the return goes round the fence (PX4's wording).
pub const AVOIDING_FENCE: &str = "RTL: avoiding geofence";
/// Announced when no way round the fence exists (PX4's wording).
pub const NO_FENCE_PATH: &str = "RTL: no geofence avoidance path; flying directly";

impl Commander {
    /// The height [m] (up, local NED origin) a return from `x` climbs to: the cone rule above,
    /// about the destination `RTL_TYPE` chooses.
    pub(super) fn rtl_return_height(&self, x: &VehicleState) -> f64 {
        let to = self.rtl_destination(&x.pos_w);
        let (dest_up, now_up) = (-to.z, -x.pos_w.z);
        let d = (x.pos_w.xy() - to.xy()).norm();
        let (ret, accept) = (self.params.rtl_return_alt_m, self.params.mission.accept_m);
        let cone = self.params.rtl_cone_rad;
        let above = if cone <= 0.0 {
            ret
        } else if d <= accept {
            2.0 * d
        } else {
            let mut h = ret;
            if d <= self.params.rtl_min_dist_m {
                h = h.min(d / cone.tan());
            }
            h.max(2.0 * accept).min(ret)
        };
        now_up.max(dest_up + above)
    }

    /// One AUTO.RTL tick: when a phase's path is flown, the next phase starts from here.
    pub(super) fn advance_rtl(&mut self, x: &VehicleState, yaw: f64, t_s: f64) {
        // Entered on the ground: nothing to return from (PX4 does not take off for a return).
        if self.guidance == Guidance::Idle {
            return;
        }
        if self.rtl_phase == RtlPhase::Return {
            self.fly_on_round_fence(x, yaw);
        }
        if !self.guidance.finished(t_s) {
            return;
        }
        match self.rtl_phase {
            RtlPhase::Climb => {
                self.rtl_phase = RtlPhase::Return;
                let to = self.rtl_destination(&x.pos_w);
                let over = Vec3::new(to.x, to.y, x.pos_w.z);
                self.rtl_way = self.way_round_fence(x, over);
                self.guidance = match self.rtl_way.first() {
                    Some(first) => {
                        let leg = self.rtl_leg(x, *first, self.rtl_way.get(1).copied(), yaw);
                        Guidance::Track(Track::new(
                            x.pos_w,
                            x.vel_w,
                            yaw,
                            t_s,
                            leg,
                            self.limits(self.cruise_speed()),
                        ))
                    }
                    None => self.path_to(x, over, yaw, self.cruise_speed(), t_s),
                };
            }
            // A point round the fence stood on: the next one is taken up above.
            RtlPhase::Return if self.rtl_way.len() > 1 => {}
            RtlPhase::Return => {
                self.rtl_way.clear();
                self.rtl_phase = RtlPhase::Descend;
                self.guidance = self.descend(x, yaw, t_s);
            }
            RtlPhase::Descend => {}
        }
    }

    /// The points a return from `x` flies through to `over` [m] (the destination at the return
    /// height, last), or none when it flies straight; announces a way round the fence or its
    /// absence. The margin is PX4's for a multicopter, 2 `NAV_ACC_RAD`.
    fn way_round_fence(&mut self, x: &VehicleState, over: Vec3) -> Vec<Vec3> {
        let margin_m = 2.0 * self.params.mission.accept_m;
        let from = [x.pos_w.x, x.pos_w.y];
        match fence_path::plan(&self.geofence, from, [over.x, over.y], margin_m) {
            FencePath::Direct => Vec::new(),
            FencePath::Around(points) => {
                self.pending.push(Event::Notice {
                    text: AVOIDING_FENCE.into(),
                    critical: false,
                });
                let mut way: Vec<Vec3> = points.iter().map(|p| Vec3::new(p[0], p[1], over.z)).collect();
                way.push(over);
                way
            }
            FencePath::NoPath => {
                self.pending.push(Event::Notice {
                    text: NO_FENCE_PATH.into(),
                    critical: true,
                });
                Vec::new()
            }
        }
    }

    /// On a way round the fence: once within `NAV_ACC_RAD` of the point flown to, the reference
    /// flies on to the next one without stopping (PX4 flies the points as waypoints).
    fn fly_on_round_fence(&mut self, x: &VehicleState, yaw: f64) {
        let (Some(at), Guidance::Track(track)) = (self.rtl_way.first().copied(), &self.guidance) else {
            return;
        };
        if self.rtl_way.len() < 2 || (x.pos_w - at).xy().norm() > self.params.mission.accept_m {
            return;
        }
        let mut track = *track;
        self.rtl_way.remove(0);
        track.leg = self.rtl_leg(x, self.rtl_way[0], self.rtl_way.get(1).copied(), yaw);
        self.guidance = Guidance::Track(track);
    }

    /// The leg to `to_w` [m], flown through towards `next_w` when there is one, heading for
    /// `to_w` (kept at `yaw` [rad] when nearly there).
    fn rtl_leg(&self, x: &VehicleState, to_w: Vec3, next_w: Option<Vec3>, yaw: f64) -> TrackLeg {
        let d = to_w - x.pos_w;
        TrackLeg {
            target_w: to_w,
            next_w,
            accept_m: self.params.mission.accept_m,
            yaw_rad: if d.xy().norm() > 1.0 { d.y.atan2(d.x) } else { yaw },
            cruise_m_s: self.cruise_speed(),
            corner_gain: self.params.mission.corner_gain,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::script::{Script, GROUND_Z_M};
    use super::super::{CommanderParams, Event, FlightMode, GeofenceAction, Outcome, Request};
    use crate::math::Vec3;
    use crate::navigation::geofence::{Shape, Zone};
    use crate::navigation::{Geofence, RallyPoints};

    fn params() -> CommanderParams {
        CommanderParams {
            rtl_return_alt_m: 15.0,
            ..Default::default()
        }
    }

    fn reposition(s: &mut Script, north_m: Option<f64>, east_m: Option<f64>, down_m: Option<f64>) {
        let to = Request::Reposition {
            north_m,
            east_m,
            down_m,
            yaw_rad: None,
            speed_m_s: None,
            change_mode: true,
        };
        assert_eq!(s.request(to), Outcome::Accepted);
        s.fly(20.0);
    }

    #[test]
    fn rtl_climbs_to_rtl_return_alt_returns_home_and_lands() {
        let mut s = Script::new(params());
        s.airborne(3.0);
        reposition(&mut s, Some(20.0), Some(10.0), None);
        s.events.clear();
        assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
        assert_eq!(s.c.mode(), FlightMode::ReturnToLaunch);
        // Straight up first, to the return altitude above home.
        let start_xy = Vec3::new(20.0, 10.0, 0.0).xy();
        let mut climbed_in_place = true;
        assert!(s.fly_until(30.0, |s| {
            climbed_in_place &= (s.x.pos_w.xy() - start_xy).norm() < 1e-9;
            s.x.pos_w.z < -15.0 + 1e-6
        }));
        assert!(climbed_in_place, "climbs before it turns home");
        let mut highest: f64 = 0.0;
        let landed = s.fly_until(200.0, |s| {
            highest = highest.max(-s.x.pos_w.z);
            !s.c.armed()
        });
        assert!(landed, "returned, landed and disarmed: {:?}", s.events);
        assert!((highest - 15.0).abs() < 1e-6, "returned at RTL_RETURN_ALT: {highest} m");
        assert!(
            (s.x.pos_w - Vec3::new(0.0, 0.0, GROUND_Z_M)).norm() < 1e-4,
            "home is nearer: {:?}",
            s.x.pos_w
        );
        assert_eq!(s.events, vec![Event::Landed, Event::Disarmed("landed")]);
    }

    #[test]
    fn close_to_home_the_cone_lowers_the_return_altitude() {
        // RTL_RETURN_ALT 15, cone 45°, RTL_MIN_DIST 10, NAV_ACC_RAD 2; 3 m up.
        for (north_m, expected_m) in [(0.0, 3.0), (1.5, 3.0), (8.0, 8.0), (30.0, 15.0)] {
            let mut s = Script::new(params());
            s.airborne(3.0);
            if north_m > 0.0 {
                reposition(&mut s, Some(north_m), None, None);
            }
            assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
            let mut highest: f64 = 0.0;
            assert!(s.fly_until(200.0, |s| {
                highest = highest.max(-s.x.pos_w.z);
                !s.c.armed()
            }));
            assert!(
                (highest - expected_m).abs() < 1e-3,
                "{north_m} m out: climbed to {highest} m"
            );
            assert!(s.x.pos_w.xy().norm() < 1e-3, "landed at home: {:?}", s.x.pos_w);
        }
    }

    #[test]
    fn a_return_asked_on_the_ground_does_not_take_off() {
        let mut s = Script::new(params());
        assert_eq!(s.request(Request::Arm { force: false }), Outcome::Accepted);
        assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
        s.fly(5.0);
        assert!(
            (s.x.pos_w.z - GROUND_Z_M).abs() < 1e-9,
            "stayed on the ground: {:?}",
            s.x.pos_w
        );
        assert!(s.until_disarmed(15.0), "auto-disarm without a take-off: {:?}", s.events);
    }

    #[test]
    fn rtl_with_a_rally_point_nearer_than_home_lands_there() {
        let mut s = Script::new(params());
        let rally = RallyPoints {
            points_w: vec![Vec3::new(40.0, 10.0, 0.0), Vec3::new(-60.0, 0.0, 0.0)],
        };
        assert_eq!(s.request(Request::SetRallyPoints(rally)), Outcome::Accepted);
        s.airborne(3.0);
        reposition(&mut s, Some(30.0), Some(0.0), None);
        assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
        assert!(s.until_disarmed(200.0), "{:?}", s.events);
        let landed_at = Vec3::new(40.0, 10.0, GROUND_Z_M);
        assert!((s.x.pos_w - landed_at).norm() < 1e-6, "{:?}", s.x.pos_w);
        // From near home, home is closer: it lands at home.
        s.airborne(3.0);
        reposition(&mut s, Some(-5.0), Some(5.0), None);
        assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
        assert!(s.until_disarmed(200.0));
        assert!(
            (s.x.pos_w - Vec3::new(0.0, 0.0, GROUND_Z_M)).norm() < 1e-4,
            "home is nearer: {:?}",
            s.x.pos_w
        );
    }

    #[test]
    fn rtl_above_the_return_altitude_keeps_its_height_and_lands_at_a_moved_home() {
        let mut s = Script::new(params());
        s.airborne(3.0);
        reposition(&mut s, Some(5.0), Some(5.0), Some(-20.0));
        assert_eq!(
            s.request(Request::SetHome(Some(Vec3::new(-4.0, 2.0, 0.0)))),
            Outcome::Accepted
        );
        assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
        let home_xy = Vec3::new(-4.0, 2.0, 0.0).xy();
        let mut heights = (f64::MAX, 0.0_f64);
        let over_home = s.fly_until(60.0, |s| {
            heights = (heights.0.min(-s.x.pos_w.z), heights.1.max(-s.x.pos_w.z));
            (s.x.pos_w.xy() - home_xy).norm() < 1e-6
        });
        assert!(over_home);
        assert!(
            (heights.0 - 20.0).abs() < 1e-6 && (heights.1 - 20.0).abs() < 1e-6,
            "{heights:?}"
        );
        assert!(s.until_disarmed(120.0));
        assert!(
            (s.x.pos_w - Vec3::new(-4.0, 2.0, GROUND_Z_M)).norm() < 1e-6,
            "{:?}",
            s.x.pos_w
        );
    }

    /// An exclusion square and circle between the vehicle and home, inside an inclusion square.
    fn fence_in_the_way() -> Geofence {
        let square = |inclusion, c: [f64; 2], h: f64| Zone {
            inclusion,
            shape: Shape::Polygon(vec![
                [c[0] - h, c[1] - h],
                [c[0] + h, c[1] - h],
                [c[0] + h, c[1] + h],
                [c[0] - h, c[1] + h],
            ]),
        };
        Geofence {
            zones: vec![
                square(true, [40.0, 0.0], 70.0),
                square(false, [55.0, 5.0], 10.0),
                Zone {
                    inclusion: false,
                    shape: Shape::Circle {
                        center: [25.0, -8.0],
                        radius_m: 8.0,
                    },
                },
            ],
        }
    }

    #[test]
    fn rtl_flies_round_exclusion_zones_in_the_way_and_lands_home() {
        let fence = fence_in_the_way();
        let mut s = Script::new(params());
        assert_eq!(s.request(Request::SetGeofence(fence.clone())), Outcome::Accepted);
        s.airborne(3.0);
        // Out past the zones, east of them.
        for (north_m, east_m) in [(0.0, 30.0), (90.0, 30.0), (90.0, 0.0)] {
            reposition(&mut s, Some(north_m), Some(east_m), None);
        }
        assert!((s.x.pos_w.xy() - Vec3::new(90.0, 0.0, 0.0).xy()).norm() < 1e-6);
        assert!(
            !s.events.iter().any(|e| matches!(e, Event::Failsafe(_))),
            "{:?}",
            s.events
        );
        s.events.clear();
        assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
        let (mut closest, mut farthest_off_line) = (f64::INFINITY, 0.0_f64);
        let landed = s.fly_until(300.0, |s| {
            let p = [s.x.pos_w.x, s.x.pos_w.y];
            for zone in &fence.zones {
                assert!(zone.allows(p), "{p:?} breaches the fence");
            }
            let off_zone = match &fence.zones[1].shape {
                Shape::Polygon(v) => {
                    let dn = (v[0][0] - p[0]).max(p[0] - v[2][0]).max(0.0);
                    let de = (v[0][1] - p[1]).max(p[1] - v[2][1]).max(0.0);
                    dn.hypot(de)
                }
                Shape::Circle { .. } => f64::INFINITY,
            };
            closest = closest.min(off_zone);
            farthest_off_line = farthest_off_line.max(p[1].abs());
            !s.c.armed()
        });
        assert!(landed, "{:?}", s.events);
        assert!(
            (s.x.pos_w - Vec3::new(0.0, 0.0, GROUND_Z_M)).norm() < 1e-3,
            "landed home: {:?}",
            s.x.pos_w
        );
        // NAV_ACC_RAD 2: a 4 m margin, cut by less than its half at the corners flown through.
        assert!(closest > 2.0, "kept {closest} m off the square");
        // Round the square's west side (5 m off the line, a 4 m margin), then east of the circle.
        assert!(
            farthest_off_line > 8.9,
            "went round: {farthest_off_line} m off the straight line"
        );
        assert_eq!(
            s.events.first(),
            Some(&Event::Notice {
                text: super::AVOIDING_FENCE.into(),
                critical: false
            })
        );
        // Without the fence the same return flies straight.
        let mut s = Script::new(params());
        s.airborne(3.0);
        reposition(&mut s, Some(90.0), Some(0.0), None);
        assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
        let mut off_line = 0.0_f64;
        assert!(s.fly_until(300.0, |s| {
            off_line = off_line.max(s.x.pos_w.y.abs());
            !s.c.armed()
        }));
        assert!(off_line < 1e-6, "{off_line}");
    }

    #[test]
    fn rtl_without_a_way_inside_the_fence_flies_straight_and_says_so() {
        // A wall across the whole inclusion zone between the vehicle and home.
        let mut fence = fence_in_the_way();
        fence.zones.truncate(1);
        fence.zones.push(Zone {
            inclusion: false,
            shape: Shape::Polygon(vec![[45.0, -80.0], [55.0, -80.0], [55.0, 80.0], [45.0, 80.0]]),
        });
        let mut p = params();
        p.failsafe.geofence_action = GeofenceAction::Warn;
        let mut s = Script::new(p);
        s.airborne(3.0);
        reposition(&mut s, Some(90.0), Some(0.0), None);
        // Uploaded in flight with GF_ACTION 1 (warn): both zones count.
        assert_eq!(s.request(Request::SetGeofence(fence)), Outcome::Accepted);
        s.events.clear();
        assert_eq!(s.request(Request::ReturnToLaunch), Outcome::Accepted);
        assert!(s.until_disarmed(300.0), "{:?}", s.events);
        assert!(
            (s.x.pos_w - Vec3::new(0.0, 0.0, GROUND_Z_M)).norm() < 1e-3,
            "{:?}",
            s.x.pos_w
        );
        assert!(
            s.events.contains(&Event::Notice {
                text: super::NO_FENCE_PATH.into(),
                critical: true
            }),
            "{:?}",
            s.events
        );
    }
}
