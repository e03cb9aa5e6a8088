//! PX4 flight modes and their `custom_mode` packing (mavlink.md §2.1):
//! `custom_mode = (main_mode << 16) | (sub_mode << 24)`.

/// Flight modes the emulator flies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FlightMode {
    /// POSCTL: hold position (no sticks).
    Position,
    /// AUTO.READY: behaves as [`FlightMode::Loiter`].
    Ready,
    /// AUTO.TAKEOFF: climb to the take-off altitude, then loiter.
    Takeoff,
    /// AUTO.LOITER ("Hold"): hold position.
    Loiter,
    /// AUTO.MISSION: fly the stored mission.
    Mission,
    /// AUTO.RTL: climb to the return altitude, fly home, land.
    ReturnToLaunch,
    /// AUTO.LAND: land here and disarm.
    Land,
    /// OFFBOARD: follow external setpoints.
    Offboard,
}

/// Why a PX4 mode number cannot be flown.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModeRefusal {
    /// A mode that needs a manual-control source (MANUAL, ALTCTL, ACRO, STABILIZED).
    NeedsManualControl,
    /// Not a PX4 mode this emulator knows.
    Unknown,
}

const MAIN_MANUAL: u8 = 1;
const MAIN_ALTCTL: u8 = 2;
const MAIN_POSCTL: u8 = 3;
const MAIN_AUTO: u8 = 4;
const MAIN_ACRO: u8 = 5;
const MAIN_OFFBOARD: u8 = 6;
const MAIN_STABILIZED: u8 = 7;

impl FlightMode {
    /// PX4 (main, sub) mode numbers.
    pub fn px4(self) -> (u8, u8) {
        match self {
            Self::Position => (MAIN_POSCTL, 0),
            Self::Ready => (MAIN_AUTO, 1),
            Self::Takeoff => (MAIN_AUTO, 2),
            Self::Loiter => (MAIN_AUTO, 3),
            Self::Mission => (MAIN_AUTO, 4),
            Self::ReturnToLaunch => (MAIN_AUTO, 5),
            Self::Land => (MAIN_AUTO, 6),
            Self::Offboard => (MAIN_OFFBOARD, 0),
        }
    }

    /// HEARTBEAT `custom_mode`.
    pub fn custom_mode(self) -> u32 {
        let (main, sub) = self.px4();
        (u32::from(main) << 16) | (u32::from(sub) << 24)
    }

    /// The mode for PX4 numbers (DO_SET_MODE p2/p3).
    pub fn from_px4(main: u8, sub: u8) -> Result<Self, ModeRefusal> {
        match (main, sub) {
            (MAIN_POSCTL, _) => Ok(Self::Position),
            (MAIN_AUTO, 1) => Ok(Self::Ready),
            (MAIN_AUTO, 2) => Ok(Self::Takeoff),
            (MAIN_AUTO, 3) => Ok(Self::Loiter),
            (MAIN_AUTO, 4) => Ok(Self::Mission),
            (MAIN_AUTO, 5) => Ok(Self::ReturnToLaunch),
            (MAIN_AUTO, 6) => Ok(Self::Land),
            (MAIN_OFFBOARD, _) => Ok(Self::Offboard),
            (MAIN_MANUAL | MAIN_ALTCTL | MAIN_ACRO | MAIN_STABILIZED, _) => Err(ModeRefusal::NeedsManualControl),
            _ => Err(ModeRefusal::Unknown),
        }
    }

    /// The mode for a packed `custom_mode` (SET_MODE message).
    pub fn from_custom_mode(custom_mode: u32) -> Result<Self, ModeRefusal> {
        Self::from_px4(((custom_mode >> 16) & 0xFF) as u8, ((custom_mode >> 24) & 0xFF) as u8)
    }

    /// The mode for a MAV_STANDARD_MODE (DO_SET_STANDARD_MODE p1, mavlink.md §2.2): position hold
    /// (1), safe recovery (5, return), mission (6), land (7), take-off (8); `None` for the others.
    pub fn from_standard_mode(standard_mode: u8) -> Option<Self> {
        match standard_mode {
            1 => Some(Self::Position),
            5 => Some(Self::ReturnToLaunch),
            6 => Some(Self::Mission),
            7 => Some(Self::Land),
            8 => Some(Self::Takeoff),
            _ => None,
        }
    }

    /// PX4's display name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Position => "POSCTL",
            Self::Ready => "AUTO.READY",
            Self::Takeoff => "AUTO.TAKEOFF",
            Self::Loiter => "AUTO.LOITER",
            Self::Mission => "AUTO.MISSION",
            Self::ReturnToLaunch => "AUTO.RTL",
            Self::Land => "AUTO.LAND",
            Self::Offboard => "OFFBOARD",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn custom_modes_match_the_px4_table() {
        let table = [
            (FlightMode::Position, 196_608),
            (FlightMode::Ready, 17_039_360),
            (FlightMode::Takeoff, 33_816_576),
            (FlightMode::Loiter, 50_593_792),
            (FlightMode::Mission, 67_371_008),
            (FlightMode::ReturnToLaunch, 84_148_224),
            (FlightMode::Land, 100_925_440),
            (FlightMode::Offboard, 393_216),
        ];
        for (mode, cm) in table {
            assert_eq!(mode.custom_mode(), cm, "{}", mode.name());
            assert_eq!(FlightMode::from_custom_mode(cm), Ok(mode));
        }
        assert_eq!(FlightMode::from_px4(1, 0), Err(ModeRefusal::NeedsManualControl));
        assert_eq!(FlightMode::from_px4(4, 9), Err(ModeRefusal::Unknown));
        assert_eq!(FlightMode::from_px4(9, 0), Err(ModeRefusal::Unknown));
    }
}
