//! Orbit mode (MAV_CMD_DO_ORBIT, PX4's POSCTL.ORBIT): approach the nearest point of the circle
//! on a rest-to-rest path, then fly the circle ([`Orbit`]) until another mode is chosen. A new
//! DO_ORBIT while orbiting changes what it names and keeps the rest (MAVLink: NaN keeps the
//! running orbit's radius, speed, heading rule and centre). Selected as a mode without a command,
//! it circles with the vehicle on the circle, as PX4 does: 10 m radius at 1 m/s, centre south.
//! The orbit goes on until another mode is chosen: DO_ORBIT's p4 (MAVLink's number of turns) is
//! not read, as PX4 does not read it. With yaw behaviour 4 (RC_CONTROLLED) the yaw stick turns
//! the heading on the circle at the stick modes' yaw rate; without sticks the heading holds.

use crate::control::VehicleState;
use crate::guidance::{Guidance, MotionLimits, Orbit, OrbitYaw, StickShaping, Sticks, ORBIT_RADIUS_M};
use crate::math::{euler_zyx, Vec3};

use super::{OrbitRequest, Outcome};

/// Radius of an orbit that names none [m].
const DEFAULT_RADIUS_M: f64 = 10.0;
/// Speed of an orbit that names none [m/s].
const DEFAULT_SPEED_M_S: f64 = 1.0;

/// The orbit flown or approached in orbit mode.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct OrbitMode {
    plan: Option<Orbit>,
}

impl OrbitMode {
    /// The orbit flown (centre [m] and radius [m], positive clockwise), `in_mode` while in
    /// orbit mode.
    pub fn status(&self, in_mode: bool) -> Option<(Vec3, f64)> {
        let o = self.plan.filter(|_| in_mode)?;
        Some((o.centre_w, if o.clockwise { o.radius_m } else { -o.radius_m }))
    }

    /// Another mode is entered: the orbit is forgotten.
    pub fn clear(&mut self) {
        self.plan = None;
    }

    /// DO_ORBIT with the vehicle in `x`, `in_air` or not, `in_mode` while orbiting (what the
    /// request leaves unset is kept), within `motion`: the orbit is planned, for the mode to be
    /// entered; refused on the ground and for a radius outside [1, 1000] m or a speed ≤ 0.
    pub fn request(
        &mut self,
        req: OrbitRequest,
        x: &VehicleState,
        in_air: bool,
        in_mode: bool,
        motion: &MotionLimits,
    ) -> Result<(), Outcome> {
        if !in_air {
            return Err(Outcome::TemporarilyRejected("Orbit: not in the air".into()));
        }
        let running = self.plan.filter(|_| in_mode);
        let signed = req
            .radius_m
            .or(running.map(|o| if o.clockwise { o.radius_m } else { -o.radius_m }))
            .unwrap_or(DEFAULT_RADIUS_M);
        if !(ORBIT_RADIUS_M.0..=ORBIT_RADIUS_M.1).contains(&signed.abs()) {
            return Err(Outcome::Denied(format!(
                "Orbit: radius {signed} m outside [{}, {}] m",
                ORBIT_RADIUS_M.0, ORBIT_RADIUS_M.1
            )));
        }
        let speed = req
            .speed_m_s
            .or(running.map(|o| o.speed_m_s))
            .unwrap_or(DEFAULT_SPEED_M_S);
        if speed <= 0.0 {
            return Err(Outcome::Denied(format!("Orbit: speed {speed} m/s")));
        }
        let centre_ne = req
            .centre_ne_m
            .or(running.map(|o| (o.centre_w.x, o.centre_w.y)))
            .unwrap_or((x.pos_w.x, x.pos_w.y));
        let centre_w = Vec3::new(centre_ne.0, centre_ne.1, req.centre_down_m.unwrap_or(x.pos_w.z));
        let yaw = req.yaw.or(running.map(|o| o.yaw)).unwrap_or_default();
        self.plan = Some(Self::plan(centre_w, signed, speed, yaw, x, motion));
        Ok(())
    }

    /// An orbit around `centre_w` [m] of signed radius `signed_m` [m] at `speed_m_s` [m/s]
    /// (capped at `MPC_XY_VEL_MAX` and by the centripetal acceleration of `lim`), starting at
    /// the point of the circle nearest to the vehicle.
    fn plan(
        centre_w: Vec3,
        signed_m: f64,
        speed_m_s: f64,
        yaw: OrbitYaw,
        x: &VehicleState,
        lim: &MotionLimits,
    ) -> Orbit {
        let radius_m = signed_m.abs();
        let (_, start_angle_rad) = Orbit::nearest_point(centre_w, radius_m, x.pos_w);
        Orbit {
            centre_w,
            radius_m,
            clockwise: signed_m > 0.0,
            speed_m_s: Orbit::speed_within(speed_m_s.min(lim.horizontal_m_s), radius_m, lim.acc_horizontal_m_s2),
            acc_m_s2: lim.acc_horizontal_m_s2,
            yaw,
            initial_yaw_rad: euler_zyx(&x.r_wb).z,
            stick_yaw_rate_rad_s: 0.0,
            start_angle_rad,
            start_s: 0.0,
        }
    }

    /// Where orbit mode's approach path goes on entry, [m] and heading [rad]: the start of the
    /// planned orbit (planned now, PX4's default, when the mode was chosen without DO_ORBIT).
    pub fn approach(&mut self, x: &VehicleState, motion: &MotionLimits) -> (Vec3, f64) {
        let plan = match self.plan {
            Some(plan) => plan,
            None => {
                let centre_w = x.pos_w - Vec3::new(DEFAULT_RADIUS_M, 0.0, 0.0);
                let plan = Self::plan(
                    centre_w,
                    DEFAULT_RADIUS_M,
                    DEFAULT_SPEED_M_S,
                    OrbitYaw::default(),
                    x,
                    motion,
                );
                self.plan = Some(plan);
                plan
            }
        };
        let start = plan.setpoint(plan.start_s);
        let to_w = start.pos_w.unwrap_or(x.pos_w);
        let to_yaw = start.yaw_rad.unwrap_or(plan.initial_yaw_rad);
        (to_w, to_yaw)
    }

    /// One orbit-mode tick flying `guidance`, `dt_s` [s] after the last: once the approach path
    /// has ended, the circle starts; on the circle an RC_CONTROLLED heading turns with the live
    /// yaw stick (`sticks`, shaped by `shaping`). The guidance to fly from now on, when it
    /// changed.
    pub fn advance(
        &mut self,
        guidance: Guidance,
        sticks: impl FnOnce() -> Option<Sticks>,
        shaping: &StickShaping,
        dt_s: f64,
        t_s: f64,
    ) -> Option<Guidance> {
        match (guidance, self.plan) {
            (Guidance::Path { .. }, Some(plan)) if guidance.finished(t_s) => {
                let orbit = Orbit { start_s: t_s, ..plan };
                self.plan = Some(orbit);
                Some(Guidance::Orbit(orbit))
            }
            (Guidance::Orbit(orbit), _) if orbit.yaw == OrbitYaw::RcControlled => {
                let rate = sticks().map_or(0.0, |s| shaping.yaw_rate(&s));
                let orbit = orbit.steered(rate, dt_s);
                self.plan = Some(orbit);
                Some(Guidance::Orbit(orbit))
            }
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::script::Script;
    use super::super::{CommanderParams, FlightMode, Outcome, Request};
    use super::*;
    use crate::math::Mat3;

    fn request(radius_m: f64, speed_m_s: f64, centre: (f64, f64)) -> Request {
        Request::Orbit(OrbitRequest {
            radius_m: Some(radius_m),
            speed_m_s: Some(speed_m_s),
            yaw: None,
            centre_ne_m: Some(centre),
            centre_down_m: Some(-10.0),
        })
    }

    #[test]
    fn do_orbit_approaches_the_circle_then_flies_it_facing_the_centre() {
        let mut s = Script::new(CommanderParams::default());
        assert_eq!(
            s.request(request(10.0, 2.0, (30.0, 0.0))),
            Outcome::TemporarilyRejected("Orbit: not in the air".into())
        );
        s.airborne(5.0);
        assert_eq!(s.request(request(10.0, 2.0, (30.0, 0.0))), Outcome::Accepted);
        assert_eq!(s.c.mode(), FlightMode::Orbit);
        s.fly(20.0);
        let centre = Vec3::new(30.0, 0.0, -10.0);
        let on_circle = |s: &Script| ((s.x.pos_w - centre).norm() - 10.0).abs() < 1e-6;
        assert!(on_circle(&s), "on the circle at the centre's height: {:?}", s.x.pos_w);
        let mut angles = Vec::new();
        for _ in 0..40 {
            s.fly(1.0);
            assert!(on_circle(&s));
            let d = s.x.pos_w - centre;
            angles.push(d.y.atan2(d.x));
            let yaw = crate::math::euler_zyx(&s.x.r_wb).z;
            assert!(
                crate::math::wrap_pi(yaw - (-d).y.atan2(-d.x)).abs() < 1e-6,
                "nose to the centre"
            );
        }
        assert!(s.x.vel_w.norm() > 1.99 && s.x.vel_w.norm() < 2.01, "{:?}", s.x.vel_w);
        let turned: f64 = angles.windows(2).map(|w| crate::math::wrap_pi(w[1] - w[0])).sum();
        assert!(turned > 7.0, "clockwise (angle growing), 80 m of arc: {turned} rad");
        assert_eq!(s.c.orbit_status(), Some((centre, 10.0)));
    }

    #[test]
    fn a_new_do_orbit_keeps_what_it_does_not_name_and_bad_values_are_denied() {
        let mut s = Script::new(CommanderParams::default());
        s.airborne(5.0);
        assert_eq!(s.request(request(-20.0, 3.0, (0.0, 40.0))), Outcome::Accepted);
        s.fly(30.0);
        let faster = Request::Orbit(OrbitRequest {
            speed_m_s: Some(5.0),
            ..Default::default()
        });
        assert_eq!(s.request(faster), Outcome::Accepted);
        s.fly(30.0);
        assert_eq!(s.c.orbit_status(), Some((Vec3::new(0.0, 40.0, -10.0), -20.0)));
        assert!((s.x.vel_w.norm() - 5.0).abs() < 1e-6, "{:?}", s.x.vel_w);
        assert!(matches!(s.request(request(0.5, 1.0, (0.0, 0.0))), Outcome::Denied(_)));
        assert!(matches!(s.request(request(10.0, -1.0, (0.0, 0.0))), Outcome::Denied(_)));
        assert_eq!(s.request(Request::SetMode(FlightMode::Loiter)), Outcome::Accepted);
        assert_eq!(s.c.orbit_status(), None);
    }

    #[test]
    fn rc_controlled_yaw_turns_with_the_yaw_stick_and_holds_without() {
        use crate::guidance::Sticks;
        let mut params = CommanderParams::default();
        // PX4 never hands an orbit to the pilot (ORBIT is not an auto control mode); here the
        // take-over is off so the stick only steers.
        params.manual.override_bits = 0;
        let shaping = params.manual.shaping;
        let mut s = Script::new(params);
        s.airborne(5.0);
        let rc = Request::Orbit(OrbitRequest {
            yaw: Some(OrbitYaw::RcControlled),
            ..OrbitRequest::default()
        });
        assert_eq!(s.request(rc), Outcome::Accepted);
        s.fly(15.0);
        let yaw = |s: &Script| crate::math::euler_zyx(&s.x.r_wb).z;
        let before = yaw(&s);
        s.fly(3.0);
        assert!((yaw(&s) - before).abs() < 1e-9, "no sticks: the heading holds");
        let stick = |s: &mut Script, y: f64, seconds: f64| {
            for _ in 0..(seconds / super::super::script::DT_S).round() as usize {
                let sticks = Sticks {
                    yaw: y,
                    ..Sticks::CENTRED
                };
                assert_eq!(s.request(Request::ManualControl(sticks)), Outcome::Accepted);
                s.step();
            }
        };
        let rate = shaping.yaw_rate(&Sticks {
            yaw: 0.5,
            ..Sticks::CENTRED
        });
        assert!(rate > 0.1, "{rate}");
        stick(&mut s, 0.5, 1.0);
        let turned = crate::math::wrap_pi(yaw(&s) - before);
        assert!(
            (turned - rate).abs() < 0.05 * rate,
            "{turned} rad for {rate} rad/s over 1 s"
        );
        assert_eq!(s.c.mode(), FlightMode::Orbit);
        let after = yaw(&s);
        stick(&mut s, 0.0, 2.0);
        assert!((yaw(&s) - after).abs() < 1e-9, "centred: the new heading holds");
        let (centre, _) = s.c.orbit_status().expect("still orbiting");
        assert!(((s.x.pos_w - centre).norm() - 10.0).abs() < 1e-6, "on the circle");
    }

    #[test]
    fn the_orbit_mode_alone_circles_with_the_vehicle_on_the_circle() {
        let mut s = Script::new(CommanderParams::default());
        s.airborne(5.0);
        let here = s.x.pos_w;
        assert_eq!(s.request(Request::SetMode(FlightMode::Orbit)), Outcome::Accepted);
        s.fly(5.0);
        let (centre, radius) = s.c.orbit_status().expect("orbiting");
        assert_eq!((centre, radius), (here - Vec3::new(10.0, 0.0, 0.0), 10.0));
        assert!(((s.x.pos_w - centre).norm() - 10.0).abs() < 1e-6);
    }

    fn at(pos_w: Vec3) -> VehicleState {
        VehicleState {
            t_s: 0.0,
            pos_w,
            vel_w: Vec3::zeros(),
            r_wb: Mat3::identity(),
            omega_b: Vec3::zeros(),
        }
    }

    #[test]
    fn a_request_keeps_what_it_leaves_unset_of_the_running_orbit_and_checks_the_rest() {
        let motion = MotionLimits::default();
        let x = at(Vec3::new(0.0, 0.0, -5.0));
        let mut o = OrbitMode::default();
        let req = OrbitRequest {
            radius_m: Some(-20.0),
            centre_ne_m: Some((0.0, 40.0)),
            ..Default::default()
        };
        assert!(matches!(
            o.request(req, &x, false, false, &motion),
            Err(Outcome::TemporarilyRejected(_))
        ));
        assert_eq!(o.request(req, &x, true, false, &motion), Ok(()));
        assert_eq!(o.status(true), Some((Vec3::new(0.0, 40.0, -5.0), -20.0)));
        assert_eq!(o.status(false), None, "not in orbit mode");
        let faster = OrbitRequest {
            speed_m_s: Some(3.0),
            ..Default::default()
        };
        assert_eq!(o.request(faster, &x, true, true, &motion), Ok(()));
        assert_eq!(o.status(true), Some((Vec3::new(0.0, 40.0, -5.0), -20.0)), "kept");
        let tiny = OrbitRequest {
            radius_m: Some(0.5),
            ..Default::default()
        };
        assert!(matches!(
            o.request(tiny, &x, true, true, &motion),
            Err(Outcome::Denied(_))
        ));
        o.clear();
        assert_eq!(o.status(true), None);
    }

    #[test]
    fn the_circle_starts_once_the_approach_is_flown() {
        let motion = MotionLimits::default();
        let x = at(Vec3::new(0.0, 0.0, -5.0));
        let mut o = OrbitMode::default();
        let (to_w, _) = o.approach(&x, &motion);
        assert!(
            (to_w - x.pos_w).norm() < 1e-9,
            "chosen as a mode: on the circle already"
        );
        let approach = Guidance::path(x.pos_w, to_w, 0.0, 0.0, &motion, 0.0);
        let shaping = StickShaping::default();
        let started = o.advance(approach, || None, &shaping, 0.01, 10.0);
        assert!(
            matches!(started, Some(Guidance::Orbit(orbit)) if orbit.start_s == 10.0),
            "{started:?}"
        );
        let circling = started.unwrap_or(approach);
        assert_eq!(
            o.advance(circling, || None, &shaping, 0.01, 10.01),
            None,
            "no RC yaw: unchanged"
        );
    }
}
