//! The inbound messages ArduCopter treats differently from PX4 (docs/ardupilot.md §2–§3), decided
//! before the shared [`ingest`](crate::mav::ingest::ingest), which handles the rest: mode changes
//! by Copter number (SET_MODE, DO_SET_MODE), NAV_TAKEOFF only in GUIDED with p7 above home,
//! NAV_LOITER_UNLIM as LOITER, guided targets (SET_POSITION_TARGET_*, SET_ATTITUDE_TARGET, a
//! MISSION_ITEM with `current` = 2) obeyed only in GUIDED and silently ignored elsewhere; the
//! mission numbered from 1 (docs/ardupilot.md §6): MISSION_ITEM as an upload item,
//! MISSION_SET_CURRENT, DO_SET_MISSION_CURRENT and MISSION_START naming the commander's item
//! seq − 1, and AUTO refused armed on the ground unless the mission starts with a take-off;
//! RC_CHANNELS_OVERRIDE for the RC receiver, and Copter's throttle rules for arming and for
//! STABILIZE and ACRO (docs/ardupilot.md §8). Pure.

use mavlink::dialects::ardupilotmega::{
    MavCmd, MavFrame, MavMessage, MavMissionResult, MavMissionType, COMMAND_LONG_DATA, MISSION_ITEM_INT_DATA,
};
use mavlink::MavHeader;

use super::copter_mission::{commander_index, item_int, starts_with_takeoff, AUTO, MISSING_TAKEOFF};
use super::copter_modes::{mode_request, CopterMode};
use super::copter_targets::{copter_attitude_target, copter_global_target, copter_local_target};
use crate::commander::{FlightMode, LandedState, Outcome, Request};
use crate::control::FlatSetpoint;
use crate::mav::identity::Identity;
use crate::mav::ingest::{Action, MissionStep};
use crate::mav::mission_xfer::mission_ack;
use crate::mav::translate::{command_int_as_long, decode_command, CommandDecision};
use crate::telemetry::Snapshot;

/// MAV_MODE_FLAG_CUSTOM_MODE_ENABLED: DO_SET_MODE p1 and SET_MODE `base_mode` must carry it.
const CUSTOM_MODE: u32 = 1;

/// What the ArduCopter face does with `message` from `sender` when the vehicle is in `state`
/// with the stored `mission` (as uploaded, item 0 the home slot) and its RC receiver's
/// `throttle` (the throttle stick the vehicle flies, [0, 1]); `None`: what
/// [`ingest`](crate::mav::ingest::ingest) decides.
#[allow(deprecated)]
pub fn copter_ingest(
    id: &Identity,
    sender: &MavHeader,
    message: &MavMessage,
    state: &Snapshot,
    mission: &[MISSION_ITEM_INT_DATA],
    throttle: f64,
) -> Option<Action> {
    let ours = |target_system: u8, target_component: u8| id.accepts(sender, target_system, target_component);
    let guided = state.mode == FlightMode::Guided;
    let ids = (sender.system_id as u8, sender.component_id);
    let on = Facts {
        state,
        mission,
        throttle,
    };
    match message {
        MavMessage::SET_MODE(m) if m.target_system == id.system_id => {
            Some(Action::SetModeMessage(
                if u32::from(m.base_mode.bits()) & CUSTOM_MODE == 0 {
                    // Copter's `_set_mode_common`: only custom modes, else UNSUPPORTED.
                    CommandDecision::Unsupported
                } else {
                    set_mode(m.custom_mode, on)
                },
            ))
        }
        MavMessage::RC_CHANNELS_OVERRIDE(o) if ours(o.target_system, o.target_component) => {
            Some(Action::RcOverride(Box::new(o.clone())))
        }
        MavMessage::COMMAND_LONG(c) if ours(c.target_system, c.target_component) => {
            if c.command == MavCmd::MAV_CMD_DO_REPOSITION {
                let decision = crate::mav::reposition::decode_long(c, &state.home);
                return Some(reposition(c.clone(), decision, state));
            }
            command(id, sender, c, on)
        }
        MavMessage::COMMAND_INT(c) if ours(c.target_system, c.target_component) => {
            let long = command_int_as_long(c);
            if c.command == MavCmd::MAV_CMD_DO_REPOSITION {
                let decision = crate::mav::reposition::decode_int(c, &long, &state.home);
                return Some(reposition(long, decision, state));
            }
            command(id, sender, &long, on)
        }
        MavMessage::SET_POSITION_TARGET_LOCAL_NED(t) if ours(t.target_system, t.target_component) => Some(if guided {
            copter_local_target(t, state)
        } else {
            Action::Ignore
        }),
        MavMessage::SET_POSITION_TARGET_GLOBAL_INT(t) if ours(t.target_system, t.target_component) => Some(if guided {
            copter_global_target(t, state)
        } else {
            Action::Ignore
        }),
        MavMessage::SET_ATTITUDE_TARGET(t) if ours(t.target_system, t.target_component) => Some(if guided {
            copter_attitude_target(t, state)
        } else {
            Action::Ignore
        }),
        MavMessage::MISSION_ITEM(m) if ours(m.target_system, m.target_component) && m.current == 2 => {
            Some(guided_goto(sender, &item_int(m), state))
        }
        MavMessage::MISSION_ITEM_INT(m) if ours(m.target_system, m.target_component) && m.current == 2 => {
            Some(guided_goto(sender, m, state))
        }
        // DroneKit uploads with MISSION_ITEM (float degrees): an item of the upload as any other.
        MavMessage::MISSION_ITEM(m) if ours(m.target_system, m.target_component) => Some(Action::Mission {
            ids,
            step: MissionStep::Item(Box::new(item_int(m))),
        }),
        MavMessage::MISSION_SET_CURRENT(m) if ours(m.target_system, m.target_component) => {
            Some(Action::Request(Request::SetMissionCurrent {
                seq: Some(commander_index(usize::from(m.seq))),
                reset: false,
            }))
        }
        _ => None,
    }
}

/// The Copter mode number `message` from `sender` asks for (SET_MODE, DO_SET_MODE by COMMAND_LONG
/// or COMMAND_INT, addressed to us), whether or not it can be flown.
#[allow(deprecated)]
pub fn asked_mode(id: &Identity, sender: &MavHeader, message: &MavMessage) -> Option<u32> {
    let number = |p2: f32| (p2 >= 0.0 && p2.fract() == 0.0 && p2 < 256.0).then_some(p2 as u32);
    match message {
        MavMessage::SET_MODE(m) if m.target_system == id.system_id => Some(m.custom_mode),
        MavMessage::COMMAND_LONG(c)
            if c.command == MavCmd::MAV_CMD_DO_SET_MODE && id.accepts(sender, c.target_system, c.target_component) =>
        {
            number(c.param2)
        }
        MavMessage::COMMAND_INT(c)
            if c.command == MavCmd::MAV_CMD_DO_SET_MODE && id.accepts(sender, c.target_system, c.target_component) =>
        {
            number(c.param2)
        }
        // MISSION_START switches to AUTO.
        MavMessage::COMMAND_LONG(c)
            if c.command == MavCmd::MAV_CMD_MISSION_START
                && id.accepts(sender, c.target_system, c.target_component) =>
        {
            Some(AUTO)
        }
        MavMessage::COMMAND_INT(c)
            if c.command == MavCmd::MAV_CMD_MISSION_START
                && id.accepts(sender, c.target_system, c.target_component) =>
        {
            Some(AUTO)
        }
        _ => None,
    }
}

/// What a command's decision reads: the vehicle's state, its stored mission (as uploaded) and
/// the throttle stick it flies [0, 1].
#[derive(Clone, Copy)]
struct Facts<'a> {
    state: &'a Snapshot,
    mission: &'a [MISSION_ITEM_INT_DATA],
    throttle: f64,
}

/// The throttle's centre band ends here: above it the pilot asks for a climb (`THR_DZ` 100 of
/// the throttle's 1000 above mid-stick) [-].
const THROTTLE_CLIMB: f64 = 0.6;
/// The throttle channel at its minimum: within `RC3_DZ` (30 µs) of 1000 µs [-].
const THROTTLE_MIN: f64 = 0.03;
/// Copter's non-take-off throttle, as a stick: half the hover throttle, the mid-stick [-].
const THROTTLE_NON_TAKEOFF: f64 = 0.25;
/// Below the centre band the throttle of STABILIZE or ACRO would drop the vehicle [-].
const THROTTLE_HOLDS: f64 = 0.4;
/// MAV_CMD_COMPONENT_ARM_DISARM p2's force.
const FORCE_ARM: f32 = 21196.0;

/// Whether the commander's `mode` is flown with the throttle as the thrust (Copter's manual
/// throttle modes STABILIZE and ACRO).
fn manual_throttle(mode: FlightMode) -> bool {
    matches!(mode, FlightMode::Stabilized | FlightMode::Acro | FlightMode::Manual)
}

impl Facts<'_> {
    /// ArduCopter refuses AUTO armed on the ground when the mission does not start with a
    /// take-off (`ModeAuto::init`).
    fn auto_refused(self) -> bool {
        self.state.armed && self.state.landed == LandedState::OnGround && !starts_with_takeoff(self.mission)
    }

    /// Copter's throttle rule for arming (`AP_Arming_Copter::arm_checks`): outside GUIDED and
    /// AUTO, a throttle above the centre band, or off its minimum in STABILIZE and ACRO, is
    /// "Throttle too high".
    fn arming_refusal(self) -> Option<Outcome> {
        let mode = self.state.mode;
        let exempt = matches!(mode, FlightMode::Guided | FlightMode::Mission);
        let high = self.throttle > THROTTLE_CLIMB || (manual_throttle(mode) && self.throttle > THROTTLE_MIN);
        (!exempt && high).then(|| Outcome::Failed("Arm: Throttle too high".into()))
    }

    /// The throttle rules of a change to Copter mode `number`: armed on the ground, a manual
    /// throttle mode entered from another with the throttle above Copter's non-take-off throttle
    /// is "throttle too high" (`Copter::set_mode`); in the air, with the throttle below the
    /// centre band, "throttle too low" (the emulator's: it would drop the vehicle).
    fn throttle_refusal(self, number: u32) -> Option<String> {
        let mode = CopterMode::by_number(number)?;
        let state = self.state;
        if !state.armed || !manual_throttle(mode.flown_as) || manual_throttle(state.mode) {
            return None;
        }
        let why = if state.landed == LandedState::OnGround {
            (self.throttle > THROTTLE_NON_TAKEOFF).then_some("throttle too high")
        } else {
            (self.throttle < THROTTLE_HOLDS).then_some("throttle too low")
        }?;
        Some(format!("Mode change to {} failed: {why}", mode.name))
    }
}

/// The commands Copter reads its own way; `None` for the others.
fn command(id: &Identity, sender: &MavHeader, c: &COMMAND_LONG_DATA, on: Facts) -> Option<Action> {
    let state = on.state;
    let decision = match c.command {
        MavCmd::MAV_CMD_DO_SET_MODE if (c.param1 as u32) & CUSTOM_MODE == 0 => CommandDecision::Refuse(
            Outcome::Denied(format!("Set mode: p1 {} without the custom mode flag", c.param1)),
        ),
        MavCmd::MAV_CMD_DO_SET_MODE if !(c.param2 >= 0.0 && c.param2.fract() == 0.0) => {
            CommandDecision::Refuse(Outcome::Denied(format!("Set mode: mode {} is not a number", c.param2)))
        }
        MavCmd::MAV_CMD_COMPONENT_ARM_DISARM if c.param1 == 1.0 && c.param2 != FORCE_ARM => match on.arming_refusal() {
            Some(refusal) => CommandDecision::Refuse(refusal),
            None => return None,
        },
        MavCmd::MAV_CMD_DO_SET_MODE => set_mode(c.param2 as u32, on),
        // The mission's seqs count the home slot: the commander's item is seq − 1.
        MavCmd::MAV_CMD_MISSION_START => match decode_command(id, sender, c, &state.home) {
            CommandDecision::Execute(_) if on.auto_refused() => CommandDecision::Critical(MISSING_TAKEOFF.into()),
            CommandDecision::Execute(Request::StartMission { first }) => {
                CommandDecision::Execute(Request::StartMission {
                    first: commander_index(first),
                })
            }
            other => other,
        },
        MavCmd::MAV_CMD_DO_SET_MISSION_CURRENT => match decode_command(id, sender, c, &state.home) {
            CommandDecision::Execute(Request::SetMissionCurrent { seq, reset }) => {
                CommandDecision::Execute(Request::SetMissionCurrent {
                    seq: seq.map(commander_index),
                    reset,
                })
            }
            other => other,
        },
        // Copter's user take-off: p7 above home [m]; the commander checks the mode (GUIDED,
        // LOITER, POSHOLD, ALT_HOLD), the motors, the ground and the height.
        MavCmd::MAV_CMD_NAV_TAKEOFF => CommandDecision::Execute(Request::UserTakeoff {
            height_m: f64::from(c.param7),
        }),
        MavCmd::MAV_CMD_NAV_LOITER_UNLIM => CommandDecision::Execute(Request::SelectMode(FlightMode::Position)),
        MavCmd::MAV_CMD_CONDITION_YAW => condition_yaw(c, state.eta.z),
        MavCmd::MAV_CMD_DO_CHANGE_SPEED => change_speed(c, state),
        _ => return None,
    };
    Some(Action::Command {
        command: c.clone(),
        decision,
    })
}

/// A change to Copter mode `number` (DO_SET_MODE's p2, SET_MODE's custom mode): AUTO refused
/// armed on the ground without a take-off first (CRITICAL "Auto: Missing Takeoff Cmd"), the
/// throttle rules, then the mode's request or Copter's refusal of the number.
fn set_mode(number: u32, on: Facts) -> CommandDecision {
    if number == AUTO && on.auto_refused() {
        return CommandDecision::Critical(MISSING_TAKEOFF.into());
    }
    match (on.throttle_refusal(number), mode_request(number)) {
        (Some(why), _) => CommandDecision::Refuse(Outcome::Failed(why)),
        (None, Ok(request)) => CommandDecision::Execute(request),
        (None, Err(refusal)) => CommandDecision::Refuse(refusal),
    }
}

/// DO_REPOSITION as Copter reads it (MAVProxy's `guided LAT LON ALT`), from the target PX4's
/// decoding found: in GUIDED, or with the mode-change flag (then entering GUIDED), the vehicle
/// flies to it in GUIDED (unset coordinates: the current ones); in another mode without the flag,
/// DENIED.
fn reposition(command: COMMAND_LONG_DATA, decision: CommandDecision, state: &Snapshot) -> Action {
    let decision = match decision {
        CommandDecision::Execute(Request::Reposition {
            north_m,
            east_m,
            down_m,
            yaw_rad,
            change_mode,
            ..
        }) => {
            if state.mode != FlightMode::Guided && !change_mode {
                CommandDecision::Refuse(Outcome::Denied(format!(
                    "Reposition: not in GUIDED (mode {}) and no mode change asked",
                    state.mode.name()
                )))
            } else {
                let here = state.pos_w;
                let pos_w = crate::math::Vec3::new(
                    north_m.unwrap_or(here.x),
                    east_m.unwrap_or(here.y),
                    down_m.unwrap_or(here.z),
                );
                CommandDecision::Execute(Request::GuidedGoto { pos_w, yaw_rad })
            }
        }
        other => other,
    };
    Action::Command { command, decision }
}

/// DO_CHANGE_SPEED as Copter reads it (`handle_MAV_CMD_DO_CHANGE_SPEED`): p2 the speed [m/s],
/// DENIED unless positive; p1 its type: 0 (airspeed) and 1 (ground speed) the horizontal speed,
/// 2 the climb and 3 the descent speed of GUIDED and AUTO (FAILED in another mode, as Copter's
/// other modes take no speed), any other DENIED.
fn change_speed(c: &COMMAND_LONG_DATA, state: &Snapshot) -> CommandDecision {
    let speed = f64::from(c.param2);
    if !(speed.is_finite() && speed > 0.0) {
        return CommandDecision::Refuse(Outcome::Denied(format!("Change speed: {} m/s", c.param2)));
    }
    let up = match c.param1 {
        0.0 | 1.0 => return CommandDecision::Execute(Request::ChangeSpeed(speed)),
        2.0 => true,
        3.0 => false,
        t => return CommandDecision::Refuse(Outcome::Denied(format!("Change speed: speed type {t}"))),
    };
    if !matches!(state.mode, FlightMode::Guided | FlightMode::Mission) {
        let mode = state.mode.name();
        return CommandDecision::Refuse(Outcome::Failed(format!("Change speed: not in GUIDED or AUTO ({mode})")));
    }
    CommandDecision::Execute(Request::ChangeVerticalSpeed { up, speed_m_s: speed })
}

/// CONDITION_YAW as Copter reads it: p1 the heading [deg, 0–360], p3 the direction of a relative
/// turn (−1 anti-clockwise, else clockwise), p4 1 for a turn relative to the heading `yaw_rad`
/// [rad], 0 for an absolute heading; out of range FAILED. The rate (p2) is the vehicle's own.
fn condition_yaw(c: &COMMAND_LONG_DATA, yaw_rad: f64) -> CommandDecision {
    let (angle, direction, relative) = (c.param1, c.param3, c.param4);
    if !((0.0..=360.0).contains(&angle) && (relative == 0.0 || relative == 1.0)) {
        return CommandDecision::Refuse(Outcome::Failed(format!(
            "Condition yaw: angle {angle} (0-360), relative {relative} (0 or 1)"
        )));
    }
    let angle_rad = f64::from(angle).to_radians();
    let target = if relative == 1.0 {
        yaw_rad + if direction < 0.0 { -angle_rad } else { angle_rad }
    } else {
        angle_rad
    };
    CommandDecision::Execute(Request::TurnTo {
        yaw_rad: crate::math::wrap_pi(target),
    })
}

/// A MISSION_ITEM(_INT) with `current` = 2, Copter's guided go-to (DroneKit's `simple_goto`): in
/// GUIDED a NAV_WAYPOINT becomes a position target (altitude AMSL in a global frame, above home
/// in a relative one); refused with MISSION_ACK ERROR outside GUIDED or for other commands.
#[allow(deprecated)] // the `_INT` frames: pymavlink scripts still send them
fn guided_goto(sender: &MavHeader, item: &MISSION_ITEM_INT_DATA, state: &Snapshot) -> Action {
    let ids = (sender.system_id as u8, sender.component_id);
    let refuse = || {
        Action::Reply(Box::new(mission_ack(
            ids,
            MavMissionType::MAV_MISSION_TYPE_MISSION,
            MavMissionResult::MAV_MISSION_ERROR,
        )))
    };
    if state.mode != FlightMode::Guided || item.command != MavCmd::MAV_CMD_NAV_WAYPOINT {
        return refuse();
    }
    let (lat, lon) = (f64::from(item.x) * 1e-7, f64::from(item.y) * 1e-7);
    let alt_amsl_m = match item.frame {
        MavFrame::MAV_FRAME_GLOBAL | MavFrame::MAV_FRAME_GLOBAL_INT => f64::from(item.z),
        MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT | MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT => {
            f64::from(item.z) + state.home.alt_amsl_m
        }
        _ => return refuse(),
    };
    if !(lat.abs() <= 90.0 && lon.abs() <= 180.0 && alt_amsl_m.is_finite()) {
        return refuse();
    }
    Action::Request(Request::offboard(FlatSetpoint {
        pos_w: Some(state.home.to_local(lat, lon, alt_amsl_m)),
        ..Default::default()
    }))
}

#[cfg(test)]
#[path = "copter_ingest_tests.rs"]
mod tests;
