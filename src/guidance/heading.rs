//! A heading reference with limited rate and acceleration, as PX4's heading smoothing shapes the
//! yaw of its AUTO paths (`MPC_YAWRAUTO_MAX`, `MPC_YAWRAUTO_ACC`): a commanded heading, or a
//! commanded heading rate, is reached through a reference the attitude loop can follow, so the
//! vehicle neither lags a step of heading rate and then overshoots it to catch up, nor swings
//! past the heading it was sent to. Pure.
//!
//! Each tick of `dt`, with reference heading ψ and rate ω:
//! ```text
//! toward ψ_sp:   e = wrap(ψ_sp − ψ),   ω_d = sign(e) · min(ω_max, √(δ² + 2 a_max |e|) − δ, |e|/dt)
//!                (the braking curve in ticks, δ = a_max dt / 2)
//! at a rate:     ω_d = clamp(ω_sp, ±ω_max)
//! ω ← ω + clamp(ω_d − ω, ±a_max dt),   ψ ← wrap(ψ + ω dt)   (the new ω: the braking curve's steps)
//! ```
//! with the heading snapped onto ψ_sp once the remaining turn is within one tick at a rate the
//! acceleration limit can stop from, so the reference rests exactly on the commanded heading.
//! The way round is chosen when ψ_sp is commanded (the short way from the reference then) and
//! kept: e counts the turn left on that way, so a reference still turning the other way brakes,
//! comes back and never flips to the long way as it passes the heading opposite ψ_sp.

use crate::math::wrap_pi;

/// The heading reference: where it points and how fast it turns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeadingSlew {
    /// ψ [rad].
    yaw_rad: f64,
    /// ω [rad/s].
    rate_rad_s: f64,
    /// The heading being turned to [rad] and the turn left to it on the way chosen [rad].
    goal: Option<(f64, f64)>,
}

/// One tick's heading setpoint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeadingStep {
    /// ψ [rad].
    pub yaw_rad: f64,
    /// ω [rad/s].
    pub rate_rad_s: f64,
    /// ω̇ over the tick [rad/s²].
    pub acc_rad_s2: f64,
}

impl HeadingSlew {
    /// At rest at heading `yaw_rad` [rad].
    pub fn at(yaw_rad: f64) -> Self {
        Self {
            yaw_rad: wrap_pi(yaw_rad),
            rate_rad_s: 0.0,
            goal: None,
        }
    }

    /// The reference heading [rad].
    pub fn yaw_rad(&self) -> f64 {
        self.yaw_rad
    }

    /// Moves the reference heading to `yaw_rad` [rad] without changing its rate (a bound on how
    /// far it may lead the vehicle).
    pub fn set_yaw(&mut self, yaw_rad: f64) {
        self.yaw_rad = wrap_pi(yaw_rad);
        self.goal = None;
    }

    /// Turns towards `target_rad` [rad] the short way within `max_rate_rad_s` [rad/s] and
    /// `max_acc_rad_s2` [rad/s²] for `dt_s` [s].
    pub fn toward(&mut self, target_rad: f64, max_rate_rad_s: f64, max_acc_rad_s2: f64, dt_s: f64) -> HeadingStep {
        let target_rad = wrap_pi(target_rad);
        let error = match self.goal {
            Some((goal, left)) if goal == target_rad => left,
            _ => wrap_pi(target_rad - self.yaw_rad),
        };
        let dv = max_acc_rad_s2 * dt_s;
        if error.abs() <= (self.rate_rad_s.abs() + dv) * dt_s && self.rate_rad_s.abs() <= dv {
            let old = self.rate_rad_s;
            self.yaw_rad = target_rad;
            self.rate_rad_s = 0.0;
            self.goal = Some((target_rad, 0.0));
            return self.step_result(old, dt_s);
        }
        // The braking curve in whole ticks of deceleration (its continuous form √(2 a |e|) is
        // reached one tick late and would carry the reference past the heading).
        let half = 0.5 * dv;
        let braking = (half * half + 2.0 * max_acc_rad_s2 * error.abs()).sqrt() - half;
        let demand = braking.min(max_rate_rad_s).min(error.abs() / dt_s.max(f64::EPSILON));
        let step = self.advance(error.signum() * demand, max_acc_rad_s2, dt_s);
        self.goal = Some((target_rad, error - self.rate_rad_s * dt_s));
        step
    }

    /// Turns at `rate_rad_s` [rad/s] (clamped to ±`max_rate_rad_s`), reached within
    /// `max_acc_rad_s2` [rad/s²] (`f64::INFINITY`: at once), for `dt_s` [s].
    pub fn at_rate(&mut self, rate_rad_s: f64, max_rate_rad_s: f64, max_acc_rad_s2: f64, dt_s: f64) -> HeadingStep {
        self.goal = None;
        self.advance(rate_rad_s.clamp(-max_rate_rad_s, max_rate_rad_s), max_acc_rad_s2, dt_s)
    }

    /// ω towards `demand` within the acceleration limit, then ψ by ω over the tick.
    fn advance(&mut self, demand_rad_s: f64, max_acc_rad_s2: f64, dt_s: f64) -> HeadingStep {
        let old = self.rate_rad_s;
        let dv = max_acc_rad_s2 * dt_s;
        self.rate_rad_s += (demand_rad_s - self.rate_rad_s).clamp(-dv, dv);
        self.yaw_rad = wrap_pi(self.yaw_rad + self.rate_rad_s * dt_s);
        self.step_result(old, dt_s)
    }

    fn step_result(&self, old_rate_rad_s: f64, dt_s: f64) -> HeadingStep {
        HeadingStep {
            yaw_rad: self.yaw_rad,
            rate_rad_s: self.rate_rad_s,
            acc_rad_s2: if dt_s > 0.0 {
                (self.rate_rad_s - old_rate_rad_s) / dt_s
            } else {
                0.0
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f64 = 1e-3;
    const RATE: f64 = std::f64::consts::FRAC_PI_4; // 45 °/s
    const ACC: f64 = std::f64::consts::FRAC_PI_3; // 60 °/s²

    #[test]
    fn a_turn_accelerates_cruises_and_brakes_onto_the_heading_without_overshoot() {
        let mut h = HeadingSlew::at(170f64.to_radians());
        let target = -100f64.to_radians(); // 90° the short way, across ±180°
        let mut steps = Vec::new();
        for _ in 0..4000 {
            steps.push(h.toward(target, RATE, ACC, DT));
        }
        let bad: Vec<_> = steps
            .iter()
            .enumerate()
            .filter(|(_, s)| s.rate_rad_s < 0.0 || s.rate_rad_s > RATE + 1e-12)
            .take(5)
            .collect();
        assert!(bad.is_empty(), "{bad:?}");
        assert!(steps.iter().all(|s| s.acc_rad_s2.abs() <= ACC + 1e-9));
        assert!(
            steps.iter().any(|s| (s.rate_rad_s - RATE).abs() < 1e-9),
            "cruises at MPC_YAWRAUTO_MAX"
        );
        let last = steps.last().unwrap();
        assert_eq!((last.yaw_rad, last.rate_rad_s), (wrap_pi(target), 0.0));
        // 90° at 45 °/s with 0.75 s ramps each way: 2.75 s.
        let arrived = steps.iter().position(|s| s.yaw_rad == wrap_pi(target)).unwrap() as f64 * DT;
        assert!((arrived - 2.75).abs() < 0.02, "{arrived}");
    }

    #[test]
    fn a_heading_commanded_while_turning_the_other_way_is_reached_the_short_way() {
        let mut h = HeadingSlew::at(0.0);
        for _ in 0..3000 {
            h.at_rate(RATE, RATE, ACC, DT);
        }
        // Turning at 45 °/s through 118°, sent to −50°: 168° the short way back. Braking takes it
        // 17° further, past 130° (opposite −50°), and it still turns back.
        let start = h.yaw_rad().to_degrees();
        assert!((start - 118.1).abs() < 0.2, "{start}");
        let target = -50f64.to_radians();
        let steps: Vec<_> = (0..8000).map(|_| h.toward(target, RATE, ACC, DT)).collect();
        let furthest = steps.iter().map(|s| s.yaw_rad).fold(f64::MIN, f64::max).to_degrees();
        assert!(
            furthest > 130.0 && furthest < 136.0,
            "braked past the opposite heading: {furthest}"
        );
        assert!(
            steps.iter().any(|s| s.rate_rad_s < -RATE + 1e-9),
            "turns back at the full rate"
        );
        assert_eq!(steps.last().unwrap().yaw_rad, wrap_pi(target));
    }

    #[test]
    fn a_rate_is_reached_within_the_acceleration_limit_and_held() {
        let mut h = HeadingSlew::at(0.0);
        let steps: Vec<_> = (0..2000).map(|_| h.at_rate(1.0, 3.0, ACC, DT)).collect();
        assert!((steps[499].rate_rad_s - 0.5 * ACC).abs() < 1e-9);
        assert_eq!(steps.last().unwrap().rate_rad_s, 1.0);
        let clamped = h.at_rate(9.0, 3.0, f64::INFINITY, DT);
        assert_eq!(clamped.rate_rad_s, 3.0);
    }
}
