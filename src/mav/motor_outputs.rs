//! The flight controller's motor outputs as PX4 SITL reports them (SERVO_OUTPUT_RAW,
//! ACTUATOR_OUTPUT_STATUS): PWM in µs, 1000–2000 for a running motor, 900 (PX4's disarmed
//! value) for one the flight controller stops. Pure.

use mavlink::dialects::ardupilotmega::{MavMessage, ACTUATOR_OUTPUT_STATUS_DATA, SERVO_OUTPUT_RAW_DATA};

use crate::telemetry::Snapshot;

/// The output of a motor the flight controller stops [µs].
pub const STOPPED_US: f64 = 900.0;

/// PX4 SITL's PWM output of motor `i` (0-based) [µs]: [`STOPPED_US`] while the flight
/// controller stops it (motors off, failure injection, left out of the allocation), else
/// 1000–2000 for a commanded speed of 0 to ω_max (ω / ω_max).
pub fn motor_output_us(s: &Snapshot, i: usize) -> f64 {
    if i >= s.rotor_count || s.rotors_stopped & (1 << i.min(31)) != 0 {
        return STOPPED_US;
    }
    1000.0 + 1000.0 * (s.rotor_commands[i] / s.rotor_max_rad_s).clamp(0.0, 1.0)
}

/// SERVO_OUTPUT_RAW of `s` at `time_usec` [µs]: the motor outputs, 0 past the rotor count.
pub(super) fn servo_output_raw(s: &Snapshot, time_usec: u64) -> MavMessage {
    let pwm = |i: usize| -> u16 {
        if i >= s.rotor_count {
            return 0;
        }
        motor_output_us(s, i).round() as u16
    };
    MavMessage::SERVO_OUTPUT_RAW(SERVO_OUTPUT_RAW_DATA {
        time_usec: time_usec as u32,
        servo1_raw: pwm(0),
        servo2_raw: pwm(1),
        servo3_raw: pwm(2),
        servo4_raw: pwm(3),
        servo5_raw: pwm(4),
        servo6_raw: pwm(5),
        servo7_raw: pwm(6),
        servo8_raw: pwm(7),
        port: 0,
        servo9_raw: pwm(8),
        servo10_raw: pwm(9),
        servo11_raw: pwm(10),
        servo12_raw: pwm(11),
        servo13_raw: pwm(12),
        servo14_raw: pwm(13),
        servo15_raw: pwm(14),
        servo16_raw: pwm(15),
    })
}

/// ACTUATOR_OUTPUT_STATUS of `s` at `time_usec` [µs]: one output per rotor, `active` the count.
pub(super) fn actuator_output_status(s: &Snapshot, time_usec: u64) -> MavMessage {
    let mut actuator = [0.0_f32; 32];
    for (i, a) in actuator.iter_mut().enumerate().take(s.rotor_count) {
        *a = motor_output_us(s, i) as f32;
    }
    MavMessage::ACTUATOR_OUTPUT_STATUS(ACTUATOR_OUTPUT_STATUS_DATA {
        time_usec,
        active: s.rotor_count as u32,
        actuator,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::guidance::Home;

    #[test]
    fn motor_outputs_go_out_as_px4_sitl_pwm_stopped_motors_at_900() {
        let mut s = Snapshot {
            t_s: 12.345,
            rotor_count: 4,
            rotor_max_rad_s: 1100.0,
            ..Snapshot::initial(Home::default())
        };
        let outputs = |s: &Snapshot| {
            let MavMessage::ACTUATOR_OUTPUT_STATUS(a) = actuator_output_status(s, 12_345_000) else {
                panic!("wrong message");
            };
            let MavMessage::SERVO_OUTPUT_RAW(r) = servo_output_raw(s, 12_345_000) else {
                panic!("wrong message");
            };
            (a, r)
        };
        let (a, r) = outputs(&s);
        assert_eq!((a.active, a.time_usec), (4, 12_345_000));
        assert_eq!(&a.actuator[..5], &[900.0, 900.0, 900.0, 900.0, 0.0], "motors off");
        assert_eq!((r.servo1_raw, r.servo5_raw), (900, 0));
        s.rotor_commands[..4].copy_from_slice(&[550.0, 0.0, 570.0, 1100.0]);
        s.rotor_speeds[..4].copy_from_slice(&[1.0, 2.0, 3.0, 4.0]);
        s.rotors_stopped = 0b0100;
        let (a, r) = outputs(&s);
        assert_eq!(
            &a.actuator[..5],
            &[1500.0, 1000.0, 900.0, 2000.0, 0.0],
            "commands, not speeds"
        );
        let raw = (r.servo1_raw, r.servo2_raw, r.servo3_raw, r.servo4_raw, r.servo5_raw);
        assert_eq!(raw, (1500, 1000, 900, 2000, 0));
    }
}
