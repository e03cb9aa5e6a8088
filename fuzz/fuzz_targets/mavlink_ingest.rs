//! Datagram bytes → handled commands, without sockets: the input is one UDP datagram; every
//! frame in it goes through `codec::decode_datagram` and `ingest::ingest` (the decisions the
//! runtime link acts on), and the resulting actions are performed the way `runtime::link` does
//! — duplicate cache, stream table, parameter table, mission transfer and validation — against
//! a `Commander` flying a perfectly tracking vehicle, stepped after every frame.
//!
//! An input starting with `F` is read as framed chunks instead (see `framed`): valid CRCs around
//! fuzzed payloads.
//!
//! Invariants beyond "no panic": every reply encodes and decodes again as one frame; a request
//! carrying a non-finite number is never accepted; the commander's setpoints, attitude targets
//! and home stay finite; an accepted parameter set reads back.
#![no_main]

use libfuzzer_sys::fuzz_target;

use rotorpilot::commander::{Commander, CommanderParams, Outcome, Request};
use rotorpilot::control::{ControllerGains, ControllerKind, FlatSetpoint, VehicleState};
use rotorpilot::math::{Mat3, UnitQuat, Vec3};
use rotorpilot::mav::codec::{decode_datagram, encode_v2, frame_v2, unsupported_command_ack, Inbound};
use rotorpilot::mav::duplicates::{CommandKey, DuplicateCache, Seen};
use rotorpilot::mav::ingest::{ingest, Action, MissionStep};
use rotorpilot::mav::mission_items::parse_mission;
use rotorpilot::mav::mission_xfer::{download_count, download_item, Completed, MissionTransfer};
use rotorpilot::mav::params::{param_error_unknown, param_value};
use rotorpilot::mav::services::autopilot_version;
use rotorpilot::mav::streams::{LinkKind, StreamTable};
use rotorpilot::mav::telemetry::{message, status_text};
use rotorpilot::mav::translate::{command_ack, result_of, CommandDecision, Identity, OneShot};
use rotorpilot::mav::{MavHeader, MavMessage, MavMissionResult, MavResult, MavSeverity, MISSION_ITEM_INT_DATA};
use rotorpilot::navigation::{Home, Mission, MissionItem};
use rotorpilot::params::{ParamTable, VehicleSettings};
use rotorpilot::runtime::vehicle::DEFAULT_ESTIMATOR;
use rotorpilot::telemetry::Snapshot;

/// Simulated time between two frames [s].
const FRAME_DT_S: f64 = 0.05;
/// Control step the parameter table validates estimator designs at [s].
const DT_S: f64 = 1e-3;

fuzz_target!(|data: &[u8]| {
    let datagram = match data.split_first() {
        Some((&FRAMED, chunks)) => framed(chunks),
        _ => data.to_vec(),
    };
    let mut link = Link::new();
    for frame in decode_datagram(&datagram) {
        link.frame(frame);
        link.step(FRAME_DT_S);
    }
    // Long enough for take-off, landing detection and the auto-disarm timers.
    for _ in 0..40 {
        link.step(0.5);
    }
});

/// First byte of an input in framed form (see [`framed`]); any other input is one raw datagram.
const FRAMED: u8 = b'F';

/// Chunks of (message id u16 LE, payload length u8, payload) → one datagram of MAVLink 2 frames
/// from the ground station with valid CRCs, so that mutations reach the payload decoders and
/// the handlers instead of dying at the checksum.
fn framed(mut chunks: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    let mut sequence = 0u8;
    while let [lo, hi, len, rest @ ..] = chunks {
        let n = usize::from(*len).min(rest.len());
        let header = MavHeader {
            system_id: 255,
            component_id: 190,
            sequence,
        };
        frame_v2(header, u32::from(u16::from_le_bytes([*lo, *hi])), &rest[..n], &mut out);
        sequence = sequence.wrapping_add(1);
        chunks = &rest[n..];
    }
    out
}

/// One link and the vehicle behind it.
struct Link {
    id: Identity,
    home: Home,
    t_s: f64,
    x: VehicleState,
    commander: Commander,
    params: ParamTable,
    streams: StreamTable,
    duplicates: DuplicateCache,
    transfer: MissionTransfer<u8>,
    store: Vec<MISSION_ITEM_INT_DATA>,
    sequence: u8,
}

impl Link {
    fn new() -> Self {
        let params = ParamTable::new(&VehicleSettings::new(
            ControllerKind::Geometric,
            ControllerGains::default(),
            Some(DEFAULT_ESTIMATOR),
        ));
        Self {
            id: Identity::autopilot(1, 4),
            home: Home::default(),
            t_s: 0.0,
            x: VehicleState {
                t_s: 0.0,
                pos_w: Vec3::new(0.0, 0.0, -0.1),
                vel_w: Vec3::zeros(),
                r_wb: Mat3::identity(),
                omega_b: Vec3::zeros(),
            },
            commander: Commander::new(CommanderParams::default()),
            params,
            streams: StreamTable::new(LinkKind::Gcs),
            duplicates: DuplicateCache::default(),
            transfer: MissionTransfer::default(),
            store: Vec::new(),
            sequence: 0,
        }
    }

    /// Encodes `msg` as the link would send it and checks that it decodes again.
    fn send(&mut self, msg: &MavMessage) {
        let header = MavHeader {
            system_id: u32::from(self.id.system_id),
            component_id: self.id.component_id,
            sequence: self.sequence,
        };
        self.sequence = self.sequence.wrapping_add(1);
        let mut buf = Vec::new();
        encode_v2(header, msg, &mut buf);
        let back = decode_datagram(&buf);
        assert!(
            matches!(&back[..], [Inbound::Message { .. }]),
            "a reply does not decode as one message: {msg:?} → {back:?}"
        );
    }

    fn frame(&mut self, frame: Inbound) {
        match frame {
            Inbound::Message { header, message, .. } => {
                // The link logs every received frame re-encoded.
                let mut logged = Vec::new();
                encode_v2(header, &message, &mut logged);
                let now_ns = (self.t_s * 1e9) as i64;
                let action = ingest(&self.id, &header, &message, &self.home, now_ns);
                self.act(&header, action);
            }
            Inbound::UnknownCommand {
                header,
                command,
                target_system,
                target_component,
            } => {
                if self.id.accepts(&header, target_system, target_component) {
                    let ours = MavHeader {
                        system_id: u32::from(self.id.system_id),
                        component_id: self.id.component_id,
                        sequence: 0,
                    };
                    let bytes = unsupported_command_ack(ours, command, header.system_id as u8, header.component_id);
                    assert_eq!(
                        decode_datagram(bytes.raw_bytes()).len(),
                        1,
                        "the hand-built ACK is one frame"
                    );
                }
            }
            Inbound::Unparsable { .. } => {}
        }
    }

    fn act(&mut self, header: &MavHeader, action: Action) {
        let now_s = self.t_s;
        match action {
            Action::Ignore => {}
            Action::GcsHeartbeat => {}
            Action::Command { command, decision } => {
                if decision == CommandDecision::NotForUs {
                    return;
                }
                let key = CommandKey::new(header, &command);
                match self.duplicates.check(key, now_s) {
                    Seen::InProgress => return,
                    Seen::Answered(result) => {
                        self.send(&command_ack(header, command.command, result));
                        return;
                    }
                    Seen::New => {}
                }
                let result = match decision {
                    CommandDecision::NotForUs => return,
                    CommandDecision::Unsupported => MavResult::MAV_RESULT_UNSUPPORTED,
                    CommandDecision::Refuse(outcome) => self.announce(&outcome),
                    CommandDecision::Reply(one_shot) => {
                        let reply = match one_shot {
                            OneShot::AutopilotVersion => Some(autopilot_version(&self.id)),
                            OneShot::Stream(stream) => message(stream, &self.snapshot()),
                        };
                        if let Some(reply) = reply {
                            self.send(&reply);
                        }
                        MavResult::MAV_RESULT_ACCEPTED
                    }
                    CommandDecision::SetMessageInterval {
                        message_id,
                        interval_us,
                    } => match self.streams.set_interval(message_id, interval_us) {
                        Ok(()) => MavResult::MAV_RESULT_ACCEPTED,
                        Err(_) => MavResult::MAV_RESULT_DENIED,
                    },
                    CommandDecision::GetMessageInterval { message_id } => match self.streams.interval_us(message_id) {
                        Some(_) => MavResult::MAV_RESULT_ACCEPTED,
                        None => MavResult::MAV_RESULT_DENIED,
                    },
                    CommandDecision::Execute(request) => {
                        let outcome = self.request(request);
                        self.announce(&outcome)
                    }
                };
                self.duplicates.answered(key, result, now_s);
                self.send(&command_ack(header, command.command, result));
            }
            Action::Request(request) => {
                self.request(request);
            }
            Action::Refuse(why) => self.send(&status_text(MavSeverity::MAV_SEVERITY_WARNING, &why)),
            Action::Reply(msg) => self.send(&msg),
            Action::DataStream {
                stream_id,
                rate_hz,
                start,
            } => self.streams.request_data_stream(stream_id, rate_hz, start),
            Action::ParamList => {
                for i in 0..self.params.len() {
                    let msg = param_value(&self.params, i).expect("every index below len has a value");
                    self.send(&msg);
                }
            }
            Action::ParamRead { name, index } => {
                let found = index
                    .or_else(|| self.params.index_of(&name))
                    .and_then(|i| param_value(&self.params, i));
                let msg = found.unwrap_or_else(|| param_error_unknown(header, &name));
                self.send(&msg);
            }
            Action::ParamSet { name, value } => match self.params.set(&name, value, DT_S) {
                Ok(index) => {
                    assert_eq!(self.params.get(index).map(|(_, v)| v), Some(value));
                    self.commander.params = self.params.settings().commander;
                    let msg = param_value(&self.params, index).expect("a set parameter has a value");
                    self.send(&msg);
                }
                Err(e) => self.send(&status_text(MavSeverity::MAV_SEVERITY_WARNING, &e.to_string())),
            },
            // The key and its storage are the runtime's (`runtime::link`), outside this harness.
            Action::SetupSigning { key, .. } => assert_eq!(format!("{key:?}"), "SigningKey(<redacted>)"),
            Action::Mission { ids, step } => {
                let peer = ids.0;
                let (out, completed) = match step {
                    MissionStep::Count(m) => self.transfer.on_count(peer, ids, &m, now_s),
                    MissionStep::Item(m) => self.transfer.on_item(peer, &m, now_s),
                    MissionStep::Clear => self.transfer.on_clear(peer, ids),
                    MissionStep::RequestList(t) => (vec![(peer, download_count(ids, t, &self.store))], None),
                    MissionStep::RequestItem { seq, mission_type } => {
                        (vec![(peer, download_item(ids, mission_type, seq, &self.store))], None)
                    }
                };
                for (_, msg) in out {
                    self.send(&msg);
                }
                match completed {
                    Some(Completed::Items(items)) => {
                        let result = match parse_mission(&items, &self.home) {
                            Ok(mission) => {
                                assert!(
                                    mission_is_finite(&mission),
                                    "accepted mission item not finite: {mission:?}"
                                );
                                self.request(Request::SetMission(mission));
                                self.store = items;
                                MavMissionResult::MAV_MISSION_ACCEPTED
                            }
                            Err(e) => {
                                let why = format!("Mission item {} refused: {:?}", e.seq, e.result);
                                self.send(&status_text(MavSeverity::MAV_SEVERITY_WARNING, &why));
                                e.result
                            }
                        };
                        for (_, msg) in self.transfer.finish(result) {
                            self.send(&msg);
                        }
                    }
                    Some(Completed::Cleared) => {
                        self.request(Request::SetMission(Mission::default()));
                        self.store.clear();
                    }
                    None => {}
                }
            }
        }
        for (_, msg) in self.transfer.tick(now_s) {
            self.send(&msg);
        }
    }

    /// The commander's answer to `request`; a request with a non-finite number is never accepted.
    fn request(&mut self, request: Request) -> Outcome {
        let finite = request_is_finite(&request);
        let shown = format!("{request:?}");
        let outcome = self.commander.request(request, &self.x, self.t_s);
        assert!(
            finite || outcome != Outcome::Accepted,
            "non-finite request accepted: {shown}"
        );
        outcome
    }

    /// The ACK result of `outcome`, with the STATUSTEXT of a refusal.
    fn announce(&mut self, outcome: &Outcome) -> MavResult {
        if let Outcome::TemporarilyRejected(why)
        | Outcome::Denied(why)
        | Outcome::Unsupported(why)
        | Outcome::Failed(why) = outcome
        {
            self.send(&status_text(MavSeverity::MAV_SEVERITY_WARNING, why));
        }
        result_of(outcome)
    }

    /// One commander tick after `dt_s` [s]; the vehicle then tracks the setpoint perfectly.
    fn step(&mut self, dt_s: f64) {
        self.t_s += dt_s;
        self.x.t_s = self.t_s;
        let thrust_over_weight = if self.commander.armed() { 1.0 } else { 0.0 };
        let tick = self.commander.update(&self.x, thrust_over_weight, self.t_s);
        assert!(self.commander.home_w().iter().all(|v| v.is_finite()), "home not finite");
        if let Some(att) = &tick.attitude {
            assert!(att.is_finite(), "attitude target not finite: {att:?}");
        }
        match tick.setpoint {
            Some(sp) => {
                assert!(setpoint_is_finite(&sp), "setpoint not finite: {sp:?}");
                if let Some(p) = sp.pos_w {
                    self.x.pos_w = p;
                }
                self.x.vel_w = sp.vel_w.unwrap_or_else(Vec3::zeros);
                if let Some(yaw) = sp.yaw_rad {
                    self.x.r_wb = *UnitQuat::from_euler_angles(0.0, 0.0, yaw).to_rotation_matrix().matrix();
                }
            }
            None => self.x.vel_w = Vec3::zeros(),
        }
    }

    /// The telemetry snapshot of the commander's state (what one-shot replies read).
    fn snapshot(&self) -> Snapshot {
        let (seq, total, state) = self.commander.mission_progress();
        Snapshot {
            t_s: self.t_s,
            pos_w: self.x.pos_w,
            vel_w: self.x.vel_w,
            omega_b: self.x.omega_b,
            accel_b: Vec3::new(0.0, 0.0, -9.81),
            armed: self.commander.armed(),
            mode: self.commander.mode(),
            landed: self.commander.landed_state(),
            home_w: self.commander.home_w(),
            mission_seq: seq as u16,
            mission_total: total as u16,
            mission_state: state,
            rotor_count: 4,
            rotor_max_rad_s: 1100.0,
            geofence_breached: self.commander.geofence_breached(),
            ..Snapshot::initial(self.home)
        }
    }
}

fn finite3(v: &Vec3) -> bool {
    v.iter().all(|c| c.is_finite())
}

fn setpoint_is_finite(sp: &FlatSetpoint) -> bool {
    [sp.pos_w, sp.vel_w, sp.acc_w].iter().flatten().all(finite3)
        && [sp.yaw_rad, sp.yaw_rate_rad_s, sp.yaw_acc_rad_s2]
            .iter()
            .flatten()
            .all(|v| v.is_finite())
}

fn mission_is_finite(m: &Mission) -> bool {
    m.items.iter().all(|item| match item {
        MissionItem::Takeoff { height_m } => height_m.is_finite(),
        MissionItem::Waypoint {
            pos_w,
            hold_s,
            accept_m,
            yaw_rad,
        } => finite3(pos_w) && hold_s.is_finite() && accept_m.is_finite() && yaw_rad.is_none_or(f64::is_finite),
        MissionItem::LoiterTime { pos_w, seconds } => finite3(pos_w) && seconds.is_finite(),
        MissionItem::Land { pos_w } => pos_w.as_ref().is_none_or(finite3),
        MissionItem::ReturnToLaunch => true,
        MissionItem::ChangeSpeed { speed_m_s } => speed_m_s.is_finite(),
        MissionItem::Delay { seconds } => seconds.is_finite(),
    })
}

fn request_is_finite(r: &Request) -> bool {
    let opt = |v: &Option<f64>| v.is_none_or(f64::is_finite);
    match r {
        Request::Arm { .. }
        | Request::Disarm { .. }
        | Request::SetMode(_)
        | Request::Land
        | Request::ReturnToLaunch
        | Request::StartMission { .. }
        | Request::GcsLinkLost
        | Request::InjectRotorFailure { .. } => true,
        Request::Takeoff { height_m } => opt(height_m),
        Request::OffboardSetpoint { setpoint, .. } => setpoint_is_finite(setpoint),
        Request::OffboardAttitude(t) => t.is_finite(),
        Request::SetMission(m) => mission_is_finite(m),
        Request::Reposition {
            north_m,
            east_m,
            down_m,
            yaw_rad,
            speed_m_s,
        } => [north_m, east_m, down_m, yaw_rad, speed_m_s].iter().all(|v| opt(v)),
        Request::ChangeSpeed(v) => v.is_finite(),
        Request::SetHome(p) => p.as_ref().is_none_or(finite3),
    }
}
