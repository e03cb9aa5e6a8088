//! A circle flown at constant height around a centre (PX4's orbit mode, MAV_CMD_DO_ORBIT), as a
//! closed form of time, so it needs no state: from rest on the circle at angle θ₀ the tangential
//! speed ramps up at the horizontal acceleration limit to the orbit speed.
//!
//! With θ measured from north towards east (clockwise seen from above), direction σ = +1
//! clockwise and −1 counter-clockwise, arc length s(τ) and speed v(τ) after τ = t − t₀:
//! ```text
//! v(τ) = min(a τ, v_o);  s(τ) = a τ²/2 (τ < v_o/a), else v_o²/2a + v_o (τ − v_o/a)
//! θ(τ) = θ₀ + σ s(τ)/r;  p = c + r (cos θ, sin θ, 0);  v = σ v(τ) (−sin θ, cos θ, 0)
//! a = −v²/r (cos θ, sin θ, 0) + σ v̇ (−sin θ, cos θ, 0)
//! v_o ≤ √(a_max r)  (the centripetal acceleration stays within MPC_ACC_HOR)
//! ```

use crate::control::FlatSetpoint;
use crate::math::{wrap_pi, Vec3};

/// Smallest and largest radius flown [m] (PX4: 1 m, `MC_ORBIT_RAD_MAX` 1000 m).
pub const ORBIT_RADIUS_M: (f64, f64) = (1.0, 1000.0);

/// Where the nose points while orbiting (MAV_CMD_DO_ORBIT p3, ORBIT_YAW_BEHAVIOUR).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum OrbitYaw {
    /// Towards the centre (0, PX4's default `MC_ORBIT_YAW_MOD`).
    #[default]
    FrontToCentre,
    /// The heading the orbit started with (1).
    HoldInitial,
    /// Not controlled: the heading the orbit started with is kept (2).
    Uncontrolled,
    /// Along the circle, in the direction of flight (3).
    FrontTangent,
    /// From the yaw stick (4, PX4's RC_CONTROLLED): the heading turns at the rate the yaw stick
    /// asks for ([`Orbit::steered`]); without sticks (or with the stick centred) it holds.
    RcControlled,
}

impl OrbitYaw {
    /// The behaviour of ORBIT_YAW_BEHAVIOUR `code`; `None` for codes MAVLink does not define.
    pub fn from_code(code: u8) -> Option<Self> {
        Some(match code {
            0 => Self::FrontToCentre,
            1 => Self::HoldInitial,
            2 => Self::Uncontrolled,
            3 => Self::FrontTangent,
            4 => Self::RcControlled,
            _ => return None,
        })
    }
}

/// One orbit: the circle, its speed and heading rule, and where and when it started.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orbit {
    /// Centre, world NED; its z is the height flown [m].
    pub centre_w: Vec3,
    /// Radius [m].
    pub radius_m: f64,
    /// Clockwise seen from above (a positive DO_ORBIT radius).
    pub clockwise: bool,
    /// Tangential speed [m/s], already within √(a_max r).
    pub speed_m_s: f64,
    /// Tangential acceleration of the ramp-up [m/s²].
    pub acc_m_s2: f64,
    /// Heading rule.
    pub yaw: OrbitYaw,
    /// Heading when the orbit started [rad]; with [`OrbitYaw::RcControlled`] the heading the
    /// yaw stick steered it to.
    pub initial_yaw_rad: f64,
    /// Heading rate the yaw stick asks for [rad/s] ([`OrbitYaw::RcControlled`]; 0 otherwise).
    pub stick_yaw_rate_rad_s: f64,
    /// Angle on the circle where it started, from north towards east [rad].
    pub start_angle_rad: f64,
    /// Simulated time it started [s].
    pub start_s: f64,
}

impl Orbit {
    /// The fastest tangential speed ≤ `wanted_m_s` [m/s] whose centripetal acceleration on a
    /// circle of `radius_m` [m] stays within `acc_m_s2` [m/s²].
    pub fn speed_within(wanted_m_s: f64, radius_m: f64, acc_m_s2: f64) -> f64 {
        wanted_m_s.min((acc_m_s2 * radius_m).sqrt())
    }

    /// The point on the circle nearest to `p_w` [m], at the orbit's height, and its angle [rad].
    pub fn nearest_point(centre_w: Vec3, radius_m: f64, p_w: Vec3) -> (Vec3, f64) {
        let d = p_w - centre_w;
        let angle = if d.xy().norm() > 1e-6 { d.y.atan2(d.x) } else { 0.0 };
        let p = centre_w + radius_m * Vec3::new(angle.cos(), angle.sin(), 0.0);
        (p, angle)
    }

    /// Angle on the circle at simulated time `t_s` [s] [rad].
    pub fn angle_at(&self, t_s: f64) -> f64 {
        let (s, _, _) = self.arc(t_s);
        wrap_pi(self.start_angle_rad + self.sign() * s / self.radius_m)
    }

    /// This orbit with its held heading turned for `dt_s` [s] at the yaw stick's `yaw_rate_rad_s`
    /// [rad/s], the rate a [`OrbitYaw::RcControlled`] setpoint feeds forward.
    pub fn steered(self, yaw_rate_rad_s: f64, dt_s: f64) -> Self {
        Self {
            initial_yaw_rad: wrap_pi(self.initial_yaw_rad + yaw_rate_rad_s * dt_s),
            stick_yaw_rate_rad_s: yaw_rate_rad_s,
            ..self
        }
    }

    /// The setpoint at simulated time `t_s` [s].
    pub fn setpoint(&self, t_s: f64) -> FlatSetpoint {
        let (s, v, dv) = self.arc(t_s);
        let sigma = self.sign();
        let theta = self.start_angle_rad + sigma * s / self.radius_m;
        let radial = Vec3::new(theta.cos(), theta.sin(), 0.0);
        let tangent = sigma * Vec3::new(-theta.sin(), theta.cos(), 0.0);
        let yaw_rate = sigma * v / self.radius_m;
        let (yaw, yaw_rate) = match self.yaw {
            OrbitYaw::FrontToCentre => (theta + std::f64::consts::PI, yaw_rate),
            OrbitYaw::FrontTangent => (theta + sigma * std::f64::consts::FRAC_PI_2, yaw_rate),
            OrbitYaw::HoldInitial | OrbitYaw::Uncontrolled => (self.initial_yaw_rad, 0.0),
            OrbitYaw::RcControlled => (self.initial_yaw_rad, self.stick_yaw_rate_rad_s),
        };
        FlatSetpoint {
            pos_w: Some(self.centre_w + self.radius_m * radial),
            vel_w: Some(v * tangent),
            acc_w: Some(-(v * v / self.radius_m) * radial + dv * tangent),
            yaw_rad: Some(wrap_pi(yaw)),
            yaw_rate_rad_s: Some(yaw_rate),
            yaw_acc_rad_s2: None,
        }
    }

    fn sign(&self) -> f64 {
        if self.clockwise {
            1.0
        } else {
            -1.0
        }
    }

    /// Arc length [m], speed [m/s] and tangential acceleration [m/s²] at `t_s` [s].
    fn arc(&self, t_s: f64) -> (f64, f64, f64) {
        let tau = (t_s - self.start_s).max(0.0);
        let (v_o, a) = (self.speed_m_s, self.acc_m_s2.max(1e-6));
        let ramp_s = v_o / a;
        if tau < ramp_s {
            (0.5 * a * tau * tau, a * tau, a)
        } else {
            (0.5 * v_o * ramp_s + v_o * (tau - ramp_s), v_o, 0.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn orbit(clockwise: bool, yaw: OrbitYaw) -> Orbit {
        Orbit {
            centre_w: Vec3::new(10.0, 0.0, -10.0),
            radius_m: 10.0,
            clockwise,
            speed_m_s: 2.0,
            acc_m_s2: 1.0,
            yaw,
            initial_yaw_rad: 0.3,
            stick_yaw_rate_rad_s: 0.0,
            start_angle_rad: std::f64::consts::PI,
            start_s: 5.0,
        }
    }

    #[test]
    fn the_orbit_stays_on_its_circle_and_ramps_up_to_its_speed() {
        let o = orbit(true, OrbitYaw::FrontToCentre);
        for k in 0..400 {
            let sp = o.setpoint(5.0 + 0.25 * k as f64);
            let p = sp.pos_w.unwrap_or_default();
            assert!(((p - o.centre_w).norm() - 10.0).abs() < 1e-9, "on the circle");
            assert_eq!(p.z, -10.0);
        }
        let start = o.setpoint(5.0);
        assert_eq!(start.vel_w, Some(Vec3::zeros()), "from rest");
        assert!((start.pos_w.unwrap_or_default() - Vec3::new(0.0, 0.0, -10.0)).norm() < 1e-9);
        let v = o.setpoint(8.0).vel_w.unwrap_or_default();
        assert!((v.norm() - 2.0).abs() < 1e-9, "at speed after v/a: {v:?}");
        // Clockwise from θ = π (south of the centre) the angle grows past π, wrapping to −π.
        assert!(o.angle_at(6.0) < 0.0, "clockwise from θ = π: {}", o.angle_at(6.0));
    }

    #[test]
    fn one_full_turn_takes_the_circumference_over_the_speed() {
        let o = orbit(false, OrbitYaw::HoldInitial);
        let ramp_s = 2.0;
        let lap_s = 2.0 * std::f64::consts::PI * 10.0 / 2.0;
        // After the ramp (1/2 · v · ramp = 2 m of arc), a lap later the angle is the same.
        let a = o.angle_at(5.0 + ramp_s);
        let b = o.angle_at(5.0 + ramp_s + lap_s);
        assert!(wrap_pi(a - b).abs() < 1e-9, "{a} {b}");
        assert_eq!(o.setpoint(30.0).yaw_rad, Some(0.3), "heading held");
    }

    #[test]
    fn the_nose_points_at_the_centre_or_along_the_circle() {
        let o = orbit(true, OrbitYaw::FrontToCentre);
        let sp = o.setpoint(20.0);
        let p = sp.pos_w.unwrap_or_default();
        let to_centre = o.centre_w - p;
        let yaw = sp.yaw_rad.unwrap_or_default();
        assert!(wrap_pi(to_centre.y.atan2(to_centre.x) - yaw).abs() < 1e-9);
        let o = orbit(true, OrbitYaw::FrontTangent);
        let sp = o.setpoint(20.0);
        let v = sp.vel_w.unwrap_or_default();
        assert!(wrap_pi(v.y.atan2(v.x) - sp.yaw_rad.unwrap_or_default()).abs() < 1e-9);
    }

    #[test]
    fn the_yaw_stick_steers_an_rc_controlled_heading_and_it_holds_without() {
        let o = orbit(true, OrbitYaw::RcControlled);
        assert_eq!(o.setpoint(20.0).yaw_rad, Some(0.3), "no stick: the heading holds");
        let mut steered = o;
        for _ in 0..100 {
            steered = steered.steered(0.5, 0.01);
        }
        let sp = steered.setpoint(20.0);
        assert!((sp.yaw_rad.unwrap_or_default() - 0.8).abs() < 1e-9, "{sp:?}");
        assert_eq!(sp.yaw_rate_rad_s, Some(0.5), "the stick's rate fed forward");
        let held = steered.steered(0.0, 0.01).setpoint(20.0);
        assert_eq!((held.yaw_rate_rad_s, held.pos_w), (Some(0.0), sp.pos_w));
        assert!((held.yaw_rad.unwrap_or_default() - 0.8).abs() < 1e-9);
        // The other behaviours ignore the stick.
        let front = orbit(true, OrbitYaw::FrontToCentre);
        assert_eq!(front.steered(0.5, 1.0).setpoint(20.0), front.setpoint(20.0));
        assert_eq!(OrbitYaw::from_code(4), Some(OrbitYaw::RcControlled));
    }

    #[test]
    fn the_speed_is_capped_by_the_centripetal_acceleration_and_codes_map() {
        assert_eq!(Orbit::speed_within(10.0, 2.0, 2.0), 2.0);
        assert_eq!(Orbit::speed_within(1.0, 100.0, 2.0), 1.0);
        let (p, angle) = Orbit::nearest_point(Vec3::new(0.0, 0.0, -5.0), 10.0, Vec3::new(0.0, 3.0, -1.0));
        assert!((p - Vec3::new(0.0, 10.0, -5.0)).norm() < 1e-9 && (angle - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert_eq!(OrbitYaw::from_code(3), Some(OrbitYaw::FrontTangent));
        assert_eq!(OrbitYaw::from_code(5), None);
    }
}
