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

use super::auto_paths::AutoPaths;
use super::plans::Plans;
use super::{CommanderParams, Event};
use crate::guidance::fence_path::{self, FencePath};
use crate::guidance::{Geofence, Guidance, Track, TrackLeg};

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

/// A return: its phase and the points still to fly through.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Rtl {
    phase: RtlPhase,
    /// The points still to fly through round the geofence, the destination last [m].
    way: Vec<Vec3>,
}

impl Default for Rtl {
    fn default() -> Self {
        Self {
            phase: RtlPhase::Climb,
            way: Vec::new(),
        }
    }
}

/// What one AUTO.RTL tick changed.
#[derive(Debug, Clone, PartialEq, Default)]
pub(super) struct RtlStep {
    /// The guidance to fly from now on, when it changed.
    pub guidance: Option<Guidance>,
    /// An announcement for the next tick (a way round the fence or its absence).
    pub notice: Option<Event>,
}

impl Rtl {
    /// The height [m] (up, local NED origin) a return from `x` to the destination `to` [m]
    /// climbs to: the cone rule of the module docs, with the settings `p`.
    pub fn return_height(p: &CommanderParams, to: Vec3, x: &VehicleState) -> f64 {
        let (dest_up, now_up) = (-to.z, -x.pos_w.z);
        let d = (x.pos_w.xy() - to.xy()).norm();
        let (ret, accept) = (p.rtl_return_alt_m, p.mission.accept_m);
        let cone = p.rtl_cone_rad;
        let above = if cone <= 0.0 {
            ret
        } else if d <= accept {
            2.0 * d
        } else {
            let mut h = ret;
            if d <= p.rtl_min_dist_m {
                h = h.min(d / cone.tan());
            }
            h.max(2.0 * accept).min(ret)
        };
        now_up.max(dest_up + above)
    }

    /// A return starts: the climb first.
    pub fn start(&mut self) {
        self.phase = RtlPhase::Climb;
    }

    /// The phase the return is in.
    #[cfg(test)]
    pub fn phase(&self) -> RtlPhase {
        self.phase
    }

    /// One AUTO.RTL tick flying `guidance`: when a phase's path is flown, the next phase starts
    /// from here (`paths` plans it, `plans` gives the destination and the fence).
    pub fn advance(
        &mut self,
        paths: &AutoPaths,
        plans: &Plans,
        guidance: Guidance,
        x: &VehicleState,
        yaw: f64,
        t_s: f64,
    ) -> RtlStep {
        let mut step = RtlStep::default();
        // Entered on the ground: nothing to return from (PX4 does not take off for a return).
        if guidance == Guidance::Idle {
            return step;
        }
        let mut guidance = guidance;
        if self.phase == RtlPhase::Return {
            if let Some(on) = self.fly_on_round_fence(paths, &guidance, x, yaw) {
                guidance = on;
                step.guidance = Some(on);
            }
        }
        if !guidance.finished(t_s) {
            return step;
        }
        match self.phase {
            RtlPhase::Climb => {
                self.phase = RtlPhase::Return;
                let to = plans.rtl_destination(&x.pos_w, paths.params().rtl_type);
                let over = Vec3::new(to.x, to.y, x.pos_w.z);
                let (way, notice) = Self::way_round_fence(paths.params(), plans.geofence(), x, over);
                self.way = way;
                step.notice = notice;
                step.guidance = Some(match self.way.first() {
                    Some(first) => {
                        let leg = Self::leg(paths, x, *first, self.way.get(1).copied(), yaw);
                        Guidance::Track(Track::new(
                            x.pos_w,
                            x.vel_w,
                            yaw,
                            t_s,
                            leg,
                            paths.limits(paths.cruise_speed()),
                        ))
                    }
                    None => paths.path_to(x, over, yaw, paths.cruise_speed(), t_s),
                });
            }
            // A point round the fence stood on: the next one is taken up above.
            RtlPhase::Return if self.way.len() > 1 => {}
            RtlPhase::Return => {
                self.way.clear();
                self.phase = RtlPhase::Descend;
                step.guidance = Some(paths.descend(x, yaw, t_s));
            }
            RtlPhase::Descend => {}
        }
        step
    }

    /// The points a return from `x` flies through to `over` [m] (the destination at the return
    /// height, last), or none when it flies straight, with the announcement of a way round the
    /// fence or its absence. The margin is PX4's for a multicopter, 2 `NAV_ACC_RAD`.
    fn way_round_fence(
        p: &CommanderParams,
        fence: &Geofence,
        x: &VehicleState,
        over: Vec3,
    ) -> (Vec<Vec3>, Option<Event>) {
        let margin_m = 2.0 * p.mission.accept_m;
        let from = [x.pos_w.x, x.pos_w.y];
        match fence_path::plan(fence, from, [over.x, over.y], margin_m) {
            FencePath::Direct => (Vec::new(), None),
            FencePath::Around(points) => {
                let notice = Event::Notice {
                    text: AVOIDING_FENCE.into(),
                    critical: false,
                };
                let mut way: Vec<Vec3> = points.iter().map(|p| Vec3::new(p[0], p[1], over.z)).collect();
                way.push(over);
                (way, Some(notice))
            }
            FencePath::NoPath => {
                let notice = Event::Notice {
                    text: NO_FENCE_PATH.into(),
                    critical: true,
                };
                (Vec::new(), Some(notice))
            }
        }
    }

    /// On a way round the fence: once within `NAV_ACC_RAD` of the point flown to, the reference
    /// flies on to the next one without stopping (PX4 flies the points as waypoints); the
    /// guidance that does, if it is time.
    fn fly_on_round_fence(
        &mut self,
        paths: &AutoPaths,
        guidance: &Guidance,
        x: &VehicleState,
        yaw: f64,
    ) -> Option<Guidance> {
        let (Some(at), Guidance::Track(track)) = (self.way.first().copied(), guidance) else {
            return None;
        };
        if self.way.len() < 2 || (x.pos_w - at).xy().norm() > paths.params().mission.accept_m {
            return None;
        }
        let mut track = *track;
        self.way.remove(0);
        track.leg = Self::leg(paths, x, self.way[0], self.way.get(1).copied(), yaw);
        Some(Guidance::Track(track))
    }

    /// The leg to `to_w` [m], flown through towards `next_w` when there is one, heading for
    /// `to_w` (kept at `yaw` [rad] when nearly there).
    fn leg(paths: &AutoPaths, x: &VehicleState, to_w: Vec3, next_w: Option<Vec3>, yaw: f64) -> TrackLeg {
        let d = to_w - x.pos_w;
        let p = paths.params();
        TrackLeg {
            target_w: to_w,
            next_w,
            accept_m: p.mission.accept_m,
            yaw_rad: if d.xy().norm() > 1.0 { d.y.atan2(d.x) } else { yaw },
            cruise_m_s: paths.cruise_speed(),
            corner_gain: p.mission.corner_gain,
        }
    }
}

#[cfg(test)]
#[path = "rtl_tests.rs"]
mod tests;
