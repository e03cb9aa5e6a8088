//! A vehicle of `rotorpilot run` in this process on ephemeral ports, and a GCS socket that talks
//! to it with the crate's codec (shared by the MAVLink integration tests).
#![allow(dead_code, deprecated, clippy::unwrap_used, clippy::expect_used)]

use std::net::SocketAddr;
use std::time::Duration;

use mavlink::dialects::ardupilotmega::{
    AttitudeTargetTypemask, MavCmd, MavFrame, MavMessage, MavMissionType, MavResult, MISSION_ITEM_INT_DATA,
    SET_ATTITUDE_TARGET_DATA,
};
use mavlink::MavHeader;
use rotorpilot::airframe::AirframeSource;
use rotorpilot::control::ControllerKind;
use rotorpilot::runners::bench::autopilot::InProcess;
use rotorpilot::runners::bench::client::{BenchClient, COMMAND_ATTEMPTS};
use rotorpilot::runtime::{Ready, RunConfig};
use rotorpilot::sitl::SensorModel;

/// A running autopilot (one vehicle of `rotorpilot run`) and the GCS socket its telemetry goes to.
pub struct Autopilot {
    /// The vehicle; declared first so that it stops (when dropped) before the GCS socket closes.
    vehicle: InProcess,
    /// The GCS socket.
    pub gcs: BenchClient,
    /// The vehicle's GCS-link address.
    pub autopilot: SocketAddr,
}

impl Autopilot {
    pub fn start(sysid: u8, airframe: &str) -> Self {
        Self::start_with(sysid, airframe, |_| {})
    }

    /// [`Self::start`] with the configuration changed by `adjust` first.
    pub fn start_with(sysid: u8, airframe: &str, adjust: impl FnOnce(&mut RunConfig)) -> Self {
        let gcs = BenchClient::bind().unwrap();
        let mut config = RunConfig {
            bind_gcs: "127.0.0.1:0".parse().unwrap(),
            gcs: gcs.local_addr().unwrap(),
            bind_api: "127.0.0.1:0".parse().unwrap(),
            api: "127.0.0.1:9".parse().unwrap(),
            // The protocol tests fly on the exact state; the navigation has its own tests.
            sensors: SensorModel::State,
            ..RunConfig::single(
                AirframeSource::resolve(airframe).unwrap(),
                ControllerKind::Geometric,
                sysid,
            )
        };
        adjust(&mut config);
        let vehicle = InProcess::start(config).unwrap();
        let autopilot = vehicle.ready().first.gcs_bind.parse().unwrap();
        Self {
            gcs,
            autopilot,
            vehicle,
        }
    }

    /// What the vehicle said when ready.
    pub fn ready(&self) -> &Ready {
        self.vehicle.ready()
    }

    pub fn send(&mut self, msg: &MavMessage) {
        self.gcs.send(msg, self.autopilot);
    }

    /// The first message from the vehicle matching `pick` within `timeout`.
    pub fn wait<T>(&self, timeout: Duration, pick: impl FnMut(&MavHeader, &MavMessage) -> Option<T>) -> Option<T> {
        self.gcs.wait(timeout, pick)
    }

    /// NAV_TAKEOFF (MIS_TAKEOFF_ALT) and arm, both ACCEPTED; the climb follows.
    pub fn take_off(&mut self) {
        let accepted = Some(MavResult::MAV_RESULT_ACCEPTED);
        assert_eq!(self.command(MavCmd::MAV_CMD_NAV_TAKEOFF, f32::NAN, (1, 1)), accepted);
        assert_eq!(
            self.command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0, (1, 1)),
            accepted
        );
    }

    /// COMMAND_LONG with `p1` (others NaN) to `target`; the ACK's result (see [`Self::command_with`]).
    pub fn command(&mut self, command: MavCmd, p1: f32, target: (u8, u8)) -> Option<MavResult> {
        let mut params = [f32::NAN; 7];
        params[0] = p1;
        self.command_with(command, params, target)
    }

    /// COMMAND_LONG with all seven `params` to `target`; the ACK's result. Sent up to
    /// `COMMAND_ATTEMPTS` (3) times with the same content, each send waited for 0.5 s, as MAVSDK
    /// does: a lost datagram is retransmitted, and a repeat of a command that was executed gets
    /// the cached ACK.
    pub fn command_with(&mut self, command: MavCmd, params: [f32; 7], target: (u8, u8)) -> Option<MavResult> {
        let (ack, _) = self.gcs.command_tries(
            self.autopilot,
            target,
            command,
            params,
            Duration::from_millis(500),
            COMMAND_ATTEMPTS,
        );
        ack.map(|(result, _)| result)
    }
}

/// SET_ATTITUDE_TARGET for 1/1: attitude `q` (w, x, y, z) and `thrust` [0, 1], body rates
/// ignored (type mask 7).
pub fn attitude_target(q: [f32; 4], thrust: f32) -> MavMessage {
    MavMessage::SET_ATTITUDE_TARGET(SET_ATTITUDE_TARGET_DATA {
        q,
        thrust,
        type_mask: AttitudeTargetTypemask::from_bits_truncate(7),
        target_system: 1,
        target_component: 1,
        ..Default::default()
    })
}

/// A MISSION_ITEM_INT for system 1 in GLOBAL_RELATIVE_ALT_INT, `north_e7` (1e-7 deg) north of
/// PX4's default home, at height `z` [m].
pub fn mission_item(seq: u16, command: MavCmd, north_e7: i32, z: f32) -> MavMessage {
    MavMessage::MISSION_ITEM_INT(MISSION_ITEM_INT_DATA {
        param1: 0.0,
        param2: 0.0,
        param3: 0.0,
        param4: f32::NAN,
        x: 473_977_420 + north_e7,
        y: 85_455_940,
        z,
        seq,
        command,
        target_system: 1,
        target_component: 1,
        frame: MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
        current: 0,
        autocontinue: 1,
        mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
    })
}
