//! A flight log as ULog bytes: the definitions when a log begins (formats, info, every parameter),
//! then per tick the records its [`Profile`] says are due, logged strings for the commander's
//! announcements, parameter changes and a synchronisation message every second. Pure: values in
//! (a [`TickView`], times in µs), bytes appended to the caller's buffer; which file they go to is
//! the runtime's business.
//!
//! Timestamps are µs since boot on the simulated clock (the clock of the telemetry's
//! `time_boot_ms`), so a ULog and a tlog of one flight line up.

use nalgebra::Rotation3;

use super::encoder::{Encoder, Fields, ParamValue};
use super::profile::Profile;
use super::topics::{Topic, ACTUATOR_MOTORS};
use crate::airframe::Airframe;
use crate::allocation::effectiveness_matrix;
use crate::commander::LandedState;
use crate::control::ControllerKind;
use crate::lockstep::TickView;
use crate::math::{Mat3, UnitQuat, Vec3, GRAVITY_M_S2};

/// Log time between two synchronisation messages [µs].
const SYNC_PERIOD_US: u64 = 1_000_000;

/// What the records are scaled by, and the masses the truth topic compares.
#[derive(Debug, Clone, PartialEq)]
pub struct RecorderSetup {
    /// Rates of the topics.
    pub profile: Profile,
    /// Rotor count.
    pub rotors: usize,
    /// Highest rotor speed [rad/s] (`actuator_motors` is the commanded speed over it).
    pub omega_max_rad_s: f64,
    /// Collective thrust at full speed [N] (`vehicle_thrust_setpoint` is over it).
    pub thrust_max_n: f64,
    /// Largest torque per body axis, FRD [N·m] (`vehicle_torque_setpoint` is over it).
    pub torque_max_b: Vec3,
    /// Mass the controller believes, m_e [kg].
    pub believed_mass_kg: f64,
    /// True mass of the plant, m_r [kg].
    pub true_mass_kg: f64,
    /// Tick step [s] (the sensors' integration interval).
    pub dt_s: f64,
}

impl RecorderSetup {
    /// The setup for airframe `af` (the controller's view: believed mass, rotor limits and
    /// geometry) on a plant of true mass `true_mass_kg` [kg], ticking every `dt_s` [s]. The
    /// thrust and per-axis torque authorities are Σ max(G_ij, 0) ω_max² over the rows of G_q.
    pub fn new(af: &Airframe, true_mass_kg: f64, profile: Profile, dt_s: f64) -> Self {
        let g = effectiveness_matrix(af);
        let w2 = af.omega_max_rad_s * af.omega_max_rad_s;
        let authority = |row: usize| g.row(row).iter().map(|v| v.max(0.0)).sum::<f64>() * w2;
        let positive = |v: f64| if v > 0.0 { v } else { 1.0 };
        Self {
            profile,
            rotors: af.rotors.len(),
            omega_max_rad_s: af.omega_max_rad_s,
            thrust_max_n: positive(authority(0)),
            torque_max_b: Vec3::new(positive(authority(1)), positive(authority(2)), positive(authority(3))),
            believed_mass_kg: af.mass_kg,
            true_mass_kg,
            dt_s,
        }
    }
}

/// Text the log's info messages carry.
#[derive(Debug, Clone, PartialEq)]
pub struct LogInfo {
    /// Software version.
    pub version: String,
    /// Airframe name.
    pub airframe: String,
    /// Control law.
    pub controller: String,
    /// UTC time of the log's start [s since the Unix epoch], when known (`run`).
    pub utc_s: Option<u64>,
}

impl LogInfo {
    /// The info of a flight of airframe `airframe` flown by `law`, started at `utc_s`.
    pub fn new(airframe: &str, law: ControllerKind, utc_s: Option<u64>) -> Self {
        Self {
            version: env!("CARGO_PKG_VERSION").to_string(),
            airframe: airframe.to_string(),
            controller: law.name().to_string(),
            utc_s,
        }
    }
}

/// Writes one flight log's records.
#[derive(Debug, Clone)]
pub struct Recorder {
    setup: RecorderSetup,
    /// Log time each topic is next due [µs].
    next_due_us: [u64; Topic::ALL.len()],
    /// Log time each on-change topic is next looked at for a change [µs].
    next_check_us: [u64; Topic::ALL.len()],
    /// Topics whose subscription has been written.
    subscribed: [bool; Topic::ALL.len()],
    /// Last payload (timestamp excluded) of the topics logged on change.
    last: [Vec<u8>; Topic::ALL.len()],
    next_sync_us: u64,
    scratch: Vec<u8>,
}

/// `t_s` [s] as µs.
pub fn micros(t_s: f64) -> u64 {
    (t_s * 1e6).round().max(0.0) as u64
}

/// The quaternion (w, x, y, z) of rotation matrix `r`.
fn quat(r: &Mat3) -> [f64; 4] {
    let q = UnitQuat::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*r));
    [q.w, q.i, q.j, q.k]
}

/// The first multiple of `every` [µs] after `t_us` (`t_us` itself when `every` is 0: every tick).
fn grid_after(t_us: u64, every: u64) -> u64 {
    t_us.checked_div(every).map_or(t_us, |k| (k + 1) * every)
}

/// False when the tick has nothing for `topic`: no snapshot (a bare flight core), the motors
/// off, no setpoint, no estimator.
/// A `vehicle_attitude` record: the quaternion (w, x, y, z).
fn quat_record(b: &mut Vec<u8>, q: [f64; 4]) {
    b.f32(q[0]).f32(q[1]).f32(q[2]).f32(q[3]);
}

/// A `vehicle_local_position` record: position [m], velocity [m/s], acceleration [m/s²]
/// (world NED), heading of `r_wb` [rad] and the validity flags.
fn local_position_record(b: &mut Vec<u8>, pos_w: &Vec3, vel_w: &Vec3, acc_w: &Vec3, r_wb: &Mat3) {
    b.f32x3((*pos_w).into()).f32x3((*vel_w).into()).f32x3((*acc_w).into());
    b.f32(r_wb[(1, 0)].atan2(r_wb[(0, 0)]));
    b.extend_from_slice(&[1, 1, 1, 1]);
}

fn has_data(topic: Topic, v: &TickView) -> bool {
    match topic {
        Topic::VehicleGlobalPosition | Topic::VehicleStatus | Topic::VehicleLandDetected | Topic::BatteryStatus => {
            v.snapshot.is_some()
        }
        Topic::VehicleAttitudeSetpoint | Topic::ControllerErrors | Topic::AllocationStatus => v.step.is_some(),
        Topic::VehicleLocalPositionSetpoint => v.setpoint.is_some(),
        Topic::ExternalWrenchEstimate => v.step.is_some_and(|s| s.estimate.is_some()),
        _ => true,
    }
}

impl Recorder {
    /// A recorder with `setup`; nothing is written before [`Self::begin`].
    pub fn new(setup: RecorderSetup) -> Self {
        Self {
            setup,
            next_due_us: [0; Topic::ALL.len()],
            next_check_us: [0; Topic::ALL.len()],
            subscribed: [false; Topic::ALL.len()],
            last: Default::default(),
            next_sync_us: 0,
            scratch: Vec::with_capacity(128),
        }
    }

    /// Starts a log at `t_us` [µs]: file header, flag bits, every topic's format, `info` and
    /// every parameter of `params`.
    pub fn begin(&mut self, out: &mut Vec<u8>, t_us: u64, info: &LogInfo, params: &[(String, ParamValue)]) {
        *self = Self::new(self.setup.clone());
        self.next_sync_us = t_us + SYNC_PERIOD_US;
        // Every topic on its rate's grid of log time, so topics of one rate share timestamps.
        for topic in Topic::ALL {
            let every = self.setup.profile.interval_us(topic);
            self.next_due_us[topic as usize] = if every == 0 { t_us } else { t_us.div_ceil(every) * every };
        }
        let mut e = Encoder::new(out);
        e.file_header(t_us);
        e.flag_bits();
        for topic in Topic::ALL {
            e.format(topic.name(), topic.fields());
        }
        e.info_text("sys_name", "rotorpilot");
        e.info_text("ver_sw", &info.version);
        e.info_text("ver_hw", "SITL");
        e.info_text("sys_os_name", std::env::consts::OS);
        e.info_text("sys_airframe", &info.airframe);
        e.info_text("sys_controller", &info.controller);
        e.info_text("log_profile", self.setup.profile.name());
        if let Some(utc) = info.utc_s {
            e.info_i32("time_ref_utc", 0);
            e.info_u32("time_start_utc", utc.min(u64::from(u32::MAX)) as u32);
        }
        for (name, value) in params {
            e.param(name, *value);
        }
    }

    /// Writes every topic's subscription again before its next record (after bytes were lost).
    pub fn forget_subscriptions(&mut self) {
        self.subscribed = [false; Topic::ALL.len()];
    }

    /// A parameter change, written in the data section (where PX4 logs changes) between the
    /// records of the ticks around it.
    pub fn param_changed(&mut self, out: &mut Vec<u8>, name: &str, value: ParamValue) {
        Encoder::new(out).param(name, value);
    }

    /// The records of one tick that are due.
    pub fn record(&mut self, out: &mut Vec<u8>, v: &TickView) {
        let t_us = micros(v.t_s);
        if t_us >= self.next_sync_us {
            self.next_sync_us = t_us + SYNC_PERIOD_US;
            Encoder::new(out).sync();
        }
        for event in v.events {
            Encoder::new(out).logged_string(event.severity(), t_us, &event.describe());
        }
        for topic in Topic::ALL {
            let i = topic as usize;
            let due = t_us >= self.next_due_us[i];
            let on_change = Profile::on_change(topic);
            if !due && !on_change {
                continue;
            }
            if on_change {
                if !due && t_us < self.next_check_us[i] {
                    continue;
                }
                let every = self.setup.profile.change_interval_us(topic);
                self.next_check_us[i] = grid_after(t_us, every);
                // Compare the fields with the last record's before writing.
                let mut fields = std::mem::take(&mut self.scratch);
                fields.clear();
                let filled = has_data(topic, v) && self.fill(topic, v, &mut fields);
                if filled && (due || self.last[i] != fields) {
                    self.last[i].clone_from(&fields);
                    self.start_record(out, topic, t_us);
                    out.extend_from_slice(&fields);
                }
                self.scratch = fields;
                continue;
            }
            if has_data(topic, v) {
                self.start_record(out, topic, t_us);
                self.fill(topic, v, out);
            }
        }
    }

    /// Subscribes `topic` on its first record, writes the data header and the timestamp, and
    /// schedules the next record.
    fn start_record(&mut self, out: &mut Vec<u8>, topic: Topic, t_us: u64) {
        let i = topic as usize;
        let interval = self.setup.profile.interval_us(topic);
        self.next_due_us[i] = grid_after(t_us, interval);
        if !self.subscribed[i] {
            self.subscribed[i] = true;
            Encoder::new(out).subscription(topic.msg_id(), topic.name());
        }
        Encoder::new(out).data(topic.msg_id(), topic.size()).u64(t_us);
    }

    /// Appends the fields of `topic` after the timestamp to `b`; false when the tick has
    /// nothing for it (no snapshot, motors off, no estimator).
    fn fill(&self, topic: Topic, v: &TickView, b: &mut Vec<u8>) -> bool {
        let s = &self.setup;
        let x = v.state;
        let nan3 = [f64::NAN; 3];
        match topic {
            Topic::VehicleAttitude => quat_record(b, quat(&x.r_wb)),
            Topic::VehicleAngularVelocity => {
                b.f32x3(x.omega_b.into());
            }
            Topic::VehicleLocalPosition => {
                let a_w = x.r_wb * v.accel_b + Vec3::new(0.0, 0.0, GRAVITY_M_S2);
                local_position_record(b, &x.pos_w, &x.vel_w, &a_w, &x.r_wb);
            }
            Topic::VehicleAttitudeGroundtruth => {
                let q = v.truth.q_wb;
                quat_record(b, [q.w, q.i, q.j, q.k]);
            }
            Topic::VehicleAngularVelocityGroundtruth => {
                b.f32x3(v.truth.omega_b.into());
            }
            Topic::VehicleLocalPositionGroundtruth => {
                let t = &v.truth;
                let r_wb = t.q_wb.to_rotation_matrix();
                local_position_record(b, &t.pos_w, &t.vel_w, &t.accel_w, r_wb.matrix());
            }
            Topic::VehicleGlobalPosition => {
                let Some(snap) = v.snapshot else { return false };
                let (lat, lon, alt) = snap.home.to_global(&x.pos_w);
                b.f64(lat).f64(lon).f32(alt);
            }
            Topic::VehicleAttitudeSetpoint => {
                let Some(step) = v.step else { return false };
                let q = quat(&step.control.r_wb_desired);
                let thrust = step.control.wrench.thrust_n / s.thrust_max_n;
                b.f32(q[0]).f32(q[1]).f32(q[2]).f32(q[3]).f32x3([0.0, 0.0, -thrust]);
            }
            Topic::VehicleLocalPositionSetpoint => {
                let Some(sp) = v.setpoint else { return false };
                let or_nan = |o: Option<Vec3>| o.map_or(nan3, Into::into);
                b.f32x3(or_nan(sp.pos_w))
                    .f32x3(or_nan(sp.vel_w))
                    .f32x3(or_nan(sp.acc_w));
                b.f32(sp.yaw_rad.unwrap_or(f64::NAN));
            }
            Topic::VehicleStatus => {
                let Some(snap) = v.snapshot else { return false };
                let arming_state = if snap.armed { 2 } else { 1 };
                // A mode without a known PX4 number (AUTO.READY, GOTO) is logged as AUTO_LOITER (4).
                b.u8(arming_state).u8(snap.mode.nav_state().unwrap_or(4)).u8(2);
                b.bool(snap.geofence_breached);
            }
            Topic::VehicleLandDetected => {
                let Some(snap) = v.snapshot else { return false };
                let landed = snap.landed == LandedState::OnGround;
                b.bool(false).bool(landed).bool(landed).bool(landed);
            }
            Topic::ActuatorMotors => {
                let omega = v.step.map(|st| st.allocation.omega());
                for i in 0..ACTUATOR_MOTORS {
                    let c = match &omega {
                        _ if i >= s.rotors => f64::NAN,
                        Some(w) => w.as_slice().get(i).map_or(f64::NAN, |w| w / s.omega_max_rad_s),
                        None => 0.0,
                    };
                    b.f32(c);
                }
            }
            Topic::VehicleThrustSetpoint => {
                let thrust = v.step.map_or(0.0, |st| st.control.wrench.thrust_n);
                b.f32x3([0.0, 0.0, -thrust / s.thrust_max_n]);
            }
            Topic::VehicleTorqueSetpoint => {
                let t = v.step.map_or(Vec3::zeros(), |st| st.control.wrench.torque_b);
                b.f32x3(t.component_div(&s.torque_max_b).into());
            }
            Topic::BatteryStatus => {
                let Some(snap) = v.snapshot else { return false };
                let bat = &snap.battery;
                b.f32(bat.cell_v * f64::from(bat.cells))
                    .f32(bat.current_a)
                    .f32(bat.consumed_mah);
                b.f32(bat.fraction).u8(bat.cells.min(255) as u8).bool(true);
            }
            Topic::SensorCombined => {
                let dt_us = (s.dt_s * 1e6).round() as u32;
                b.f32x3(x.omega_b.into())
                    .u32(dt_us)
                    .i32(0)
                    .f32x3(v.accel_b.into())
                    .u32(dt_us);
            }
            Topic::ExternalWrenchEstimate => {
                let Some(e) = v.step.and_then(|st| st.estimate) else {
                    return false;
                };
                b.f32x3(e.force_w.into()).f32x3(e.torque_b.into()).f32(e.mass_kg);
            }
            Topic::ExternalWrenchTruth => {
                let mismatch = (s.true_mass_kg - s.believed_mass_kg) * GRAVITY_M_S2;
                let t = &v.truth;
                b.f32x3(t.external_and_drag_force_w().into())
                    .f32x3(t.external_torque_b.into());
                b.f32(s.true_mass_kg).f32(mismatch);
                b.f32x3(t.wind_w.into()).f32x3(t.drag_force_w.into());
            }
            Topic::ControllerErrors => {
                let Some(step) = v.step else { return false };
                let e = &step.control.errors;
                b.f32x3(e.pos_w.into())
                    .f32x3(e.vel_w.into())
                    .f32x3(e.attitude.into())
                    .f32x3(e.rate.into());
            }
            Topic::AllocationStatus => {
                let Some(step) = v.step else { return false };
                let a = &step.allocation;
                b.f32(a.applied.thrust_n).f32x3(a.applied.torque_b.into());
                b.bool(a.saturation.is_saturated());
            }
        }
        true
    }
}

#[cfg(test)]
#[path = "recorder_tests.rs"]
mod tests;
