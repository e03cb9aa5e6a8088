//! Stick input (MANUAL_CONTROL, a joystick or QGroundControl's virtual one; ArduCopter's RC channels) and how PX4's stick
//! modes read it: the deadzone and expo curves of position and altitude control, the throttle
//! curve of the modes where the throttle stick sets the thrust, and the stick → attitude and
//! stick → body-rate maps of STABILIZED and ACRO. Pure.
//!
//! ```text
//! deadzone(s, d) = 0 for |s| ≤ d, else sign(s) (|s| − d) / (1 − d)
//! expo(s, e)     = (1 − e) s + e s³
//! throttle → thrust:  t < ½: T_min + (T_hover − T_min) · 2t;   t ≥ ½: T_hover + (1 − T_hover) · (2t − 1)
//! ```

use crate::math::Vec3;

/// One sample of the sticks, PX4's manual_control_setpoint convention.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sticks {
    /// Roll stick, right positive [-1, 1].
    pub roll: f64,
    /// Pitch stick, forward positive (nose down) [-1, 1].
    pub pitch: f64,
    /// Yaw stick, clockwise seen from above positive [-1, 1].
    pub yaw: f64,
    /// Throttle stick, 0 all the way down, ½ centred, 1 all the way up [0, 1].
    pub throttle: f64,
}

/// A MANUAL_CONTROL axis PX4 would not fly.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("MANUAL_CONTROL {axis} = {value} is outside [-1000, 1000]")]
pub struct StickError {
    /// The field (`x`, `y`, `z` or `r`).
    pub axis: &'static str,
    /// Its value.
    pub value: i16,
}

/// MANUAL_CONTROL marks an axis it does not drive with this value.
const AXIS_UNUSED: i16 = i16::MAX;

impl Sticks {
    /// Every stick centred, the throttle at half: hold where it is.
    pub const CENTRED: Sticks = Sticks {
        roll: 0.0,
        pitch: 0.0,
        yaw: 0.0,
        throttle: 0.5,
    };

    /// The sticks of one MANUAL_CONTROL: `x` pitch, `y` roll, `r` yaw in [-1000, 1000] and `z`
    /// throttle in [0, 1000] (PX4's convention, MAVSDK's `set_manual_control_input` sends it);
    /// an axis at `INT16_MAX` is unused and reads centred; a negative throttle reads 0.
    pub fn from_manual_control(x: i16, y: i16, z: i16, r: i16) -> Result<Self, StickError> {
        let axis = |name: &'static str, value: i16, centre: f64| -> Result<f64, StickError> {
            match value {
                AXIS_UNUSED => Ok(centre),
                -1000..=1000 => Ok(f64::from(value) / 1000.0),
                _ => Err(StickError { axis: name, value }),
            }
        };
        Ok(Self {
            pitch: axis("x", x, 0.0)?,
            roll: axis("y", y, 0.0)?,
            throttle: axis("z", z, 0.5)?.max(0.0),
            yaw: axis("r", r, 0.0)?,
        })
    }

    /// The sticks of RC channels 1–4 (RCMAP's order: roll, pitch, throttle, yaw) [µs], read
    /// over the standard 1000–2000 µs travel: roll and yaw right of 1500 positive, pitch below
    /// 1500 forward (nose down, as ArduPilot's pitch channel reads), throttle 1000 at 0 and 2000
    /// at 1; a value beyond the travel reads as its end.
    pub fn from_rc(roll_us: u16, pitch_us: u16, throttle_us: u16, yaw_us: u16) -> Self {
        let centred = |us: u16| ((f64::from(us) - 1500.0) / 500.0).clamp(-1.0, 1.0);
        Self {
            roll: centred(roll_us),
            pitch: -centred(pitch_us),
            yaw: centred(yaw_us),
            throttle: ((f64::from(throttle_us) - 1000.0) / 1000.0).clamp(0.0, 1.0),
        }
    }

    /// True when every number is finite.
    pub fn is_finite(&self) -> bool {
        [self.roll, self.pitch, self.yaw, self.throttle]
            .iter()
            .all(|v| v.is_finite())
    }

    /// The throttle stick as a climb demand [-1, 1]: centred 0, up 1, down −1.
    pub fn climb(&self) -> f64 {
        (2.0 * self.throttle - 1.0).clamp(-1.0, 1.0)
    }
}

/// How the stick modes read the sticks (PX4 names and defaults in brackets).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StickShaping {
    /// Deadzone of the sticks that hold position and height [-] (`MPC_HOLD_DZ`, 0.1).
    pub deadzone: f64,
    /// Expo of the horizontal sticks in POSCTL [-] (`MPC_XY_MAN_EXPO`, 0.6).
    pub xy_expo: f64,
    /// Expo of the throttle stick's climb demand [-] (`MPC_Z_MAN_EXPO`, 0.6).
    pub z_expo: f64,
    /// Expo of the yaw stick [-] (`MPC_YAW_EXPO`, 0.6).
    pub yaw_expo: f64,
    /// Horizontal speed at full stick in POSCTL [m/s] (`MPC_VEL_MANUAL`, 10).
    pub velocity_m_s: f64,
    /// Tilt at full stick in ALTCTL and STABILIZED [rad] (`MPC_MAN_TILT_MAX`, 35°).
    pub tilt_max_rad: f64,
    /// Heading rate at full yaw stick [rad/s] (`MPC_MAN_Y_MAX`, 150 °/s).
    pub yaw_rate_max_rad_s: f64,
    /// Body rates at full stick in ACRO, roll / pitch / yaw [rad/s] (`MC_ACRO_R_MAX` 100,
    /// `MC_ACRO_P_MAX` 100, `MC_ACRO_Y_MAX` 100 °/s).
    pub acro_rates_rad_s: Vec3,
    /// Thrust with the throttle stick all the way down, fraction of the maximum [-]
    /// (`MPC_MANTHR_MIN`, 0.08).
    pub thrust_min: f64,
    /// Thrust with the throttle stick centred, fraction of the maximum [-] (`MPC_THR_HOVER`,
    /// 0.5; the flight controller starts it at the airframe's hover thrust, as PX4's hover
    /// thrust estimator would find it).
    pub thrust_hover: f64,
}

impl Default for StickShaping {
    fn default() -> Self {
        Self {
            deadzone: 0.1,
            xy_expo: 0.6,
            z_expo: 0.6,
            yaw_expo: 0.6,
            velocity_m_s: 10.0,
            tilt_max_rad: 35f64.to_radians(),
            yaw_rate_max_rad_s: 150f64.to_radians(),
            acro_rates_rad_s: Vec3::repeat(100f64.to_radians()),
            thrust_min: 0.08,
            thrust_hover: 0.5,
        }
    }
}

impl StickShaping {
    /// The horizontal stick demand in the heading frame (forward, right) [-]: deadzone, then
    /// expo, on each axis; its norm is at most 1.
    pub fn horizontal(&self, s: &Sticks) -> (f64, f64) {
        let shape = |v: f64| expo(deadzone(v, self.deadzone), self.xy_expo);
        let (f, r) = (shape(s.pitch), shape(s.roll));
        let n = f.hypot(r);
        if n > 1.0 {
            (f / n, r / n)
        } else {
            (f, r)
        }
    }

    /// The climb demand, up positive [-1, 1]: deadzone, then expo.
    pub fn climb(&self, s: &Sticks) -> f64 {
        expo(deadzone(s.climb(), self.deadzone), self.z_expo)
    }

    /// The heading rate the yaw stick asks for [rad/s]: deadzone, expo, `MPC_MAN_Y_MAX`.
    pub fn yaw_rate(&self, s: &Sticks) -> f64 {
        expo(deadzone(s.yaw, self.deadzone), self.yaw_expo) * self.yaw_rate_max_rad_s
    }

    /// The tilt the roll and pitch sticks ask for, as (roll, pitch) Euler angles [rad]: the
    /// stick vector (capped at 1) scaled to `MPC_MAN_TILT_MAX`; pitch forward is nose down.
    pub fn tilt(&self, s: &Sticks) -> (f64, f64) {
        let (r, p) = (s.roll.clamp(-1.0, 1.0), s.pitch.clamp(-1.0, 1.0));
        let n = r.hypot(p).max(1.0);
        (r / n * self.tilt_max_rad, -p / n * self.tilt_max_rad)
    }

    /// The body rates ACRO asks for [rad/s]: roll right, pitch forward (nose down, so a
    /// negative pitch rate), yaw clockwise.
    pub fn acro_rates(&self, s: &Sticks) -> Vec3 {
        let r = &self.acro_rates_rad_s;
        Vec3::new(
            s.roll.clamp(-1.0, 1.0) * r.x,
            -s.pitch.clamp(-1.0, 1.0) * r.y,
            s.yaw.clamp(-1.0, 1.0) * r.z,
        )
    }

    /// The thrust the throttle stick sets in STABILIZED and ACRO, fraction of the maximum:
    /// the two-segment curve through `MPC_MANTHR_MIN`, `MPC_THR_HOVER` and full thrust.
    pub fn thrust(&self, s: &Sticks) -> f64 {
        let t = s.throttle.clamp(0.0, 1.0);
        if t < 0.5 {
            self.thrust_min + (self.thrust_hover - self.thrust_min) * 2.0 * t
        } else {
            self.thrust_hover + (1.0 - self.thrust_hover) * (2.0 * t - 1.0)
        }
    }
}

/// Zero within `d` of the centre, rescaled to reach ±1 at the ends.
fn deadzone(v: f64, d: f64) -> f64 {
    let v = v.clamp(-1.0, 1.0);
    if v.abs() <= d {
        0.0
    } else {
        v.signum() * (v.abs() - d) / (1.0 - d)
    }
}

/// PX4's expo curve: linear at `e` = 0, cubic at `e` = 1.
fn expo(v: f64, e: f64) -> f64 {
    let e = e.clamp(0.0, 1.0);
    (1.0 - e) * v + e * v * v * v
}

/// Time constant of the low-passed stick rates [s] (PX4's `MovingDiff`, 0.1 s).
const STICK_RATE_TAU_S: f64 = 0.1;

/// Whether the sticks are being moved: each axis's rate of change, low-passed, as PX4's manual
/// control input judges a pilot taking over (a stick held deflected is not moving). Pure.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StickMotion {
    last: Option<(Sticks, f64)>,
    /// Low-passed rates of roll, pitch, yaw and throttle [1/s].
    rates: [f64; 4],
}

impl StickMotion {
    /// Takes a stick sample arriving at `t_s` [s].
    pub fn sample(&mut self, s: Sticks, t_s: f64) {
        if let Some((last, t0)) = self.last {
            let dt = t_s - t0;
            if dt > 0.0 {
                let alpha = dt / (dt + STICK_RATE_TAU_S);
                let now = [s.roll, s.pitch, s.yaw, s.throttle];
                let before = [last.roll, last.pitch, last.yaw, last.throttle];
                for ((rate, v), v0) in self.rates.iter_mut().zip(now).zip(before) {
                    let raw = (v - v0) / dt;
                    if raw.is_finite() {
                        *rate += alpha * (raw - *rate);
                    }
                }
            }
        }
        self.last = Some((s, t_s));
    }

    /// True when any axis moves faster than `threshold_per_s` [1/s] (`COM_RC_STICK_OV` % per
    /// second: 0.3/s by default).
    pub fn moving(&self, threshold_per_s: f64) -> bool {
        self.rates.iter().any(|r| r.abs() > threshold_per_s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn manual_control_axes_map_as_px4_reads_them() {
        let s = Sticks::from_manual_control(500, -1000, 1000, 250).expect("valid");
        assert_eq!((s.pitch, s.roll, s.throttle, s.yaw), (0.5, -1.0, 1.0, 0.25));
        let unused = Sticks::from_manual_control(i16::MAX, i16::MAX, i16::MAX, i16::MAX).expect("valid");
        assert_eq!(unused, Sticks::CENTRED);
        assert_eq!(Sticks::from_manual_control(0, 0, -300, 0).map(|s| s.throttle), Ok(0.0));
        let err = Sticks::from_manual_control(0, 1001, 0, 0).expect_err("out of range");
        assert_eq!(err.to_string(), "MANUAL_CONTROL y = 1001 is outside [-1000, 1000]");
    }

    #[test]
    fn the_deadzone_holds_and_full_stick_reaches_full_demand() {
        let k = StickShaping::default();
        let at = |pitch, roll, throttle, yaw| Sticks {
            roll,
            pitch,
            yaw,
            throttle,
        };
        assert_eq!(k.horizontal(&at(0.09, -0.09, 0.5, 0.0)), (0.0, 0.0));
        assert_eq!(k.climb(&at(0.0, 0.0, 0.54, 0.0)), 0.0);
        assert_eq!(k.yaw_rate(&at(0.0, 0.0, 0.5, 0.1)), 0.0);
        assert_eq!(k.horizontal(&at(1.0, 0.0, 0.5, 0.0)), (1.0, 0.0));
        assert_eq!(k.climb(&at(0.0, 0.0, 1.0, 0.0)), 1.0);
        assert_eq!(k.climb(&at(0.0, 0.0, 0.0, 0.0)), -1.0);
        assert!((k.yaw_rate(&at(0.0, 0.0, 0.5, -1.0)) + 150f64.to_radians()).abs() < 1e-12);
        let (f, r) = k.horizontal(&at(1.0, 1.0, 0.5, 0.0));
        assert!((f.hypot(r) - 1.0).abs() < 1e-12, "a diagonal is capped at full demand");
        // Half stick past the deadzone: the expo softens it.
        let half = k.horizontal(&at(0.55, 0.0, 0.5, 0.0)).0;
        assert!((half - (0.4 * 0.5 + 0.6 * 0.125)).abs() < 1e-12, "{half}");
    }

    #[test]
    fn the_throttle_curve_passes_through_min_hover_and_full() {
        let k = StickShaping {
            thrust_hover: 0.4,
            ..Default::default()
        };
        let throttle = |t| Sticks {
            throttle: t,
            ..Sticks::CENTRED
        };
        assert!((k.thrust(&throttle(0.0)) - 0.08).abs() < 1e-12);
        assert!((k.thrust(&throttle(0.5)) - 0.4).abs() < 1e-12);
        assert!((k.thrust(&throttle(1.0)) - 1.0).abs() < 1e-12);
        assert!((k.thrust(&throttle(0.75)) - 0.7).abs() < 1e-12);
    }

    #[test]
    fn tilt_and_acro_rates_follow_the_stick_directions() {
        let k = StickShaping::default();
        let forward_right = Sticks {
            roll: 1.0,
            pitch: 1.0,
            ..Sticks::CENTRED
        };
        let (roll, pitch) = k.tilt(&forward_right);
        assert!(roll > 0.0 && pitch < 0.0, "right wing down, nose down");
        assert!(
            (roll.hypot(pitch) - 35f64.to_radians()).abs() < 1e-12,
            "capped at the tilt limit"
        );
        let rates = k.acro_rates(&forward_right);
        assert!(rates.x > 0.0 && rates.y < 0.0 && rates.z == 0.0);
    }

    #[test]
    fn sticks_are_moving_while_they_move_not_while_held_deflected() {
        let mut m = StickMotion::default();
        let at = |roll: f64| Sticks {
            roll,
            ..Sticks::CENTRED
        };
        // Held fully right for a second: not moving.
        for k in 0..50 {
            m.sample(at(1.0), f64::from(k) * 0.02);
        }
        assert!(!m.moving(0.3));
        // Swept back to centre over half a second (2/s): moving.
        for k in 0..25 {
            m.sample(at(1.0 - f64::from(k + 1) * 0.04), 1.0 + f64::from(k) * 0.02);
        }
        assert!(m.moving(0.3));
    }
}
