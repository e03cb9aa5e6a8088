//! The values that cross the machine's boundary: its clocks ([`Now`]), how it starts
//! ([`LinkConfig`]), what it is handed back ([`VehicleReply`]) and what it hands out
//! ([`Transmit`], [`ToVehicle`], [`KeyToStore`], [`Said`]).

use std::sync::Arc;

use crate::commander::{Outcome, Request};
use crate::mav::logs::{LogStore, MemLogStore};
use crate::mav::signing::{Signing, SigningKey};
use crate::mav::streams::LinkKind;
use crate::mav::translate::Identity;
use crate::params::{ParamError, ParamTable};
use crate::telemetry::Snapshot;

/// The two clocks of one input [s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Now {
    /// Wall time since the machine started [s].
    pub wall_s: f64,
    /// Simulated time of the vehicle [s].
    pub sim_s: f64,
}

impl Now {
    /// Wall time `wall_s` and simulated time `sim_s` [s].
    pub fn new(wall_s: f64, sim_s: f64) -> Self {
        Self { wall_s, sim_s }
    }
}

/// One datagram to send.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Transmit<A> {
    /// The link whose socket sends it.
    pub link: LinkKind,
    /// Destination.
    pub to: A,
    /// One MAVLink 2 frame (signed when the vehicle has a key).
    pub bytes: Vec<u8>,
}

/// Names a request whose answer the machine waits for ([`LinkMachine::handle_reply`](super::LinkMachine::handle_reply)).
pub type Token = u64;

/// What the link asks of the vehicle.
#[derive(Debug, Clone, PartialEq)]
pub enum VehicleRequest {
    /// A commander request (commands, setpoints, modes, missions, link loss).
    Commander(Request),
    /// A parameter set.
    SetParam {
        /// Parameter name.
        name: String,
        /// New value.
        value: f64,
    },
}

/// A request for the vehicle; with a token, the answer is expected through
/// [`LinkMachine::handle_reply`](super::LinkMachine::handle_reply).
#[derive(Debug, Clone, PartialEq)]
pub struct ToVehicle {
    /// Present when the link waits for the answer.
    pub token: Option<Token>,
    /// What to do.
    pub request: VehicleRequest,
}

/// The vehicle's answer to a [`ToVehicle`] with a token.
#[derive(Debug, Clone, PartialEq)]
pub enum VehicleReply {
    /// The commander's answer.
    Outcome(Outcome),
    /// A parameter set's result and the table after it.
    Param {
        /// The parameter's index, or why the set was refused.
        result: Result<usize, ParamError>,
        /// The table as it now is: the one its owner publishes, shared, not a copy.
        table: Arc<ParamTable>,
    },
    /// The request could not be queued (the vehicle's inbox is full).
    Busy,
}

/// A key (or its removal) the runtime writes to the `--signing-key` file, with the timestamp;
/// the result comes back through [`LinkMachine::handle_stored`](super::LinkMachine::handle_stored).
#[derive(Debug, Clone, PartialEq)]
pub struct KeyToStore {
    /// The new key; `None`: signing switched off (the file is removed).
    pub key: Option<SigningKey>,
    /// Signing timestamp at the change [10 µs since 2015].
    pub timestamp: u64,
}

/// How a machine starts.
#[derive(Debug)]
pub struct LinkConfig<A> {
    /// Our system and component ids and vehicle type.
    pub identity: Identity,
    /// The links and the remote each always sends telemetry to; the position is the link id
    /// of outgoing signatures (GCS 0, API 1 in the autopilot).
    pub links: Vec<(LinkKind, A)>,
    /// The vehicle's parameters at start (the table its owner publishes, shared).
    pub params: Arc<ParamTable>,
    /// The vehicle's state at start (as the state channel carries it, shared).
    pub snapshot: Arc<Snapshot>,
    /// Signing key and timestamp at start.
    pub signing: Signing,
    /// The wall clock at wall time 0, as a signing timestamp [10 µs since 2015]: the signing
    /// clock and SYSTEM_TIME are this plus wall time (0: no clock; SYSTEM_TIME then says 0).
    pub signing_epoch: u64,
    /// SETUP_SIGNING keys are kept (a key file): a change waits for [`LinkMachine::handle_stored`](super::LinkMachine::handle_stored).
    pub key_store: bool,
    /// Received frames are handed out for the tlog ([`LinkMachine::poll_received`](super::LinkMachine::poll_received)).
    pub record_received: bool,
    /// The flight logs served by the log protocol and at `/fs/microsd/log` over FTP.
    pub logs: Box<dyn LogStore>,
}

impl<A> LinkConfig<A> {
    /// A vehicle with `identity` on `links`, `params` and `snapshot` at start; no signing key,
    /// no key file, received frames not recorded, no flight logs.
    pub fn new(
        identity: Identity,
        links: Vec<(LinkKind, A)>,
        params: impl Into<Arc<ParamTable>>,
        snapshot: impl Into<Arc<Snapshot>>,
    ) -> Self {
        Self {
            identity,
            links,
            params: params.into(),
            snapshot: snapshot.into(),
            signing: Signing::new(None, 0),
            signing_epoch: 0,
            key_store: false,
            record_received: false,
            logs: Box::new(MemLogStore::default()),
        }
    }
}

/// A STATUSTEXT the link said to a client (a refusal, a calibration step, a signing change), for
/// the flight log; the commander's announcements to everyone are logged by the recorder.
#[derive(Debug, Clone, PartialEq)]
pub struct Said {
    /// Simulated time of the vehicle's latest tick [s].
    pub t_s: f64,
    /// MAV_SEVERITY (0 emergency … 7 debug).
    pub severity: u8,
    /// The text.
    pub text: String,
}
