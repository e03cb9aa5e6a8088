//! Horizontal circle at constant altitude. The angle θ about the centre starts at 0 — the start
//! point is `centre + R·[1, 0, 0]`, due north of the centre — and its rate ramps from rest to
//! ±2π/P with the minimum-jerk law over the ramp time, so velocity and acceleration are
//! continuous from rest. With a lap count it ramps down symmetrically, ending exactly `laps`
//! turns after the start, and holds there. Position `p = c + R·[cos θ, sin θ, 0]`: increasing θ
//! turns north → east, clockwise seen from above in NED.

use super::error::positive;
use super::quintic::{min_jerk, min_jerk_integral};
use super::{TrajectoryError, TrajectorySample};
use crate::math::{wrap_pi, Vec3};
use std::f64::consts::{FRAC_PI_2, TAU};

/// Heading along the circle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CircleYaw {
    /// A constant heading [rad].
    Fixed(f64),
    /// Nose along the direction of travel (θ ± π/2), with rate and acceleration feed-forward.
    Tangent,
}

/// What a [`Circle`] is built from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CircleParams {
    /// Centre, world NED [m]; its z is the altitude flown.
    pub centre_w: Vec3,
    /// Radius [m].
    pub radius_m: f64,
    /// Time per lap at full speed [s].
    pub period_s: f64,
    /// Time to ramp the angular rate up from rest (and down, with laps) [s].
    pub ramp_s: f64,
    /// Laps, counted from start to stop, ramps included; `None` circles forever.
    pub laps: Option<f64>,
    /// Clockwise seen from above (north → east) if true, else counter-clockwise.
    pub clockwise: bool,
    /// Heading mode.
    pub yaw: CircleYaw,
}

/// A validated circle; see the module documentation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Circle {
    params: CircleParams,
    /// Full angular rate 2π/P [rad/s].
    omega: f64,
    /// Start of the ramp down, if the laps end [s].
    ramp_down_s: Option<f64>,
}

impl Circle {
    /// Validates `params`; errors name the scenario field (`centre`, `radius`, `period`, `ramp`,
    /// `laps`, `yaw`). With laps, `laps · period` must be at least the ramp time.
    pub fn new(params: CircleParams) -> Result<Self, TrajectoryError> {
        if !params.centre_w.iter().all(|c| c.is_finite()) {
            return Err(TrajectoryError::new("centre", "must be finite numbers".into()));
        }
        positive("radius", params.radius_m)?;
        positive("period", params.period_s)?;
        positive("ramp", params.ramp_s)?;
        if let CircleYaw::Fixed(y) = params.yaw {
            if !y.is_finite() {
                return Err(TrajectoryError::new("yaw", format!("must be finite, got {y}")));
            }
        }
        let ramp_down_s = match params.laps {
            None => None,
            Some(n) => {
                positive("laps", n)?;
                let (turning, ramp) = (n * params.period_s, params.ramp_s);
                if turning < ramp {
                    let reason = format!("laps × period ({turning} s) must be at least the ramp time ({ramp} s)");
                    return Err(TrajectoryError::new("laps", reason));
                }
                Some(turning)
            }
        };
        let omega = TAU / params.period_s;
        Ok(Self {
            params,
            omega,
            ramp_down_s,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &CircleParams {
        &self.params
    }

    /// Start (and, with whole laps, end) point `centre + R·[1, 0, 0]` [m].
    pub fn start_w(&self) -> Vec3 {
        self.params.centre_w + Vec3::new(self.params.radius_m, 0.0, 0.0)
    }

    /// Time at which the circle comes to rest, `laps · P + ramp`; `None` without laps [s].
    pub fn duration_s(&self) -> Option<f64> {
        self.ramp_down_s.map(|t| t + self.params.ramp_s)
    }

    /// Unsigned angle travelled and its first three time derivatives at `t_s`
    /// [rad, rad/s, rad/s², rad/s³].
    fn angle(&self, t_s: f64) -> [f64; 4] {
        let (w, tr) = (self.omega, self.params.ramp_s);
        if t_s <= 0.0 {
            return [0.0; 4];
        }
        if t_s < tr {
            let tau = t_s / tr;
            let [s, ds, dds, _] = min_jerk(tau);
            return [w * tr * min_jerk_integral(tau), w * s, w * ds / tr, w * dds / (tr * tr)];
        }
        match self.ramp_down_s {
            Some(td) if t_s >= td + tr => [w * td, 0.0, 0.0, 0.0],
            Some(td) if t_s > td => {
                let u = (t_s - td) / tr;
                let [s, ds, dds, _] = min_jerk(u);
                let theta = w * (td - 0.5 * tr) + w * tr * (u - min_jerk_integral(u));
                [theta, w * (1.0 - s), -w * ds / tr, -w * dds / (tr * tr)]
            }
            _ => [w * (t_s - 0.5 * tr), w, 0.0, 0.0],
        }
    }

    /// Sample at time `t_s` [s] from the start.
    pub fn sample(&self, t_s: f64) -> TrajectorySample {
        let sign = if self.params.clockwise { 1.0 } else { -1.0 };
        let [th, th1, th2, th3] = self.angle(t_s).map(|x| sign * x);
        let r = self.params.radius_m;
        let (sn, cs) = th.sin_cos();
        let (radial, along) = (Vec3::new(cs, sn, 0.0), Vec3::new(-sn, cs, 0.0));
        let (yaw_rad, yaw_rate_rad_s, yaw_acc_rad_s2) = match self.params.yaw {
            CircleYaw::Fixed(y) => (wrap_pi(y), 0.0, 0.0),
            CircleYaw::Tangent => (wrap_pi(th + sign * FRAC_PI_2), th1, th2),
        };
        TrajectorySample {
            pos_w: self.params.centre_w + radial * r,
            vel_w: along * (r * th1),
            acc_w: along * (r * th2) - radial * (r * th1 * th1),
            jerk_w: along * (r * (th3 - th1.powi(3))) - radial * (3.0 * r * th1 * th2),
            yaw_rad,
            yaw_rate_rad_s,
            yaw_acc_rad_s2,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::testutil::{assert_continuous, assert_derivatives, random_times};
    use super::*;

    fn circle(laps: Option<f64>, clockwise: bool, yaw: CircleYaw) -> Circle {
        let centre_w = Vec3::new(1.0, -2.0, -3.0);
        let (radius_m, period_s, ramp_s) = (2.0, 8.0, 5.0);
        Circle::new(CircleParams {
            centre_w,
            radius_m,
            period_s,
            ramp_s,
            laps,
            clockwise,
            yaw,
        })
        .unwrap()
    }

    #[test]
    fn steady_radius_speed_and_tangent_heading() {
        for clockwise in [true, false] {
            let c = circle(None, clockwise, CircleYaw::Tangent);
            assert_eq!(
                c.sample(0.0),
                TrajectorySample::at_rest(c.start_w(), c.sample(0.0).yaw_rad)
            );
            for t in random_times(3, 0.0, 100.0, 200) {
                let s = c.sample(t);
                let d = s.pos_w - c.params().centre_w;
                assert!((d.norm() - 2.0).abs() < 1e-12 && d.z == 0.0);
                if t > 5.0 {
                    assert!((s.vel_w.norm() - TAU * 2.0 / 8.0).abs() < 1e-12);
                    let w2 = (TAU / 8.0).powi(2);
                    assert!((s.acc_w + d * w2).norm() < 1e-9 && (s.jerk_w + s.vel_w * w2).norm() < 1e-9);
                }
                if t > 1e-3 {
                    let along = s.vel_w.y.atan2(s.vel_w.x);
                    assert!(wrap_pi(s.yaw_rad - along).abs() < 1e-9, "t = {t}");
                }
                // Clockwise from above means the heading increases (NED yaw is clockwise).
                assert!(s.yaw_rate_rad_s * if clockwise { 1.0 } else { -1.0 } >= 0.0);
            }
        }
    }

    #[test]
    fn derivatives_and_continuity_across_ramps() {
        for (yaw, laps) in [(CircleYaw::Tangent, Some(1.5)), (CircleYaw::Fixed(2.0), Some(2.0))] {
            for clockwise in [true, false] {
                let c = circle(laps, clockwise, yaw);
                let end = c.duration_s().unwrap();
                let joins = [0.0, 5.0, end - 5.0, end];
                let mut times = random_times(4, -1.0, end + 1.0, 300);
                for j in joins {
                    assert_continuous(|t| c.sample(t), j);
                    times.extend([j - 1e-3, j - 1e-5, j + 1e-5, j + 1e-3]);
                }
                assert_derivatives(|t| c.sample(t), &times);
            }
        }
    }

    #[test]
    fn laps_end_at_rest_where_they_should() {
        let c = circle(Some(2.0), true, CircleYaw::Tangent);
        assert_eq!(c.duration_s(), Some(2.0 * 8.0 + 5.0));
        let s = c.sample(30.0);
        assert!((s.pos_w - c.start_w()).norm() < 1e-12);
        assert_eq!(
            (s.vel_w, s.acc_w, s.jerk_w),
            (Vec3::zeros(), Vec3::zeros(), Vec3::zeros())
        );
        assert!((s.yaw_rad - FRAC_PI_2).abs() < 1e-12);
        let half = circle(Some(0.75), false, CircleYaw::Fixed(1.0)).sample(99.0);
        assert!((half.pos_w - Vec3::new(1.0, 0.0, -3.0)).norm() < 1e-12);
        assert_eq!(half.yaw_rad, 1.0);
    }

    #[test]
    fn errors_name_the_field() {
        let ok = *circle(None, true, CircleYaw::Tangent).params();
        let e = |p: CircleParams| Circle::new(p).unwrap_err().to_string();
        assert_eq!(
            e(CircleParams { radius_m: 0.0, ..ok }),
            "trajectory.radius: must be positive, got 0"
        );
        assert!(e(CircleParams {
            period_s: f64::NAN,
            ..ok
        })
        .starts_with("trajectory.period:"));
        assert!(e(CircleParams { ramp_s: -1.0, ..ok }).starts_with("trajectory.ramp:"));
        assert!(e(CircleParams { laps: Some(0.5), ..ok }).starts_with("trajectory.laps: laps ×"));
        let centre_w = Vec3::new(0.0, f64::INFINITY, 0.0);
        assert!(e(CircleParams { centre_w, ..ok }).starts_with("trajectory.centre:"));
        let yaw = CircleYaw::Fixed(f64::NAN);
        assert!(e(CircleParams { yaw, ..ok }).starts_with("trajectory.yaw:"));
    }
}
