//! The motion limits every path and every offboard setpoint keeps (PX4's multicopter position
//! control limits, parameter names in brackets): speed, acceleration and heading rate.

use crate::math::Vec3;

/// PX4's horizontal position gain `MPC_XY_P` [1/s]: a position error becomes a velocity demand.
const POSITION_GAIN_XY_PER_S: f64 = 0.95;
/// PX4's vertical position gain `MPC_Z_P` [1/s].
const POSITION_GAIN_Z_PER_S: f64 = 1.0;

/// Peak speed over mean speed of a quintic rest-to-rest move: max ṡ = 15/8 [-].
const QUINTIC_PEAK_SPEED: f64 = 1.875;
/// Peak acceleration of a quintic over distance / duration²: max s̈ = 10/√3 [-].
const QUINTIC_PEAK_ACC: f64 = 5.773_502_691_896_258;

/// Limits of the reference motion, per component.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionLimits {
    /// Horizontal speed [m/s] (`MPC_XY_VEL_MAX`, 12; AUTO paths fly at most the cruise speed).
    pub horizontal_m_s: f64,
    /// Climb speed [m/s] (`MPC_Z_VEL_MAX_UP`, 3).
    pub up_m_s: f64,
    /// Descent speed [m/s] (`MPC_Z_VEL_MAX_DN`, 1.5).
    pub down_m_s: f64,
    /// Horizontal acceleration [m/s²] (`MPC_ACC_HOR`, 3).
    pub acc_horizontal_m_s2: f64,
    /// Upward acceleration [m/s²] (`MPC_ACC_UP_MAX`, 4).
    pub acc_up_m_s2: f64,
    /// Downward acceleration [m/s²] (`MPC_ACC_DOWN_MAX`, 3).
    pub acc_down_m_s2: f64,
    /// Heading rate towards a commanded heading [rad/s] (`MPC_YAWRAUTO_MAX`, 45 °/s).
    pub yaw_rate_auto_rad_s: f64,
    /// Heading acceleration of the same turns [rad/s²] (`MPC_YAWRAUTO_ACC`, 60 °/s²).
    pub yaw_acc_auto_rad_s2: f64,
    /// Largest commanded heading rate [rad/s] (`MC_YAWRATE_MAX`, 200 °/s).
    pub yaw_rate_max_rad_s: f64,
}

impl Default for MotionLimits {
    fn default() -> Self {
        Self {
            horizontal_m_s: 12.0,
            up_m_s: 3.0,
            down_m_s: 1.5,
            acc_horizontal_m_s2: 3.0,
            acc_up_m_s2: 4.0,
            acc_down_m_s2: 3.0,
            yaw_rate_auto_rad_s: 45f64.to_radians(),
            yaw_acc_auto_rad_s2: 60f64.to_radians(),
            yaw_rate_max_rad_s: 200f64.to_radians(),
        }
    }
}

impl MotionLimits {
    /// The shortest duration [s] of a quintic move over `delta_w` [m] turning by `dyaw_rad` [rad]
    /// that keeps every limit: peak speed 15/8 · d/T and peak acceleration 10/√3 · d/T² per
    /// component along a straight line, peak heading rate 15/8 · Δψ/T.
    pub fn quintic_duration_s(&self, delta_w: Vec3, dyaw_rad: f64) -> f64 {
        let floor = |x: f64| x.max(0.1);
        let horizontal = delta_w.xy().norm();
        let up = (-delta_w.z).max(0.0);
        let down = delta_w.z.max(0.0);
        let by_speed = [
            horizontal / floor(self.horizontal_m_s),
            up / floor(self.up_m_s),
            down / floor(self.down_m_s),
            dyaw_rad.abs() / floor(self.yaw_rate_auto_rad_s),
        ]
        .into_iter()
        .fold(0.0, f64::max)
            * QUINTIC_PEAK_SPEED;
        let by_acc = [
            horizontal / floor(self.acc_horizontal_m_s2),
            up / floor(self.acc_up_m_s2),
            down / floor(self.acc_down_m_s2),
        ]
        .into_iter()
        .fold(0.0, f64::max);
        by_speed.max((QUINTIC_PEAK_ACC * by_acc).sqrt())
    }

    /// `v` [m/s] with its horizontal norm and its climb and descent speeds within the limits.
    pub fn clamp_velocity(&self, v: Vec3) -> Vec3 {
        let xy = v.xy().norm();
        let s = if xy > self.horizontal_m_s {
            self.horizontal_m_s / xy
        } else {
            1.0
        };
        Vec3::new(v.x * s, v.y * s, v.z.clamp(-self.up_m_s, self.down_m_s))
    }

    /// The position setpoint `p_sp_w` [m] moved to within the reach of the vehicle at `p_w` [m]
    /// that PX4's position loop allows: its P gains (`MPC_XY_P`, `MPC_Z_P`) turn at most the
    /// velocity limits' worth of error into a velocity demand, so the error is at most
    /// `MPC_XY_VEL_MAX / MPC_XY_P` across, `MPC_Z_VEL_MAX_UP / MPC_Z_P` above and
    /// `MPC_Z_VEL_MAX_DN / MPC_Z_P` below. A reference that left the vehicle behind (the estimate
    /// jumped at a height reset, a failure held it back) is then flown at the speed limits
    /// instead of as one large step, which asked a free fall.
    pub fn within_reach(&self, p_sp_w: Vec3, p_w: Vec3) -> Vec3 {
        let e = p_sp_w - p_w;
        let e = self.clamp_velocity(Vec3::new(
            e.x * POSITION_GAIN_XY_PER_S,
            e.y * POSITION_GAIN_XY_PER_S,
            e.z * POSITION_GAIN_Z_PER_S,
        ));
        p_w + Vec3::new(
            e.x / POSITION_GAIN_XY_PER_S,
            e.y / POSITION_GAIN_XY_PER_S,
            e.z / POSITION_GAIN_Z_PER_S,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn duration_keeps_the_binding_limit() {
        let l = MotionLimits::default();
        // 50 m north at 12 m/s: the acceleration binds (√(5.77 · 50 / 3) = 9.8 s > 7.8 s).
        let t = l.quintic_duration_s(Vec3::new(50.0, 0.0, 0.0), 0.0);
        assert!((t - (QUINTIC_PEAK_ACC * 50.0 / 3.0).sqrt()).abs() < 1e-9, "{t}");
        // 500 m: the speed binds.
        let t = l.quintic_duration_s(Vec3::new(500.0, 0.0, 0.0), 0.0);
        assert!((t - 1.875 * 500.0 / 12.0).abs() < 1e-9, "{t}");
        // A half turn in place at 45 °/s: 1.875 × 4 s.
        let t = l.quintic_duration_s(Vec3::zeros(), std::f64::consts::PI);
        assert!((t - 7.5).abs() < 1e-9, "{t}");
    }

    #[test]
    fn a_setpoint_far_from_the_vehicle_is_pulled_within_the_position_loops_reach() {
        let l = MotionLimits::default();
        let p = Vec3::new(0.0, 0.0, -60.0);
        // 22 m below after a height reset: 1.5 m below (MPC_Z_VEL_MAX_DN / MPC_Z_P).
        assert_eq!(
            l.within_reach(Vec3::new(0.0, 0.0, -38.0), p),
            Vec3::new(0.0, 0.0, -58.5)
        );
        assert_eq!(
            l.within_reach(Vec3::new(0.0, 0.0, -70.0), p),
            Vec3::new(0.0, 0.0, -63.0)
        );
        let far = l.within_reach(Vec3::new(100.0, 0.0, -60.0), p);
        assert!((far.x - 12.0 / 0.95).abs() < 1e-12);
        // Close setpoints are untouched.
        let near = Vec3::new(1.0, -2.0, -59.0);
        assert!((l.within_reach(near, p) - near).norm() < 1e-12);
    }

    #[test]
    fn velocity_clamp_is_per_component() {
        let l = MotionLimits::default();
        let v = l.clamp_velocity(Vec3::new(30.0, 40.0, -10.0));
        assert!((v.xy().norm() - 12.0).abs() < 1e-12 && v.z == -3.0);
        assert_eq!(l.clamp_velocity(Vec3::new(1.0, 0.0, 9.0)), Vec3::new(1.0, 0.0, 1.5));
    }
}
