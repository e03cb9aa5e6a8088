//! A vehicle's MAVLink endpoint with virtual clocks, and the ground-station side of it: the
//! bench the in-process link tests (`link_machine.rs`, `link_liveness.rs`) drive.
#![allow(dead_code, deprecated, clippy::unwrap_used, clippy::expect_used)]

use mavlink::dialects::ardupilotmega::*;
use mavlink::Message;
use rotorpilot::control::{ControllerGains, ControllerKind};
use rotorpilot::guidance::Home;
use rotorpilot::mav::codec::{decode_datagram, encode_v2, Inbound};
use rotorpilot::mav::gcs::{command_long, gcs_header};
use rotorpilot::mav::link::{LinkConfig, LinkMachine, Now, ToVehicle};
use rotorpilot::mav::streams::LinkKind;
use rotorpilot::mav::translate::Identity;
use rotorpilot::params::{ParamTable, VehicleSettings};
use rotorpilot::telemetry::Snapshot;

pub use LinkKind::{Api, Gcs};

/// The configured remote of the GCS link, of the API link, and a second ground station.
pub const QGC: u16 = 14550;
pub const SDK: u16 = 14540;
pub const OTHER: u16 = 40000;

pub fn table() -> ParamTable {
    ParamTable::new(&VehicleSettings::new(
        ControllerKind::Geometric,
        ControllerGains::default(),
        None,
    ))
}

/// A vehicle's endpoint, the clocks, and what came out of it.
pub struct Bench {
    pub m: LinkMachine<u16>,
    pub now: Now,
    /// The snapshot the vehicle publishes.
    pub state: Snapshot,
}

impl Bench {
    pub fn new() -> Self {
        Self::with(|_| {})
    }

    pub fn with(adjust: impl FnOnce(&mut LinkConfig<u16>)) -> Self {
        let state = Snapshot::initial(Home::default());
        let mut config = LinkConfig::new(Identity::autopilot(1, 4), vec![(Gcs, QGC), (Api, SDK)], table(), state);
        adjust(&mut config);
        let mut bench = Self {
            m: LinkMachine::new(config),
            now: Now::new(0.0, 0.0),
            state,
        };
        bench.tick();
        bench.out();
        bench
    }

    /// Moves both clocks to (`wall_s`, `sim_s`) and runs the due duties.
    pub fn at(&mut self, wall_s: f64, sim_s: f64) {
        self.now = Now::new(wall_s, sim_s);
        self.tick();
    }

    pub fn tick(&mut self) {
        self.state.t_s = self.now.sim_s;
        self.m.handle_state(self.state);
        self.m.handle_timeout(self.now);
    }

    /// `msg` from the ground station at `from` on `link`.
    pub fn send(&mut self, link: LinkKind, from: u16, msg: MavMessage) {
        let mut bytes = Vec::new();
        encode_v2(gcs_header(0), &msg, &mut bytes);
        self.m.handle_datagram(self.now, link, from, &bytes);
    }

    /// Everything sent since the last call: (link, destination, message), in order.
    pub fn out(&mut self) -> Vec<(LinkKind, u16, MavMessage)> {
        let mut out = Vec::new();
        while let Some(t) = self.m.poll_transmit() {
            for frame in decode_datagram(&t.bytes) {
                let Inbound::Message { message, .. } = frame else {
                    panic!("not a message: {frame:?}");
                };
                out.push((t.link, t.to, *message));
            }
        }
        out
    }

    /// Where the HEARTBEATs on `link` went since the last call.
    pub fn heartbeats_to(&mut self, link: LinkKind) -> Vec<u16> {
        let out = self.out();
        named(&out, "HEARTBEAT")
            .iter()
            .filter(|(l, ..)| *l == link)
            .map(|t| t.1)
            .collect()
    }

    /// How many `name` messages go out on `link` while the clocks step through `times`
    /// ((wall, simulated) [s]), each step's duties run.
    pub fn count_sent(&mut self, name: &str, link: LinkKind, times: impl IntoIterator<Item = (f64, f64)>) -> usize {
        let mut count = 0;
        for (wall_s, sim_s) in times {
            self.at(wall_s, sim_s);
            count += named(&self.out(), name).iter().filter(|(l, ..)| *l == link).count();
        }
        count
    }

    /// Every request for the vehicle since the last call.
    pub fn asks(&mut self) -> Vec<ToVehicle> {
        std::iter::from_fn(|| self.m.poll_vehicle()).collect()
    }
}

pub fn command(command: MavCmd, param1: f32) -> MavMessage {
    let params = [param1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    MavMessage::COMMAND_LONG(command_long((1, 1), command, params))
}

pub fn gcs_heartbeat() -> MavMessage {
    MavMessage::HEARTBEAT(HEARTBEAT_DATA {
        mavtype: MavType::MAV_TYPE_GCS,
        autopilot: MavAutopilot::MAV_AUTOPILOT_INVALID,
        ..Default::default()
    })
}

pub fn param_id(name: &str) -> mavlink::types::CharArray<16> {
    let mut id = [0u8; 16];
    id[..name.len()].copy_from_slice(name.as_bytes());
    id.into()
}

pub fn param_set(name: &str, value: f32) -> MavMessage {
    MavMessage::PARAM_SET(PARAM_SET_DATA {
        param_value: value,
        target_system: 1,
        target_component: 1,
        param_id: param_id(name),
        param_type: MavParamType::MAV_PARAM_TYPE_REAL32,
    })
}

pub fn named<'a>(out: &'a [(LinkKind, u16, MavMessage)], name: &str) -> Vec<&'a (LinkKind, u16, MavMessage)> {
    out.iter().filter(|(_, _, m)| m.message_name() == name).collect()
}

/// The custom modes of the HEARTBEATs in `out`, in order.
pub fn custom_modes(out: &[(LinkKind, u16, MavMessage)]) -> Vec<u32> {
    out.iter()
        .filter_map(|(_, _, m)| match m {
            MavMessage::HEARTBEAT(hb) => Some(hb.custom_mode),
            _ => None,
        })
        .collect()
}

pub fn acks(out: &[(LinkKind, u16, MavMessage)]) -> Vec<MavResult> {
    out.iter()
        .filter_map(|(_, _, m)| match m {
            MavMessage::COMMAND_ACK(a) => Some(a.result),
            _ => None,
        })
        .collect()
}
