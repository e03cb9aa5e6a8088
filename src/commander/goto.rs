//! DO_REPOSITION and the GOTO mode (PX4's multicopter Goto: NAVIGATION_STATE_GOTO, AUTO sub
//! mode 21). What a reposition does follows PX4's commander ([`RepositionAction`]):
//! - with the mode-change flag, a horizontal target is flown in GOTO, and so is a height or a
//!   heading alone while in GOTO (GOTO's target keeps its other coordinates); anything else
//!   holds in AUTO.LOITER (every coordinate unset: hold here, a pause);
//! - without it, AUTO.LOITER flies to the target and holds there in AUTO.LOITER, GOTO takes it as
//!   its new target, and any other mode refuses it (DENIED).
//!
//! GOTO flies on a moving reference (the one-leg [`Track`] missions fly, so that a new target or
//! speed changes its course without a stop), with the heading given or else towards the target
//! while farther than `NAV_ACC_RAD` (PX4's `MPC_YAW_MODE` 0; the heading stays once there), and
//! then holds on the target, still in GOTO. Its horizontal speed is PX4's GotoControl's: the
//! reposition's or DO_CHANGE_SPEED's, applied at once, within `MPC_XY_CRUISE` (the default), with
//! the horizontal acceleration scaled down alike once the reference is within that speed:
//!
//! ```text
//! v_goto = min(v_cmd or MPC_XY_CRUISE, MPC_XY_CRUISE),   a_xy = MPC_ACC_HOR · v_goto / MPC_XY_CRUISE   (|v_ref,xy| ≤ v_goto)
//! ```
//! with `MPC_XY_CRUISE` itself within `MPC_XY_VEL_MAX`. The reference's acceleration is not
//! jerk-limited (PX4's GotoControl smooths it with `MPC_JERK_AUTO`), so a real vehicle overshoots
//! the speed a little as it does on a mission leg.
//!
//! A new target forgets DO_CHANGE_SPEED's speed unless it brings one (PX4's navigator resets the
//! cruising speed). Entered without a fresh target (a pilot's mode given back after a failsafe's
//! hold), GOTO holds where the vehicle is, as PX4's does. Pure.

use crate::control::VehicleState;
use crate::guidance::{Track, TrackLeg};
use crate::math::{euler_zyx, Vec3};

use super::auto_paths::AutoPaths;
use super::{FlightMode, Outcome};

/// What a DO_REPOSITION does (PX4's commander).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum RepositionAction {
    /// Fly to the target in GOTO: entered, or its target changed.
    Goto,
    /// Enter AUTO.LOITER and fly to the target there (every coordinate unset: hold here).
    Hold,
    /// Fly to the target in the AUTO.LOITER already flown.
    InHold,
    /// Refused: no mode change asked, and neither AUTO.LOITER nor GOTO to fly it in.
    Refused,
}

impl RepositionAction {
    /// What a reposition asking (`change_mode`) for a mode change does in `mode`, when it gives a
    /// `horizontal` target (north or east) and a `height_or_heading`.
    pub(super) fn decide(mode: FlightMode, change_mode: bool, horizontal: bool, height_or_heading: bool) -> Self {
        match (change_mode, mode) {
            (true, _) if horizontal || (mode == FlightMode::Goto && height_or_heading) => Self::Goto,
            (true, _) => Self::Hold,
            (false, FlightMode::Goto) => Self::Goto,
            (false, FlightMode::Loiter) => Self::InHold,
            (false, _) => Self::Refused,
        }
    }
}

/// One DO_REPOSITION's target (NED metres and radians; `None` = unset) and speed [m/s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct RepositionTarget {
    /// North, east, down [m].
    pub ned_m: [Option<f64>; 3],
    /// Heading [rad].
    pub yaw_rad: Option<f64>,
    /// Horizontal speed [m/s].
    pub speed_m_s: Option<f64>,
}

impl RepositionTarget {
    /// The point aimed at: each unset coordinate taken from `base_w` [m].
    fn point(&self, base_w: Vec3) -> Vec3 {
        let [n, e, d] = self.ned_m;
        Vec3::new(n.unwrap_or(base_w.x), e.unwrap_or(base_w.y), d.unwrap_or(base_w.z))
    }

    /// The reposition gives a horizontal target (north or east).
    pub fn horizontal(&self) -> bool {
        let [n, e, _] = self.ned_m;
        n.is_some() || e.is_some()
    }

    /// The reposition gives a height or a heading.
    pub fn height_or_heading(&self) -> bool {
        self.ned_m[2].is_some() || self.yaw_rad.is_some()
    }

    /// The point [m] a reposition flies to from `base_w` [m] (unset coordinates taken from it),
    /// refused when not finite.
    pub fn point_from(&self, base_w: Vec3) -> Result<Vec3, Outcome> {
        let to = self.point(base_w);
        if !to.iter().all(|v| v.is_finite()) {
            return Err(Outcome::Denied("Reposition refused: bad target".into()));
        }
        Ok(to)
    }

    /// GOTO's heading [rad] flying from `x` to `to` [m]: the one given, else towards the target
    /// while farther than `accept_m` [m], else the running track's (`running`) or the vehicle's.
    pub fn goto_heading(&self, to: Vec3, running: Option<Track>, x: &VehicleState, accept_m: f64) -> f64 {
        let yaw = euler_zyx(&x.r_wb).z;
        let towards = to - x.pos_w;
        match self.yaw_rad {
            Some(h) => h,
            None if towards.xy().norm() > accept_m => towards.y.atan2(towards.x),
            None => running.map_or(yaw, |t| t.leg.yaw_rad),
        }
    }
}

impl AutoPaths<'_> {
    /// `MPC_XY_CRUISE` as flown [m/s]: within `MPC_XY_VEL_MAX`, which caps it.
    fn goto_cruise(&self) -> f64 {
        let p = self.params();
        p.cruise_speed_m_s.min(p.motion.horizontal_m_s)
    }

    /// GOTO's horizontal speed [m/s]: the reposition's or DO_CHANGE_SPEED's, else
    /// `MPC_XY_CRUISE`, within `MPC_XY_CRUISE`.
    fn goto_speed(&self) -> f64 {
        self.cruise_speed().min(self.goto_cruise())
    }

    /// GOTO's track from `x` to `to_w` [m] at `heading` [rad]: the running one (`running`) with
    /// the new leg, keeping the reference's motion, else a new one from the vehicle at heading
    /// `yaw` [rad]; paced by [`Self::pace_goto`].
    pub fn goto_track(
        &self,
        running: Option<Track>,
        to_w: Vec3,
        heading: f64,
        x: &VehicleState,
        yaw: f64,
        t_s: f64,
    ) -> Track {
        let p = self.params();
        let leg = TrackLeg {
            target_w: to_w,
            next_w: None,
            accept_m: p.mission.accept_m,
            yaw_rad: heading,
            cruise_m_s: self.goto_speed(),
            corner_gain: p.mission.corner_gain,
        };
        let mut track = match running {
            Some(mut track) => {
                track.leg = leg;
                track
            }
            None => Track::new(x.pos_w, x.vel_w, yaw, t_s, leg, self.limits(self.goto_cruise())),
        };
        self.pace_goto(&mut track);
        track
    }

    /// One GOTO tick of `track`: the speed asked now, and the horizontal acceleration scaled to
    /// it once the reference is within it (module docs).
    pub fn pace_goto(&self, track: &mut Track) {
        let speed = self.goto_speed();
        let cruise = self.goto_cruise();
        let mut limits = self.limits(cruise);
        track.leg.cruise_m_s = speed;
        if cruise > 0.0 && track.vel_w().xy().norm() <= speed {
            limits.acc_horizontal_m_s2 *= (speed / cruise).clamp(0.0, 1.0);
        }
        track.set_limits(limits);
    }
}

#[cfg(test)]
#[path = "goto_tests.rs"]
mod tests;
