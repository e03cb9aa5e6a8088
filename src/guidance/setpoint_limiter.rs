//! Offboard setpoints made flyable: a reference point that follows the raw setpoint within the
//! [`MotionLimits`], so a 50 m position step, a velocity step or a half-turn of heading arrive
//! at limited speed, acceleration and heading rate, and the controllers track a feasible motion.
//!
//! Each tick, with reference position p, velocity v and heading ψ:
//! ```text
//! position set:   v_d = v_stop(p_sp − p) + c,  c = v_ff − ê (ê · v_ff) limited to |v_stop|
//!                 (feed-forward across only, and only as fast as the reference can stop)
//!                 v_stop(e) = ê · (K_p |e| near p_sp, else √(2 a_max (|e| − a_max/2K_p²)))
//! velocity only:  v_d = v_sp
//! v_d clamped to MPC_XY_VEL_MAX, MPC_Z_VEL_MAX_UP / _DN
//! a = clamp(K (v_d − v), a_max);   v ← v + a dt;   p ← p + dt (v_old + v)/2
//! acceleration feed-forward a;   K = 1/dt toward a position, K_v for a velocity alone
//! heading set:    ψ turned the short way within MPC_YAWRAUTO_MAX and MPC_YAWRAUTO_ACC
//!                 ([`HeadingSlew::toward`])
//! rate only:      ψ turned at clamp(ψ̇_sp, MC_YAWRATE_MAX) from the first tick
//!                 ([`HeadingSlew::at_rate`]), then ψ ← ψ_v + clamp(wrap(ψ − ψ_v), ±Δψ_lead)
//! ```
//! A velocity demand alone is approached at most at the acceleration limit and, close to it,
//! exponentially with time constant 1/K_v: the acceleration is continuous in the demand, so a
//! demand that jitters (a body-frame velocity turned by a noisy heading estimate) cannot become
//! acceleration spikes of jitter/dt. Under a rate-only heading command the reference never leads
//! the vehicle's heading ψ_v by more than Δψ_lead: a vehicle that cannot turn for a while (its
//! rotors saturated) resumes the commanded rate instead of spinning to catch up, as PX4 flies a
//! yaw rate as a feed-forward on its current heading.
//! An acceleration-only setpoint passes unchanged (the controllers' tilt limit bounds it).
//! Along the line to a commanded position the speed is the one from which the reference can
//! still stop there, so a velocity feed-forward cannot carry the vehicle past the point (PX4
//! adds it and settles |v_ff|/K_p beyond; this emulator stops on the point).

use crate::control::{FlatSetpoint, VehicleState};
use crate::math::{euler_zyx, wrap_pi, Vec3};

use super::heading::{HeadingSlew, HeadingStep};
use super::MotionLimits;

/// Gain from position error to the velocity demand [1/s] (PX4 `MPC_XY_P` 0.95 feeds a velocity
/// loop with its own lag; here the reference itself must arrive, within 0.1 m of a 3 m step in 3 s).
const POSITION_GAIN_PER_S: f64 = 2.0;
/// K_v: gain from the velocity reference's error to its acceleration [1/s] (a time constant of
/// 0.2 s below the acceleration limit: a 1 cm/s jitter of the demand asks 5 cm/s²).
const VELOCITY_GAIN_PER_S: f64 = 5.0;
/// Δψ_lead: the most a rate-only heading reference leads the vehicle's heading [rad].
const MAX_HEADING_LEAD_RAD: f64 = 0.35;

/// The reference an offboard setpoint stream is flown through.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SetpointLimiter {
    pos_w: Vec3,
    vel_w: Vec3,
    heading: HeadingSlew,
}

impl SetpointLimiter {
    /// A reference at the vehicle's position, velocity and heading.
    pub fn at(x: &VehicleState) -> Self {
        Self {
            pos_w: x.pos_w,
            vel_w: x.vel_w,
            heading: HeadingSlew::at(euler_zyx(&x.r_wb).z),
        }
    }

    /// The setpoint to fly this tick for the raw (world-frame) setpoint `raw`, stepping the
    /// reference by `dt_s` [s] within `lim`.
    pub fn step(&mut self, raw: &FlatSetpoint, x: &VehicleState, lim: &MotionLimits, dt_s: f64) -> FlatSetpoint {
        let (yaw_rad, yaw_rate, yaw_acc) = self.step_heading(raw, euler_zyx(&x.r_wb).z, lim, dt_s);
        let demand = match (raw.pos_w, raw.vel_w) {
            (Some(p), ff) => Some(toward(p - self.pos_w, ff.unwrap_or_default(), lim)),
            (None, Some(v)) => Some(v),
            (None, None) => None,
        };
        let heading = FlatSetpoint {
            yaw_rad: Some(yaw_rad),
            yaw_rate_rad_s: Some(yaw_rate),
            yaw_acc_rad_s2: Some(yaw_acc),
            ..FlatSetpoint::default()
        };
        let Some(demand) = demand else {
            // Acceleration only: follow the vehicle so a later position starts where it is.
            self.pos_w = x.pos_w;
            self.vel_w = x.vel_w;
            return FlatSetpoint {
                acc_w: raw.acc_w,
                ..heading
            };
        };
        // The stopping profile toward a position is the reference's own smooth function: followed
        // exactly (within the limits), or the reference would lag it past the point.
        let gain = if raw.pos_w.is_some() {
            1.0 / dt_s
        } else {
            VELOCITY_GAIN_PER_S
        };
        let ramp = limit_acceleration(gain * (lim.clamp_velocity(demand) - self.vel_w), lim);
        let old = self.vel_w;
        self.vel_w += ramp * dt_s;
        let acc = ramp + raw.acc_w.unwrap_or_default();
        if raw.pos_w.is_some() {
            self.pos_w += 0.5 * dt_s * (old + self.vel_w);
        } else {
            self.pos_w = x.pos_w;
        }
        FlatSetpoint {
            pos_w: raw.pos_w.map(|_| self.pos_w),
            vel_w: Some(self.vel_w),
            acc_w: Some(acc),
            ..heading
        }
    }

    /// Heading, heading rate and heading acceleration of this tick, the vehicle heading
    /// `yaw_rad` [rad].
    fn step_heading(&mut self, raw: &FlatSetpoint, yaw_rad: f64, lim: &MotionLimits, dt_s: f64) -> (f64, f64, f64) {
        let acc = lim.yaw_acc_auto_rad_s2;
        let step = match (raw.yaw_rad, raw.yaw_rate_rad_s) {
            (Some(target), _) => self.heading.toward(target, lim.yaw_rate_auto_rad_s, acc, dt_s),
            (None, Some(r)) => {
                // A commanded rate is flown at once (PX4 feeds an offboard yaw rate forward as
                // it comes), within the lead.
                let step = self.heading.at_rate(r, lim.yaw_rate_max_rad_s, f64::INFINITY, dt_s);
                let lead = wrap_pi(step.yaw_rad - yaw_rad).clamp(-MAX_HEADING_LEAD_RAD, MAX_HEADING_LEAD_RAD);
                self.heading.set_yaw(yaw_rad + lead);
                HeadingStep {
                    yaw_rad: self.heading.yaw_rad(),
                    ..step
                }
            }
            (None, None) => self.heading.at_rate(0.0, lim.yaw_rate_max_rad_s, acc, dt_s),
        };
        (step.yaw_rad, step.rate_rad_s, step.acc_rad_s2)
    }
}

/// Velocity demand towards a point `e_w` [m] away with feed-forward `ff_w` [m/s]: along the
/// line to the point the stopping profile alone (so the feed-forward cannot carry the reference
/// past it), across the line the feed-forward.
fn toward(e_w: Vec3, ff_w: Vec3, lim: &MotionLimits) -> Vec3 {
    let e_xy = e_w.xy();
    let d_xy = e_xy.norm();
    let v_xy = if d_xy > 1e-9 {
        let dir = e_xy / d_xy;
        let ff = ff_w.xy();
        let stop = stopping_speed(d_xy, lim.acc_horizontal_m_s2);
        // Across the line, the feed-forward no faster than the reference could still stop from:
        // close to the point the line's direction is ill-defined, and an unlimited cross term
        // would turn the feed-forward into a demand at right angles to wherever the last
        // millimetres point (a limit cycle around the point).
        let across = ff - dir * ff.dot(&dir);
        let across_speed = across.norm();
        let across = if across_speed > stop {
            across * (stop / across_speed)
        } else {
            across
        };
        dir * stop + across
    } else {
        nalgebra::Vector2::zeros()
    };
    // Climbing towards a point above stops with the downward acceleration, and back.
    let v_z = if e_w.z < 0.0 {
        -stopping_speed(-e_w.z, lim.acc_down_m_s2)
    } else {
        stopping_speed(e_w.z, lim.acc_up_m_s2)
    };
    Vec3::new(v_xy.x, v_xy.y, v_z)
}

/// Speed [m/s] from which deceleration `a` [m/s²] stops on a point `e` [m] ahead, and that
/// decays as K_p e close to it (the square-root controller: linear below e₀ = a/K_p², where both
/// branches meet at a/K_p with the same slope, so the deceleration asked never exceeds `a`).
pub(super) fn stopping_speed(e: f64, a: f64) -> f64 {
    let k = POSITION_GAIN_PER_S;
    let e0 = a / (k * k);
    if e <= e0 {
        k * e
    } else {
        (2.0 * a * (e - 0.5 * e0)).sqrt()
    }
}

/// An acceleration `a` [m/s²] within the acceleration limits (horizontal by its norm, up and
/// down on their own).
fn limit_acceleration(a: Vec3, lim: &MotionLimits) -> Vec3 {
    let max_xy = lim.acc_horizontal_m_s2;
    let xy = a.xy().norm();
    let s = if xy > max_xy { max_xy / xy } else { 1.0 };
    let z = a.z.clamp(-lim.acc_up_m_s2, lim.acc_down_m_s2);
    Vec3::new(a.x * s, a.y * s, z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Mat3;

    const DT: f64 = 0.001;

    fn still(p: Vec3) -> VehicleState {
        VehicleState {
            t_s: 0.0,
            pos_w: p,
            vel_w: Vec3::zeros(),
            r_wb: Mat3::identity(),
            omega_b: Vec3::zeros(),
        }
    }

    /// The vehicle at `p` with heading `yaw` [rad], at rest.
    fn heading(p: Vec3, yaw: f64) -> VehicleState {
        VehicleState {
            r_wb: crate::math::UnitQuat::from_euler_angles(0.0, 0.0, yaw)
                .to_rotation_matrix()
                .into_inner(),
            ..still(p)
        }
    }

    /// Runs the reference alone (a vehicle that tracks it perfectly) for `seconds`; the
    /// reference setpoints.
    fn fly(l: &mut SetpointLimiter, raw: FlatSetpoint, seconds: f64) -> Vec<FlatSetpoint> {
        let lim = MotionLimits::default();
        (0..(seconds / DT) as usize)
            .map(|_| {
                let x = heading(l.pos_w, l.heading.yaw_rad());
                l.step(&raw, &x, &lim, DT)
            })
            .collect()
    }

    #[test]
    fn a_fifty_metre_step_keeps_speed_and_acceleration_and_does_not_overshoot() {
        let mut l = SetpointLimiter::at(&still(Vec3::new(0.0, 0.0, -10.0)));
        let raw = FlatSetpoint {
            pos_w: Some(Vec3::new(50.0, 0.0, -10.0)),
            vel_w: Some(Vec3::new(1.0, 0.0, 0.0)),
            yaw_rad: Some(0.0),
            ..Default::default()
        };
        let sps = fly(&mut l, raw, 40.0);
        let lim = MotionLimits::default();
        let peak_v = sps.iter().map(|s| s.vel_w.unwrap().norm()).fold(0.0, f64::max);
        let peak_a = sps.iter().map(|s| s.acc_w.unwrap().norm()).fold(0.0, f64::max);
        let max_x = sps.iter().map(|s| s.pos_w.unwrap().x).fold(f64::MIN, f64::max);
        assert!(peak_v <= lim.horizontal_m_s + 1e-9 && peak_v > 5.0, "{peak_v}");
        assert!(peak_a <= lim.acc_horizontal_m_s2 + 1e-6, "{peak_a}");
        assert!(max_x <= 50.0 + 1e-6, "overshoot to {max_x}");
        let end = sps.last().unwrap();
        assert!((end.pos_w.unwrap().x - 50.0).abs() < 0.01 && end.vel_w.unwrap().norm() < 0.01);
    }

    #[test]
    fn a_climb_keeps_the_climb_speed_and_a_descent_its_own() {
        let mut l = SetpointLimiter::at(&still(Vec3::new(0.0, 0.0, -0.1)));
        let up = FlatSetpoint {
            pos_w: Some(Vec3::new(0.0, 0.0, -30.0)),
            ..Default::default()
        };
        let peak_up = fly(&mut l, up, 20.0)
            .iter()
            .map(|s| -s.vel_w.unwrap().z)
            .fold(0.0, f64::max);
        assert!((peak_up - 3.0).abs() < 1e-9, "{peak_up}");
        let down = FlatSetpoint {
            vel_w: Some(Vec3::new(0.0, 0.0, 9.0)),
            ..Default::default()
        };
        let sps = fly(&mut l, down, 5.0);
        assert!((sps.last().unwrap().vel_w.unwrap() - Vec3::new(0.0, 0.0, 1.5)).norm() < 1e-6);
        assert_eq!(sps.last().unwrap().pos_w, None);
    }

    #[test]
    fn heading_turns_the_short_way_at_the_auto_rate() {
        let mut l = SetpointLimiter::at(&heading(Vec3::zeros(), 170f64.to_radians()));
        // To −170°: 20° through ±180°, not 340° back.
        let raw = FlatSetpoint {
            vel_w: Some(Vec3::new(0.0, 0.0, 0.0)),
            yaw_rad: Some(-170f64.to_radians()),
            ..Default::default()
        };
        let sps = fly(&mut l, raw, 2.0);
        let rates: Vec<f64> = sps.iter().map(|s| s.yaw_rate_rad_s.unwrap()).collect();
        assert!(rates.iter().all(|r| *r >= 0.0 && *r <= 45f64.to_radians() + 1e-9));
        assert!(sps
            .iter()
            .all(|s| s.yaw_acc_rad_s2.unwrap().abs() <= 60f64.to_radians() + 1e-9));
        assert!((sps.last().unwrap().yaw_rad.unwrap() + 170f64.to_radians()).abs() < 1e-9);
    }

    #[test]
    fn a_yaw_rate_alone_turns_the_heading() {
        let mut l = SetpointLimiter::at(&still(Vec3::zeros()));
        let raw = FlatSetpoint {
            vel_w: Some(Vec3::zeros()),
            yaw_rate_rad_s: Some(60f64.to_radians()),
            ..Default::default()
        };
        let sps = fly(&mut l, raw, 1.0);
        assert!((sps.last().unwrap().yaw_rad.unwrap() - 60f64.to_radians()).abs() < 1e-3);
        assert!(sps.iter().all(|s| s.yaw_rate_rad_s == Some(60f64.to_radians())));
    }

    #[test]
    fn a_jittering_velocity_demand_asks_no_acceleration_spikes() {
        // 5 m/s forward turned by a heading estimate with 0.2° of noise (±8.7 mm/s across).
        let mut l = SetpointLimiter::at(&still(Vec3::zeros()));
        let lim = MotionLimits::default();
        let mut peak_after_ramp: f64 = 0.0;
        for k in 0..10_000 {
            let noise = if k % 2 == 0 { 0.2f64 } else { -0.2 }.to_radians();
            let raw = FlatSetpoint {
                vel_w: Some(Vec3::new(5.0 * noise.cos(), 5.0 * noise.sin(), 0.0)),
                yaw_rad: Some(0.0),
                ..Default::default()
            };
            let sp = l.step(&raw, &still(l.pos_w), &lim, DT);
            let a = sp.acc_w.unwrap().norm();
            assert!(a <= lim.acc_horizontal_m_s2 + 1e-9, "{a}");
            if k > 5_000 {
                peak_after_ramp = peak_after_ramp.max(a);
            }
        }
        assert!((l.vel_w.x - 5.0).abs() < 1e-3, "{}", l.vel_w);
        assert!(peak_after_ramp < 0.1, "jitter became {peak_after_ramp} m/s²");
    }

    #[test]
    fn a_heading_that_cannot_turn_holds_the_rate_reference_close_and_resumes_the_rate() {
        let mut l = SetpointLimiter::at(&still(Vec3::zeros()));
        let lim = MotionLimits::default();
        let raw = FlatSetpoint {
            vel_w: Some(Vec3::zeros()),
            yaw_rate_rad_s: Some(30f64.to_radians()),
            ..Default::default()
        };
        // Stuck at 0 for 5 s: the reference stays within the lead, at the commanded rate.
        for _ in 0..5_000 {
            let sp = l.step(&raw, &heading(Vec3::zeros(), 0.0), &lim, DT);
            assert!(sp.yaw_rad.unwrap().abs() <= MAX_HEADING_LEAD_RAD + 1e-12);
            assert_eq!(sp.yaw_rate_rad_s, Some(30f64.to_radians()));
        }
        // Free again: it turns on at the commanded rate from the lead it had.
        let sps = fly(&mut l, raw, 1.0);
        let turned = wrap_pi(sps.last().unwrap().yaw_rad.unwrap() - MAX_HEADING_LEAD_RAD);
        assert!((turned - 30f64.to_radians()).abs() < 1e-3, "{}", turned.to_degrees());
    }

    #[test]
    fn a_feed_forward_does_not_circle_a_point_reached_off_its_line() {
        // The reference starts a millimetre beside the line to the point: as it arrives, the
        // line's direction turns sideways, and the feed-forward must not follow it.
        let mut l = SetpointLimiter::at(&still(Vec3::new(0.0, 1e-3, -10.0)));
        let raw = FlatSetpoint {
            pos_w: Some(Vec3::new(50.0, 0.0, -10.0)),
            vel_w: Some(Vec3::new(1.0, 0.0, 0.0)),
            yaw_rad: Some(0.0),
            ..Default::default()
        };
        let sps = fly(&mut l, raw, 30.0);
        let late = &sps[15_000..];
        let worst_y = late.iter().map(|s| s.pos_w.unwrap().y.abs()).fold(0.0, f64::max);
        let worst_a = late.iter().map(|s| s.acc_w.unwrap().norm()).fold(0.0, f64::max);
        assert!(
            worst_y < 2e-3 && worst_a < 0.05,
            "circling: {worst_y} m across, {worst_a} m/s²"
        );
        assert!((sps.last().unwrap().pos_w.unwrap() - Vec3::new(50.0, 0.0, -10.0)).norm() < 0.01);
    }
}
