//! Test helper: a [`Commander`] flying a scripted vehicle. The vehicle tracks the commander's
//! position setpoint exactly (as the MAVLink fuzz target's vehicle does), rests on flat ground
//! at z = [`GROUND_Z_M`] (NED, the gear height) and is pressed onto it (thrust over weight
//! [`PRESSED_THRUST`]) when the setpoint asks to go below; thrust over weight is 1 in the air and
//! 0 with the motors off or an attitude target without thrust (the touch-down cut), when the
//! vehicle drops to the ground; an attitude target with thrust holds the vehicle where it is. Each step is [`DT_S`] of
//! simulated time: the input streams' liveness as a link judges it (offboard setpoints and
//! sticks, [`StreamLiveness`], in simulated time), failsafes (with a set electrical power), then
//! the commander's tick, as the runtime does.

use crate::control::VehicleState;
use crate::math::{Mat3, UnitQuat, Vec3};
use crate::mav::link::liveness::StreamLiveness;

use super::{Commander, CommanderParams, CommanderTick, Event, FlightMode, Outcome, Request};

/// Where the vehicle rests on the ground, NED [m].
pub const GROUND_Z_M: f64 = -0.1;
/// Step [s].
pub const DT_S: f64 = 0.01;
/// Thrust over weight while pressed onto the ground [-].
pub const PRESSED_THRUST: f64 = 0.2;

/// A commander and the vehicle it flies.
pub struct Script {
    /// The commander under test.
    pub c: Commander,
    /// The vehicle's state.
    pub x: VehicleState,
    /// Electrical power drawn while armed [W] (drains the battery gauge).
    pub power_w: f64,
    /// Every event so far, in order.
    pub events: Vec<Event>,
    /// Last step's thrust over weight [-].
    thrust_over_weight: f64,
    /// The last tick's output.
    pub last: Option<CommanderTick>,
    /// The link's view of the streams the script sends.
    streams: StreamLiveness,
}

impl Script {
    /// Disarmed on the ground at the origin with `params`.
    pub fn new(params: CommanderParams) -> Self {
        Self {
            c: Commander::new(params),
            x: VehicleState {
                t_s: 0.0,
                pos_w: Vec3::new(0.0, 0.0, GROUND_Z_M),
                vel_w: Vec3::zeros(),
                r_wb: Mat3::identity(),
                omega_b: Vec3::zeros(),
            },
            power_w: 0.0,
            events: Vec::new(),
            thrust_over_weight: 0.0,
            last: None,
            streams: StreamLiveness::default(),
        }
    }

    /// Simulated time [s].
    pub fn t(&self) -> f64 {
        self.x.t_s
    }

    /// Sends `request` now.
    pub fn request(&mut self, request: Request) -> Outcome {
        let t_s = self.x.t_s;
        if let Some(stream) = request.input_stream() {
            self.streams.heard(stream, t_s, t_s);
        }
        self.c.request(request, &self.x, t_s)
    }

    /// One step: the streams' loss, failsafes, the commander's tick, the vehicle follows.
    /// Returns the step's events.
    pub fn step(&mut self) -> Vec<Event> {
        let t_s = self.x.t_s;
        for stream in self.streams.lost(t_s, t_s, &self.c.params) {
            self.c.request(Request::StreamLost(stream), &self.x, t_s);
        }
        let power_w = if self.c.armed() { self.power_w } else { 0.0 };
        let mut events = self.c.check_failsafes(&self.x, power_w, DT_S, t_s);
        let tick = self.c.update(&self.x, self.thrust_over_weight, t_s);
        events.extend(tick.events.iter().cloned());
        let old = self.x.pos_w;
        let (target, vel, yaw) = match (tick.setpoint, tick.attitude) {
            (Some(sp), _) => {
                let vel = sp.vel_w.unwrap_or_else(Vec3::zeros);
                let target = sp.pos_w.unwrap_or(old + vel * DT_S);
                (Some(target), vel, sp.yaw_rad)
            }
            (None, Some(a)) if a.thrust_fraction > 0.0 => (Some(old), Vec3::zeros(), None),
            (None, _) => (None, Vec3::zeros(), None),
        };
        match target {
            Some(p) if p.z > GROUND_Z_M => {
                self.x.pos_w = Vec3::new(p.x, p.y, GROUND_Z_M);
                self.x.vel_w = Vec3::zeros();
                self.thrust_over_weight = PRESSED_THRUST;
            }
            Some(p) => {
                self.x.pos_w = p;
                self.x.vel_w = vel;
                self.thrust_over_weight = 1.0;
            }
            None => {
                self.x.pos_w.z = GROUND_Z_M;
                self.x.vel_w = Vec3::zeros();
                self.thrust_over_weight = 0.0;
            }
        }
        if let Some(yaw) = yaw {
            self.x.r_wb = *UnitQuat::from_euler_angles(0.0, 0.0, yaw).to_rotation_matrix().matrix();
        }
        self.x.t_s += DT_S;
        self.last = Some(tick);
        self.events.extend(events.iter().cloned());
        events
    }

    /// Flies `seconds` [s]; the events on the way.
    pub fn fly(&mut self, seconds: f64) -> Vec<Event> {
        let mut events = Vec::new();
        for _ in 0..(seconds / DT_S).round() as usize {
            events.extend(self.step());
        }
        events
    }

    /// Flies until `done` holds (checked after each step), at most `max_s` [s]; whether it did.
    pub fn fly_until(&mut self, max_s: f64, mut done: impl FnMut(&Self) -> bool) -> bool {
        for _ in 0..(max_s / DT_S).round() as usize {
            self.step();
            if done(self) {
                return true;
            }
        }
        false
    }

    /// Arms, takes off to `height_m` [m] and flies until the take-off hands over to AUTO.LOITER.
    pub fn airborne(&mut self, height_m: f64) {
        assert_eq!(
            self.request(Request::Takeoff {
                height_m: Some(height_m)
            }),
            Outcome::Accepted
        );
        assert_eq!(self.request(Request::Arm { force: false }), Outcome::Accepted);
        let up = self.fly_until(60.0, |s| s.c.mode() == FlightMode::Loiter);
        assert!(up && self.c.in_air(), "took off to {height_m} m: {:?}", self.events);
    }

    /// Flies until disarmed on the ground, at most `max_s` [s]; whether it did.
    pub fn until_disarmed(&mut self, max_s: f64) -> bool {
        self.fly_until(max_s, |s| !s.c.armed())
    }
}
