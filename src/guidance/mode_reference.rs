//! What to fly right now, as the commander's modes need it (PX4 AUTO modes; docs/mavlink.md §2.1):
//! hold a point, follow a rest-to-rest path (take-off climb, return leg), or descend (fast high
//! up, at the landing speed near the ground) until the ground stops the vehicle (landing), or
//! fly a circle (orbit).

use crate::control::{FlatSetpoint, VehicleState};
use crate::math::Vec3;

use super::trajectory::Quintic;
use super::{DescentProfile, MotionLimits, Orbit, Track};

/// How far the landing reference may run ahead of the vehicle below it [m]; keeps the position
/// error (and so the thrust reduction) bounded once the ground stops the descent.
const LAND_LEAD_MAX_M: f64 = 0.5;

/// The reference generator of the active mode.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Guidance {
    /// Disarmed or idle on the ground: no setpoint, motors off.
    Idle,
    /// Hold `pos_w` [m] at `yaw_rad` [rad].
    Hold {
        /// Point held, world NED [m].
        pos_w: Vec3,
        /// Heading [rad].
        yaw_rad: f64,
    },
    /// Follow `path`, started at `start_s` [s]; holds its goal after the end.
    Path {
        /// Rest-to-rest path.
        path: Quintic,
        /// Simulated time the path started [s].
        start_s: f64,
    },
    /// Descend over `xy_w` at the speeds of `profile` (fast high up, the landing speed near the
    /// ground), starting from `z_start_m` at `start_s`; heights are −z (home is on the ground).
    Descend {
        /// Horizontal position held, world NED [m] (z ignored).
        xy_w: Vec3,
        /// Heading [rad].
        yaw_rad: f64,
        /// z where the descent began, NED [m].
        z_start_m: f64,
        /// Simulated time the descent began [s].
        start_s: f64,
        /// Downward speed when the descent began [m/s] (negative in a climb).
        start_down_m_s: f64,
        /// Descent speed by height.
        profile: DescentProfile,
    },
    /// Fly a circle (orbit mode).
    Orbit(Orbit),
    /// Fly mission waypoints, through those that allow it (docs/mavlink.md §7.1).
    Track(Track),
}

impl Guidance {
    /// A rest-to-rest path from `from_w` to `to_w` [m], turning from heading `from_yaw_rad` to
    /// `to_yaw_rad` [rad] the short way, whose speeds, accelerations and heading rate stay within
    /// `limits`, at least 1 s long.
    pub fn path(
        from_w: Vec3,
        to_w: Vec3,
        from_yaw_rad: f64,
        to_yaw_rad: f64,
        limits: &MotionLimits,
        start_s: f64,
    ) -> Self {
        let dyaw = crate::math::wrap_pi(to_yaw_rad - from_yaw_rad);
        let duration_s = limits.quintic_duration_s(to_w - from_w, dyaw).max(1.0);
        Self::Path {
            path: Quintic {
                start_w: from_w,
                goal_w: to_w,
                duration_s,
                start_yaw_rad: from_yaw_rad,
                goal_yaw_rad: to_yaw_rad,
            },
            start_s,
        }
    }

    /// Setpoint at simulated time `t_s` [s] for the vehicle in state `x` (a track steps its
    /// reference to `t_s`); `None` for motors off.
    pub fn setpoint(&mut self, t_s: f64, x: &VehicleState) -> Option<FlatSetpoint> {
        if let Self::Track(track) = self {
            return Some(track.step(t_s));
        }
        match *self {
            Self::Idle => None,
            Self::Hold { pos_w, yaw_rad } => Some(FlatSetpoint::hold(pos_w, yaw_rad)),
            Self::Path { path, start_s } => Some(path.sample(t_s - start_s).setpoint()),
            Self::Orbit(orbit) => Some(orbit.setpoint(t_s)),
            Self::Track(_) => None,
            Self::Descend {
                xy_w,
                yaw_rad,
                z_start_m,
                start_s,
                start_down_m_s,
                profile,
            } => {
                let (height_m, speed_m_s, acc_m_s2) = profile.sample_from(-z_start_m, start_down_m_s, t_s - start_s);
                let z = (-height_m).min(x.pos_w.z + LAND_LEAD_MAX_M);
                Some(FlatSetpoint {
                    vel_w: Some(Vec3::new(0.0, 0.0, speed_m_s)),
                    acc_w: Some(Vec3::new(0.0, 0.0, acc_m_s2)),
                    ..FlatSetpoint::hold(Vec3::new(xy_w.x, xy_w.y, z), yaw_rad)
                })
            }
        }
    }

    /// True when a path has reached its goal (always true for the other kinds).
    pub fn finished(&self, t_s: f64) -> bool {
        match self {
            Self::Path { path, start_s } => t_s - start_s >= path.duration_s,
            Self::Track(track) => track.arrived(),
            _ => true,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Mat3;

    fn at(z: f64) -> VehicleState {
        VehicleState {
            t_s: 0.0,
            pos_w: Vec3::new(1.0, 2.0, z),
            vel_w: Vec3::zeros(),
            r_wb: Mat3::identity(),
            omega_b: Vec3::zeros(),
        }
    }

    const LIMITS: MotionLimits = MotionLimits {
        horizontal_m_s: 5.0,
        up_m_s: 2.0,
        down_m_s: 1.0,
        acc_horizontal_m_s2: 100.0,
        acc_up_m_s2: 100.0,
        acc_down_m_s2: 100.0,
        yaw_rate_auto_rad_s: 1.0,
        yaw_acc_auto_rad_s2: 1.0,
        yaw_rate_max_rad_s: 3.0,
    };

    /// Peak (horizontal, up, down) speeds of `g` over 30 s from `start_s` [m/s].
    fn peaks(g: &mut Guidance, start_s: f64) -> (f64, f64, f64) {
        let mut peak = (0.0_f64, 0.0_f64, 0.0_f64);
        for k in 0..3000 {
            let v = g.setpoint(start_s + k as f64 * 0.01, &at(0.0)).unwrap().vel_w.unwrap();
            peak = (peak.0.max(v.xy().norm()), peak.1.max(-v.z), peak.2.max(v.z));
        }
        peak
    }

    #[test]
    fn path_respects_the_speed_limit_and_ends_at_rest() {
        let mut g = Guidance::path(Vec3::zeros(), Vec3::new(0.0, 0.0, -5.0), 0.0, 0.0, &LIMITS, 10.0);
        let (_, peak, _) = peaks(&mut g, 10.0);
        assert!(peak <= 2.0 + 1e-9 && peak > 1.9, "{peak}");
        assert!(g.finished(14.7) && !g.finished(14.6));
        assert_eq!(
            g.setpoint(20.0, &at(0.0)).unwrap().pos_w,
            Some(Vec3::new(0.0, 0.0, -5.0))
        );
    }

    #[test]
    fn each_component_keeps_its_own_limit() {
        // 10 m north and 4 m down: the descent (1 m/s) sets the duration, not the cruise speed.
        let mut g = Guidance::path(Vec3::zeros(), Vec3::new(10.0, 0.0, 4.0), 0.0, 0.0, &LIMITS, 0.0);
        let (horizontal, up, down) = peaks(&mut g, 0.0);
        assert!(down <= 1.0 + 1e-9 && down > 0.99, "{down}");
        assert!((horizontal - 2.5).abs() < 0.01 && up == 0.0, "{horizontal} {up}");
        // 20 m east and 1 m up: the horizontal limit binds.
        let mut g = Guidance::path(Vec3::zeros(), Vec3::new(0.0, 20.0, -1.0), 0.0, 0.0, &LIMITS, 0.0);
        let (horizontal, _, _) = peaks(&mut g, 0.0);
        assert!(horizontal <= 5.0 + 1e-9 && horizontal > 4.99, "{horizontal}");
    }

    #[test]
    fn descent_leads_the_vehicle_by_at_most_half_a_metre() {
        let mut g = Guidance::Descend {
            xy_w: Vec3::new(1.0, 2.0, 0.0),
            yaw_rad: 0.0,
            z_start_m: -3.0,
            start_s: 0.0,
            start_down_m_s: 0.0,
            profile: DescentProfile::default(),
        };
        assert!((g.setpoint(1.0, &at(-3.0)).unwrap().pos_w.unwrap().z + 2.5).abs() < 1e-12);
        // The ground stopped the vehicle at z = −0.1: the reference stays 0.5 m below it.
        assert!((g.setpoint(100.0, &at(-0.1)).unwrap().pos_w.unwrap().z - 0.4).abs() < 1e-12);
        assert_eq!(Guidance::Idle.clone().setpoint(0.0, &at(0.0)), None);
    }
}
