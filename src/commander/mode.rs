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

const MAIN_POSCTL: u8 = 3;
const MAIN_AUTO: u8 = 4;
const MAIN_OFFBOARD: u8 = 6;
/// MANUAL (1), ALTCTL (2), ACRO (5) and STABILIZED (7): modes that need a manual-control source.
const MAIN_MANUAL_CONTROL: [u8; 4] = [1, 2, 5, 7];

/// (mode, PX4 main mode, PX4 sub mode, MAV_STANDARD_MODE, PX4 display name).
type ModeRow = (FlightMode, u8, u8, Option<u8>, &'static str);

/// Each mode in declaration order (indexed by `mode as usize`): PX4 main and sub mode
/// (px4_custom_mode.h; POSCTL and OFFBOARD take any sub mode), the MAV_STANDARD_MODE it answers
/// to (mavlink.md §2.2: position hold 1, safe recovery 5, mission 6, land 7, take-off 8), and
/// PX4's display name. The one table behind every mapping below.
const MODES: [ModeRow; 8] = [
    (FlightMode::Position, MAIN_POSCTL, 0, Some(1), "POSCTL"),
    (FlightMode::Ready, MAIN_AUTO, 1, None, "AUTO.READY"),
    (FlightMode::Takeoff, MAIN_AUTO, 2, Some(8), "AUTO.TAKEOFF"),
    (FlightMode::Loiter, MAIN_AUTO, 3, None, "AUTO.LOITER"),
    (FlightMode::Mission, MAIN_AUTO, 4, Some(6), "AUTO.MISSION"),
    (FlightMode::ReturnToLaunch, MAIN_AUTO, 5, Some(5), "AUTO.RTL"),
    (FlightMode::Land, MAIN_AUTO, 6, Some(7), "AUTO.LAND"),
    (FlightMode::Offboard, MAIN_OFFBOARD, 0, None, "OFFBOARD"),
];

impl FlightMode {
    /// The mode's row of [`MODES`].
    fn row(self) -> &'static ModeRow {
        &MODES[self as usize]
    }

    /// PX4 (main, sub) mode numbers.
    pub fn px4(self) -> (u8, u8) {
        let (_, main, sub, _, _) = *self.row();
        (main, sub)
    }

    /// HEARTBEAT `custom_mode`.
    pub fn custom_mode(self) -> u32 {
        let (main, sub) = self.px4();
        (u32::from(main) << 16) | (u32::from(sub) << 24)
    }

    /// The mode for PX4 numbers (DO_SET_MODE p2/p3).
    pub fn from_px4(main: u8, sub: u8) -> Result<Self, ModeRefusal> {
        let flown = MODES
            .iter()
            .find(|(_, m, s, _, _)| *m == main && (main != MAIN_AUTO || *s == sub));
        match flown {
            Some((mode, ..)) => Ok(*mode),
            None if MAIN_MANUAL_CONTROL.contains(&main) => Err(ModeRefusal::NeedsManualControl),
            None => Err(ModeRefusal::Unknown),
        }
    }

    /// The mode for a packed `custom_mode` (SET_MODE message).
    pub fn from_custom_mode(custom_mode: u32) -> Result<Self, ModeRefusal> {
        Self::from_px4(((custom_mode >> 16) & 0xFF) as u8, ((custom_mode >> 24) & 0xFF) as u8)
    }

    /// The mode for a MAV_STANDARD_MODE (DO_SET_STANDARD_MODE p1, mavlink.md §2.2): position hold
    /// (1), safe recovery (5, return), mission (6), land (7), take-off (8); `None` for the others.
    pub fn from_standard_mode(standard_mode: u8) -> Option<Self> {
        MODES
            .iter()
            .find(|(.., standard, _)| *standard == Some(standard_mode))
            .map(|(mode, ..)| *mode)
    }

    /// PX4's display name.
    pub fn name(self) -> &'static str {
        self.row().4
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
        assert_eq!(FlightMode::from_px4(4, 0), Err(ModeRefusal::Unknown));
        let standard = [1, 5, 6, 7, 8, 2].map(FlightMode::from_standard_mode);
        let expected = [
            Some(FlightMode::Position),
            Some(FlightMode::ReturnToLaunch),
            Some(FlightMode::Mission),
            Some(FlightMode::Land),
            Some(FlightMode::Takeoff),
            None,
        ];
        assert_eq!(standard, expected);
        for (k, (mode, ..)) in MODES.iter().enumerate() {
            assert_eq!(*mode as usize, k, "{} is in its row", mode.name());
        }
    }
}
