//! One UDP datagram → the shipped `LinkMachine` (signing, ingest, commands, parameters, missions,
//! logs, SETUP_SIGNING), whose requests a stub vehicle answers: a `Commander` tracking perfectly. An
//! input starting with `F` is framed chunks (valid CRCs around fuzzed payloads); `S` the same with
//! a signing key on the vehicle, so every unsigned frame but HEARTBEAT is dropped. Invariants
//! beyond "no panic": every datagram out is one frame; a request with a non-finite number is never
//! accepted; setpoints, attitude targets and home stay finite; an accepted parameter reads back.
#![no_main]

use libfuzzer_sys::fuzz_target;

use rotorpilot::commander::{Commander, Outcome};
use rotorpilot::control::{ControllerGains, ControllerKind, VehicleState};
use rotorpilot::guidance::Home;
use rotorpilot::math::{UnitQuat, Vec3};
use rotorpilot::mav::codec::{decode_datagram, frame_v2};
use rotorpilot::mav::gcs::gcs_header;
use rotorpilot::mav::link::{LinkConfig, LinkMachine, Now, ToVehicle, VehicleReply, VehicleRequest};
use rotorpilot::mav::logs::MemLogStore;
use rotorpilot::mav::signing::{Signing, SigningKey};
use rotorpilot::mav::streams::LinkKind;
use rotorpilot::mav::translate::Identity;
use rotorpilot::params::{ParamTable, VehicleSettings};
use rotorpilot::runtime::vehicle::DEFAULT_ESTIMATOR;
use rotorpilot::telemetry::Snapshot;

const DT_S: f64 = 1e-3; // the control step estimator designs are checked at [s]
const GCS: u8 = 7;
static METADATA: std::sync::OnceLock<Option<rotorpilot::mav::metadata::MetadataFiles>> = std::sync::OnceLock::new();

fuzz_target!(|data: &[u8]| {
    let (datagram, key) = match data.split_first() {
        Some((b'F', chunks)) => (framed(chunks), None),
        Some((b'S', chunks)) => (framed(chunks), Some(SigningKey::from_passphrase("fuzz"))),
        _ => (data.to_vec(), None),
    };
    let mut v = Stub::new(key);
    v.machine.handle_datagram(v.now(), LinkKind::Gcs, GCS, &datagram);
    v.settle(0.05);
    // Long enough for take-off, landing detection, the auto-disarm timers and link loss.
    (0..40).for_each(|_| v.settle(0.5));
});

/// Chunks of (message id u16 LE, payload length u8, payload) → one datagram of CRC-valid frames.
fn framed(mut chunks: &[u8]) -> Vec<u8> {
    let (mut out, mut sequence) = (Vec::new(), 0u8);
    while let [lo, hi, len, rest @ ..] = chunks {
        let n = usize::from(*len).min(rest.len());
        let header = gcs_header(sequence);
        frame_v2(header, u32::from(u16::from_le_bytes([*lo, *hi])), &rest[..n], &mut out);
        sequence = sequence.wrapping_add(1);
        chunks = &rest[n..];
    }
    out
}

/// The machine and the vehicle behind it.
struct Stub {
    machine: LinkMachine<u8>,
    commander: Commander,
    params: ParamTable,
    x: VehicleState,
}

impl Stub {
    fn new(key: Option<SigningKey>) -> Self {
        let (kind, gains) = (ControllerKind::Geometric, ControllerGains::default());
        let settings = VehicleSettings::new(kind, gains, Some(DEFAULT_ESTIMATOR));
        let (params, snapshot) = (ParamTable::new(&settings), Snapshot::initial(Home::default()));
        let links = vec![(LinkKind::Gcs, GCS), (LinkKind::Api, GCS + 1)];
        let mut config = LinkConfig::new(Identity::autopilot(1, 4), links, params.clone(), snapshot);
        (config.signing, config.key_store, config.record_received) = (Signing::new(key, 1), true, true);
        config.logs = Box::new(MemLogStore::from_iter([(1_767_261_600, vec![7; 200])]));
        let metadata = METADATA.get_or_init(|| rotorpilot::mav::metadata::MetadataFiles::new(&params).ok());
        Self {
            machine: LinkMachine::with_metadata(config, metadata.clone()),
            commander: Commander::new(settings.commander),
            params,
            x: VehicleState::at_rest(0.0, Vec3::new(0.0, 0.0, -0.1)),
        }
    }

    fn now(&self) -> Now {
        Now::new(self.x.t_s, self.x.t_s)
    }

    /// Answers every request, steps `dt_s` [s], runs the link's duties, checks what it sends.
    fn settle(&mut self, dt_s: f64) {
        while let Some(ToVehicle { token, request }) = self.machine.poll_vehicle() {
            let reply = self.serve(request);
            if let Some(token) = token {
                self.machine.handle_reply(self.now(), token, reply);
            }
        }
        while self.machine.poll_store().is_some() {
            self.machine.handle_stored(self.now(), Ok(()));
        }
        self.step(dt_s);
        self.machine.handle_timeout(self.now());
        while let Some(t) = self.machine.poll_transmit() {
            assert_eq!(decode_datagram(&t.bytes).len(), 1, "{:?}", t.bytes);
        }
        while self.machine.poll_received().is_some() {}
    }

    fn serve(&mut self, request: VehicleRequest) -> VehicleReply {
        match request {
            VehicleRequest::Commander(request) => {
                let (finite, shown) = (request.is_finite(), format!("{request:?}"));
                let outcome = self.commander.request(request, &self.x, self.x.t_s);
                assert!(finite || outcome != Outcome::Accepted, "accepted: {shown}");
                VehicleReply::Outcome(outcome)
            }
            VehicleRequest::SetParam { name, value } => {
                let result = self.params.set(&name, value, DT_S);
                if let Ok(index) = result {
                    assert_eq!(self.params.get(index).map(|(_, v)| v), Some(value));
                    self.commander.params = self.params.settings().commander;
                }
                VehicleReply::Param {
                    result,
                    table: std::sync::Arc::new(self.params.clone()),
                }
            }
        }
    }

    /// One commander tick after `dt_s` [s]; the vehicle then tracks the setpoint perfectly.
    fn step(&mut self, dt_s: f64) {
        self.x.t_s += dt_s;
        let thrust_over_weight = if self.commander.armed() { 1.0 } else { 0.0 };
        let tick = self.commander.update(&self.x, thrust_over_weight, self.x.t_s);
        assert!(self.commander.home_w().iter().all(|v| v.is_finite()), "home not finite");
        assert!(tick.attitude.is_none_or(|a| a.is_finite()), "attitude target");
        let sp = tick.setpoint.unwrap_or_default();
        assert!(sp.is_finite(), "setpoint not finite: {sp:?}");
        self.x.pos_w = sp.pos_w.unwrap_or(self.x.pos_w);
        self.x.vel_w = sp.vel_w.unwrap_or_else(Vec3::zeros);
        if let Some(yaw) = sp.yaw_rad {
            self.x.r_wb = *UnitQuat::from_euler_angles(0.0, 0.0, yaw).to_rotation_matrix().matrix();
        }
        for event in tick.events {
            self.machine.handle_event(self.now(), event);
        }
        let snapshot = Snapshot::initial(Home::default()).with_state(&self.x);
        self.machine.handle_state(snapshot.with_commander(&self.commander));
    }
}
