//! PX4 flight modes and their `custom_mode` packing (docs/mavlink.md §2.1):
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
    /// MANUAL: for a multicopter PX4 flies it as STABILIZED.
    Manual,
    /// ALTCTL: the sticks set the tilt and the climb rate, the height holds.
    Altitude,
    /// ACRO: the sticks set the body rates and the throttle the thrust.
    Acro,
    /// STABILIZED: the sticks set the tilt and the heading rate, the throttle the thrust.
    Stabilized,
    /// POSCTL.ORBIT: fly a circle (MAV_CMD_DO_ORBIT).
    Orbit,
    /// AUTO.FOLLOW_TARGET: follow the target FOLLOW_TARGET reports (follow-me).
    FollowTarget,
    /// GOTO (AUTO sub mode 21, PX4's multicopter Goto): fly to a DO_REPOSITION target, then hold
    /// there; entered only by DO_REPOSITION with the mode-change flag.
    Goto,
    /// GUIDED (ArduCopter's, for the ArduPilot personality; PX4 has no such mode): hold, or
    /// take off in place, or fly the latest guided target (position targets persist, velocity,
    /// acceleration and attitude targets stop at their stream's loss); no failsafe on silence.
    Guided,
}

/// Why a PX4 mode number cannot be flown.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModeRefusal {
    /// Not a PX4 mode this emulator knows.
    Unknown,
    /// A mode PX4 enters only on a command of its own, never by its number (Goto: DO_REPOSITION).
    NotByNumber,
}

const MAIN_MANUAL: u8 = 1;
const MAIN_ALTCTL: u8 = 2;
const MAIN_POSCTL: u8 = 3;
const MAIN_AUTO: u8 = 4;
const MAIN_ACRO: u8 = 5;
const MAIN_OFFBOARD: u8 = 6;
const MAIN_STABILIZED: u8 = 7;

/// How PX4 names and numbers one mode.
struct ModeRow {
    mode: FlightMode,
    /// PX4 main mode (px4_custom_mode.h).
    main: u8,
    /// PX4 sub mode (AUTO modes; POSCTL and OFFBOARD take any).
    sub: u8,
    /// The MAV_STANDARD_MODE it answers to, if any.
    standard: Option<u8>,
    /// PX4's display name in its shell and logs.
    name: &'static str,
    /// PX4's navigation state number (vehicle_status.nav_state); AUTO.READY has none, nor has
    /// GOTO here (PX4's number for it is not known to this emulator).
    nav_state: Option<u8>,
    /// The name a ground station shows (PX4's mode UI name, sent in AVAILABLE_MODES).
    ui_name: &'static str,
}

const fn row(
    mode: FlightMode,
    (main, sub): (u8, u8),
    standard: Option<u8>,
    name: &'static str,
    nav_state: Option<u8>,
    ui_name: &'static str,
) -> ModeRow {
    ModeRow {
        mode,
        main,
        sub,
        standard,
        name,
        nav_state,
        ui_name,
    }
}

/// Each mode in declaration order (indexed by `mode as usize`): PX4 main and sub mode, the
/// MAV_STANDARD_MODE it answers to (position hold 1, safe recovery 5, mission 6, land 7,
/// take-off 8, altitude hold 4, orbit 2; PX4 gives AUTO.LOITER, OFFBOARD, the manual-thrust
/// modes and GOTO none), PX4's display name, its navigation state and its UI name. The one table
/// behind every mapping below.
const MODES: [ModeRow; 16] = [
    row(
        FlightMode::Position,
        (MAIN_POSCTL, 0),
        Some(1),
        "POSCTL",
        Some(2),
        "Position",
    ),
    row(FlightMode::Ready, (MAIN_AUTO, 1), None, "AUTO.READY", None, "Ready"),
    row(
        FlightMode::Takeoff,
        (MAIN_AUTO, 2),
        Some(8),
        "AUTO.TAKEOFF",
        Some(17),
        "Takeoff",
    ),
    row(FlightMode::Loiter, (MAIN_AUTO, 3), None, "AUTO.LOITER", Some(4), "Hold"),
    row(
        FlightMode::Mission,
        (MAIN_AUTO, 4),
        Some(6),
        "AUTO.MISSION",
        Some(3),
        "Mission",
    ),
    row(
        FlightMode::ReturnToLaunch,
        (MAIN_AUTO, 5),
        Some(5),
        "AUTO.RTL",
        Some(5),
        "Return",
    ),
    row(FlightMode::Land, (MAIN_AUTO, 6), Some(7), "AUTO.LAND", Some(18), "Land"),
    row(
        FlightMode::Offboard,
        (MAIN_OFFBOARD, 0),
        None,
        "OFFBOARD",
        Some(14),
        "Offboard",
    ),
    row(FlightMode::Manual, (MAIN_MANUAL, 0), None, "MANUAL", Some(0), "Manual"),
    row(
        FlightMode::Altitude,
        (MAIN_ALTCTL, 0),
        Some(4),
        "ALTCTL",
        Some(1),
        "Altitude",
    ),
    row(FlightMode::Acro, (MAIN_ACRO, 0), None, "ACRO", Some(10), "Acro"),
    row(
        FlightMode::Stabilized,
        (MAIN_STABILIZED, 0),
        None,
        "STABILIZED",
        Some(15),
        "Stabilized",
    ),
    row(FlightMode::Orbit, (MAIN_POSCTL, 1), Some(2), "ORBIT", Some(21), "Orbit"),
    row(
        FlightMode::FollowTarget,
        (MAIN_AUTO, 8),
        None,
        "AUTO.FOLLOW_TARGET",
        Some(19),
        "Follow Me",
    ),
    // px4_custom_mode.h names sub mode 21 PX4_CUSTOM_SUB_MODE_GOTO, without AUTO_.
    row(FlightMode::Goto, (MAIN_AUTO, 21), None, "GOTO", None, "Goto"),
    // No PX4 number selects GUIDED (OFFBOARD's row comes first); a PX4-faced vehicle never
    // enters it, and would show it as OFFBOARD, the PX4 mode that flies external targets.
    row(FlightMode::Guided, (MAIN_OFFBOARD, 0), None, "GUIDED", None, "Guided"),
];

impl FlightMode {
    /// The mode's row of [`MODES`].
    fn row(self) -> &'static ModeRow {
        &MODES[self as usize]
    }

    /// PX4 (main, sub) mode numbers.
    pub fn px4(self) -> (u8, u8) {
        (self.row().main, self.row().sub)
    }

    /// HEARTBEAT `custom_mode`.
    pub fn custom_mode(self) -> u32 {
        let (main, sub) = self.px4();
        (u32::from(main) << 16) | (u32::from(sub) << 24)
    }

    /// The mode for PX4 numbers (DO_SET_MODE p2/p3): the row with both numbers; outside AUTO
    /// (whose sub modes are modes of their own) an unknown sub mode means the main mode. GOTO is
    /// refused: PX4's DO_SET_MODE has no case for its sub mode, DO_REPOSITION enters it.
    pub fn from_px4(main: u8, sub: u8) -> Result<Self, ModeRefusal> {
        let exact = MODES.iter().find(|r| r.main == main && r.sub == sub);
        let main_only = || MODES.iter().find(|r| r.main == main && r.sub == 0 && main != MAIN_AUTO);
        match exact.or_else(main_only).map(|r| r.mode) {
            Some(Self::Goto) => Err(ModeRefusal::NotByNumber),
            Some(mode) => Ok(mode),
            None => Err(ModeRefusal::Unknown),
        }
    }

    /// The mode for a packed `custom_mode` (SET_MODE message).
    pub fn from_custom_mode(custom_mode: u32) -> Result<Self, ModeRefusal> {
        Self::from_px4(((custom_mode >> 16) & 0xFF) as u8, ((custom_mode >> 24) & 0xFF) as u8)
    }

    /// The mode for a MAV_STANDARD_MODE (DO_SET_STANDARD_MODE p1): position hold (1), altitude
    /// hold (4), safe recovery (5, return), mission (6), land (7), take-off (8); `None` for the
    /// others.
    pub fn from_standard_mode(standard_mode: u8) -> Option<Self> {
        MODES.iter().find(|r| r.standard == Some(standard_mode)).map(|r| r.mode)
    }

    /// The MAV_STANDARD_MODE this mode answers to (`None`: non-standard).
    pub fn standard_mode(self) -> Option<u8> {
        self.row().standard
    }

    /// PX4's navigation state number (`vehicle_status.nav_state`); AUTO.READY and GOTO have none.
    pub fn nav_state(self) -> Option<u8> {
        self.row().nav_state
    }

    /// PX4's display name.
    pub fn name(self) -> &'static str {
        self.row().name
    }

    /// The name a ground station shows (PX4's UI name: "Hold", "Offboard", ...).
    pub fn ui_name(self) -> &'static str {
        self.row().ui_name
    }

    /// True for the modes flown from the sticks (MANUAL_CONTROL): MANUAL, ALTCTL, POSCTL, ACRO,
    /// STABILIZED.
    pub fn flown_by_sticks(self) -> bool {
        matches!(
            self,
            Self::Manual | Self::Altitude | Self::Position | Self::Acro | Self::Stabilized
        )
    }

    /// True for the modes where the throttle stick sets the thrust (MANUAL, ACRO, STABILIZED).
    pub fn manual_thrust(self) -> bool {
        matches!(self, Self::Manual | Self::Acro | Self::Stabilized)
    }

    /// The modes a ground station can select, in PX4's navigation-state order (the order of
    /// AVAILABLE_MODES): manual, altitude, position, mission, hold, return, acro, offboard,
    /// stabilized, take-off, land, follow-me, orbit. Not GOTO, which no mode number selects.
    pub fn selectable() -> Vec<Self> {
        let mut modes: Vec<(u8, Self)> = MODES.iter().filter_map(|r| Some((r.nav_state?, r.mode))).collect();
        modes.sort_by_key(|(nav_state, _)| *nav_state);
        modes.into_iter().map(|(_, mode)| mode).collect()
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
            (FlightMode::Manual, 65_536),
            (FlightMode::Altitude, 131_072),
            (FlightMode::Acro, 327_680),
            (FlightMode::Stabilized, 458_752),
            (FlightMode::Orbit, 16_973_824),
            (FlightMode::FollowTarget, 134_479_872),
        ];
        for (mode, cm) in table {
            assert_eq!(mode.custom_mode(), cm, "{}", mode.name());
            assert_eq!(FlightMode::from_custom_mode(cm), Ok(mode));
        }
        // GOTO shows in HEARTBEAT as 4/21 but no DO_SET_MODE or SET_MODE selects it.
        assert_eq!(FlightMode::Goto.custom_mode(), 352_583_680);
        assert_eq!(FlightMode::from_px4(4, 21), Err(ModeRefusal::NotByNumber));
        assert_eq!(FlightMode::from_custom_mode(352_583_680), Err(ModeRefusal::NotByNumber));
        assert_eq!(
            (
                FlightMode::Goto.name(),
                FlightMode::Goto.ui_name(),
                FlightMode::Goto.nav_state()
            ),
            ("GOTO", "Goto", None)
        );
        assert_eq!(FlightMode::from_px4(4, 9), Err(ModeRefusal::Unknown));
        assert_eq!(FlightMode::from_px4(9, 0), Err(ModeRefusal::Unknown));
        assert_eq!(FlightMode::from_px4(4, 0), Err(ModeRefusal::Unknown));
        assert_eq!(
            FlightMode::from_px4(3, 7),
            Ok(FlightMode::Position),
            "POSCTL takes any sub mode"
        );
        let standard = [1, 5, 6, 7, 8, 3, 4, 2].map(FlightMode::from_standard_mode);
        let expected = [
            Some(FlightMode::Position),
            Some(FlightMode::ReturnToLaunch),
            Some(FlightMode::Mission),
            Some(FlightMode::Land),
            Some(FlightMode::Takeoff),
            None,
            Some(FlightMode::Altitude),
            Some(FlightMode::Orbit),
        ];
        assert_eq!(standard, expected);
        for (k, r) in MODES.iter().enumerate() {
            assert_eq!(r.mode as usize, k, "{} is in its row", r.mode.name());
        }
        use FlightMode::*;
        assert_eq!(
            FlightMode::selectable(),
            [
                Manual,
                Altitude,
                Position,
                Mission,
                Loiter,
                ReturnToLaunch,
                Acro,
                Offboard,
                Stabilized,
                Takeoff,
                Land,
                FollowTarget,
                Orbit
            ]
        );
        assert_eq!((Loiter.ui_name(), Loiter.standard_mode()), ("Hold", None));
    }
}
