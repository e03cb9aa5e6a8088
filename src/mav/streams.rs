//! Per-link telemetry rates (docs/mavlink.md §5): PX4 SITL defaults for the GCS and API links, or
//! ArduCopter's (nothing until asked, docs/mavlink.md §5.1), changed by SET_MESSAGE_INTERVAL and
//! REQUEST_DATA_STREAM (each personality's groups); an ArduCopter-faced link also keeps the rate
//! of each of Copter's groups ([`CopterGroup`]), which its `SRn_*` parameters show and set
//! (docs/ardupilot.md §5.2); given the time, which streams are due. Pure: the link passes the
//! simulated time, in seconds.

use super::ardupilot::copter_streams::{CopterGroup, GROUP_COUNT};
use super::identity::Personality;
use super::stream_messages::TelemetryStream;

/// Fastest stream period: one tick [s].
const MIN_PERIOD_S: f64 = 0.001;

/// Which default rate table a link starts from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinkKind {
    /// QGC / MAVProxy (PX4 "normal" mode).
    Gcs,
    /// MAVSDK (PX4 "onboard" mode).
    Api,
}

/// PX4's default rate [Hz] of `stream` on a link of `kind`; 0 = off (docs/mavlink.md §5).
pub fn default_rate_hz(kind: LinkKind, stream: TelemetryStream) -> f64 {
    use TelemetryStream::*;
    let (gcs, api) = match stream {
        SysStatus | ExtendedSysState => (1.0, 5.0),
        GlobalPosition => (5.0, 50.0),
        LocalPosition => (1.0, 30.0),
        Attitude => (15.0, 100.0),
        AttitudeQuaternion => (0.0, 50.0),
        AttitudeTarget => (2.0, 10.0),
        PositionTarget => (1.5, 10.0),
        GpsRawInt => (1.0, 10.0),
        VfrHud => (4.0, 10.0),
        HomePosition | BatteryStatus | CurrentMode => (0.5, 0.5),
        MissionCurrent => (1.0, 1.0),
        ServoOutputRaw | ActuatorOutputStatus => (1.0, 10.0),
        HighresImu => (0.0, 50.0),
        ExternalForce | ExternalTorque | MassEstimate => (10.0, 10.0),
        OrbitStatus => (5.0, 5.0),
        EstimatorStatus => (0.5, 0.5),
        ScaledPressure => (1.0, 1.0),
        // The simulator's truth: off unless asked for (MAVSDK's set_rate_ground_truth).
        GroundTruth => (0.0, 0.0),
        // ArduPilot's message: off unless asked for (REQUEST_DATA_STREAM, SET_MESSAGE_INTERVAL).
        EkfStatusReport => (0.0, 0.0),
        SystemTime => (0.0, 1.0),
        // ArduPilot's own messages: never on a PX4-faced link (not in its table).
        RawImu | PowerStatus | Meminfo | NavControllerOutput | PositionTargetGlobal | RcChannels | Simstate | Ahrs2
        | Ahrs | Vibration => (0.0, 0.0),
        EventSequence => (
            1.0 / super::events::CURRENT_SEQUENCE_PERIOD_S,
            1.0 / super::events::CURRENT_SEQUENCE_PERIOD_S,
        ),
    };
    match kind {
        LinkKind::Gcs => gcs,
        LinkKind::Api => api,
    }
}

/// The default rate [Hz] of `stream` on a `kind` link of a vehicle presenting itself as
/// `personality`: PX4's ([`default_rate_hz`]), or 0 (off) for ArduCopter, whose stream rates
/// (SRn_*) default to 0.
fn default_rate(personality: Personality, kind: LinkKind, stream: TelemetryStream) -> f64 {
    match personality {
        Personality::Px4 => default_rate_hz(kind, stream),
        Personality::ArduPilot => 0.0,
    }
}

/// The REQUEST_DATA_STREAM groups of a PX4-faced link, as MAVProxy asks for them: ALL (0) is
/// every stream of the link.
fn px4_group(stream_id: u8) -> &'static [TelemetryStream] {
    use TelemetryStream::*;
    match stream_id {
        0 => &TelemetryStream::ALL,
        1 => &[HighresImu, ScaledPressure],
        2 => &[SysStatus, ExtendedSysState, GpsRawInt, MissionCurrent],
        6 => &[GlobalPosition, LocalPosition],
        10 => &[Attitude],
        11 => &[VfrHud],
        12 => &[BatteryStatus, EkfStatusReport],
        _ => &[],
    }
}

/// A refused rate change.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NotStreamable;

#[derive(Debug, Clone, Copy, PartialEq)]
struct RateEntry {
    stream: TelemetryStream,
    period_s: Option<f64>,
    next_s: f64,
}

/// Rates of one link.
#[derive(Debug, Clone, PartialEq)]
pub struct StreamTable {
    kind: LinkKind,
    personality: Personality,
    entries: Vec<RateEntry>,
    /// The rate of each of Copter's groups [Hz] as last set (REQUEST_DATA_STREAM, `SRn_*`);
    /// all 0 (Copter's defaults) and unused on a PX4-faced link.
    group_hz: [u16; GROUP_COUNT],
}

impl StreamTable {
    /// The default table of a `kind` link of a vehicle presenting itself as `personality`: PX4's
    /// streams at PX4's defaults ([`default_rate_hz`]), or every stream off for ArduCopter (its
    /// stream rates default to 0: nothing periodic but the heartbeat until a ground station asks).
    pub fn new(kind: LinkKind, personality: Personality) -> Self {
        Self {
            kind,
            personality,
            entries: TelemetryStream::ALL
                .into_iter()
                .filter(|s| personality == Personality::ArduPilot || !s.ardupilot_only())
                .map(|stream| RateEntry {
                    stream,
                    period_s: period(default_rate(personality, kind, stream)),
                    next_s: 0.0,
                })
                .collect(),
            group_hz: [0; GROUP_COUNT],
        }
    }

    /// Whether this link streams `stream` at all (SET_MESSAGE_INTERVAL, REQUEST_MESSAGE): a
    /// PX4-faced link not ArduPilot's own messages.
    pub fn offers(&self, stream: TelemetryStream) -> bool {
        self.entries.iter().any(|e| e.stream == stream)
    }

    /// SET_MESSAGE_INTERVAL: `interval_us` −1 off, 0 default, else the period (clamped to one tick).
    pub fn set_interval(&mut self, message_id: u32, interval_us: f32) -> Result<(), NotStreamable> {
        if !interval_us.is_finite() || !self.entries.iter().any(|e| e.stream.message_id() == message_id) {
            return Err(NotStreamable);
        }
        let (kind, personality) = (self.kind, self.personality);
        // DEBUG_VECT carries two streams (EXT_F, EXT_T): both follow its interval.
        for e in self.entries.iter_mut().filter(|e| e.stream.message_id() == message_id) {
            e.period_s = if interval_us < 0.0 {
                None
            } else if interval_us == 0.0 {
                period(default_rate(personality, kind, e.stream))
            } else {
                Some((f64::from(interval_us) * 1e-6).max(MIN_PERIOD_S))
            };
            e.next_s = 0.0;
        }
        Ok(())
    }

    /// Current interval of `message_id` [µs] (−1 off), as MESSAGE_INTERVAL reports it.
    pub fn interval_us(&self, message_id: u32) -> Option<i32> {
        let e = self.entries.iter().find(|e| e.stream.message_id() == message_id)?;
        Some(e.period_s.map_or(-1, |p| (p * 1e6).round() as i32))
    }

    /// REQUEST_DATA_STREAM (MAVProxy): the group `stream_id` at `rate_hz`, or off when `start`
    /// is false or the rate 0 (docs/mavlink.md §5; ALL = 0); the groups are the personality's
    /// ([`CopterGroup::requested`] for ArduCopter, whose group rates it sets); an unknown group
    /// changes nothing. No reply.
    pub fn request_data_stream(&mut self, stream_id: u8, rate_hz: u16, start: bool) {
        let rate_hz = if start { rate_hz } else { 0 };
        match self.personality {
            Personality::Px4 => {
                let group = px4_group(stream_id);
                for e in self.entries.iter_mut().filter(|e| group.contains(&e.stream)) {
                    e.period_s = period(f64::from(rate_hz));
                    e.next_s = 0.0;
                }
            }
            Personality::ArduPilot => {
                for group in CopterGroup::requested(stream_id) {
                    self.set_group_rate(group, rate_hz);
                }
            }
        }
    }

    /// The rate of Copter's `group` [Hz] as last set (0: off), what `SRn_*` shows.
    pub fn group_rate(&self, group: CopterGroup) -> u16 {
        self.group_hz[group.index()]
    }

    /// Sets Copter's `group` to `rate_hz` (0: off), as a PARAM_SET of its `SRn_*` parameter and
    /// REQUEST_DATA_STREAM do: every message of the group at that rate.
    pub fn set_group_rate(&mut self, group: CopterGroup, rate_hz: u16) {
        if self.personality != Personality::ArduPilot {
            return;
        }
        self.group_hz[group.index()] = rate_hz;
        for e in self
            .entries
            .iter_mut()
            .filter(|e| CopterGroup::of_stream(e.stream) == Some(group))
        {
            e.period_s = period(f64::from(rate_hz));
            e.next_s = 0.0;
        }
    }

    /// Streams due at `now_s` [s]; each is rescheduled one period later.
    pub fn due(&mut self, now_s: f64) -> Vec<TelemetryStream> {
        let mut out = Vec::new();
        for e in &mut self.entries {
            if let Some(p) = e.period_s {
                if now_s >= e.next_s {
                    // Skip missed periods rather than bursting to catch up.
                    e.next_s = if now_s - e.next_s > p { now_s + p } else { e.next_s + p };
                    out.push(e.stream);
                }
            }
        }
        out
    }
}

fn period(rate_hz: f64) -> Option<f64> {
    (rate_hz > 0.0).then(|| (1.0 / rate_hz).max(MIN_PERIOD_S))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn count(t: &mut StreamTable, stream: TelemetryStream, seconds: f64) -> usize {
        let mut n = 0;
        let mut now = 0.0;
        while now < seconds {
            n += t.due(now).iter().filter(|s| **s == stream).count();
            now += 0.005;
        }
        n
    }

    #[test]
    fn defaults_differ_per_link_and_rates_hold() {
        let mut gcs = StreamTable::new(LinkKind::Gcs, Personality::Px4);
        assert_eq!(count(&mut gcs, TelemetryStream::Attitude, 10.0), 150);
        assert_eq!(gcs.interval_us(31), Some(-1), "ATTITUDE_QUATERNION off on the GCS link");
        let mut api = StreamTable::new(LinkKind::Api, Personality::Px4);
        assert_eq!(count(&mut api, TelemetryStream::GlobalPosition, 2.0), 100);
    }

    #[test]
    fn set_message_interval_and_request_data_stream() {
        let mut t = StreamTable::new(LinkKind::Gcs, Personality::Px4);
        t.set_interval(32, 20_000.0).unwrap();
        assert_eq!(t.interval_us(32), Some(20_000));
        assert_eq!(count(&mut t, TelemetryStream::LocalPosition, 1.0), 50);
        t.set_interval(32, -1.0).unwrap();
        assert_eq!(count(&mut t, TelemetryStream::LocalPosition, 1.0), 0);
        t.set_interval(32, 0.0).unwrap();
        assert_eq!(t.interval_us(32), Some(1_000_000));
        t.set_interval(30, 10.0).unwrap();
        assert_eq!(t.interval_us(30), Some(1000), "clamped to one tick");
        assert_eq!(t.set_interval(999, 1000.0), Err(NotStreamable));
        t.request_data_stream(10, 4, true);
        assert_eq!(t.interval_us(30), Some(250_000));
        t.request_data_stream(0, 0, false);
        assert_eq!(t.interval_us(33), Some(-1));
    }

    /// The streams of `t` on at `rate_hz` (interval 1/rate), and whether every other is off.
    fn on_at(t: &StreamTable, rate_hz: f64) -> (Vec<TelemetryStream>, bool) {
        let want = (1e6 / rate_hz).round() as i32;
        let mut on = Vec::new();
        let mut others_off = true;
        for stream in TelemetryStream::ALL.into_iter().filter(|s| t.offers(*s)) {
            match t.interval_us(stream.message_id()) {
                Some(i) if i == want => on.push(stream),
                Some(-1) => {}
                _ => others_off = false,
            }
        }
        (on, others_off)
    }

    fn ardupilot() -> StreamTable {
        StreamTable::new(LinkKind::Gcs, Personality::ArduPilot)
    }

    #[test]
    fn an_ardupilot_link_sends_nothing_until_asked() {
        for kind in [LinkKind::Gcs, LinkKind::Api] {
            let mut t = StreamTable::new(kind, Personality::ArduPilot);
            let mut now = 0.0;
            while now < 10.0 {
                assert!(t.due(now).is_empty(), "{kind:?} at {now} s");
                now += 0.005;
            }
            assert!(
                TelemetryStream::ALL.iter().all(|s| t.offers(*s)),
                "every message on request"
            );
        }
        let mut t = ardupilot();
        t.set_interval(178, 100_000.0).unwrap();
        assert_eq!(
            count(&mut t, TelemetryStream::Ahrs2, 1.0),
            10,
            "SET_MESSAGE_INTERVAL as on PX4"
        );
        t.set_interval(178, 0.0).unwrap();
        assert_eq!(t.interval_us(178), Some(-1), "the default is off");
    }

    #[test]
    fn ardupilot_groups_hold_copters_messages() {
        use TelemetryStream::*;
        let groups: [(u8, &[TelemetryStream]); 12] = [
            (1, &[RawImu, ScaledPressure]),
            (
                2,
                &[
                    SysStatus,
                    GpsRawInt,
                    MissionCurrent,
                    PowerStatus,
                    Meminfo,
                    NavControllerOutput,
                    PositionTargetGlobal,
                ],
            ),
            (3, &[ServoOutputRaw, RcChannels]),
            (4, &[]),
            (5, &[]),
            (6, &[LocalPosition, GlobalPosition]),
            (7, &[]),
            (10, &[Attitude, Simstate, Ahrs2]),
            (11, &[VfrHud]),
            (12, &[SystemTime, BatteryStatus, EkfStatusReport, Ahrs, Vibration]),
            (13, &[]),
            (200, &[]),
        ];
        let sorted = |mut v: Vec<u32>| {
            v.sort_unstable();
            v
        };
        let mut all = Vec::new();
        for (id, expected) in groups {
            let mut t = ardupilot();
            t.request_data_stream(id, 4, true);
            let (on, others_off) = on_at(&t, 4.0);
            assert!(others_off, "group {id}: nothing else on");
            let ids = |v: &[TelemetryStream]| sorted(v.iter().map(|s| s.message_id()).collect());
            assert_eq!(ids(&on), ids(expected), "group {id}");
            all.extend_from_slice(expected);
            t.request_data_stream(id, 4, false);
            assert!(on_at(&t, 4.0).0.is_empty(), "group {id} stopped");
        }
        // ALL: every group at 4 Hz, nothing else (no PX4-only message).
        let mut t = ardupilot();
        t.request_data_stream(0, 4, true);
        let (on, others_off) = on_at(&t, 4.0);
        assert!(others_off);
        assert_eq!(on.len(), all.len());
        assert!(all.iter().all(|s| on.contains(s)));
        for px4_only in [
            ExtendedSysState,
            HighresImu,
            CurrentMode,
            HomePosition,
            EventSequence,
            AttitudeQuaternion,
        ] {
            assert!(!on.contains(&px4_only), "{px4_only:?}");
        }
        assert_eq!(count(&mut t, Ahrs2, 2.0), 8, "4 Hz");
        // A stop, and a start at rate 0, turn them off.
        t.request_data_stream(10, 0, true);
        assert_eq!(t.interval_us(30), Some(-1));
        assert_eq!(t.interval_us(33), Some(250_000), "the other groups stay");
        t.request_data_stream(0, 4, false);
        assert!(on_at(&t, 4.0).0.is_empty());
        assert_eq!(count(&mut t, GlobalPosition, 2.0), 0);
    }

    #[test]
    fn an_ardupilot_link_keeps_the_rate_of_each_group() {
        let mut t = ardupilot();
        assert!(
            CopterGroup::ALL.iter().all(|g| t.group_rate(*g) == 0),
            "Copter's SRn_* are 0"
        );
        t.request_data_stream(0, 4, true);
        assert_eq!(t.group_rate(CopterGroup::Position), 4);
        assert_eq!(t.group_rate(CopterGroup::Adsb), 4);
        assert_eq!(t.group_rate(CopterGroup::Params), 0, "ALL leaves PARAMS alone");
        t.set_group_rate(CopterGroup::Position, 2);
        assert_eq!(t.interval_us(33), Some(500_000), "GLOBAL_POSITION_INT at SRn_POSITION");
        assert_eq!(t.interval_us(32), Some(500_000));
        assert_eq!(t.interval_us(30), Some(250_000), "EXTRA1 stays");
        t.request_data_stream(6, 9, false);
        assert_eq!((t.group_rate(CopterGroup::Position), t.interval_us(33)), (0, Some(-1)));
        // SET_MESSAGE_INTERVAL changes a message, not its group's rate (as Copter).
        t.set_interval(30, 100_000.0).unwrap();
        assert_eq!(t.group_rate(CopterGroup::Extra1), 4);
        let mut px4 = StreamTable::new(LinkKind::Gcs, Personality::Px4);
        px4.set_group_rate(CopterGroup::Position, 2);
        assert_eq!(px4.interval_us(33), Some(200_000), "no Copter groups on PX4");
    }

    #[test]
    fn a_px4_link_keeps_px4s_streams() {
        let t = StreamTable::new(LinkKind::Gcs, Personality::Px4);
        let offered: Vec<TelemetryStream> = TelemetryStream::ALL.into_iter().filter(|s| t.offers(*s)).collect();
        assert_eq!(offered, TelemetryStream::ALL[..27], "PX4's streams, in PX4's order");
        let mut t = StreamTable::new(LinkKind::Api, Personality::Px4);
        assert_eq!(t.set_interval(178, 100_000.0), Err(NotStreamable), "no AHRS2 on PX4");
        t.request_data_stream(0, 4, true);
        assert_eq!(t.interval_us(245), Some(250_000), "PX4's ALL: EXTENDED_SYS_STATE too");
        assert_eq!(t.interval_us(27), None);
    }
}
