//! The reference a mission flies its waypoints on (PX4's AUTO trajectory, docs/mavlink.md §7.1):
//! a point that moves towards the current waypoint at the cruise speed, slowing so that it
//! arrives at the speed the waypoint allows, and turns its velocity within the acceleration
//! limits. A waypoint the mission flies through (no hold, a next waypoint) allows the corner
//! speed of PX4's trajectory; any other is arrived at standing still.
//!
//! ```text
//! α = ∠(p_wp − p, p_wp − p_next)          (π straight on, π/2 a right-angle turn)
//! v_wp = min( √(P a_xy R tan(α/2)), v_stop(|p_next − p_wp|), v_cruise )   flown through, else 0
//! v_d = û · min( √(v_wp² + 2 a_u d) (v_wp > 0) or v_stop(d) (v_wp = 0), v_max,u ),   d = |p_wp − p|
//! a = clamp((v_d − v) / dt, a_max);   v ← v + a dt;   p ← p + dt (v_old + v)/2
//! ```
//! P is `MPC_XY_TRAJ_P`, R the waypoint's acceptance radius, a_u and v_max,u the acceleration
//! and speed along û = (p_wp − p)/d that keep every component within its limit. Pure.

use crate::control::FlatSetpoint;
use crate::math::Vec3;

use super::heading::HeadingSlew;
use super::setpoint_limiter::stopping_speed;
use super::MotionLimits;

/// The leg being flown: its waypoint and what the waypoint allows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackLeg {
    /// The waypoint, world NED [m].
    pub target_w: Vec3,
    /// The next waypoint when this one is flown through (no hold), world NED [m].
    pub next_w: Option<Vec3>,
    /// Horizontal acceptance radius [m] (the corner's radius).
    pub accept_m: f64,
    /// Heading flown towards [rad].
    pub yaw_rad: f64,
    /// Cruise speed [m/s].
    pub cruise_m_s: f64,
    /// Share of the horizontal acceleration the corner turns with (`MPC_XY_TRAJ_P`) [-].
    pub corner_gain: f64,
}

/// The moving reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Track {
    pos_w: Vec3,
    vel_w: Vec3,
    heading: HeadingSlew,
    last_s: f64,
    limits: MotionLimits,
    /// The leg flown.
    pub leg: TrackLeg,
}

impl Track {
    /// A reference at `pos_w` [m] moving at `vel_w` [m/s] with heading `yaw_rad` [rad] at
    /// `t_s` [s], flying `leg` within `limits`.
    pub fn new(pos_w: Vec3, vel_w: Vec3, yaw_rad: f64, t_s: f64, leg: TrackLeg, limits: MotionLimits) -> Self {
        Self {
            pos_w,
            vel_w,
            heading: HeadingSlew::at(yaw_rad),
            last_s: t_s,
            limits,
            leg,
        }
    }

    /// The reference's position [m].
    pub fn pos_w(&self) -> Vec3 {
        self.pos_w
    }

    /// The reference's velocity [m/s].
    pub fn vel_w(&self) -> Vec3 {
        self.vel_w
    }

    /// The limits kept.
    pub fn limits(&self) -> MotionLimits {
        self.limits
    }

    /// Keeps `limits` from the next step on; the reference keeps its motion.
    pub fn set_limits(&mut self, limits: MotionLimits) {
        self.limits = limits;
    }

    /// The reference stands on its waypoint.
    pub fn arrived(&self) -> bool {
        (self.leg.target_w - self.pos_w).norm() < 1e-3 && self.vel_w.norm() < 1e-3
    }

    /// The speed the waypoint allows [m/s] (module docs): the corner speed when flown through.
    pub fn waypoint_speed(&self) -> f64 {
        let (leg, lim) = (&self.leg, &self.limits);
        let Some(next) = leg.next_w else { return 0.0 };
        let (inbound, outbound) = (leg.target_w - self.pos_w, leg.target_w - next);
        let out_xy = outbound.xy().norm();
        if out_xy < leg.accept_m || inbound.norm() < 1e-9 {
            return 0.0;
        }
        let cos = (inbound.normalize().dot(&outbound.normalize())).clamp(-1.0, 1.0);
        let alpha = cos.acos().min(std::f64::consts::PI - 1e-6);
        let turn = (leg.corner_gain * lim.acc_horizontal_m_s2 * leg.accept_m * (0.5 * alpha).tan()).sqrt();
        turn.min(stopping_speed(out_xy, lim.acc_horizontal_m_s2))
            .min(leg.cruise_m_s)
    }

    /// Steps the reference to `t_s` [s] and gives its setpoint.
    pub fn step(&mut self, t_s: f64) -> FlatSetpoint {
        let lim = self.limits;
        let dt = (t_s - self.last_s).clamp(0.0, 0.1);
        self.last_s = t_s;
        let to = self.leg.target_w - self.pos_w;
        let d = to.norm();
        let demand = if d > 1e-9 {
            let u = to / d;
            let (v_max, a_max) = along(&u, &lim, self.leg.cruise_m_s);
            let v_wp = self.waypoint_speed();
            let speed = if v_wp > 0.0 {
                (v_wp * v_wp + 2.0 * a_max * d).sqrt()
            } else {
                stopping_speed(d, a_max)
            };
            u * speed.min(v_max)
        } else {
            Vec3::zeros()
        };
        let acc = if dt > 0.0 {
            clamp_acceleration((demand - self.vel_w) / dt, &lim)
        } else {
            Vec3::zeros()
        };
        let old = self.vel_w;
        self.vel_w += acc * dt;
        self.pos_w += 0.5 * dt * (old + self.vel_w);
        let heading = self
            .heading
            .toward(self.leg.yaw_rad, lim.yaw_rate_auto_rad_s, lim.yaw_acc_auto_rad_s2, dt);
        FlatSetpoint {
            pos_w: Some(self.pos_w),
            vel_w: Some(self.vel_w),
            acc_w: Some(acc),
            yaw_rad: Some(heading.yaw_rad),
            yaw_rate_rad_s: Some(heading.rate_rad_s),
            yaw_acc_rad_s2: Some(heading.acc_rad_s2),
        }
    }
}

/// The speed [m/s] and acceleration [m/s²] along the unit direction `u` that keep the
/// horizontal (`cruise_m_s`, `MPC_ACC_HOR`), climb and descent limits of every component.
fn along(u: &Vec3, lim: &MotionLimits, cruise_m_s: f64) -> (f64, f64) {
    let xy = u.xy().norm();
    let (v_z, a_z) = if u.z < 0.0 {
        (lim.up_m_s, lim.acc_up_m_s2)
    } else {
        (lim.down_m_s, lim.acc_down_m_s2)
    };
    let bound = |limit: f64, share: f64| if share > 1e-9 { limit / share } else { f64::INFINITY };
    let v = bound(cruise_m_s.min(lim.horizontal_m_s), xy).min(bound(v_z, u.z.abs()));
    let a = bound(lim.acc_horizontal_m_s2, xy).min(bound(a_z, u.z.abs()));
    (v, a)
}

/// `a` [m/s²] within the acceleration limits (horizontal by its norm, up and down on their own).
fn clamp_acceleration(a: Vec3, lim: &MotionLimits) -> Vec3 {
    let xy = a.xy().norm();
    let s = if xy > lim.acc_horizontal_m_s2 {
        lim.acc_horizontal_m_s2 / xy
    } else {
        1.0
    };
    Vec3::new(a.x * s, a.y * s, a.z.clamp(-lim.acc_up_m_s2, lim.acc_down_m_s2))
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f64 = 0.001;

    fn leg(target: Vec3, next: Option<Vec3>) -> TrackLeg {
        TrackLeg {
            target_w: target,
            next_w: next,
            accept_m: 2.0,
            yaw_rad: 0.0,
            cruise_m_s: 5.0,
            corner_gain: 0.5,
        }
    }

    /// A reference at rest at `from` flying to `target`, then `next`.
    fn track(from: Vec3, target: Vec3, next: Option<Vec3>) -> Track {
        Track::new(
            from,
            Vec3::zeros(),
            0.0,
            0.0,
            leg(target, next),
            MotionLimits::default(),
        )
    }

    #[test]
    fn a_right_angle_corner_allows_px4s_corner_speed_and_a_straight_one_the_cruise() {
        let t = track(
            Vec3::zeros(),
            Vec3::new(20.0, 0.0, 0.0),
            Some(Vec3::new(20.0, 20.0, 0.0)),
        );
        // √(0.5 · 3 · 2 · tan 45°) = 1.73 m/s.
        assert!((t.waypoint_speed() - 3f64.sqrt()).abs() < 1e-9);
        let straight = track(
            Vec3::zeros(),
            Vec3::new(20.0, 0.0, 0.0),
            Some(Vec3::new(40.0, 0.0, 0.0)),
        );
        assert!((straight.waypoint_speed() - 5.0).abs() < 1e-9);
        let last = track(Vec3::zeros(), Vec3::new(20.0, 0.0, 0.0), None);
        assert_eq!(last.waypoint_speed(), 0.0);
    }

    #[test]
    fn a_waypoint_flown_through_straight_on_is_passed_at_cruise_and_the_last_is_stopped_on() {
        let mut t = track(
            Vec3::zeros(),
            Vec3::new(40.0, 0.0, 0.0),
            Some(Vec3::new(80.0, 0.0, 0.0)),
        );
        let mut k = 0;
        while (t.pos_w() - t.leg.target_w).norm() > 2.0 {
            k += 1;
            let sp = t.step(f64::from(k) * DT);
            assert!(sp.vel_w.unwrap().norm() <= 5.0 + 1e-9 && sp.acc_w.unwrap().norm() <= 3.0 + 1e-9);
        }
        assert!(
            (t.vel_w.norm() - 5.0).abs() < 1e-6,
            "passes at cruise: {}",
            t.vel_w.norm()
        );
        t.leg = leg(Vec3::new(80.0, 0.0, 0.0), None);
        for _ in 0..30_000 {
            k += 1;
            t.step(f64::from(k) * DT);
        }
        assert!(t.arrived(), "{:?} {:?}", t.pos_w(), t.vel_w);
    }

    #[test]
    fn a_corner_is_turned_within_the_acceleration_limit() {
        let corner = Vec3::new(20.0, 0.0, -5.0);
        let next = Vec3::new(20.0, 20.0, -5.0);
        let mut t = track(Vec3::new(0.0, 0.0, -5.0), corner, Some(next));
        let mut k = 0;
        while (t.pos_w() - corner).xy().norm() > 2.0 {
            k += 1;
            t.step(f64::from(k) * DT);
        }
        // Entering the acceptance radius at the speed that still arrives at the corner at its
        // corner speed: √(v_wp² + 2 a R) = √(3 + 12).
        let at_corner = t.vel_w.norm();
        assert!((at_corner - 15f64.sqrt()).abs() < 0.05, "{at_corner}");
        t.leg = leg(next, None);
        let mut worst_acc: f64 = 0.0;
        for _ in 0..20_000 {
            k += 1;
            worst_acc = worst_acc.max(t.step(f64::from(k) * DT).acc_w.unwrap().norm());
        }
        assert!(worst_acc <= 3.0 + 1e-9 && t.arrived());
    }
}
