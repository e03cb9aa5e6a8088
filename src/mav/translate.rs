//! MAVLink messages ↔ the commander's requests and state (docs/mavlink.md §1–§3). Pure.
//!
//! Addressing (docs/mavlink.md §3.1): a command is ours when `target_system ∈ {own, 0}` and
//! `target_component ∈ {1, 0}` and it does not come from our own ids. NaN parameters mean
//! "not set". Results map to MAV_RESULT with the refusal reason kept for STATUSTEXT.

use mavlink::dialects::ardupilotmega::{MavCmd, MavMessage, COMMAND_INT_DATA, COMMAND_LONG_DATA};
use mavlink::MavHeader;

use crate::commander::{FlightMode, ModeRefusal, Outcome, Request};
use crate::guidance::Home;

pub use super::identity::{command_ack, heartbeat, result_of, Identity};
use super::services::one_shot;
pub use super::services::OneShot;
use super::stream_messages::TelemetryStream;

/// Force-arm magic numbers in ARM_DISARM param2: the spec's and MAVProxy's.
const FORCE_MAGIC: [f32; 2] = [21196.0, 2989.0];

/// What to do with a COMMAND_LONG.
#[derive(Debug, Clone, PartialEq)]
pub enum CommandDecision {
    /// Not addressed to us: ignore silently.
    NotForUs,
    /// A commander request to execute; its outcome is the ACK.
    Execute(Request),
    /// Refused before execution (bad parameters, unknown mode), with the reason.
    Refuse(Outcome),
    /// Refused as FAILED, the reason said in a critical STATUSTEXT (ArduCopter's refusal to
    /// enter a mode, "Auto: Missing Takeoff Cmd").
    Critical(String),
    /// A command this emulator does not implement.
    Unsupported,
    /// Understood, but about something this emulator does not simulate: ACK UNSUPPORTED and a
    /// STATUSTEXT with the reason.
    NotSimulated(String),
    /// PREFLIGHT_CALIBRATION: ACK and the `[cal]` STATUSTEXTs ([`super::calibration`]).
    Calibrate(super::calibration::Calibration),
    /// ACK ACCEPTED, then send this message to the requester (REQUEST_MESSAGE and friends).
    Reply(OneShot),
    /// SET_MESSAGE_INTERVAL on this link (docs/mavlink.md §5): −1 off, 0 default, else µs.
    SetMessageInterval {
        /// Message id.
        message_id: u32,
        /// Interval [µs].
        interval_us: f32,
    },
    /// GET_MESSAGE_INTERVAL: ACK, then MESSAGE_INTERVAL.
    GetMessageInterval {
        /// Message id.
        message_id: u32,
    },
}

/// COMMAND_INT as the equivalent COMMAND_LONG: x/y (INT32_MAX = unset) become param5/param6.
pub fn command_int_as_long(c: &COMMAND_INT_DATA) -> COMMAND_LONG_DATA {
    let unset = |v: i32| if v == i32::MAX { f32::NAN } else { v as f32 };
    COMMAND_LONG_DATA {
        param1: c.param1,
        param2: c.param2,
        param3: c.param3,
        param4: c.param4,
        param5: unset(c.x),
        param6: unset(c.y),
        param7: c.z,
        command: c.command,
        target_system: c.target_system,
        target_component: c.target_component,
        confirmation: 0,
    }
}

/// `None` for NaN ("not set", docs/mavlink.md §3.1).
fn param(x: f32) -> Option<f32> {
    (!x.is_nan()).then_some(x)
}

/// GET_HOME_POSITION and REQUEST_AUTOPILOT_CAPABILITIES are deprecated but MAVProxy and MAVSDK
/// still send them (docs/mavlink.md §3.2, §12).
///
/// Decides what a COMMAND_LONG from `sender` means; `home_amsl_m` [m] turns NAV_TAKEOFF's AMSL
/// param7 into a height above home (a value below home AMSL is taken as the height itself, as
/// MAVProxy's `takeoff 5` sends).
#[allow(deprecated)]
pub fn decode_command(id: &Identity, sender: &MavHeader, cmd: &COMMAND_LONG_DATA, origin: &Home) -> CommandDecision {
    let home_amsl_m = origin.alt_amsl_m;
    if !id.accepts(sender, cmd.target_system, cmd.target_component) {
        return CommandDecision::NotForUs;
    }
    match cmd.command {
        MavCmd::MAV_CMD_COMPONENT_ARM_DISARM => {
            let force = FORCE_MAGIC.contains(&cmd.param2);
            match param(cmd.param1) {
                Some(1.0) => CommandDecision::Execute(Request::Arm { force }),
                Some(0.0) => CommandDecision::Execute(Request::Disarm { force }),
                _ => CommandDecision::Refuse(Outcome::Denied(format!(
                    "Arm/disarm: param1 {} is not 0 or 1",
                    cmd.param1
                ))),
            }
        }
        MavCmd::MAV_CMD_NAV_TAKEOFF => {
            let height_m = param(cmd.param7).map(|amsl| {
                let amsl = f64::from(amsl);
                if amsl >= home_amsl_m {
                    amsl - home_amsl_m
                } else {
                    amsl
                }
            });
            CommandDecision::Execute(Request::Takeoff { height_m })
        }
        MavCmd::MAV_CMD_NAV_LAND => CommandDecision::Execute(Request::Land),
        MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH => CommandDecision::Execute(Request::ReturnToLaunch),
        MavCmd::MAV_CMD_DO_SET_MODE => {
            let custom = param(cmd.param1).is_some_and(|p| (p as u32) & 1 == 1);
            let (Some(main), sub) = (param(cmd.param2), param(cmd.param3).unwrap_or(0.0)) else {
                return CommandDecision::Refuse(Outcome::Denied("Set mode: no main mode".into()));
            };
            if !custom {
                return CommandDecision::Refuse(Outcome::Denied("Set mode: only PX4 custom modes".into()));
            }
            match FlightMode::from_px4(main as u8, sub as u8) {
                Ok(mode) => CommandDecision::Execute(Request::SetMode(mode)),
                Err(ModeRefusal::Unknown) => {
                    CommandDecision::Refuse(Outcome::Denied(format!("Unknown mode {main}/{sub}")))
                }
                // PX4's answer to its Goto sub mode: "Unsupported auto mode", TEMPORARILY_REJECTED.
                Err(ModeRefusal::NotByNumber) => CommandDecision::Refuse(Outcome::TemporarilyRejected(format!(
                    "Mode {main}/{sub} is entered by DO_REPOSITION only"
                ))),
            }
        }
        MavCmd::MAV_CMD_DO_SET_STANDARD_MODE => match param(cmd.param1) {
            Some(p) => match FlightMode::from_standard_mode(p as u8) {
                Some(mode) if p.fract() == 0.0 && (0.0..=255.0).contains(&p) => {
                    CommandDecision::Execute(Request::SetMode(mode))
                }
                _ => CommandDecision::Refuse(Outcome::Failed(format!("Standard mode {p} not available"))),
            },
            None => CommandDecision::Refuse(Outcome::Denied("Set standard mode: no mode".into())),
        },
        MavCmd::MAV_CMD_INJECT_FAILURE => super::failure::inject_failure(cmd),
        MavCmd::MAV_CMD_PREFLIGHT_CALIBRATION => match super::calibration::decode(cmd) {
            Some(calibration) => CommandDecision::Calibrate(calibration),
            None => CommandDecision::Unsupported,
        },
        MavCmd::MAV_CMD_DO_ORBIT => {
            let centre = |x: f32| (!x.is_nan()).then_some(f64::from(x));
            super::orbit::decode_orbit(cmd, centre(cmd.param5).zip(centre(cmd.param6)), origin)
        }
        MavCmd::MAV_CMD_DO_REPOSITION => super::reposition::decode_long(cmd, origin),
        MavCmd::MAV_CMD_DO_CHANGE_SPEED => match param(cmd.param2) {
            Some(v) if v > 0.0 && v.is_finite() => CommandDecision::Execute(Request::ChangeSpeed(f64::from(v))),
            _ => CommandDecision::Refuse(Outcome::Denied(format!("Change speed: {} m/s", cmd.param2))),
        },
        MavCmd::MAV_CMD_DO_SET_HOME => {
            if param(cmd.param1) == Some(1.0) {
                CommandDecision::Execute(Request::SetHome(None))
            } else {
                let given = |x: f32| param(x).map(f64::from);
                set_home_at(given(cmd.param5), given(cmd.param6), given(cmd.param7), origin)
            }
        }
        MavCmd::MAV_CMD_MISSION_START => {
            let first = param(cmd.param1).unwrap_or(0.0);
            if !(first >= 0.0 && first.fract() == 0.0) {
                return CommandDecision::Refuse(Outcome::Denied(format!("Mission start: bad item {first}")));
            }
            CommandDecision::Execute(Request::StartMission { first: first as usize })
        }
        MavCmd::MAV_CMD_DO_SET_MISSION_CURRENT => {
            // p1: the item (−1: unchanged); p2: 1 starts the mission's DO_JUMP counts over.
            let seq = param(cmd.param1).unwrap_or(-1.0);
            let reset = param(cmd.param2) == Some(1.0);
            if seq == -1.0 && !reset {
                return CommandDecision::Refuse(Outcome::Denied("Set mission current: nothing to change".into()));
            }
            if !(seq == -1.0 || (seq >= 0.0 && seq.fract() == 0.0 && seq < 65536.0)) {
                return CommandDecision::Refuse(Outcome::Denied(format!("Set mission current: bad item {seq}")));
            }
            CommandDecision::Execute(Request::SetMissionCurrent {
                seq: (seq >= 0.0).then_some(seq as usize),
                reset,
            })
        }
        MavCmd::MAV_CMD_REQUEST_MESSAGE => match one_shot(cmd.param1, cmd.param2) {
            Some(m) => CommandDecision::Reply(m),
            None => CommandDecision::Refuse(Outcome::Denied(format!("Message {} not available", cmd.param1))),
        },
        MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL => match (param(cmd.param1), param(cmd.param2)) {
            (Some(id), Some(interval_us)) if id >= 0.0 => CommandDecision::SetMessageInterval {
                message_id: id as u32,
                interval_us,
            },
            _ => CommandDecision::Refuse(Outcome::Denied("Set message interval: bad parameters".into())),
        },
        MavCmd::MAV_CMD_GET_MESSAGE_INTERVAL => match param(cmd.param1) {
            Some(id) if id >= 0.0 => CommandDecision::GetMessageInterval { message_id: id as u32 },
            _ => CommandDecision::Refuse(Outcome::Denied("Get message interval: bad message id".into())),
        },
        MavCmd::MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES => CommandDecision::Reply(OneShot::AutopilotVersion),
        MavCmd::MAV_CMD_REQUEST_PROTOCOL_VERSION => CommandDecision::Reply(OneShot::ProtocolVersion),
        MavCmd::MAV_CMD_GET_HOME_POSITION => {
            CommandDecision::Reply(OneShot::TelemetryStream(TelemetryStream::HomePosition))
        }
        _ => CommandDecision::Unsupported,
    }
}

/// The mode a SET_MODE message (#11) asks for, when it is addressed to us and names a PX4 mode.
/// The message is deprecated in the spec but QGC 4.x changes modes with it (docs/mavlink.md §2.2).
#[allow(deprecated)]
pub fn decode_set_mode(id: &Identity, message: &MavMessage) -> Option<FlightMode> {
    match message {
        MavMessage::SET_MODE(m) if m.target_system == id.system_id => FlightMode::from_custom_mode(m.custom_mode).ok(),
        _ => None,
    }
}

/// A COMMAND_INT: positional commands use the exact degE7 x/y and the frame of z
/// (docs/mavlink.md §3.2: GLOBAL(_INT) → z AMSL, GLOBAL_RELATIVE_ALT(_INT) → z above home; other frames
/// UNSUPPORTED_MAV_FRAME); the rest decode as the equivalent COMMAND_LONG.
#[allow(deprecated)]
pub fn decode_command_int(id: &Identity, sender: &MavHeader, cmd: &COMMAND_INT_DATA, origin: &Home) -> CommandDecision {
    let long = command_int_as_long(cmd);
    if !id.accepts(sender, cmd.target_system, cmd.target_component) {
        return decode_command(id, sender, &long, origin);
    }
    if cmd.command == MavCmd::MAV_CMD_DO_ORBIT {
        let given = cmd.x != i32::MAX && cmd.y != i32::MAX;
        let centre = given.then(|| (f64::from(cmd.x) * 1e-7, f64::from(cmd.y) * 1e-7));
        return super::orbit::decode_orbit(&long, centre, origin);
    }
    if cmd.command == MavCmd::MAV_CMD_DO_SET_HOME && cmd.param1 != 1.0 {
        // The exact degE7 position; z is AMSL as PX4's commander reads it, whatever the frame.
        let degrees = |v: i32| (v != i32::MAX).then(|| f64::from(v) * 1e-7);
        let alt = param(cmd.z).map(f64::from);
        return set_home_at(degrees(cmd.x), degrees(cmd.y), alt, origin);
    }
    if cmd.command != MavCmd::MAV_CMD_DO_REPOSITION {
        return decode_command(id, sender, &long, origin);
    }
    super::reposition::decode_int(cmd, &long, origin)
}

/// DO_SET_HOME at latitude, longitude [deg] and altitude [m AMSL], each `None` when not given.
fn set_home_at(lat: Option<f64>, lon: Option<f64>, alt: Option<f64>, origin: &Home) -> CommandDecision {
    match (lat, lon, alt) {
        (Some(lat), Some(lon), Some(alt)) if !on_earth(lat, lon, alt) => CommandDecision::Refuse(Outcome::Denied(
            format!("Set home: {lat:.2}, {lon:.2}, {alt:.0} m is no place"),
        )),
        (Some(lat), Some(lon), Some(alt)) => {
            CommandDecision::Execute(Request::SetHome(Some(origin.to_local(lat, lon, alt))))
        }
        _ => CommandDecision::Refuse(Outcome::Denied("Set home: position not given".into())),
    }
}

/// Latitude [deg] in ±90, longitude [deg] in ±180 and altitude [m AMSL] in −1 km … 100 km.
pub(super) fn on_earth(lat_deg: f64, lon_deg: f64, alt_m: f64) -> bool {
    lat_deg.abs() <= 90.0 && lon_deg.abs() <= 180.0 && (-1_000.0..=100_000.0).contains(&alt_m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mav::gcs::{command_long, gcs_header};

    const NAN: f32 = f32::NAN;

    #[test]
    fn addressing_follows_the_rules() {
        let id = Identity::autopilot(1, 4);
        let arm = |t| {
            decode_command(
                &id,
                &gcs_header(0),
                &command_long(
                    t,
                    MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
                    [1.0, 0.0, NAN, NAN, NAN, NAN, NAN],
                ),
                &Home::default(),
            )
        };
        assert_eq!(arm((1, 1)), CommandDecision::Execute(Request::Arm { force: false }));
        assert_eq!(arm((0, 0)), CommandDecision::Execute(Request::Arm { force: false }));
        assert_eq!(arm((2, 1)), CommandDecision::NotForUs);
        assert_eq!(arm((1, 100)), CommandDecision::NotForUs);
        let own = MavHeader {
            system_id: 1,
            component_id: 1,
            sequence: 0,
        };
        assert!(!id.accepts(&own, 1, 1));
    }

    #[test]
    #[allow(deprecated)]
    fn arm_force_takeoff_altitude_and_modes_decode() {
        let id = Identity::autopilot(1, 6);
        let d = |c, p| decode_command(&id, &gcs_header(0), &command_long((1, 1), c, p), &Home::default());
        for magic in FORCE_MAGIC {
            assert_eq!(
                d(
                    MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
                    [0.0, magic, 0.0, 0.0, 0.0, 0.0, 0.0]
                ),
                CommandDecision::Execute(Request::Disarm { force: true })
            );
        }
        assert!(matches!(
            d(
                MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
                [2.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
            ),
            CommandDecision::Refuse(Outcome::Denied(_))
        ));
        let takeoff = |p7| d(MavCmd::MAV_CMD_NAV_TAKEOFF, [NAN, NAN, NAN, NAN, NAN, NAN, p7]);
        assert_eq!(
            takeoff(NAN),
            CommandDecision::Execute(Request::Takeoff { height_m: None })
        );
        assert_eq!(
            takeoff(498.0),
            CommandDecision::Execute(Request::Takeoff { height_m: Some(10.0) }),
            "AMSL"
        );
        assert_eq!(
            takeoff(5.0),
            CommandDecision::Execute(Request::Takeoff { height_m: Some(5.0) }),
            "MAVProxy"
        );
        // MAVSDK's offboard.stop() sends p1 = 129 (custom | armed): only the custom bit counts.
        assert_eq!(
            d(MavCmd::MAV_CMD_DO_SET_MODE, [129.0, 4.0, 3.0, NAN, NAN, NAN, NAN]),
            CommandDecision::Execute(Request::SetMode(FlightMode::Loiter))
        );
        assert_eq!(
            d(
                MavCmd::MAV_CMD_DO_SET_STANDARD_MODE,
                [5.0, NAN, NAN, NAN, NAN, NAN, NAN]
            ),
            CommandDecision::Execute(Request::SetMode(FlightMode::ReturnToLaunch))
        );
        assert!(matches!(
            d(
                MavCmd::MAV_CMD_DO_SET_STANDARD_MODE,
                [3.0, NAN, NAN, NAN, NAN, NAN, NAN]
            ),
            CommandDecision::Refuse(Outcome::Failed(_))
        ));
        assert_eq!(
            d(
                MavCmd::MAV_CMD_DO_SET_STANDARD_MODE,
                [6.0, NAN, NAN, NAN, NAN, NAN, NAN]
            ),
            CommandDecision::Execute(Request::SetMode(FlightMode::Mission))
        );
        assert_eq!(
            d(MavCmd::MAV_CMD_DO_SET_MODE, [1.0, 2.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
            CommandDecision::Execute(Request::SetMode(FlightMode::Altitude))
        );
        assert!(matches!(
            d(MavCmd::MAV_CMD_DO_SET_MODE, [1.0, 4.0, 12.0, 0.0, 0.0, 0.0, 0.0]),
            CommandDecision::Refuse(Outcome::Denied(_))
        ));
        assert!(
            matches!(
                d(MavCmd::MAV_CMD_DO_SET_MODE, [1.0, 4.0, 21.0, 0.0, 0.0, 0.0, 0.0]),
                CommandDecision::Refuse(Outcome::TemporarilyRejected(_))
            ),
            "Goto is entered by DO_REPOSITION only"
        );
        assert_eq!(d(MavCmd::MAV_CMD_DO_SET_SERVO, [0.0; 7]), CommandDecision::Unsupported);
        assert_eq!(
            d(MavCmd::MAV_CMD_REQUEST_MESSAGE, [148.0, NAN, NAN, NAN, NAN, NAN, NAN]),
            CommandDecision::Reply(OneShot::AutopilotVersion)
        );
        assert_eq!(
            d(MavCmd::MAV_CMD_GET_HOME_POSITION, [NAN; 7]),
            CommandDecision::Reply(OneShot::TelemetryStream(TelemetryStream::HomePosition))
        );
        assert_eq!(
            d(MavCmd::MAV_CMD_REQUEST_MESSAGE, [435.0, 3.0, NAN, NAN, NAN, NAN, NAN]),
            CommandDecision::Reply(OneShot::AvailableModes(3))
        );
        assert!(matches!(
            d(MavCmd::MAV_CMD_REQUEST_MESSAGE, [437.0, NAN, NAN, NAN, NAN, NAN, NAN]),
            CommandDecision::Refuse(Outcome::Denied(_))
        ));
        assert_eq!(
            d(MavCmd::MAV_CMD_REQUEST_PROTOCOL_VERSION, [NAN; 7]),
            CommandDecision::Reply(OneShot::ProtocolVersion)
        );
        let int = COMMAND_INT_DATA {
            command: MavCmd::MAV_CMD_NAV_TAKEOFF,
            x: i32::MAX,
            z: 493.0,
            target_system: 1,
            target_component: 1,
            ..Default::default()
        };
        let long = command_int_as_long(&int);
        assert!(long.param5.is_nan());
        assert_eq!(
            decode_command(&id, &gcs_header(0), &long, &Home::default()),
            CommandDecision::Execute(Request::Takeoff { height_m: Some(5.0) })
        );
    }

    #[test]
    fn set_home_by_command_int_takes_the_exact_position() {
        let id = Identity::autopilot(1, 1);
        let home = Home::default();
        let lat_e7 = (home.lat_deg * 1e7).round() as i32 + 900; // ≈ 10 m north
        let int = COMMAND_INT_DATA {
            command: MavCmd::MAV_CMD_DO_SET_HOME,
            frame: mavlink::dialects::ardupilotmega::MavFrame::MAV_FRAME_GLOBAL,
            x: lat_e7,
            y: (home.lon_deg * 1e7).round() as i32,
            z: (home.alt_amsl_m - 5.0) as f32,
            target_system: 1,
            target_component: 1,
            ..Default::default()
        };
        let CommandDecision::Execute(Request::SetHome(Some(p))) = decode_command_int(&id, &gcs_header(0), &int, &home)
        else {
            panic!("DO_SET_HOME as COMMAND_INT is executed");
        };
        assert!((p.x - 10.0).abs() < 0.05 && p.y.abs() < 0.05, "{p:?}");
        assert!((p.z - 5.0).abs() < 1e-3, "5 m below the origin: {p:?}");
        let unset = COMMAND_INT_DATA { x: i32::MAX, ..int };
        assert!(matches!(
            decode_command_int(&id, &gcs_header(0), &unset, &home),
            CommandDecision::Refuse(Outcome::Denied(_))
        ));
    }
}
