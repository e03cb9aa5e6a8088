//! What to fly right now, as the commander's modes need it (PX4 AUTO modes; mavlink.md §2.1):
//! hold a point, follow a rest-to-rest path (take-off climb, return leg), or descend at a
//! constant speed until the ground stops the vehicle (landing).

use crate::control::{FlatSetpoint, VehicleState};
use crate::math::Vec3;

use super::trajectory::Quintic;

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
    /// Descend at `speed_m_s` [m/s] over `xy_w`, starting from `z_start_m` at `start_s`.
    Descend {
        /// Horizontal position held, world NED [m] (z ignored).
        xy_w: Vec3,
        /// Heading [rad].
        yaw_rad: f64,
        /// z where the descent began, NED [m].
        z_start_m: f64,
        /// Simulated time the descent began [s].
        start_s: f64,
        /// Descent speed [m/s].
        speed_m_s: f64,
    },
}

impl Guidance {
    /// A rest-to-rest path from `from_w` to `to_w` [m] whose peak speed stays below `speed_m_s`
    /// [m/s] (a quintic's peak is 1.875 × the mean), at least 1 s long.
    pub fn path(from_w: Vec3, to_w: Vec3, yaw_rad: f64, speed_m_s: f64, start_s: f64) -> Self {
        let duration_s = (1.875 * (to_w - from_w).norm() / speed_m_s.max(0.1)).max(1.0);
        Self::Path {
            path: Quintic {
                start_w: from_w,
                goal_w: to_w,
                duration_s,
                start_yaw_rad: yaw_rad,
                goal_yaw_rad: yaw_rad,
            },
            start_s,
        }
    }

    /// Setpoint at simulated time `t_s` [s] for the vehicle in state `x`; `None` for motors off.
    pub fn setpoint(&self, t_s: f64, x: &VehicleState) -> Option<FlatSetpoint> {
        match *self {
            Self::Idle => None,
            Self::Hold { pos_w, yaw_rad } => Some(FlatSetpoint::hold(pos_w, yaw_rad)),
            Self::Path { path, start_s } => Some(path.sample(t_s - start_s).setpoint()),
            Self::Descend {
                xy_w,
                yaw_rad,
                z_start_m,
                start_s,
                speed_m_s,
            } => {
                let z = (z_start_m + speed_m_s * (t_s - start_s)).min(x.pos_w.z + LAND_LEAD_MAX_M);
                Some(FlatSetpoint {
                    vel_w: Some(Vec3::new(0.0, 0.0, speed_m_s)),
                    ..FlatSetpoint::hold(Vec3::new(xy_w.x, xy_w.y, z), yaw_rad)
                })
            }
        }
    }

    /// True when a path has reached its goal (always true for the other kinds).
    pub fn finished(&self, t_s: f64) -> bool {
        match self {
            Self::Path { path, start_s } => t_s - start_s >= path.duration_s,
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

    #[test]
    fn path_respects_the_speed_limit_and_ends_at_rest() {
        let g = Guidance::path(Vec3::zeros(), Vec3::new(0.0, 0.0, -5.0), 0.0, 2.0, 10.0);
        let mut peak: f64 = 0.0;
        for k in 0..1000 {
            let sp = g.setpoint(10.0 + k as f64 * 0.01, &at(0.0)).unwrap();
            peak = peak.max(sp.vel_w.unwrap().norm());
        }
        assert!(peak <= 2.0 + 1e-9 && peak > 1.9, "{peak}");
        assert!(g.finished(14.7) && !g.finished(14.6));
        assert_eq!(
            g.setpoint(20.0, &at(0.0)).unwrap().pos_w,
            Some(Vec3::new(0.0, 0.0, -5.0))
        );
    }

    #[test]
    fn descent_leads_the_vehicle_by_at_most_half_a_metre() {
        let g = Guidance::Descend {
            xy_w: Vec3::new(1.0, 2.0, 0.0),
            yaw_rad: 0.0,
            z_start_m: -3.0,
            start_s: 0.0,
            speed_m_s: 0.7,
        };
        assert!((g.setpoint(1.0, &at(-3.0)).unwrap().pos_w.unwrap().z + 2.5).abs() < 1e-12);
        // The ground stopped the vehicle at z = −0.1: the reference stays 0.5 m below it.
        assert!((g.setpoint(100.0, &at(-0.1)).unwrap().pos_w.unwrap().z - 0.4).abs() < 1e-12);
        assert_eq!(Guidance::Idle.setpoint(0.0, &at(0.0)), None);
    }
}
