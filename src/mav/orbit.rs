//! MAV_CMD_DO_ORBIT as PX4 reads it, and ORBIT_EXECUTION_STATUS (360) as PX4 reports it. Pure.
//!
//! DO_ORBIT: p1 radius [m] (positive clockwise), p2 tangential speed [m/s], p3 yaw behaviour
//! (ORBIT_YAW_BEHAVIOUR 0–4; 5, UNCHANGED, keeps the running orbit's, or `MC_ORBIT_YAW_MOD`'s
//! default when not orbiting yet), p5/p6 centre latitude/longitude [deg], p7 centre altitude AMSL
//! [m] (PX4 reads it as AMSL whatever the COMMAND_INT frame); NaN keeps the running orbit's value
//! (or the vehicle's position and height for the centre). p4, MAVLink's number of turns, is not
//! read, as PX4 does not read it: the orbit goes on until another mode is chosen.

use mavlink::dialects::ardupilotmega::{MavFrame, MavMessage, COMMAND_LONG_DATA, ORBIT_EXECUTION_STATUS_DATA};

use crate::commander::{OrbitRequest, Outcome, Request};
use crate::guidance::{Home, OrbitYaw};
use crate::telemetry::Snapshot;

use super::translate::CommandDecision;

/// What a DO_ORBIT asks, or why it is refused; `centre_deg` is its latitude and longitude
/// [deg] when given (COMMAND_INT passes the exact degE7 values, COMMAND_LONG p5/p6).
pub fn decode_orbit(cmd: &COMMAND_LONG_DATA, centre_deg: Option<(f64, f64)>, origin: &Home) -> CommandDecision {
    let given = |x: f32| (!x.is_nan()).then_some(f64::from(x));
    let yaw = match given(cmd.param3) {
        // NaN, or ORBIT_YAW_BEHAVIOUR_UNCHANGED.
        None => None,
        Some(5.0) => None,
        Some(code) => match OrbitYaw::from_code(code as u8).filter(|_| code.fract() == 0.0 && code >= 0.0) {
            Some(yaw) => Some(yaw),
            None => return refuse(format!("Orbit: yaw behaviour {code} is not an ORBIT_YAW_BEHAVIOUR")),
        },
    };
    let centre_ne_m = match centre_deg {
        Some((lat, lon)) if lat.abs() <= 90.0 && lon.abs() <= 180.0 => {
            let p = origin.to_local(lat, lon, origin.alt_amsl_m);
            Some((p.x, p.y))
        }
        None => None,
        Some((lat, lon)) => return refuse(format!("Orbit: centre {lat}, {lon} is not a place")),
    };
    CommandDecision::Execute(Request::Orbit(OrbitRequest {
        radius_m: given(cmd.param1),
        speed_m_s: given(cmd.param2),
        yaw,
        centre_ne_m,
        centre_down_m: given(cmd.param7).map(|amsl| origin.alt_amsl_m - amsl),
    }))
}

fn refuse(why: String) -> CommandDecision {
    CommandDecision::Refuse(Outcome::Denied(why))
}

/// ORBIT_EXECUTION_STATUS of the orbit flown, in MAV_FRAME_GLOBAL (centre latitude and
/// longitude [degE7], altitude AMSL [m]), as PX4 sends it; `None` when not orbiting.
pub fn orbit_execution_status(s: &Snapshot) -> Option<MavMessage> {
    let (centre_w, radius_m) = s.orbit?;
    let (lat, lon, alt) = s.home.to_global(&centre_w);
    Some(MavMessage::ORBIT_EXECUTION_STATUS(ORBIT_EXECUTION_STATUS_DATA {
        time_usec: super::stream_messages::time_usec(s),
        radius: radius_m as f32,
        frame: MavFrame::MAV_FRAME_GLOBAL,
        x: (lat * 1e7).round() as i32,
        y: (lon * 1e7).round() as i32,
        z: alt as f32,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    fn orbit(p: [f32; 7]) -> CommandDecision {
        let cmd = COMMAND_LONG_DATA {
            param1: p[0],
            param2: p[1],
            param3: p[2],
            param4: p[3],
            param5: p[4],
            param6: p[5],
            param7: p[6],
            ..Default::default()
        };
        let centre = |x: f32| (!x.is_nan()).then_some(f64::from(x));
        decode_orbit(&cmd, centre(p[4]).zip(centre(p[5])), &Home::default())
    }

    #[test]
    fn do_orbit_decodes_as_px4_reads_it_and_refuses_what_is_not_a_place() {
        let home = Home::default();
        let nan = f32::NAN;
        let CommandDecision::Execute(Request::Orbit(r)) =
            orbit([-15.0, 2.0, 3.0, nan, home.lat_deg as f32, home.lon_deg as f32, 498.0])
        else {
            panic!()
        };
        assert_eq!(
            (r.radius_m, r.speed_m_s, r.yaw),
            (Some(-15.0), Some(2.0), Some(OrbitYaw::FrontTangent))
        );
        let (n, e) = r.centre_ne_m.unwrap_or_default();
        assert!(n.abs() < 0.5 && e.abs() < 0.5, "home, to f32 precision: {n} {e}");
        assert!((r.centre_down_m.unwrap_or_default() - (home.alt_amsl_m - 498.0)).abs() < 1e-3);
        let CommandDecision::Execute(Request::Orbit(r)) = orbit([nan; 7]) else {
            panic!()
        };
        assert_eq!(r, OrbitRequest::default(), "NaN keeps everything");
        // p4 (three turns) is ignored as PX4 ignores it; yaw behaviour 5 keeps the running one.
        let CommandDecision::Execute(Request::Orbit(r)) = orbit([nan, nan, 5.0, 3.0, nan, nan, nan]) else {
            panic!()
        };
        assert_eq!(r, OrbitRequest::default(), "UNCHANGED yaw, no turn count");
        let CommandDecision::Execute(Request::Orbit(r)) = orbit([nan, nan, 4.0, 1.0, nan, nan, nan]) else {
            panic!()
        };
        assert_eq!(r.yaw, Some(OrbitYaw::RcControlled));
        assert!(matches!(
            orbit([10.0, 1.0, 7.0, nan, nan, nan, nan]),
            CommandDecision::Refuse(_)
        ));
        assert!(matches!(
            orbit([10.0, 1.0, 0.0, nan, 95.0, 8.0, nan]),
            CommandDecision::Refuse(_)
        ));
    }

    #[test]
    fn the_status_names_the_centre_in_global_coordinates() {
        let home = Home::default();
        let mut s = Snapshot::initial(home);
        assert_eq!(orbit_execution_status(&s), None);
        s.orbit = Some((Vec3::new(0.0, 0.0, -10.0), -20.0));
        let Some(MavMessage::ORBIT_EXECUTION_STATUS(m)) = orbit_execution_status(&s) else {
            panic!()
        };
        assert_eq!(m.radius, -20.0);
        assert_eq!(m.x, (home.lat_deg * 1e7).round() as i32);
        assert!((f64::from(m.z) - (home.alt_amsl_m + 10.0)).abs() < 1e-3);
    }
}
