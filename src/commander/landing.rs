//! What the land detector's verdict changes (PX4's land detector and auto-disarm):
//! - on the ground, a setpoint that does not ask to climb idles the motors;
//! - pushed against the ground (ground contact, maybe landed) while descending to land (a
//!   vertical speed setpoint of at least [`LANDING_DESCENT_SHARE`] of `MPC_LAND_SPEED`, PX4's
//!   "in descend"), the thrust is cut and the attitude the vehicle has is held, as PX4's
//!   position controller does while landing: no torque fights the ground over an attitude error
//!   of the estimate, and "maybe landed" can follow; any other setpoint that pushes down (a
//!   position on the ground) becomes a descent at the landing speed below the vehicle, which
//!   in the air only descends gently and on the ground lowers the thrust;
//! - a lift-off with nothing to fly (idle in a hold mode, lifted by a gust) holds position;
//! - auto-disarm (`COM_DISARM_LAND` after a touch-down, `COM_DISARM_PRFLT` when never airborne
//!   since arming) happens only while the detector says landed, so no path stops the motors in
//!   the air except a termination.

use crate::control::{AttitudeTarget, FlatSetpoint, VehicleState};
use crate::math::{euler_zyx, UnitQuat, Vec3};

use super::land_detector::LandDetector;

/// A position setpoint this far below (above) the vehicle asks to descend (climb) [m].
const SETPOINT_MARGIN_M: f64 = 0.05;
/// A vertical speed setpoint beyond this asks to descend or climb [m/s].
const SETPOINT_SPEED_M_S: f64 = 0.1;
/// A vertical speed setpoint of at least this share of `MPC_LAND_SPEED` is a descent to land
/// (PX4's land detector: 90 %) [-].
pub const LANDING_DESCENT_SHARE: f64 = 0.9;
/// An attitude target with thrust below this fraction of the weight asks to descend [-].
const DESCENT_THRUST_OF_WEIGHT: f64 = 0.9;

/// What the mode asks the motors to do this tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum FlightDemand {
    /// Fly a position / velocity / acceleration setpoint.
    Flat(FlatSetpoint),
    /// Fly an attitude or rate target with thrust.
    Attitude(AttitudeTarget),
    /// Motors off.
    Idle,
}

/// The setpoint asks the vehicle in `x` to go down or to stay below where it is.
pub(super) fn asks_descent(sp: &FlatSetpoint, x: &VehicleState) -> bool {
    sp.vel_w.is_some_and(|v| v.z > SETPOINT_SPEED_M_S)
        || sp.pos_w.is_some_and(|p| p.z > x.pos_w.z + SETPOINT_MARGIN_M)
        || (sp.pos_w.is_none() && sp.vel_w.is_none() && sp.acc_w.is_some_and(|a| a.z > SETPOINT_SPEED_M_S))
}

/// The setpoint is a position on the ground whose z is `ground_z_m` [m] (or below it): the vehicle
/// at it rests on its landing gear, so it asks to stay down (an offboard position back at the
/// take-off height touches down and lands, as the ground station expects).
fn on_the_ground(sp: &FlatSetpoint, ground_z_m: Option<f64>) -> bool {
    match (sp.pos_w, ground_z_m) {
        (Some(p), Some(g)) => p.z > g - SETPOINT_MARGIN_M && !sp.vel_w.is_some_and(|v| v.z < -SETPOINT_SPEED_M_S),
        _ => false,
    }
}

/// The setpoint descends to land: a vertical speed of at least [`LANDING_DESCENT_SHARE`] of
/// `land_speed_m_s` [m/s].
fn descends_to_land(sp: &FlatSetpoint, land_speed_m_s: f64) -> bool {
    sp.vel_w.is_some_and(|v| v.z >= LANDING_DESCENT_SHARE * land_speed_m_s)
}

/// The setpoint asks the vehicle in `x` to go up.
pub(super) fn asks_climb(sp: &FlatSetpoint, x: &VehicleState) -> bool {
    sp.vel_w.is_some_and(|v| v.z < -SETPOINT_SPEED_M_S)
        || sp.pos_w.is_some_and(|p| p.z < x.pos_w.z - SETPOINT_MARGIN_M)
        || (sp.pos_w.is_none() && sp.vel_w.is_none() && sp.acc_w.is_some_and(|a| a.z < -SETPOINT_SPEED_M_S))
}

/// Whether this tick's `command` asks the vehicle in `x` to go down (the land detector's
/// "descent commanded"), with the last tick's `thrust_over_weight` [-] and the ground the
/// detector last touched at `ground_z_m` [m].
pub(super) fn descent_commanded(
    command: &FlightDemand,
    x: &VehicleState,
    thrust_over_weight: f64,
    ground_z_m: Option<f64>,
) -> bool {
    match command {
        FlightDemand::Flat(sp) => asks_descent(sp, x) || on_the_ground(sp, ground_z_m),
        FlightDemand::Attitude(_) => thrust_over_weight < DESCENT_THRUST_OF_WEIGHT,
        FlightDemand::Idle => true,
    }
}

/// What an armed vehicle in `x` flies of `command` given the land detector's verdict
/// (`detector`, after its update) and `MPC_LAND_SPEED` `land_speed_m_s` [m/s]: on the ground only
/// a climb or an attitude target (else idle); pushed against the ground by a landing descent, the
/// touch-down; by another setpoint, a gentle descent below.
pub(super) fn near_ground(
    detector: &LandDetector,
    command: FlightDemand,
    x: &VehicleState,
    land_speed_m_s: f64,
) -> FlightDemand {
    if detector.landed() {
        return match command {
            FlightDemand::Flat(sp) if asks_climb(&sp, x) => command,
            FlightDemand::Attitude(_) => command,
            _ => FlightDemand::Idle,
        };
    }
    let land_speed = land_speed_m_s;
    match command {
        FlightDemand::Flat(sp) if detector.touching_down() => {
            if descends_to_land(&sp, land_speed) {
                FlightDemand::Attitude(touch_down(x))
            } else {
                FlightDemand::Flat(descend_below(x, &sp, land_speed))
            }
        }
        // The last metre to a position on the ground: a gentle descent that the ground stops,
        // rather than a hover on the landing gear that a touch-down would drop from.
        FlightDemand::Flat(sp)
            if on_the_ground(&sp, detector.ground_z_m())
                && detector.near_ground(x)
                && !descends_to_land(&sp, land_speed) =>
        {
            FlightDemand::Flat(descend_below(x, &sp, land_speed))
        }
        _ => command,
    }
}

/// How far below the vehicle the descent reference sits [m] (the landing guidance's lead).
const DESCENT_LEAD_M: f64 = 0.5;

/// The reference of a vehicle in `x` pushed against the ground by a setpoint that is no landing
/// descent: below it, descending at `speed_m_s` [m/s] (`MPC_LAND_SPEED`), level at the
/// setpoint's heading.
fn descend_below(x: &VehicleState, sp: &FlatSetpoint, speed_m_s: f64) -> FlatSetpoint {
    let below = x.pos_w + Vec3::new(0.0, 0.0, DESCENT_LEAD_M);
    FlatSetpoint {
        vel_w: Some(Vec3::new(0.0, 0.0, speed_m_s)),
        yaw_rate_rad_s: Some(0.0),
        ..FlatSetpoint::hold(below, sp.yaw_rad.unwrap_or(euler_zyx(&x.r_wb).z))
    }
}

/// The target of a vehicle in `x` pushed against the ground by a landing descent: no thrust, the attitude it has,
/// no rotation (PX4 cuts the thrust setpoint in ground contact and maybe landed, yaw setpoint at
/// the current yaw). The estimated attitude, not the level one, so that an error of the estimate
/// (a few degrees of tilt from an unobservable accelerometer bias) commands no torque against
/// the landing gear.
fn touch_down(x: &VehicleState) -> AttitudeTarget {
    AttitudeTarget {
        q_wb: Some(UnitQuat::from_matrix(&x.r_wb)),
        omega_b: Some(Vec3::zeros()),
        thrust_fraction: 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Commander, Event};
    use super::*;

    fn at(z: f64) -> VehicleState {
        VehicleState::at_rest(0.0, Vec3::new(0.0, 0.0, z))
    }

    #[test]
    fn setpoints_ask_descent_or_climb_by_position_velocity_or_acceleration() {
        let x = at(-0.1);
        let ground = FlatSetpoint::hold(Vec3::zeros(), 0.0);
        assert!(asks_descent(&ground, &x) && !asks_climb(&ground, &x));
        let up = FlatSetpoint::hold(Vec3::new(0.0, 0.0, -5.0), 0.0);
        assert!(asks_climb(&up, &x) && !asks_descent(&up, &x));
        let here = FlatSetpoint::hold(x.pos_w, 0.0);
        assert!(!asks_climb(&here, &x) && !asks_descent(&here, &x));
        let sink = FlatSetpoint {
            vel_w: Some(Vec3::new(0.0, 0.0, 1.0)),
            ..Default::default()
        };
        assert!(asks_descent(&sink, &x));
        let push_up = FlatSetpoint {
            acc_w: Some(Vec3::new(0.0, 0.0, -2.0)),
            ..Default::default()
        };
        assert!(asks_climb(&push_up, &x));
    }

    fn ticks(c: &mut Commander, x: &VehicleState, thrust: f64, from_s: f64, seconds: f64) -> Vec<Event> {
        let mut events = Vec::new();
        for k in 0..(seconds * 1000.0) as usize {
            events.extend(c.update(x, thrust, from_s + k as f64 * 1e-3).events);
        }
        events
    }

    #[test]
    fn idle_on_the_ground_disarms_after_com_disarm_prflt() {
        let mut c = Commander::new(super::super::CommanderParams::default());
        let ground = at(-0.1);
        assert_eq!(
            c.request(super::super::Request::Arm { force: false }, &ground, 0.0),
            super::super::Outcome::Accepted
        );
        assert_eq!(c.update(&ground, 0.0, 0.0).setpoint, None);
        let events = ticks(&mut c, &ground, 0.0, 0.001, 10.5);
        assert_eq!(events, vec![Event::Disarmed("no takeoff")]);
    }

    #[test]
    fn a_gust_that_lifts_an_idle_vehicle_makes_it_hold_and_it_never_disarms_in_the_air() {
        use super::super::{FlightMode, LandedState, Request};
        let mut c = Commander::new(super::super::CommanderParams::default());
        let ground = at(-0.1);
        c.request(Request::Arm { force: false }, &ground, 0.0);
        ticks(&mut c, &ground, 0.0, 0.0, 5.0);
        assert_eq!(c.landed_state(), LandedState::OnGround);
        let lifted = at(-1.0);
        let tick = c.update(&lifted, 0.0, 5.0);
        assert_eq!(tick.events, vec![Event::Airborne]);
        assert_eq!(tick.setpoint.and_then(|sp| sp.pos_w), Some(lifted.pos_w));
        assert_eq!(c.landed_state(), LandedState::InAir);
        // Hovering there long past COM_DISARM_PRFLT in every hold mode: still armed, in the air.
        for (k, mode) in [FlightMode::Position, FlightMode::Loiter, FlightMode::Ready]
            .into_iter()
            .enumerate()
        {
            c.request(Request::SetMode(mode), &lifted, 5.0 + k as f64 * 10.0);
            let events = ticks(&mut c, &lifted, 1.0, 5.001 + k as f64 * 10.0, 10.0);
            assert!(events.is_empty(), "{mode:?}: {events:?}");
            assert!(c.armed() && c.landed_state() == LandedState::InAir, "{mode:?}");
        }
        // A disarm request in the air is refused; AUTO.LAND reports landing.
        assert!(matches!(
            c.request(Request::Disarm { force: false }, &lifted, 40.0),
            super::super::Outcome::TemporarilyRejected(_)
        ));
        c.request(Request::Land, &lifted, 40.0);
        assert_eq!(c.landed_state(), LandedState::Landing);
    }

    #[test]
    fn a_setpoint_that_is_no_landing_descent_becomes_a_gentle_descent_below() {
        let x = at(-0.1);
        let on_ground = FlatSetpoint::hold(Vec3::new(3.0, 0.0, 0.0), 1.0);
        assert!(!descends_to_land(&on_ground, 0.7));
        let sp = descend_below(&x, &on_ground, 0.7);
        assert_eq!(sp.pos_w, Some(Vec3::new(0.0, 0.0, 0.4)));
        assert_eq!(sp.vel_w, Some(Vec3::new(0.0, 0.0, 0.7)));
        assert_eq!(sp.yaw_rad, Some(1.0));
        assert!(asks_descent(&sp, &x) && descends_to_land(&sp, 0.7));
    }

    #[test]
    fn touch_down_cuts_the_thrust_and_holds_the_attitude_the_vehicle_has() {
        let mut x = at(-0.1);
        let tilted = UnitQuat::from_euler_angles(0.05, -0.03, 1.0);
        x.r_wb = tilted.to_rotation_matrix().into_inner();
        let target = touch_down(&x);
        assert_eq!(target.thrust_fraction, 0.0);
        assert_eq!(target.omega_b, Some(Vec3::zeros()));
        assert!(target.q_wb.is_some_and(|q| q.angle_to(&tilted) < 1e-12));
    }

    #[test]
    fn a_descent_is_commanded_by_a_setpoint_below_low_thrust_or_idle_motors() {
        let x = at(-3.0);
        let below = FlightDemand::Flat(FlatSetpoint::hold(Vec3::new(0.0, 0.0, -1.0), 0.0));
        let here = FlightDemand::Flat(FlatSetpoint::hold(x.pos_w, 0.0));
        assert!(descent_commanded(&below, &x, 1.0, None));
        assert!(!descent_commanded(&here, &x, 1.0, None));
        let ground = FlightDemand::Flat(FlatSetpoint::hold(Vec3::new(0.0, 0.0, -0.1), 0.0));
        assert!(!descent_commanded(&ground, &at(-0.1), 1.0, None));
        let pressed = descent_commanded(&ground, &at(-0.1), 1.0, Some(-0.1));
        assert!(pressed, "a position on the ground");
        let attitude = FlightDemand::Attitude(touch_down(&x));
        assert!(descent_commanded(&attitude, &x, 0.5, None));
        assert!(!descent_commanded(&attitude, &x, 1.0, None));
        assert!(descent_commanded(&FlightDemand::Idle, &x, 1.0, None));
        let detector = LandDetector::default();
        assert!(detector.landed(), "a new detector starts on the ground");
        assert_eq!(
            near_ground(&detector, here, &x, 0.7),
            FlightDemand::Idle,
            "landed: no climb asked"
        );
        let up = FlightDemand::Flat(FlatSetpoint::hold(Vec3::new(0.0, 0.0, -5.0), 0.0));
        assert_eq!(near_ground(&detector, up, &x, 0.7), up, "a climb is flown");
    }
}
