//! Hold one point at one heading, forever.

use super::TrajectorySample;
use crate::math::Vec3;

/// Hold `pos_w` at heading `yaw_rad`, at rest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hover {
    /// Position held, world NED [m].
    pub pos_w: Vec3,
    /// Heading held [rad].
    pub yaw_rad: f64,
}

impl Hover {
    /// Sample at any time [s]: the same point at rest.
    pub fn sample(&self, _t_s: f64) -> TrajectorySample {
        TrajectorySample::at_rest(self.pos_w, self.yaw_rad)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holds_point_and_heading_at_rest() {
        let h = Hover {
            pos_w: Vec3::new(1.0, 2.0, -3.0),
            yaw_rad: 4.0,
        };
        for t in [-1.0, 0.0, 7.5] {
            let s = h.sample(t);
            assert_eq!(s.pos_w, h.pos_w);
            assert_eq!(s.vel_w, Vec3::zeros());
            assert_eq!(s.jerk_w, Vec3::zeros());
            assert!((s.yaw_rad - (4.0 - std::f64::consts::TAU)).abs() < 1e-15);
            assert_eq!((s.yaw_rate_rad_s, s.yaw_acc_rad_s2), (0.0, 0.0));
        }
    }
}
