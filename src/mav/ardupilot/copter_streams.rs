//! ArduCopter's stream groups (docs/ardupilot.md §4, docs/mavlink.md §5.1): the ten groups of
//! `GCS_MAVLINK::streams` in Copter's order, each with the suffix of its `SRn_*` rate parameter,
//! its MAV_DATA_STREAM id (REQUEST_DATA_STREAM) and the messages it holds here. A link's rate
//! of a group is the number both REQUEST_DATA_STREAM and a PARAM_SET of `SRn_*` set. Pure.

use crate::mav::stream_messages::TelemetryStream;

/// Number of Copter's stream groups.
pub const GROUP_COUNT: usize = 10;

/// One of Copter's stream groups, in Copter's order (`GCS_MAVLINK::streams`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CopterGroup {
    /// RAW_SENSORS: RAW_IMU, SCALED_PRESSURE.
    RawSensors,
    /// EXTENDED_STATUS: SYS_STATUS, POWER_STATUS, MEMINFO, MISSION_CURRENT, GPS_RAW_INT,
    /// NAV_CONTROLLER_OUTPUT, POSITION_TARGET_GLOBAL_INT.
    ExtendedStatus,
    /// RC_CHANNELS: SERVO_OUTPUT_RAW, RC_CHANNELS.
    RcChannels,
    /// RAW_CONTROLLER: empty for Copter.
    RawController,
    /// POSITION: GLOBAL_POSITION_INT, LOCAL_POSITION_NED.
    Position,
    /// EXTRA1: ATTITUDE, SIMSTATE, AHRS2.
    Extra1,
    /// EXTRA2: VFR_HUD.
    Extra2,
    /// EXTRA3: AHRS, SYSTEM_TIME, BATTERY_STATUS, EKF_STATUS_REPORT, VIBRATION.
    Extra3,
    /// PARAMS: Copter's pacing of parameter lists; no stream here (a list is paced by the link).
    Params,
    /// ADSB: ADSB_VEHICLE; no traffic is simulated, so nothing here.
    Adsb,
}

impl CopterGroup {
    /// Every group, in Copter's order (the order of the `SRn_*` parameters).
    pub const ALL: [Self; GROUP_COUNT] = [
        Self::RawSensors,
        Self::ExtendedStatus,
        Self::RcChannels,
        Self::RawController,
        Self::Position,
        Self::Extra1,
        Self::Extra2,
        Self::Extra3,
        Self::Params,
        Self::Adsb,
    ];

    /// Place in [`Self::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// The suffix of its rate parameter (`SR0_` + `POSITION`).
    pub fn suffix(self) -> &'static str {
        match self {
            Self::RawSensors => "RAW_SENS",
            Self::ExtendedStatus => "EXT_STAT",
            Self::RcChannels => "RC_CHAN",
            Self::RawController => "RAW_CTRL",
            Self::Position => "POSITION",
            Self::Extra1 => "EXTRA1",
            Self::Extra2 => "EXTRA2",
            Self::Extra3 => "EXTRA3",
            Self::Params => "PARAMS",
            Self::Adsb => "ADSB",
        }
    }

    /// Its MAV_DATA_STREAM id (RAW_SENSORS 1, EXTENDED_STATUS 2, RC_CHANNELS 3,
    /// RAW_CONTROLLER 4, POSITION 6, EXTRA1 10, EXTRA2 11, EXTRA3 12); `None` for PARAMS and
    /// ADSB, which REQUEST_DATA_STREAM names only as ALL.
    pub fn data_stream_id(self) -> Option<u8> {
        Some(match self {
            Self::RawSensors => 1,
            Self::ExtendedStatus => 2,
            Self::RcChannels => 3,
            Self::RawController => 4,
            Self::Position => 6,
            Self::Extra1 => 10,
            Self::Extra2 => 11,
            Self::Extra3 => 12,
            Self::Params | Self::Adsb => return None,
        })
    }

    /// The groups REQUEST_DATA_STREAM `stream_id` sets: ALL (0) every group but PARAMS (Copter
    /// keeps its parameter pacing out of ALL), else the group with that id; none for another id.
    pub fn requested(stream_id: u8) -> impl Iterator<Item = Self> {
        Self::ALL.into_iter().filter(move |g| match stream_id {
            0 => *g != Self::Params,
            id => g.data_stream_id() == Some(id),
        })
    }

    /// The group that holds `stream` on an ArduCopter-faced link; `None` for a message in no
    /// group (asked for only by SET_MESSAGE_INTERVAL).
    pub fn of_stream(stream: TelemetryStream) -> Option<Self> {
        use TelemetryStream::*;
        Some(match stream {
            RawImu | ScaledPressure => Self::RawSensors,
            SysStatus | PowerStatus | Meminfo | MissionCurrent | GpsRawInt | NavControllerOutput
            | PositionTargetGlobal => Self::ExtendedStatus,
            ServoOutputRaw | RcChannels => Self::RcChannels,
            GlobalPosition | LocalPosition => Self::Position,
            Attitude | Simstate | Ahrs2 => Self::Extra1,
            VfrHud => Self::Extra2,
            Ahrs | SystemTime | BatteryStatus | EkfStatusReport | Vibration => Self::Extra3,
            _ => return None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_are_in_copters_order_with_their_ids() {
        for (i, g) in CopterGroup::ALL.iter().enumerate() {
            assert_eq!(g.index(), i);
        }
        let suffixes: Vec<&str> = CopterGroup::ALL.iter().map(|g| g.suffix()).collect();
        assert_eq!(
            suffixes,
            [
                "RAW_SENS", "EXT_STAT", "RC_CHAN", "RAW_CTRL", "POSITION", "EXTRA1", "EXTRA2", "EXTRA3", "PARAMS",
                "ADSB"
            ]
        );
        let all: Vec<CopterGroup> = CopterGroup::requested(0).collect();
        assert_eq!(all.len(), 9);
        assert!(!all.contains(&CopterGroup::Params));
        assert!(all.contains(&CopterGroup::Adsb));
        assert_eq!(CopterGroup::requested(6).collect::<Vec<_>>(), [CopterGroup::Position]);
        assert_eq!(CopterGroup::requested(5).count(), 0, "no group has id 5");
        assert_eq!(CopterGroup::requested(13).count(), 0);
        assert_eq!(
            CopterGroup::of_stream(TelemetryStream::GlobalPosition),
            Some(CopterGroup::Position)
        );
        assert_eq!(CopterGroup::of_stream(TelemetryStream::HighresImu), None);
    }
}
