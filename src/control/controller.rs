//! One interface over the three laws: [`Controller::update`] takes the vehicle state, a
//! setpoint and optionally the estimator's wrench, and returns the body wrench (u_T, τ_b).
//!
//! It owns what every law shares: setpoint resolution, heading hold, compensation on/off, and
//! the fault rule: a non-finite input or output never reaches the motors; the controller
//! returns its last good output with `flags.non_finite` (or `rpy_singular`) set.

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::allocation::Wrench;
use crate::math::{Mat3, Vec3};
use crate::wrench_estimator::WrenchEstimate;

use super::attitude_target::AttitudeTarget;
use super::gains::{ControllerGains, VehicleModel};
use super::geometric::{DesiredRateMode, GeometricLaw};
use super::reference::{HeadingHold, LawInput};
use super::rpy_law::RpyLaw;
use super::{ControlFlags, ControlOutput, FlatSetpoint, TrackingErrors, VehicleState};

/// Which control law flies the vehicle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ControllerKind {
    /// Geometric tracking on SE(3) (docs/control.md §5).
    #[default]
    Geometric,
    /// Hierarchical RPY law with feedback linearisation (docs/control.md §4).
    Hierarchical,
    /// Passivity-based RPY law (docs/control.md §6).
    Passivity,
}

impl ControllerKind {
    /// Every law, in a fixed order.
    pub const ALL: [ControllerKind; 3] = [Self::Geometric, Self::Hierarchical, Self::Passivity];

    /// Lower-case name used in files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Geometric => "geometric",
            Self::Hierarchical => "hierarchical",
            Self::Passivity => "passivity",
        }
    }
}

impl std::str::FromStr for ControllerKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL.into_iter().find(|k| k.name() == s).ok_or_else(|| {
            let hint = crate::suggest::did_you_mean(s, Self::ALL.iter().map(|k| k.name()));
            format!("unknown controller {s:?}{hint}; expected geometric, hierarchical or passivity")
        })
    }
}

/// A controller that cannot be built.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ControllerError {
    /// A gain or limit is not acceptable.
    #[error("controller gains: {0}")]
    Gains(String),
    /// The vehicle model is not physical.
    #[error("controller vehicle model: mass, inertia and maximum thrust must be positive")]
    Model,
    /// The sample time is not a positive number.
    #[error("controller sample time {0} s must be a positive number")]
    SampleTime(f64),
}

/// What the controller reads each tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ControlInput<'a> {
    /// Vehicle state.
    pub state: &'a VehicleState,
    /// Setpoint.
    pub setpoint: &'a FlatSetpoint,
    /// Estimated external wrench; subtracted only when compensation is on.
    pub estimate: Option<WrenchEstimate>,
}

/// Flight controller: the active law, its gains and the shared guards.
#[derive(Debug, Clone, PartialEq)]
pub struct Controller {
    kind: ControllerKind,
    model: VehicleModel,
    gains: ControllerGains,
    compensate: bool,
    heading: HeadingHold,
    geometric: GeometricLaw,
    /// The hierarchical and the passivity-based law (only the active one runs).
    rpy: RpyLaw,
    last_good: Option<ControlOutput>,
}

impl Controller {
    /// Controller running `kind` for `model` at sample time `ts_s` [s].
    ///
    /// ```
    /// use rotorpilot::control::{ControlInput, Controller, ControllerGains, ControllerKind, FlatSetpoint, VehicleModel, VehicleState};
    /// use rotorpilot::math::{Mat3, Vec3};
    /// let model = VehicleModel { mass_kg: 1.5, inertia_kg_m2: Vec3::new(1.2416, 1.2416, 2.4832), thrust_max_n: 28.0 };
    /// let mut c = Controller::new(ControllerKind::Geometric, model, ControllerGains::default(), 1e-3).unwrap();
    /// let state = VehicleState { t_s: 0.0, pos_w: Vec3::zeros(), vel_w: Vec3::zeros(), r_wb: Mat3::identity(), omega_b: Vec3::zeros() };
    /// let out = c.update(&ControlInput { state: &state, setpoint: &FlatSetpoint::hold(Vec3::zeros(), 0.0), estimate: None });
    /// assert!((out.wrench.thrust_n - 1.5 * 9.81).abs() < 1e-12);
    /// ```
    pub fn new(
        kind: ControllerKind,
        model: VehicleModel,
        gains: ControllerGains,
        ts_s: f64,
    ) -> Result<Self, ControllerError> {
        gains.validate().map_err(ControllerError::Gains)?;
        let positive = |x: f64| x.is_finite() && x > 0.0;
        if !(positive(model.mass_kg)
            && model.inertia_kg_m2.iter().all(|i| positive(*i))
            && positive(model.thrust_max_n))
        {
            return Err(ControllerError::Model);
        }
        if !positive(ts_s) {
            return Err(ControllerError::SampleTime(ts_s));
        }
        let tau = gains.limits.derivative_tau_s;
        Ok(Self {
            kind,
            model,
            gains,
            compensate: false,
            heading: HeadingHold::default(),
            geometric: GeometricLaw::new(ts_s, tau, DesiredRateMode::Numerical),
            rpy: RpyLaw::new(ts_s, tau),
            last_good: None,
        })
    }

    /// Active law.
    pub fn kind(&self) -> ControllerKind {
        self.kind
    }

    /// Switches law; the new law's derivative filters restart from the next sample, so its
    /// first output has no derivative spike.
    pub fn set_kind(&mut self, kind: ControllerKind) {
        if kind != self.kind {
            self.kind = kind;
            self.geometric.reset();
            self.rpy.reset();
        }
    }

    /// Gains in use.
    pub fn gains(&self) -> &ControllerGains {
        &self.gains
    }

    /// Replaces the gains; refused (and nothing changed) if any is not acceptable.
    pub fn set_gains(&mut self, gains: ControllerGains) -> Result<(), ControllerError> {
        gains.validate().map_err(ControllerError::Gains)?;
        self.gains = gains;
        Ok(())
    }

    /// Selects how the geometric law obtains ω_{b,d} (docs/control.md §5.3).
    pub fn set_desired_rate_mode(&mut self, mode: DesiredRateMode, ts_s: f64) {
        self.geometric = GeometricLaw::new(ts_s, self.gains.limits.derivative_tau_s, mode);
    }

    /// Turns compensation of the estimated external wrench on or off.
    pub fn set_compensation(&mut self, on: bool) {
        self.compensate = on;
    }

    /// True when the estimate is subtracted.
    pub fn compensation(&self) -> bool {
        self.compensate
    }

    /// Vehicle model the laws use.
    pub fn model(&self) -> &VehicleModel {
        &self.model
    }

    /// One tick of the active law.
    pub fn update(&mut self, input: &ControlInput) -> ControlOutput {
        let ext = input.estimate.filter(|_| self.compensate);
        if !(input.state.is_finite() && input.setpoint.is_finite() && ext.is_none_or(|e| e.is_finite())) {
            return self.hold(ControlFlags {
                non_finite: true,
                ..Default::default()
            });
        }
        let g = &self.gains;
        let law = LawInput::resolve(
            &self.model,
            &g.limits,
            input.state,
            input.setpoint,
            &mut self.heading,
            ext.as_ref(),
        );
        let mut flags = ControlFlags::default();
        let out = match self.kind {
            ControllerKind::Geometric => Some(self.geometric.update(&g.geometric, &law)),
            ControllerKind::Hierarchical => self.rpy.update(&g.hierarchical, &law, &mut flags),
            ControllerKind::Passivity => self.rpy.update(&g.passivity, &law, &mut flags),
        };
        match out {
            Some(out) if out.is_finite() => {
                self.last_good = Some(out);
                out
            }
            Some(_) => self.hold(ControlFlags {
                non_finite: true,
                ..flags
            }),
            None => self.hold(flags),
        }
    }

    /// One tick of direct attitude / rate control (offboard SET_ATTITUDE_TARGET), with the
    /// geometric attitude gains whatever law is active; same fault rule as [`Self::update`].
    pub fn update_attitude(&mut self, x: &VehicleState, target: &AttitudeTarget) -> ControlOutput {
        if !(x.is_finite() && target.is_finite()) {
            return self.hold(ControlFlags {
                non_finite: true,
                ..Default::default()
            });
        }
        let out = super::attitude_target::track_attitude(&self.model, &self.gains.geometric, x, target);
        if out.is_finite() {
            self.last_good = Some(out);
            out
        } else {
            self.hold(ControlFlags {
                non_finite: true,
                ..out.flags
            })
        }
    }

    /// The last good output with `flags`; before any good output, zero thrust and torque.
    fn hold(&self, flags: ControlFlags) -> ControlOutput {
        let base = self.last_good.unwrap_or(ControlOutput {
            wrench: Wrench {
                thrust_n: 0.0,
                torque_b: Vec3::zeros(),
            },
            r_wb_desired: Mat3::identity(),
            eta_desired: Vec3::zeros(),
            errors: TrackingErrors::default(),
            flags,
        });
        ControlOutput { flags, ..base }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::GRAVITY_M_S2;

    fn controller(kind: ControllerKind) -> Controller {
        Controller::new(kind, VehicleModel::homework(28.0), ControllerGains::default(), 1e-3).unwrap()
    }

    fn at(pos_w: Vec3) -> VehicleState {
        VehicleState::at_rest(0.0, pos_w)
    }

    fn run(c: &mut Controller, x: &VehicleState, sp: &FlatSetpoint, est: Option<WrenchEstimate>) -> ControlOutput {
        c.update(&ControlInput {
            state: x,
            setpoint: sp,
            estimate: est,
        })
    }

    #[test]
    fn every_law_hovers_with_weight_and_no_torque() {
        for kind in ControllerKind::ALL {
            let out = run(
                &mut controller(kind),
                &at(Vec3::zeros()),
                &FlatSetpoint::hold(Vec3::zeros(), 0.0),
                None,
            );
            assert!((out.wrench.thrust_n - 1.5 * GRAVITY_M_S2).abs() < 1e-12, "{kind:?}");
            assert!(out.wrench.torque_b.norm() < 1e-12, "{kind:?}");
            assert_eq!(out.flags, ControlFlags::default());
        }
    }

    #[test]
    fn every_law_climbs_when_low_and_pitches_nose_down_to_go_north() {
        for kind in ControllerKind::ALL {
            let low = run(
                &mut controller(kind),
                &at(Vec3::new(0.0, 0.0, 1.0)),
                &FlatSetpoint::hold(Vec3::zeros(), 0.0),
                None,
            );
            assert!(low.wrench.thrust_n > 1.5 * GRAVITY_M_S2, "{kind:?}");
            let north = run(
                &mut controller(kind),
                &at(Vec3::zeros()),
                &FlatSetpoint::hold(Vec3::new(1.0, 0.0, 0.0), 0.0),
                None,
            );
            assert!(north.wrench.torque_b.y < 0.0 && north.eta_desired.y < 0.0, "{kind:?}");
            let east = run(
                &mut controller(kind),
                &at(Vec3::zeros()),
                &FlatSetpoint::hold(Vec3::new(0.0, 1.0, 0.0), 0.0),
                None,
            );
            assert!(east.wrench.torque_b.x > 0.0 && east.eta_desired.x > 0.0, "{kind:?}");
            let turn = run(
                &mut controller(kind),
                &at(Vec3::zeros()),
                &FlatSetpoint::hold(Vec3::zeros(), 0.5),
                None,
            );
            assert!(turn.wrench.torque_b.z > 0.0, "{kind:?}");
        }
    }

    #[test]
    fn non_finite_input_holds_the_last_good_output() {
        for kind in ControllerKind::ALL {
            let mut c = controller(kind);
            let sp = FlatSetpoint::hold(Vec3::new(0.0, 0.0, -1.0), 0.0);
            let good = run(&mut c, &at(Vec3::zeros()), &sp, None);
            let mut bad = at(Vec3::zeros());
            bad.vel_w.x = f64::NAN;
            let held = run(&mut c, &bad, &sp, None);
            assert!(held.flags.non_finite && held.flags.is_fault());
            assert_eq!(held.wrench, good.wrench);
            let bad_sp = FlatSetpoint {
                acc_w: Some(Vec3::new(f64::INFINITY, 0.0, 0.0)),
                ..sp
            };
            assert_eq!(run(&mut c, &at(Vec3::zeros()), &bad_sp, None).wrench, good.wrench);
        }
        // Before any good output: motors idle.
        let mut c = controller(ControllerKind::Geometric);
        let mut bad = at(Vec3::zeros());
        bad.r_wb[(0, 0)] = f64::NAN;
        let out = run(&mut c, &bad, &FlatSetpoint::hold(Vec3::zeros(), 0.0), None);
        assert_eq!(out.wrench.thrust_n, 0.0);
    }

    #[test]
    fn compensation_subtracts_the_estimate_only_when_on() {
        let est = WrenchEstimate {
            force_w: Vec3::new(0.0, 0.0, 2.0),
            torque_b: Vec3::new(0.0, 0.0, 0.2),
            mass_kg: 1.5,
        };
        for kind in ControllerKind::ALL {
            let x = at(Vec3::zeros());
            let sp = FlatSetpoint::hold(Vec3::zeros(), 0.0);
            let off = run(&mut controller(kind), &x, &sp, Some(est));
            assert!((off.wrench.thrust_n - 1.5 * GRAVITY_M_S2).abs() < 1e-12);
            let mut c = controller(kind);
            c.set_compensation(true);
            let on = run(&mut c, &x, &sp, Some(est));
            // A downward push of 2 N needs 2 N more thrust; a yaw torque of 0.2 N·m is cancelled.
            assert!(
                (on.wrench.thrust_n - (1.5 * GRAVITY_M_S2 + 2.0)).abs() < 1e-9,
                "{kind:?}"
            );
            assert!((on.wrench.torque_b.z + 0.2).abs() < 1e-12, "{kind:?}");
        }
    }

    #[test]
    fn rpy_laws_hold_at_the_singularity_and_geometric_does_not_need_to() {
        let x = VehicleState::at_rest_turned(0.0, 1.56, 0.0);
        for kind in [ControllerKind::Hierarchical, ControllerKind::Passivity] {
            let out = run(&mut controller(kind), &x, &FlatSetpoint::hold(Vec3::zeros(), 0.0), None);
            assert!(out.flags.rpy_singular && out.wrench.thrust_n == 0.0);
        }
        // Beyond 90° (Ψ ≥ 1): flagged, but the geometric law still steers back.
        let x = VehicleState::at_rest_turned(0.0, 1.6, 0.0);
        let out = run(
            &mut controller(ControllerKind::Geometric),
            &x,
            &FlatSetpoint::hold(Vec3::zeros(), 0.0),
            None,
        );
        assert!(!out.flags.is_fault() && out.flags.large_attitude_error);
        assert!(out.wrench.torque_b.y < 0.0, "pitches back towards level");
    }

    #[test]
    fn kinds_parse_from_their_names_and_gains_are_validated_on_set() {
        for kind in ControllerKind::ALL {
            assert_eq!(kind.name().parse::<ControllerKind>(), Ok(kind));
        }
        assert!("pid".parse::<ControllerKind>().unwrap_err().contains("pid"));
        let mut c = controller(ControllerKind::Passivity);
        let mut bad = ControllerGains::default();
        bad.passivity.sigma = f64::NAN;
        assert!(c.set_gains(bad).is_err());
        assert_eq!(*c.gains(), ControllerGains::default());
        c.set_kind(ControllerKind::Hierarchical);
        assert_eq!(c.kind(), ControllerKind::Hierarchical);
    }
}
