//! ArduCopter SITL's RC receiver (docs/ardupilot.md §8): 16 channels resting at SITL's values,
//! each overridden by RC_CHANNELS_OVERRIDE (or MANUAL_CONTROL, which Copter turns into overrides
//! of the stick channels) for `RC_OVERRIDE_TIME` after its last override, the RC_CHANNELS the
//! vehicle reports, and the sticks the channels give the commander. Pure: time is a value
//! (simulated time, as SITL's clock).
//!
//! ```text
//! RCMAP: channel 1 roll, 2 pitch, 3 throttle, 4 yaw
//! roll  = (ch1 − 1500) / 500      pitch = (1500 − ch2) / 500 (low PWM: nose down)
//! yaw   = (ch4 − 1500) / 500      throttle = (ch3 − 1000) / 1000
//! ```

use mavlink::dialects::ardupilotmega::{MavMessage, RC_CHANNELS_DATA, RC_CHANNELS_OVERRIDE_DATA};

use crate::guidance::Sticks;

/// Channels the receiver has (SITL's `SIM_RC_CHANCOUNT` default, `NUM_RC_CHANNELS`).
pub const CHANNELS: usize = 16;
/// How long an override stays in force after it was sent (`RC_OVERRIDE_TIME` default) [s].
pub const RC_OVERRIDE_TIME_S: f64 = 3.0;
/// SITL's resting channels (`SITL_State::init`): sticks centred, throttle at its minimum,
/// channels 5 and 8 at 1800, 6 and 7 at 1000, 9–16 not driven (0) [µs].
pub const SITL_IDLE_US: [u16; CHANNELS] = [1500, 1500, 1000, 1500, 1800, 1000, 1000, 1800, 0, 0, 0, 0, 0, 0, 0, 0];
/// RSSI when no RSSI source is configured (`RSSI_TYPE` 0): 255, "unknown".
const RSSI_UNKNOWN: u8 = u8::MAX;
/// RC_CHANNELS_OVERRIDE's "leave this channel as it is".
const IGNORE: u16 = u16::MAX;
/// Channels 9–18: "release this channel" (UINT16_MAX − 1).
const RELEASE_HIGH: u16 = u16::MAX - 1;

/// The receiver: the override of each channel (its value [µs] and when it was sent [s]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CopterReceiver {
    overrides: [Option<(u16, f64)>; CHANNELS],
}

impl CopterReceiver {
    /// An RC_CHANNELS_OVERRIDE arrived at `t_s` [s], as ArduPilot reads it
    /// (`GCS_MAVLINK::handle_rc_channels_override`): channels 1–8 UINT16_MAX leaves the channel
    /// as it is, 0 releases it; channels 9–16 0 and UINT16_MAX leave it, UINT16_MAX − 1 releases
    /// it; any other value overrides the channel, as sent (no range check), from now.
    pub fn handle_override(&mut self, o: &RC_CHANNELS_OVERRIDE_DATA, t_s: f64) {
        let sent = [
            o.chan1_raw,
            o.chan2_raw,
            o.chan3_raw,
            o.chan4_raw,
            o.chan5_raw,
            o.chan6_raw,
            o.chan7_raw,
            o.chan8_raw,
            o.chan9_raw,
            o.chan10_raw,
            o.chan11_raw,
            o.chan12_raw,
            o.chan13_raw,
            o.chan14_raw,
            o.chan15_raw,
            o.chan16_raw,
        ];
        for (i, value) in sent.into_iter().enumerate() {
            let value = match (i < 8, value) {
                (_, IGNORE) | (false, 0) => continue,
                (false, RELEASE_HIGH) => 0,
                (_, v) => v,
            };
            self.overrides[i] = (value != 0).then_some((value, t_s));
        }
    }

    /// A MANUAL_CONTROL's `sticks` arrived at `t_s` [s]: Copter overrides the stick channels
    /// with them (`GCS_MAVLINK::handle_manual_control`), in the 1000–2000 µs range.
    pub fn handle_sticks(&mut self, sticks: Sticks, t_s: f64) {
        let us = |v: f64| v.round().clamp(1000.0, 2000.0) as u16;
        let values = [
            us(1500.0 + 500.0 * sticks.roll),
            us(1500.0 - 500.0 * sticks.pitch),
            us(1000.0 + 1000.0 * sticks.throttle),
            us(1500.0 + 500.0 * sticks.yaw),
        ];
        for (i, value) in values.into_iter().enumerate() {
            self.overrides[i] = Some((value, t_s));
        }
    }

    /// The override of channel index `i` in force at `t_s` [s].
    fn override_at(&self, i: usize, t_s: f64) -> Option<u16> {
        self.overrides[i]
            .filter(|(_, sent_s)| t_s - sent_s < RC_OVERRIDE_TIME_S)
            .map(|(v, _)| v)
    }

    /// The channels as the vehicle sees them at `t_s` [s]: each override in force, else SITL's
    /// resting value [µs].
    pub fn channels(&self, t_s: f64) -> [u16; CHANNELS] {
        std::array::from_fn(|i| self.override_at(i, t_s).unwrap_or(SITL_IDLE_US[i]))
    }

    /// The throttle channel as a stick at `t_s` [s] [0, 1] (what the arming and mode checks read).
    pub fn throttle(&self, t_s: f64) -> f64 {
        let [.., throttle, _] = self.stick_channels(t_s);
        Sticks::from_rc(1500, 1500, throttle, 1500).throttle
    }

    /// Channels 1–4 (roll, pitch, throttle, yaw) at `t_s` [s].
    fn stick_channels(&self, t_s: f64) -> [u16; 4] {
        let c = self.channels(t_s);
        [c[0], c[1], c[2], c[3]]
    }

    /// The sticks the commander flies at `t_s` [s], `in_air` or not: the stick channels as
    /// [`Sticks::from_rc`] reads them, except a throttle channel without an override in force,
    /// which rests at its minimum on the ground (as SITL's) and centred in the air (holds the
    /// height: the emulator's safety rule, docs/ardupilot.md §8).
    pub fn sticks(&self, t_s: f64, in_air: bool) -> Sticks {
        let [roll, pitch, throttle, yaw] = self.stick_channels(t_s);
        let mut sticks = Sticks::from_rc(roll, pitch, throttle, yaw);
        if in_air && self.override_at(2, t_s).is_none() {
            sticks.throttle = Sticks::CENTRED.throttle;
        }
        sticks
    }

    /// RC_CHANNELS at `t_s` [s], stamped `time_boot_ms`: the 16 channels as the vehicle sees
    /// them, 17 and 18 not driven (0), the count 16, RSSI unknown (255).
    pub fn rc_channels(&self, t_s: f64, time_boot_ms: u32) -> MavMessage {
        let c = self.channels(t_s);
        MavMessage::RC_CHANNELS(RC_CHANNELS_DATA {
            time_boot_ms,
            chancount: CHANNELS as u8,
            chan1_raw: c[0],
            chan2_raw: c[1],
            chan3_raw: c[2],
            chan4_raw: c[3],
            chan5_raw: c[4],
            chan6_raw: c[5],
            chan7_raw: c[6],
            chan8_raw: c[7],
            chan9_raw: c[8],
            chan10_raw: c[9],
            chan11_raw: c[10],
            chan12_raw: c[11],
            chan13_raw: c[12],
            chan14_raw: c[13],
            chan15_raw: c[14],
            chan16_raw: c[15],
            chan17_raw: 0,
            chan18_raw: 0,
            rssi: RSSI_UNKNOWN,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn override_of(first8: [u16; 8]) -> RC_CHANNELS_OVERRIDE_DATA {
        RC_CHANNELS_OVERRIDE_DATA {
            chan1_raw: first8[0],
            chan2_raw: first8[1],
            chan3_raw: first8[2],
            chan4_raw: first8[3],
            chan5_raw: first8[4],
            chan6_raw: first8[5],
            chan7_raw: first8[6],
            chan8_raw: first8[7],
            ..Default::default()
        }
    }

    #[test]
    fn the_receiver_rests_at_sitl_values_and_reports_sixteen_channels() {
        let rx = CopterReceiver::default();
        assert_eq!(rx.channels(0.0), SITL_IDLE_US);
        let MavMessage::RC_CHANNELS(rc) = rx.rc_channels(0.0, 42) else {
            unreachable!()
        };
        assert_eq!((rc.chancount, rc.rssi, rc.time_boot_ms), (16, 255, 42));
        assert_eq!(
            (rc.chan1_raw, rc.chan3_raw, rc.chan5_raw, rc.chan9_raw),
            (1500, 1000, 1800, 0)
        );
        assert_eq!(rx.throttle(0.0), 0.0, "throttle at its minimum");
        let on_ground = rx.sticks(0.0, false);
        assert_eq!(
            (on_ground.roll, on_ground.pitch, on_ground.yaw, on_ground.throttle),
            (0.0, 0.0, 0.0, 0.0)
        );
        assert_eq!(
            rx.sticks(0.0, true).throttle,
            0.5,
            "a resting throttle holds in the air"
        );
    }

    #[test]
    fn overrides_apply_per_channel_until_rc_override_time() {
        let mut rx = CopterReceiver::default();
        // DroneKit's example: 8 channels, 0 for those it does not set (released).
        rx.handle_override(&override_of([110, 210, 310, 4100, 510, 610, 710, 810]), 1.0);
        assert_eq!(&rx.channels(1.0)[..8], &[110, 210, 310, 4100, 510, 610, 710, 810]);
        rx.handle_override(&override_of([u16::MAX, 0, 1900, u16::MAX, 0, 0, 0, 0]), 2.0);
        let c = rx.channels(2.0);
        assert_eq!(&c[..5], &[110, 1500, 1900, 4100, 1800], "UINT16_MAX keeps, 0 releases");
        assert_eq!(rx.channels(3.99)[0], 110, "channel 1 still in force 2.99 s after");
        assert_eq!(rx.channels(4.0)[0], 1500, "RC_OVERRIDE_TIME after its last override");
        assert_eq!(rx.channels(4.99)[2], 1900);
        assert_eq!(rx.channels(5.0), SITL_IDLE_US, "all back to the receiver");
        // Channels 9–16: 0 and UINT16_MAX leave them, UINT16_MAX − 1 releases.
        let high = |v: u16| RC_CHANNELS_OVERRIDE_DATA {
            chan9_raw: v,
            chan10_raw: 0,
            ..override_of([u16::MAX; 8])
        };
        rx.handle_override(&high(1200), 6.0);
        assert_eq!((rx.channels(6.0)[8], rx.channels(6.0)[9]), (1200, 0));
        rx.handle_override(&high(0), 7.0);
        assert_eq!(rx.channels(7.0)[8], 1200, "0 leaves channel 9 as it is");
        rx.handle_override(&high(u16::MAX - 1), 7.5);
        assert_eq!(rx.channels(7.5)[8], 0, "UINT16_MAX − 1 releases it");
    }

    #[test]
    fn stick_channels_fly_as_the_sticks_and_manual_control_overrides_them() {
        let mut rx = CopterReceiver::default();
        rx.handle_override(&override_of([2000, 1250, 1900, 1000, 0, 0, 0, 0]), 0.0);
        let s = rx.sticks(0.5, true);
        assert_eq!((s.roll, s.pitch, s.yaw), (1.0, 0.5, -1.0));
        assert!(
            (s.throttle - 0.9).abs() < 1e-12,
            "an overridden throttle is flown in the air"
        );
        assert!((rx.throttle(0.5) - 0.9).abs() < 1e-12);
        rx.handle_override(&override_of([0, 0, 300, 0, 0, 0, 0, 0]), 1.0);
        assert_eq!(
            rx.sticks(1.0, true).throttle,
            0.0,
            "below the range reads as the minimum"
        );
        let mut rx = CopterReceiver::default();
        let sticks = Sticks {
            roll: 0.5,
            pitch: 1.0,
            yaw: -0.25,
            throttle: 0.75,
        };
        rx.handle_sticks(sticks, 0.0);
        assert_eq!(&rx.channels(0.0)[..4], &[1750, 1000, 1750, 1375]);
        assert_eq!(rx.sticks(0.0, false), sticks, "one conversion each way");
    }
}
