//! Per-link telemetry rates (docs/mavlink.md §5): PX4 SITL defaults for the GCS and API links,
//! changed by SET_MESSAGE_INTERVAL and REQUEST_DATA_STREAM; given the time, which streams are
//! due. Pure: the link passes the simulated time, in seconds.

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

/// Default rate [Hz] of `stream` on a link of `kind`; 0 = off (docs/mavlink.md §5).
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
    entries: Vec<RateEntry>,
}

impl StreamTable {
    /// The default table of a `kind` link.
    pub fn new(kind: LinkKind) -> Self {
        Self {
            kind,
            entries: TelemetryStream::ALL
                .iter()
                .map(|&stream| RateEntry {
                    stream,
                    period_s: period(default_rate_hz(kind, stream)),
                    next_s: 0.0,
                })
                .collect(),
        }
    }

    /// SET_MESSAGE_INTERVAL: `interval_us` −1 off, 0 default, else the period (clamped to one tick).
    pub fn set_interval(&mut self, message_id: u32, interval_us: f32) -> Result<(), NotStreamable> {
        let kind = self.kind;
        if !interval_us.is_finite() || !self.entries.iter().any(|e| e.stream.message_id() == message_id) {
            return Err(NotStreamable);
        }
        // DEBUG_VECT carries two streams (EXT_F, EXT_T): both follow its interval.
        for e in self.entries.iter_mut().filter(|e| e.stream.message_id() == message_id) {
            e.period_s = if interval_us < 0.0 {
                None
            } else if interval_us == 0.0 {
                period(default_rate_hz(kind, e.stream))
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
    /// is false (docs/mavlink.md §5; ALL = 0).
    pub fn request_data_stream(&mut self, stream_id: u8, rate_hz: u16, start: bool) {
        use TelemetryStream::*;
        let group: &[TelemetryStream] = match stream_id {
            0 => &TelemetryStream::ALL,
            1 => &[HighresImu, ScaledPressure],
            2 => &[SysStatus, ExtendedSysState, GpsRawInt, MissionCurrent],
            6 => &[GlobalPosition, LocalPosition],
            10 => &[Attitude],
            11 => &[VfrHud],
            12 => &[BatteryStatus, EkfStatusReport],
            _ => &[],
        };
        for e in self.entries.iter_mut().filter(|e| group.contains(&e.stream)) {
            e.period_s = if start && rate_hz > 0 {
                period(f64::from(rate_hz))
            } else {
                None
            };
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
        let mut gcs = StreamTable::new(LinkKind::Gcs);
        assert_eq!(count(&mut gcs, TelemetryStream::Attitude, 10.0), 150);
        assert_eq!(gcs.interval_us(31), Some(-1), "ATTITUDE_QUATERNION off on the GCS link");
        let mut api = StreamTable::new(LinkKind::Api);
        assert_eq!(count(&mut api, TelemetryStream::GlobalPosition, 2.0), 100);
    }

    #[test]
    fn set_message_interval_and_request_data_stream() {
        let mut t = StreamTable::new(LinkKind::Gcs);
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
}
