//! The estimator's input read from a ULog flight log (`rotorpilot estimate --log FILE.ulg`): the
//! samples of every tick that has the world velocity (`vehicle_local_position` vx, vy, vz), the
//! attitude (`vehicle_attitude` q), the body rates (`vehicle_angular_velocity` xyz) and, while
//! the motors run, the applied wrench (`allocation_status` thrust, torque; none logged means
//! the motors are off: no wrench). The Euler angles come from q and their rates from
//! η̇ = Q(η)⁻¹ ω_b. A full-profile log (`sim`, `fly --log`, `run --log-profile full`) has them
//! at every tick; `run`'s default profile every 20 ms (`--ts 0.02`). Pure: bytes in, samples
//! out; the parsing is px4-ulog's.

use std::collections::BTreeMap;

use px4_ulog::stream_parser::{DataMessage, LogParser};

use super::log_replay::{check_sample, euler_rates, LogError, LogSample};
use crate::math::{euler_zyx, UnitQuat, Vec3};

/// What one tick's records hold.
#[derive(Debug, Clone, Copy, Default)]
struct TickRecords {
    vel_w: Option<Vec3>,
    q_wb: Option<[f64; 4]>,
    omega_b: Option<Vec3>,
    wrench: Option<(f64, Vec3)>,
}

/// The `float` fields `names` of `msg`; the first missing one is named in the error.
fn floats<const N: usize>(msg: &DataMessage, names: [&str; N]) -> Result<[f64; N], String> {
    let mut out = [0.0; N];
    for (slot, name) in out.iter_mut().zip(names) {
        let parser = msg
            .flattened_format
            .get_field_parser::<f32>(name)
            .map_err(|e| format!("{}.{name}: {e:?}", msg.flattened_format.message_name()))?;
        *slot = f64::from(parser.parse(msg.data));
    }
    Ok(out)
}

/// Files the record `msg` under its timestamp.
fn file(ticks: &mut BTreeMap<u64, TickRecords>, msg: &DataMessage) -> Result<(), String> {
    let name = msg.flattened_format.message_name();
    if msg.multi_id.value() != 0 {
        return Ok(());
    }
    let stamp = || -> Result<u64, String> {
        let p = msg
            .flattened_format
            .get_field_parser::<u64>("timestamp")
            .map_err(|e| format!("{name}.timestamp: {e:?}"))?;
        Ok(p.parse(msg.data))
    };
    let v3 = |v: [f64; 3]| Vec3::new(v[0], v[1], v[2]);
    match name {
        "vehicle_local_position" => {
            ticks.entry(stamp()?).or_default().vel_w = Some(v3(floats(msg, ["vx", "vy", "vz"])?))
        }
        "vehicle_attitude" => {
            ticks.entry(stamp()?).or_default().q_wb = Some(floats(msg, ["q[0]", "q[1]", "q[2]", "q[3]"])?)
        }
        "vehicle_angular_velocity" => {
            ticks.entry(stamp()?).or_default().omega_b = Some(v3(floats(msg, ["xyz[0]", "xyz[1]", "xyz[2]"])?))
        }
        "allocation_status" => {
            let [f, x, y, z] = floats(msg, ["thrust", "torque[0]", "torque[1]", "torque[2]"])?;
            ticks.entry(stamp()?).or_default().wrench = Some((f, Vec3::new(x, y, z)));
        }
        _ => {}
    }
    Ok(())
}

/// The samples of the ULog file `bytes` (from `origin`), checking that they follow each other at
/// `ts_s` [s].
pub fn parse_ulog(bytes: &[u8], origin: &str, ts_s: f64) -> Result<Vec<LogSample>, LogError> {
    let err = |column: Option<&str>, reason: String| LogError {
        origin: origin.to_string(),
        line: 0,
        column: column.map(str::to_string),
        reason,
    };
    let mut ticks = BTreeMap::new();
    let mut first_error: Option<String> = None;
    let mut on_data = |msg: &DataMessage| {
        if first_error.is_none() {
            first_error = file(&mut ticks, msg).err();
        }
    };
    let mut parser = LogParser::default();
    parser.set_data_message_callback(&mut on_data);
    parser
        .consume_bytes(bytes)
        .map_err(|e| err(None, format!("not a ULog file it can read: {e:?}")))?;
    drop(parser);
    if let Some(why) = first_error {
        return Err(err(None, why));
    }
    let mut samples: Vec<LogSample> = Vec::new();
    for (t_us, rec) in ticks {
        let (Some(vel_w), Some(q), Some(omega_b)) = (rec.vel_w, rec.q_wb, rec.omega_b) else {
            continue;
        };
        let t_s = t_us as f64 * 1e-6;
        let r_wb = UnitQuat::from_quaternion(nalgebra::Quaternion::new(q[0], q[1], q[2], q[3])).to_rotation_matrix();
        let eta = euler_zyx(r_wb.matrix());
        let place = format!("t = {t_s} s");
        let eta_dot = euler_rates(&eta, &omega_b)
            .ok_or_else(|| err(Some(&place), format!("pitch {} rad: Euler rates undefined", eta.y)))?;
        let (thrust_n, torque_b) = rec.wrench.unwrap_or((0.0, Vec3::zeros()));
        let sample = LogSample {
            t_s,
            thrust_n,
            torque_b,
            vel_w,
            eta,
            eta_dot,
        };
        check_sample(samples.last(), &sample, ts_s).map_err(|(_, why)| {
            err(
                Some(&place),
                format!(
                    "{why}: the estimator needs every sample at --ts (every tick of a full-profile log \
                     at --ts 0.001: sim, fly --log, run --log-profile full; a run --log default-profile \
                     log at --ts 0.02)"
                ),
            )
        })?;
        samples.push(sample);
    }
    if samples.is_empty() {
        return Err(err(
            None,
            "no tick has vehicle_local_position, vehicle_attitude and vehicle_angular_velocity together".into(),
        ));
    }
    Ok(samples)
}
