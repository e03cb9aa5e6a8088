//! ArduCopter's flight modes as its ground stations see them (docs/ardupilot.md §2): Copter's
//! mode numbers and names (ArduCopter `mode.h`), each flown as one of the commander's modes, the
//! request that selects it, the number a HEARTBEAT shows and the HEARTBEAT itself. Pure.

use mavlink::dialects::ardupilotmega::{MavAutopilot, MavMessage, MavModeFlag, MavState, HEARTBEAT_DATA};

use crate::commander::{FlightMode, LandedState, MissionState, Outcome, Request};
use crate::mav::identity::Identity;
use crate::telemetry::Snapshot;

/// CIRCLE's radius, ArduCopter's `CIRCLE_RADIUS` default [m].
pub const CIRCLE_RADIUS_M: f64 = 10.0;
/// CIRCLE's turn rate, ArduCopter's `CIRCLE_RATE` default, positive clockwise [deg/s].
pub const CIRCLE_RATE_DEG_S: f64 = 20.0;

/// One Copter mode: its number, its name and the commander mode that flies it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CopterMode {
    /// Copter's mode number (HEARTBEAT `custom_mode`, DO_SET_MODE p2).
    pub number: u8,
    /// Copter's name for it, as pymavlink's and DroneKit's mode tables spell it.
    pub name: &'static str,
    /// The commander mode that flies it.
    pub flown_as: FlightMode,
}

const fn copter(number: u8, name: &'static str, flown_as: FlightMode) -> CopterMode {
    CopterMode { number, name, flown_as }
}

/// The Copter modes the emulator flies. The first row flown as a commander mode is the number a
/// HEARTBEAT shows for it, unless a ground station asked for a later row flown the same way
/// (POSHOLD as LOITER's position hold, SMART_RTL as RTL, GUIDED_NOGPS as GUIDED).
const COPTER_MODES: [CopterMode; 14] = [
    copter(0, "STABILIZE", FlightMode::Stabilized),
    copter(1, "ACRO", FlightMode::Acro),
    copter(2, "ALT_HOLD", FlightMode::Altitude),
    copter(3, "AUTO", FlightMode::Mission),
    copter(4, "GUIDED", FlightMode::Guided),
    copter(5, "LOITER", FlightMode::Position),
    copter(6, "RTL", FlightMode::ReturnToLaunch),
    copter(7, "CIRCLE", FlightMode::Orbit),
    copter(9, "LAND", FlightMode::Land),
    copter(17, "BRAKE", FlightMode::Loiter),
    copter(23, "FOLLOW", FlightMode::FollowTarget),
    copter(16, "POSHOLD", FlightMode::Position),
    copter(21, "SMART_RTL", FlightMode::ReturnToLaunch),
    copter(20, "GUIDED_NOGPS", FlightMode::Guided),
];

/// Copter's names of the modes it has that the emulator does not fly (`mode.h`).
const NOT_FLOWN: [(u8, &str); 11] = [
    (11, "DRIFT"),
    (13, "SPORT"),
    (14, "FLIP"),
    (15, "AUTOTUNE"),
    (18, "THROW"),
    (19, "AVOID_ADSB"),
    (22, "FLOWHOLD"),
    (24, "ZIGZAG"),
    (25, "SYSTEMID"),
    (26, "AUTOROTATE"),
    (28, "TURTLE"),
];

impl CopterMode {
    /// The mode numbered `number`, if the emulator flies it.
    pub fn by_number(number: u32) -> Option<Self> {
        COPTER_MODES.iter().find(|m| u32::from(m.number) == number).copied()
    }

    /// The mode called `name` (Copter's spelling, any case), if the emulator flies it.
    pub fn by_name(name: &str) -> Option<Self> {
        COPTER_MODES.iter().find(|m| m.name.eq_ignore_ascii_case(name)).copied()
    }

    /// Every mode the emulator flies, in Copter's number order.
    pub fn all() -> Vec<Self> {
        let mut modes = COPTER_MODES.to_vec();
        modes.sort_by_key(|m| m.number);
        modes
    }

    /// The commander request that selects it: CIRCLE circles the point `CIRCLE_RADIUS` ahead
    /// (so the vehicle is on its circle at once) at `CIRCLE_RATE`; every other mode is a switch
    /// to the mode that flies it, as Copter changes modes (checked armed, not disarmed).
    pub fn request(self) -> Request {
        match self.number {
            7 => Request::Circle {
                radius_m: CIRCLE_RADIUS_M,
                speed_m_s: CIRCLE_RADIUS_M * CIRCLE_RATE_DEG_S.to_radians(),
            },
            _ => Request::SelectMode(self.flown_as),
        }
    }
}

/// The request for DO_SET_MODE / SET_MODE's `custom_mode` `number`, or Copter's refusal: a mode
/// Copter has but the emulator does not fly is refused by name, a number Copter does not have
/// as such (both FAILED, as Copter answers a mode it cannot enter).
pub fn mode_request(number: u32) -> Result<Request, Outcome> {
    if let Some(mode) = CopterMode::by_number(number) {
        return Ok(mode.request());
    }
    match NOT_FLOWN.iter().find(|(n, _)| u32::from(*n) == number) {
        Some((_, name)) => Err(Outcome::Failed(format!("Mode change to {name} failed: not emulated"))),
        None => Err(Outcome::Failed(format!("No such mode {number}"))),
    }
}

/// Which Copter number the HEARTBEAT shows: the one a ground station asked for last while the
/// commander flies it, else the first row flown as the commander's mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ModeShown {
    asked: Option<u8>,
    /// The number shown while the vehicle was last armed.
    armed_shown: Option<u8>,
    /// The mission's return item is being flown (ArduCopter flies it in AUTO).
    return_item: bool,
}

impl ModeShown {
    /// A ground station asked for mode `number` (noted whether or not the commander takes it:
    /// only a mode the commander then flies is shown by it).
    pub fn handle_asked(&mut self, number: u32) {
        if let Some(mode) = CopterMode::by_number(number) {
            self.asked = Some(mode.number);
        }
    }

    /// The vehicle's latest `state`: while armed, the number shown is remembered (a landing that
    /// ends in the commander's hold keeps showing it, [`Self::shown`]).
    pub fn handle_state(&mut self, state: &Snapshot) {
        if state.armed {
            self.armed_shown = Some(self.shown(state));
        }
    }

    /// Whether the commander's return is the mission's NAV_RETURN_TO_LAUNCH item.
    pub fn handle_return_item(&mut self, flying_it: bool) {
        self.return_item = flying_it;
    }

    /// The Copter mode number asked for last, if any.
    pub fn asked(&self) -> Option<u32> {
        self.asked.map(u32::from)
    }

    /// The Copter number of the commander's `mode`. Modes no Copter number selects show as the
    /// Copter mode that flies them so: PX4's take-off, GOTO and OFFBOARD as GUIDED (Copter takes
    /// off, repositions and follows external targets in GUIDED), AUTO.READY as BRAKE, MANUAL
    /// as STABILIZE.
    pub fn number(&self, mode: FlightMode) -> u8 {
        if let Some(asked) = self.asked.and_then(|n| CopterMode::by_number(u32::from(n))) {
            if asked.flown_as == mode {
                return asked.number;
            }
        }
        let shown_as = match mode {
            FlightMode::Takeoff | FlightMode::Goto | FlightMode::Offboard => FlightMode::Guided,
            FlightMode::Ready => FlightMode::Loiter,
            FlightMode::Manual => FlightMode::Stabilized,
            other => other,
        };
        COPTER_MODES
            .iter()
            .find(|m| m.flown_as == shown_as)
            .map_or(0, |m| m.number)
    }

    /// The Copter number the HEARTBEAT shows for `state`: [`Self::number`] of its mode, except
    /// that the commander's boot hold shows as STABILIZE (Copter's boot mode, asked for at boot:
    /// never armed, no mode asked for), that a mission flown to its end in AUTO stays AUTO
    /// (ArduCopter loiters in AUTO there; the commander holds in its hold mode), that the
    /// mission's return item shows AUTO (ArduCopter returns in AUTO's RTL submode), and that a
    /// vehicle disarmed after a landing stays in the mode it landed in (RTL, LAND, AUTO …:
    /// ArduCopter keeps the mode; the commander falls back to its hold unless BRAKE was asked
    /// for).
    pub fn shown(&self, state: &Snapshot) -> u8 {
        let hold = state.mode == FlightMode::Loiter;
        if hold && !state.armed && self.asked.is_none() && self.armed_shown.is_none() {
            return 0;
        }
        if self.asked == Some(3) && hold && state.mission_state == MissionState::Complete {
            return 3;
        }
        if self.asked == Some(3) && self.return_item && state.mode == FlightMode::ReturnToLaunch {
            return 3;
        }
        match self.armed_shown {
            Some(landed_in) if hold && !state.armed && self.asked != Some(17) => landed_in,
            _ => self.number(state.mode),
        }
    }
}

/// ArduCopter's HEARTBEAT for `state` (ArduCopter `GCS_MAVLink_Copter.cpp`): autopilot
/// ARDUPILOTMEGA; base mode always custom | stabilize | manual input, + guided while the
/// position controller flies (armed in a mode that holds a position), + armed; custom mode the
/// Copter number `shown`; system status BOOT until the attitude is known, CRITICAL while a
/// `failsafe` is active (Copter's GCS, battery and EKF failsafes, [`super::copter_failsafes`]),
/// STANDBY on the ground (armed or not), ACTIVE in the air.
pub fn copter_heartbeat(id: &Identity, state: &Snapshot, shown: &ModeShown, failsafe: bool) -> MavMessage {
    use MavModeFlag as F;
    let mut base = F::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED
        | F::MAV_MODE_FLAG_STABILIZE_ENABLED
        | F::MAV_MODE_FLAG_MANUAL_INPUT_ENABLED;
    if state.armed {
        base |= F::MAV_MODE_FLAG_SAFETY_ARMED;
        if state.mode.needs_position() {
            base |= F::MAV_MODE_FLAG_GUIDED_ENABLED;
        }
    }
    let system_status = if !state.nav.validity.attitude {
        MavState::MAV_STATE_BOOT
    } else if failsafe {
        MavState::MAV_STATE_CRITICAL
    } else if state.landed == LandedState::OnGround {
        MavState::MAV_STATE_STANDBY
    } else {
        MavState::MAV_STATE_ACTIVE
    };
    MavMessage::HEARTBEAT(HEARTBEAT_DATA {
        custom_mode: u32::from(shown.shown(state)),
        mavtype: id.mav_type,
        autopilot: MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA,
        base_mode: base,
        system_status,
        mavlink_version: 3,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::guidance::Home;
    use crate::mav::identity::Personality;

    #[test]
    fn copter_numbers_select_the_modes_that_fly_them() {
        let table = [
            (0, "STABILIZE"),
            (1, "ACRO"),
            (2, "ALT_HOLD"),
            (3, "AUTO"),
            (4, "GUIDED"),
            (5, "LOITER"),
            (6, "RTL"),
            (7, "CIRCLE"),
            (9, "LAND"),
            (16, "POSHOLD"),
            (17, "BRAKE"),
            (20, "GUIDED_NOGPS"),
            (21, "SMART_RTL"),
            (23, "FOLLOW"),
        ];
        let all: Vec<(u8, &str)> = CopterMode::all().iter().map(|m| (m.number, m.name)).collect();
        assert_eq!(all, table);
        assert_eq!(mode_request(4), Ok(Request::SelectMode(FlightMode::Guided)));
        assert_eq!(mode_request(17), Ok(Request::SelectMode(FlightMode::Loiter)));
        assert!(matches!(mode_request(7), Ok(Request::Circle { radius_m, .. }) if radius_m == 10.0));
        assert_eq!(
            mode_request(14),
            Err(Outcome::Failed("Mode change to FLIP failed: not emulated".into()))
        );
        assert_eq!(mode_request(8), Err(Outcome::Failed("No such mode 8".into())));
        assert_eq!(CopterMode::by_name("smart_rtl").map(|m| m.number), Some(21));
    }

    #[test]
    fn the_heartbeat_shows_the_number_asked_for_while_its_mode_flies() {
        let mut shown = ModeShown::default();
        assert_eq!(shown.number(FlightMode::Position), 5, "LOITER by default");
        assert_eq!(shown.number(FlightMode::Loiter), 17, "PX4's hold is BRAKE");
        assert_eq!(shown.number(FlightMode::Takeoff), 4);
        shown.handle_asked(16);
        assert_eq!(shown.number(FlightMode::Position), 16, "POSHOLD asked for");
        assert_eq!(
            shown.number(FlightMode::ReturnToLaunch),
            6,
            "a failsafe's RTL shows as RTL"
        );
        shown.handle_asked(99);
        assert_eq!(
            shown.number(FlightMode::Position),
            16,
            "an unknown number changes nothing"
        );
        shown.handle_asked(21);
        assert_eq!(shown.number(FlightMode::ReturnToLaunch), 21);
        assert_eq!(shown.number(FlightMode::Position), 5);
    }

    #[test]
    fn a_vehicle_disarmed_after_landing_stays_in_the_mode_it_landed_in() {
        let mut shown = ModeShown::default();
        let mut s = Snapshot::initial(Home::default());
        shown.handle_state(&s);
        assert_eq!(shown.shown(&s), 0, "booted: STABILIZE");
        shown.handle_asked(4);
        s.mode = FlightMode::Guided;
        s.armed = true;
        shown.handle_state(&s);
        s.mode = FlightMode::ReturnToLaunch;
        shown.handle_state(&s);
        assert_eq!(shown.shown(&s), 6);
        s.mode = FlightMode::Loiter;
        s.armed = false;
        shown.handle_state(&s);
        assert_eq!(shown.shown(&s), 6, "landed and disarmed in RTL");
        shown.handle_asked(17);
        assert_eq!(shown.shown(&s), 17, "BRAKE asked for");
    }

    #[test]
    fn heartbeat_flags_and_status_follow_copter() {
        let id = Identity::autopilot(1, 6).with_personality(Personality::ArduPilot);
        let mut s = Snapshot::initial(Home::default());
        s.mode = FlightMode::Guided;
        let hb_in = |s: &Snapshot, failsafe: bool| match copter_heartbeat(&id, s, &ModeShown::default(), failsafe) {
            MavMessage::HEARTBEAT(hb) => hb,
            _ => unreachable!(),
        };
        let hb = |s: &Snapshot| hb_in(s, false);
        let h = hb(&s);
        assert_eq!(h.autopilot, MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA);
        assert_eq!(h.mavtype, mavlink::dialects::ardupilotmega::MavType::MAV_TYPE_HEXAROTOR);
        assert_eq!((h.custom_mode, h.base_mode.bits()), (4, 81));
        assert_eq!(h.system_status, MavState::MAV_STATE_STANDBY);
        s.armed = true;
        assert_eq!(hb(&s).base_mode.bits(), 217, "armed and navigating");
        assert_eq!(hb(&s).system_status, MavState::MAV_STATE_STANDBY, "armed on the ground");
        s.landed = LandedState::InAir;
        assert_eq!(hb(&s).system_status, MavState::MAV_STATE_ACTIVE);
        s.mode = FlightMode::Stabilized;
        assert_eq!((hb(&s).custom_mode, hb(&s).base_mode.bits()), (0, 209));
        s.geofence_breached = true;
        assert_eq!(
            hb(&s).system_status,
            MavState::MAV_STATE_ACTIVE,
            "a breach is no failsafe"
        );
        assert_eq!(hb_in(&s, true).system_status, MavState::MAV_STATE_CRITICAL);
        s.landed = LandedState::OnGround;
        assert_eq!(
            hb_in(&s, true).system_status,
            MavState::MAV_STATE_CRITICAL,
            "on the ground too"
        );
        s.nav.validity.attitude = false;
        assert_eq!(hb_in(&s, true).system_status, MavState::MAV_STATE_BOOT);
    }

    #[test]
    fn a_mission_flown_to_its_end_in_auto_stays_auto() {
        let mut s = Snapshot::initial(Home::default());
        s.mode = FlightMode::Loiter;
        s.mission_state = MissionState::Complete;
        let mut shown = ModeShown::default();
        assert_eq!(shown.shown(&s), 0, "booted: STABILIZE");
        shown.handle_asked(17);
        assert_eq!(shown.shown(&s), 17, "not asked for AUTO: PX4's hold is BRAKE");
        shown.handle_asked(3);
        assert_eq!(shown.shown(&s), 3, "the mission ended in AUTO");
        s.mission_state = MissionState::Paused;
        assert_eq!(shown.shown(&s), 17, "the hold for another reason");
        s.mission_state = MissionState::Complete;
        s.mode = FlightMode::Land;
        assert_eq!(shown.shown(&s), 9);
        s.mode = FlightMode::Loiter;
        shown.handle_asked(5);
        assert_eq!(shown.shown(&s), 17, "LOITER asked for since");
        let id = Identity::autopilot(1, 4).with_personality(Personality::ArduPilot);
        shown.handle_asked(3);
        let MavMessage::HEARTBEAT(hb) = copter_heartbeat(&id, &s, &shown, false) else {
            unreachable!()
        };
        assert_eq!(hb.custom_mode, 3);
    }
}
