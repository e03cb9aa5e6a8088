//! The reference POSCTL and ALTCTL fly from the sticks: a point that moves at the velocity the
//! sticks ask for, reached within the acceleration limits, so centred sticks brake to a stop and
//! hold the point where the reference stopped.
//!
//! Each tick, with reference position p, velocity v and heading ψ (heading frame → world by ψ):
//! ```text
//! POSCTL:  v_d,xy = R(ψ) (f, r) · MPC_VEL_MANUAL        (f, r: shaped pitch and roll sticks)
//! both:    v_d,z  = −c · MPC_Z_VEL_MAX_UP (c > 0) or −c · MPC_Z_VEL_MAX_DN   (c: shaped climb)
//!          v ← v + clamp(v_d − v, a_max dt);   p ← p + dt (v_old + v)/2;   ψ ← ψ + ψ̇_stick dt
//!          |p − p_vehicle| ≤ LEASH_M on each of the horizontal plane and the vertical
//! ALTCTL:  horizontally the vehicle's own position and velocity with the feed-forward
//!          a_xy = g tan θ_stick along R(ψ) (pitch, roll) — the sticks set the tilt, the height holds
//! ```

use crate::control::{FlatSetpoint, VehicleState};
use crate::math::{euler_zyx, wrap_pi, Vec3};

use super::sticks::{StickShaping, Sticks};
use super::MotionLimits;

/// Standard gravity [m/s²].
const G_M_S2: f64 = 9.80665;
/// How far the reference may lead the vehicle [m]: a vehicle that cannot follow (a gust, a
/// rotor lost) is not pulled by a point running away.
const LEASH_M: f64 = 2.0;

/// The reference of the stick modes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StickReference {
    pos_w: Vec3,
    vel_w: Vec3,
    yaw_rad: f64,
}

impl StickReference {
    /// A reference where the vehicle is, moving as it moves, at its heading: centred sticks
    /// then brake it within the acceleration limits.
    pub fn at(x: &VehicleState) -> Self {
        Self {
            pos_w: x.pos_w,
            vel_w: x.vel_w,
            yaw_rad: euler_zyx(&x.r_wb).z,
        }
    }

    /// The reference position [m].
    pub fn pos_w(&self) -> Vec3 {
        self.pos_w
    }

    /// One POSCTL tick of `dt_s` [s]: the setpoint for sticks `s`.
    pub fn position(
        &mut self,
        s: &Sticks,
        x: &VehicleState,
        shaping: &StickShaping,
        lim: &MotionLimits,
        dt_s: f64,
    ) -> FlatSetpoint {
        let (f, r) = shaping.horizontal(s);
        let speed = shaping.velocity_m_s.min(lim.horizontal_m_s);
        let along = self.heading_to_world(f * speed, r * speed);
        let demand = Vec3::new(along.x, along.y, self.climb_demand(s, shaping, lim));
        self.step(demand, x, shaping, s, lim, dt_s)
    }

    /// One ALTCTL tick of `dt_s` [s]: the height (and heading) from the sticks as in POSCTL,
    /// horizontally the tilt the sticks set, with no position or velocity held.
    pub fn altitude(
        &mut self,
        s: &Sticks,
        x: &VehicleState,
        shaping: &StickShaping,
        lim: &MotionLimits,
        dt_s: f64,
    ) -> FlatSetpoint {
        let demand = Vec3::new(x.vel_w.x, x.vel_w.y, self.climb_demand(s, shaping, lim));
        self.vel_w.x = x.vel_w.x;
        self.vel_w.y = x.vel_w.y;
        let sp = self.step(demand, x, shaping, s, lim, dt_s);
        let (roll, pitch) = shaping.tilt(s);
        // Forward acceleration for a nose-down pitch, rightward for a right roll.
        let a = self.heading_to_world(G_M_S2 * (-pitch).tan(), G_M_S2 * roll.tan());
        self.pos_w.x = x.pos_w.x;
        self.pos_w.y = x.pos_w.y;
        FlatSetpoint {
            pos_w: Some(Vec3::new(x.pos_w.x, x.pos_w.y, self.pos_w.z)),
            vel_w: Some(Vec3::new(x.vel_w.x, x.vel_w.y, self.vel_w.z)),
            acc_w: sp.acc_w.map(|acc| Vec3::new(a.x, a.y, acc.z)),
            ..sp
        }
    }

    /// Vertical demand [m/s], down positive.
    fn climb_demand(&self, s: &Sticks, shaping: &StickShaping, lim: &MotionLimits) -> f64 {
        let c = shaping.climb(s);
        if c >= 0.0 {
            -c * lim.up_m_s
        } else {
            -c * lim.down_m_s
        }
    }

    /// (forward, right) in the heading frame → world NED (horizontal).
    fn heading_to_world(&self, forward: f64, right: f64) -> Vec3 {
        let (sn, cs) = self.yaw_rad.sin_cos();
        Vec3::new(cs * forward - sn * right, sn * forward + cs * right, 0.0)
    }

    /// Moves the reference towards `demand_w` [m/s] within the limits; the setpoint.
    fn step(
        &mut self,
        demand_w: Vec3,
        x: &VehicleState,
        shaping: &StickShaping,
        s: &Sticks,
        lim: &MotionLimits,
        dt_s: f64,
    ) -> FlatSetpoint {
        let old = self.vel_w;
        let dv = demand_w - self.vel_w;
        let dv_xy = dv.xy();
        let max_xy = lim.acc_horizontal_m_s2 * dt_s;
        let dv_xy = if dv_xy.norm() > max_xy {
            dv_xy * (max_xy / dv_xy.norm())
        } else {
            dv_xy
        };
        let dv_z = dv.z.clamp(-lim.acc_up_m_s2 * dt_s, lim.acc_down_m_s2 * dt_s);
        self.vel_w += Vec3::new(dv_xy.x, dv_xy.y, dv_z);
        self.pos_w += 0.5 * dt_s * (old + self.vel_w);
        self.keep_on_leash(x);
        let yaw_rate = shaping.yaw_rate(s);
        self.yaw_rad = wrap_pi(self.yaw_rad + yaw_rate * dt_s);
        FlatSetpoint {
            pos_w: Some(self.pos_w),
            vel_w: Some(self.vel_w),
            acc_w: Some((self.vel_w - old) / dt_s),
            yaw_rad: Some(self.yaw_rad),
            yaw_rate_rad_s: Some(yaw_rate),
            yaw_acc_rad_s2: None,
        }
    }

    /// Pulls the reference back within [`LEASH_M`] of the vehicle.
    fn keep_on_leash(&mut self, x: &VehicleState) {
        let e = self.pos_w - x.pos_w;
        let e_xy = e.xy();
        if e_xy.norm() > LEASH_M {
            let back = e_xy * (LEASH_M / e_xy.norm());
            self.pos_w.x = x.pos_w.x + back.x;
            self.pos_w.y = x.pos_w.y + back.y;
        }
        self.pos_w.z = x.pos_w.z + e.z.clamp(-LEASH_M, LEASH_M);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT_S: f64 = 0.001;

    /// A vehicle that is wherever the setpoint says.
    fn follow(r: &mut StickReference, s: &Sticks, x: &mut VehicleState, seconds: f64, altitude: bool) -> FlatSetpoint {
        let (k, lim) = (StickShaping::default(), MotionLimits::default());
        let mut sp = FlatSetpoint::default();
        for _ in 0..(seconds / DT_S).round() as usize {
            sp = if altitude {
                r.altitude(s, x, &k, &lim, DT_S)
            } else {
                r.position(s, x, &k, &lim, DT_S)
            };
            let v = sp.vel_w.unwrap_or_default();
            x.pos_w = sp.pos_w.unwrap_or(x.pos_w);
            x.vel_w = v + sp.acc_w.map_or(Vec3::zeros(), |a| Vec3::new(a.x, a.y, 0.0) * DT_S);
        }
        sp
    }

    fn hovering() -> VehicleState {
        VehicleState::at_rest(0.0, Vec3::new(0.0, 0.0, -5.0))
    }

    #[test]
    fn centred_sticks_hold_the_point_where_the_vehicle_was() {
        let mut x = hovering();
        let mut r = StickReference::at(&x);
        let sp = follow(&mut r, &Sticks::CENTRED, &mut x, 3.0, false);
        assert_eq!(sp.pos_w, Some(Vec3::new(0.0, 0.0, -5.0)));
        assert_eq!(sp.vel_w, Some(Vec3::zeros()));
    }

    #[test]
    fn full_pitch_flies_forward_at_mpc_vel_manual_and_centring_brakes_to_a_hold() {
        let mut x = hovering();
        let mut r = StickReference::at(&x);
        let forward = Sticks {
            pitch: 1.0,
            ..Sticks::CENTRED
        };
        let sp = follow(&mut r, &forward, &mut x, 6.0, false);
        let v = sp.vel_w.unwrap_or_default();
        assert!((v - Vec3::new(10.0, 0.0, 0.0)).norm() < 1e-9, "{v:?}");
        follow(&mut r, &Sticks::CENTRED, &mut x, 5.0, false);
        let stopped = r.pos_w();
        let sp = follow(&mut r, &Sticks::CENTRED, &mut x, 2.0, false);
        assert_eq!(sp.pos_w, Some(stopped), "holds where it braked to");
        assert!(stopped.x > 45.0 && stopped.y.abs() < 1e-9 && (stopped.z + 5.0).abs() < 1e-9);
    }

    #[test]
    fn the_sticks_are_read_in_the_heading_frame_and_the_yaw_stick_turns_it() {
        let mut x = hovering();
        let mut r = StickReference::at(&x);
        let turn = Sticks {
            yaw: 1.0,
            ..Sticks::CENTRED
        };
        let sp = follow(&mut r, &turn, &mut x, 0.6, false);
        let yaw = sp.yaw_rad.unwrap_or_default();
        assert!(
            (yaw - 1.5f64.to_radians() * 60.0).abs() < 1e-6,
            "150 °/s for 0.6 s: {yaw}"
        );
        let right = Sticks {
            roll: 1.0,
            ..Sticks::CENTRED
        };
        let sp = follow(&mut r, &right, &mut x, 6.0, false);
        let v = sp.vel_w.unwrap_or_default();
        // Heading 90°: right is south (−north).
        assert!((v - Vec3::new(-10.0, 0.0, 0.0)).norm() < 1e-6, "{v:?}");
    }

    #[test]
    fn the_throttle_climbs_and_descends_at_the_speed_caps() {
        let mut x = hovering();
        let mut r = StickReference::at(&x);
        let up = Sticks {
            throttle: 1.0,
            ..Sticks::CENTRED
        };
        let sp = follow(&mut r, &up, &mut x, 2.0, false);
        assert!((sp.vel_w.unwrap_or_default().z + 3.0).abs() < 1e-9);
        let down = Sticks {
            throttle: 0.0,
            ..Sticks::CENTRED
        };
        let sp = follow(&mut r, &down, &mut x, 2.0, false);
        assert!((sp.vel_w.unwrap_or_default().z - 1.5).abs() < 1e-9);
    }

    #[test]
    fn a_reference_taken_from_a_moving_vehicle_brakes_within_the_acceleration_limit() {
        let mut x = VehicleState {
            vel_w: Vec3::new(6.0, 0.0, 0.0),
            ..hovering()
        };
        let mut r = StickReference::at(&x);
        let sp = follow(&mut r, &Sticks::CENTRED, &mut x, 1.0, false);
        assert!(
            (sp.vel_w.unwrap_or_default().x - 3.0).abs() < 1e-9,
            "MPC_ACC_HOR 3 m/s² for 1 s"
        );
        follow(&mut r, &Sticks::CENTRED, &mut x, 2.0, false);
        assert!(
            (r.pos_w().x - 6.0).abs() < 1e-6,
            "stops v²/2a = 6 m on: {:?}",
            r.pos_w()
        );
    }

    #[test]
    fn the_reference_never_leads_a_vehicle_that_does_not_follow_by_more_than_the_leash() {
        let x = hovering();
        let mut r = StickReference::at(&x);
        let forward = Sticks {
            pitch: 1.0,
            throttle: 1.0,
            ..Sticks::CENTRED
        };
        for _ in 0..10_000 {
            r.position(&forward, &x, &StickShaping::default(), &MotionLimits::default(), DT_S);
        }
        let e = r.pos_w() - x.pos_w;
        assert!(
            (e.xy().norm() - LEASH_M).abs() < 1e-9 && (e.z + LEASH_M).abs() < 1e-9,
            "{e:?}"
        );
    }

    #[test]
    fn altitude_mode_turns_the_sticks_into_tilt_and_holds_the_height() {
        let mut x = hovering();
        let mut r = StickReference::at(&x);
        let forward = Sticks {
            pitch: 1.0,
            ..Sticks::CENTRED
        };
        let sp = follow(&mut r, &forward, &mut x, 1.0, true);
        let a = sp.acc_w.unwrap_or_default();
        assert!(
            (a.x - G_M_S2 * 35f64.to_radians().tan()).abs() < 1e-9 && a.y.abs() < 1e-9,
            "{a:?}"
        );
        assert_eq!(sp.pos_w.map(|p| p.z), Some(-5.0), "height held");
        assert_eq!(sp.pos_w.map(|p| p.x), Some(x.pos_w.x), "no horizontal position held");
        assert!(x.vel_w.x > 5.0, "it accelerated forward: {:?}", x.vel_w);
    }
}
