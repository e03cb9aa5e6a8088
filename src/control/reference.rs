//! Turns an optional-field [`FlatSetpoint`] into the concrete errors and feed-forwards every
//! law uses (docs/control.md §2, eqs. (2.1)–(2.3)), following the semantics documented on
//! [`FlatSetpoint`], and bundles them with the rest of what a law reads in one tick
//! ([`LawInput`]).

use crate::math::{euler_zyx, Vec3};
use crate::wrench_estimator::WrenchEstimate;

use super::gains::{ControlLimits, VehicleModel};
use super::{FlatSetpoint, VehicleState};

/// What every law reads in one tick (docs/control.md §4–§6).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LawInput<'a> {
    /// Vehicle model.
    pub model: &'a VehicleModel,
    /// Guards.
    pub limits: &'a ControlLimits,
    /// Vehicle state.
    pub state: &'a VehicleState,
    /// Translational errors and feed-forward.
    pub translation: TranslationReference,
    /// Heading reference.
    pub heading: HeadingReference,
    /// Estimated external wrench to subtract; `None` when compensation is off.
    pub estimate: Option<&'a WrenchEstimate>,
}

impl<'a> LawInput<'a> {
    /// The input for state `x` and setpoint `sp`: errors by [`translation`], heading by `heading`.
    pub fn resolve(
        model: &'a VehicleModel,
        limits: &'a ControlLimits,
        x: &'a VehicleState,
        sp: &FlatSetpoint,
        heading: &mut HeadingHold,
        estimate: Option<&'a WrenchEstimate>,
    ) -> Self {
        Self {
            model,
            limits,
            state: x,
            translation: translation(x, sp),
            heading: heading.resolve(x, sp),
            estimate,
        }
    }

    /// f̂_e, world NED [N], the "[− f̂_e]" term of the outer loops; zero without compensation.
    pub fn force_hat_w(&self) -> Vec3 {
        self.estimate.map_or(Vec3::zeros(), |e| e.force_w)
    }

    /// τ̂_e^b, body FRD [N·m], the "[− τ̂_e^b]" term of the inner loops; zero without compensation.
    pub fn torque_hat_b(&self) -> Vec3 {
        self.estimate.map_or(Vec3::zeros(), |e| e.torque_b)
    }
}

/// Translational errors and feed-forward of one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TranslationReference {
    /// e_p = p_b − p_{b,d} [m]; zero when no position is commanded.
    pub e_p: Vec3,
    /// ė_p = ṗ_b − ṗ_{b,d} [m/s]; zero when neither position nor velocity is commanded.
    pub e_v: Vec3,
    /// p̈_{b,d} [m/s²].
    pub acc_w: Vec3,
    /// Position the errors refer to (the vehicle's own when none is commanded) [m].
    pub pos_w: Vec3,
}

/// Heading reference of one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeadingReference {
    /// ψ_d [rad].
    pub yaw_rad: f64,
    /// ψ̇_d [rad/s].
    pub yaw_rate_rad_s: f64,
    /// ψ̈_d [rad/s²].
    pub yaw_acc_rad_s2: f64,
}

/// Errors and feed-forwards of the translational loop.
pub fn translation(x: &VehicleState, sp: &FlatSetpoint) -> TranslationReference {
    let e_p = sp.pos_w.map_or(Vec3::zeros(), |p| x.pos_w - p);
    let e_v = match (sp.pos_w, sp.vel_w) {
        (_, Some(v)) => x.vel_w - v,
        (Some(_), None) => x.vel_w,
        (None, None) => Vec3::zeros(),
    };
    TranslationReference {
        e_p,
        e_v,
        acc_w: sp.acc_w.unwrap_or_default(),
        pos_w: sp.pos_w.unwrap_or(x.pos_w),
    }
}

/// Remembers the last commanded heading so a setpoint without yaw holds it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct HeadingHold {
    held_rad: Option<f64>,
}

impl HeadingHold {
    /// Heading reference for this tick: the commanded yaw, else the last commanded one, else
    /// the vehicle's heading when the hold began.
    pub fn resolve(&mut self, x: &VehicleState, sp: &FlatSetpoint) -> HeadingReference {
        let yaw_rad = match sp.yaw_rad {
            Some(yaw) => *self.held_rad.insert(yaw),
            None => *self.held_rad.get_or_insert_with(|| euler_zyx(&x.r_wb).z),
        };
        HeadingReference {
            yaw_rad,
            yaw_rate_rad_s: sp.yaw_rate_rad_s.unwrap_or(0.0),
            yaw_acc_rad_s2: sp.yaw_acc_rad_s2.unwrap_or(0.0),
        }
    }

    /// Forgets the held heading.
    pub fn reset(&mut self) {
        self.held_rad = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Mat3;

    fn state() -> VehicleState {
        VehicleState {
            pos_w: Vec3::new(1.0, 2.0, -3.0),
            vel_w: Vec3::new(0.5, 0.0, 0.0),
            ..VehicleState::at_rest_turned(0.0, 0.0, 0.7)
        }
    }

    #[test]
    fn optional_fields_follow_the_documented_semantics() {
        let x = state();
        let vel_only = FlatSetpoint {
            vel_w: Some(Vec3::new(1.0, 0.0, 0.0)),
            ..Default::default()
        };
        let r = translation(&x, &vel_only);
        assert_eq!(r.e_p, Vec3::zeros());
        assert_eq!(r.e_v, Vec3::new(-0.5, 0.0, 0.0));
        let pos_only = FlatSetpoint {
            pos_w: Some(Vec3::zeros()),
            ..Default::default()
        };
        let r = translation(&x, &pos_only);
        assert_eq!(r.e_p, x.pos_w);
        assert_eq!(r.e_v, x.vel_w);
        let acc_only = FlatSetpoint {
            acc_w: Some(Vec3::new(0.0, 1.0, 0.0)),
            ..Default::default()
        };
        let r = translation(&x, &acc_only);
        assert_eq!(
            (r.e_p, r.e_v, r.acc_w),
            (Vec3::zeros(), Vec3::zeros(), Vec3::new(0.0, 1.0, 0.0))
        );
    }

    #[test]
    fn missing_yaw_holds_the_heading() {
        let mut hold = HeadingHold::default();
        let x = state();
        assert!((hold.resolve(&x, &FlatSetpoint::default()).yaw_rad - 0.7).abs() < 1e-12);
        let turned = VehicleState {
            r_wb: Mat3::identity(),
            ..x
        };
        assert!((hold.resolve(&turned, &FlatSetpoint::default()).yaw_rad - 0.7).abs() < 1e-12);
        let sp = FlatSetpoint {
            yaw_rad: Some(-1.0),
            ..Default::default()
        };
        assert_eq!(hold.resolve(&x, &sp).yaw_rad, -1.0);
        assert_eq!(hold.resolve(&x, &FlatSetpoint::default()).yaw_rad, -1.0);
    }
}
