//! The simulated vehicle: rigid body + rotors + ground/ceiling effect + contact + disturbances.

use nalgebra::{UnitQuaternion, Vector3};
use rand_chacha::ChaCha8Rng;

use crate::contact::Contact;
use crate::disturbance::{drag_w, external_wrench};
use crate::params::PlantParams;
use crate::rigid_body::{MassProperties, RigidBodyState, StageLoads};
use crate::rotor::{rotor_wrench_b, MotorBank};
use crate::sensors::SensorSample;
use crate::wind::{WindField, WindSettings};

/// Longest step the plant accepts [s]; longer ones are refused rather than integrated badly.
pub const MAX_DT_S: f64 = 0.1;

/// What happened in one [`Plant::step`]; the plant never panics, it reports.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct StepStatus {
    /// `dt` was not finite or outside (0, [`MAX_DT_S`]]: nothing was integrated.
    pub dt_rejected: bool,
    /// Some rotor command was missing, extra or not finite; a missing or non-finite one was
    /// taken as "motor off".
    pub command_rejected: bool,
    /// Integration produced a non-finite state; the previous state was kept.
    pub state_non_finite: bool,
    /// The vehicle rests on the ground after the step.
    pub on_ground: bool,
    /// A rotor touches the ceiling after the step.
    pub at_ceiling: bool,
}

/// Everything the simulator knows exactly, for logging and tests (never for the controller).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TruthState {
    /// Simulated time [s].
    pub t_s: f64,
    /// Rigid-body state.
    pub body: RigidBodyState,
    /// Acceleration in world NED over the last step [m/s²].
    pub accel_w: Vector3<f64>,
    /// Mean body rate over the last step, body FRD [rad/s]: the rotation from the previous
    /// attitude to the current one over the step length (docs/model.md §10.2, eq. (10.3)), what a
    /// rate-integrating gyroscope measures; it includes the levelling of a landing, which the
    /// body rate `body.omega_b` (zeroed by the contact) does not.
    pub mean_omega_b: Vector3<f64>,
    /// Resting on the ground.
    pub on_ground: bool,
    /// Touching the ceiling.
    pub at_ceiling: bool,
    /// Scripted external force at the start of the last step, world NED [N].
    pub external_force_w: Vector3<f64>,
    /// Scripted external torque at the start of the last step, body FRD [N·m].
    pub external_torque_b: Vector3<f64>,
    /// The air's velocity at the vehicle over the last step, world NED [m/s].
    pub wind_w: Vector3<f64>,
    /// Aerodynamic drag at the start of the last step, wind included, world NED [N]
    /// (docs/model.md §5.1, eq. (5.2)).
    pub drag_force_w: Vector3<f64>,
}

/// The simulated multirotor. Deterministic: same parameters, commands and seed give
/// bit-identical trajectories.
///
/// ```
/// use firmware_sim::{Plant, PlantParams, DEFAULT_DT_S};
/// let params = PlantParams::from_toml_str(include_str!("../../airframes/octo.toml"), "octo").unwrap();
/// let hover = params.hover_speed_rad_s();
/// let mut plant = Plant::new(params);
/// for _ in 0..2000 {
///     plant.step(&[1.05 * hover; 8], DEFAULT_DT_S);
/// }
/// assert!(plant.truth().body.pos_w.z < -0.1, "climbed off the ground");
/// ```
#[derive(Debug, Clone)]
pub struct Plant {
    params: PlantParams,
    mass: MassProperties,
    contact: Contact,
    body: RigidBodyState,
    motors: MotorBank,
    command: Vec<f64>,
    factor: Vec<f64>,
    elapsed_ns: u64,
    accel_w: Vector3<f64>,
    mean_omega_b: Vector3<f64>,
    on_ground: bool,
    at_ceiling: bool,
    external_force_w: Vector3<f64>,
    external_torque_b: Vector3<f64>,
    wind: WindField,
    drag_force_w: Vector3<f64>,
    /// Ground and ceiling effect switched on (contact is always on).
    proximity_enabled: (bool, bool),
    /// Rotors that have failed: commanded zero whatever the controller asks (they spin down
    /// with the motor lag).
    failed: Vec<bool>,
}

impl Plant {
    /// A plant at its initial pose, motors stopped; on the ground unless the file says otherwise.
    pub fn new(params: PlantParams) -> Self {
        let n = params.rotors.len();
        let contact = Contact {
            ground_z_m: params.ground.plane_z_m,
            gear_height_m: params.gear_height_m,
            ceiling_z_m: params.ceiling.as_ref().map(|c| c.plane_z_m),
        };
        let pos_w = params
            .initial
            .pos_w
            .unwrap_or(Vector3::new(0.0, 0.0, contact.resting_z_m()));
        let body = RigidBodyState {
            pos_w,
            vel_w: Vector3::zeros(),
            q_wb: UnitQuaternion::from_euler_angles(0.0, 0.0, params.initial.yaw_rad),
            omega_b: Vector3::zeros(),
        };
        let on_ground = pos_w.z >= contact.resting_z_m();
        let wind = params.wind.clone();
        Self {
            mass: MassProperties {
                mass_kg: params.mass_kg,
                inertia_kg_m2: params.inertia_kg_m2,
            },
            motors: MotorBank::new(n, &params.rotor),
            command: vec![0.0; n],
            factor: vec![1.0; n],
            contact,
            body,
            params,
            elapsed_ns: 0,
            accel_w: Vector3::zeros(),
            mean_omega_b: Vector3::zeros(),
            on_ground,
            at_ceiling: false,
            external_force_w: Vector3::zeros(),
            external_torque_b: Vector3::zeros(),
            wind: WindField::new(wind, 0),
            drag_force_w: Vector3::zeros(),
            proximity_enabled: (true, true),
            failed: vec![false; n],
        }
    }

    /// The parameters the plant was built from.
    pub fn params(&self) -> &PlantParams {
        &self.params
    }

    /// Places the body in a given state (test and scenario set-up).
    pub fn set_body_state(&mut self, body: RigidBodyState) {
        self.body = body;
        self.on_ground = false;
    }

    /// Sets motor speeds directly, clamped to the motor limits [rad/s] (test and scenario set-up).
    pub fn set_motor_speeds(&mut self, omega_rad_s: &[f64]) {
        self.clamp_commands(omega_rad_s);
        self.motors.set(&self.command);
    }

    /// Current motor speeds [rad/s].
    pub fn motor_speeds(&self) -> &[f64] {
        self.motors.speeds()
    }

    /// Ground × ceiling thrust factor of each rotor used in the last step [-].
    pub fn proximity_factors(&self) -> &[f64] {
        &self.factor
    }

    /// Exact state.
    pub fn truth(&self) -> TruthState {
        TruthState {
            t_s: self.time_s(),
            body: self.body,
            accel_w: self.accel_w,
            mean_omega_b: self.mean_omega_b,
            on_ground: self.on_ground,
            at_ceiling: self.at_ceiling,
            external_force_w: self.external_force_w,
            external_torque_b: self.external_torque_b,
            wind_w: self.wind.velocity_w(),
            drag_force_w: self.drag_force_w,
        }
    }

    /// Restarts the wind's turbulence from `seed` (the run's seed: same seed, same gusts).
    pub fn seed_wind(&mut self, seed: u64) {
        self.wind = WindField::new(self.wind.settings().clone(), seed);
    }

    /// Replaces the wind settings from now on (parameters set in flight); the turbulence
    /// keeps its random stream.
    pub fn set_wind(&mut self, settings: WindSettings) {
        self.wind.set_settings(settings);
    }

    /// The wind settings in force.
    pub fn wind(&self) -> &WindSettings {
        self.wind.settings()
    }

    /// Simulated time [s], counted in whole nanoseconds so it never drifts.
    pub fn time_s(&self) -> f64 {
        self.elapsed_ns as f64 * 1e-9
    }

    /// A sensor sample of the current state with the configured noise drawn from `rng`.
    pub fn sense(&self, rng: &mut ChaCha8Rng) -> SensorSample {
        self.params.noise.sample(self.time_s(), &self.body, self.accel_w, rng)
    }

    /// Advances by `dt_s` [s] with commanded rotor speeds `omega_cmd_rad_s` [rad/s] held for the
    /// whole step (zero-order hold). Motor lag, ground/ceiling factors (evaluated at the start of
    /// the step), disturbances and drag enter the RK4 stages; contact is applied after.
    pub fn step(&mut self, omega_cmd_rad_s: &[f64], dt_s: f64) -> StepStatus {
        let mut status = StepStatus {
            on_ground: self.on_ground,
            at_ceiling: self.at_ceiling,
            ..Default::default()
        };
        if !(dt_s.is_finite() && dt_s > 0.0 && dt_s <= MAX_DT_S) {
            status.dt_rejected = true;
            return status;
        }
        status.command_rejected = self.clamp_commands(omega_cmd_rad_s);
        let rc = self.params.rotor;
        self.motors.plan(&self.command, &rc, dt_s);
        self.update_proximity_factors();

        let t0 = self.time_s();
        let (force0, torque0) = external_wrench(&self.params.disturbances, t0);
        self.external_force_w = force0;
        self.external_torque_b = torque0;
        let height_m = self.contact.ground_z_m - self.body.pos_w.z;
        let wind_w = self.wind.advance(t0, dt_s, height_m, &self.body.vel_w);
        let params = &self.params;
        let drag = |r_wb: &nalgebra::Matrix3<f64>, v_w: &Vector3<f64>| {
            drag_w(
                &params.linear_drag_n_s_m,
                &params.quadratic_drag_n_s2_m2,
                r_wb,
                &(v_w - wind_w),
            )
        };
        self.drag_force_w = drag(self.body.q_wb.to_rotation_matrix().matrix(), &self.body.vel_w);
        let motors = &self.motors;
        let factor = &self.factor;
        let loads = |stage: usize, s: &RigidBodyState| {
            let (speeds, t) = match stage {
                0 => (motors.speeds(), t0),
                1 | 2 => (motors.at_half(), t0 + 0.5 * dt_s),
                _ => (motors.at_end(), t0 + dt_s),
            };
            let (thrust_b, rotor_torque_b) = rotor_wrench_b(&params.rotors, &rc, speeds, factor);
            let (ext_f_w, ext_t_b) = if params.disturbances.is_empty() {
                (Vector3::zeros(), Vector3::zeros())
            } else {
                external_wrench(&params.disturbances, t)
            };
            let r_wb = s.q_wb.to_rotation_matrix().into_inner();
            let drag_w = drag(&r_wb, &s.vel_w);
            StageLoads {
                force_w: r_wb * thrust_b + ext_f_w + drag_w,
                torque_b: rotor_torque_b + ext_t_b,
            }
        };
        let mut next = self.mass.rk4_step(&self.body, dt_s, loads);
        self.motors.commit();
        self.elapsed_ns += (dt_s * 1e9).round() as u64;

        let finite = next
            .pos_w
            .iter()
            .chain(next.vel_w.iter())
            .chain(next.omega_b.iter())
            .all(|x| x.is_finite())
            && next.q_wb.coords.iter().all(|x| x.is_finite());
        if !finite {
            status.state_non_finite = true;
            return status;
        }
        self.on_ground = self.contact.resolve_ground(&mut next);
        let top_z = self.top_hub_z(&next);
        self.at_ceiling = self.contact.resolve_ceiling(&mut next, top_z);
        self.accel_w = (next.vel_w - self.body.vel_w) / dt_s;
        self.mean_omega_b = (self.body.q_wb.inverse() * next.q_wb).scaled_axis() / dt_s;
        self.body = next;
        status.on_ground = self.on_ground;
        status.at_ceiling = self.at_ceiling;
        status
    }

    /// Copies commands into the clamped buffer; returns true if any was missing, extra or bad.
    fn clamp_commands(&mut self, cmd: &[f64]) -> bool {
        let rc = &self.params.rotor;
        let mut rejected = cmd.len() != self.command.len();
        for (i, slot) in self.command.iter_mut().enumerate() {
            *slot = match cmd.get(i) {
                _ if self.failed[i] => 0.0,
                Some(w) if w.is_finite() => w.clamp(rc.omega_min_rad_s, rc.omega_max_rad_s),
                _ => {
                    rejected = true;
                    0.0
                }
            };
        }
        rejected
    }

    /// Fails (`true`) or repairs rotor `index` (0-based); false when there is no such rotor.
    pub fn set_rotor_failed(&mut self, index: usize, failed: bool) -> bool {
        match self.failed.get_mut(index) {
            Some(slot) => {
                *slot = failed;
                true
            }
            None => false,
        }
    }

    /// Which rotors have failed (the ESCs report it).
    pub fn failed_rotors(&self) -> &[bool] {
        &self.failed
    }

    /// Turns the aerodynamic ground and ceiling effects on or off (contact with the planes
    /// stays); an effect the airframe file does not configure stays off.
    pub fn set_proximity_effects(&mut self, ground: bool, ceiling: bool) {
        self.proximity_enabled = (ground, ceiling);
        if !ground && !ceiling {
            self.factor.iter_mut().for_each(|f| *f = 1.0);
        }
    }

    /// Thrust factor of each rotor from its hub's distance to ground and ceiling
    /// (docs/ground_ceiling.md §5.1–§5.2), held over the step.
    fn update_proximity_factors(&mut self) {
        let ground = &self.params.ground;
        let ceiling = self.params.ceiling.as_ref().filter(|_| self.proximity_enabled.1);
        let ground_effect = ground.effect.as_ref().filter(|_| self.proximity_enabled.0);
        if ground_effect.is_none() && ceiling.is_none() {
            self.factor.iter_mut().for_each(|f| *f = 1.0);
            return;
        }
        let r_wb = self.body.q_wb.to_rotation_matrix();
        for (k, rotor) in self.factor.iter_mut().zip(&self.params.rotors) {
            let hub_z = self.body.pos_w.z + (r_wb * rotor.hub_b).z;
            let mut f = 1.0;
            if let Some(effect) = ground_effect {
                f *= effect.factor(ground.plane_z_m - hub_z);
            }
            if let Some(c) = ceiling {
                f *= c.effect.factor(hub_z - c.plane_z_m);
            }
            *k = f;
        }
    }

    fn top_hub_z(&self, s: &RigidBodyState) -> f64 {
        let r_wb = s.q_wb.to_rotation_matrix();
        self.params
            .rotors
            .iter()
            .map(|r| s.pos_w.z + (r_wb * r.hub_b).z)
            .fold(f64::INFINITY, f64::min)
    }
}
