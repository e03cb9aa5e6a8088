//! Land detector: whether the vehicle is on the ground, judged from what the vehicle does, never
//! from which command started the flight (PX4's multicopter land detector, in three stages).
//!
//! ```text
//! in air ── ground contact ──(T/3)── maybe landed ──(T/3)── landed
//!   ground contact: descent commanded ∧ |v_z| < LNDMC_Z_VEL_MAX ∧ |v_xy| < LNDMC_XY_VEL_MAX
//!                   ∧ height above the ground < GROUND_CONTACT_HEIGHT_M
//!   maybe landed:   ground contact ∧ thrust < LOW_THRUST_OF_HOVER · m g ∧ |ω| < LNDMC_ROT_MAX
//! landed ── lift-off ── in air
//!   lift-off: armed ∧ (climbing faster than LNDMC_Z_VEL_MAX ∨ higher than LIFT_OFF_HEIGHT_M
//!             above the ground)
//! ```
//!
//! T is `LNDMC_TRIG_TIME`: a landing is declared once every condition has held for T (a third
//! for ground contact, two thirds with low thrust too). Disarmed means landed. The ground height
//! is where the vehicle last rested (at boot, disarmed and still, or landed); the world of this
//! emulator is flat, so that is also the ground under any later touch-down.

use crate::control::VehicleState;

/// Height above the ground within which ground contact can be declared [m].
const GROUND_CONTACT_HEIGHT_M: f64 = 1.0;
/// Height above the ground that counts as airborne whatever the speed [m].
const LIFT_OFF_HEIGHT_M: f64 = 0.3;
/// Collective thrust below this fraction of the believed weight is "low" [-] (PX4: 30 % of the
/// way from minimum to hover thrust).
pub const LOW_THRUST_OF_HOVER: f64 = 0.3;
/// Speed below which a disarmed vehicle counts as resting, so its height is the ground's [m/s].
const RESTING_SPEED_M_S: f64 = 0.1;

/// Land-detector settings (PX4 parameter names in brackets).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LandDetectorParams {
    /// Vertical speed below which the vehicle may be landed [m/s] (`LNDMC_Z_VEL_MAX`, 0.25).
    pub z_vel_max_m_s: f64,
    /// Horizontal speed below which the vehicle may be landed [m/s] (`LNDMC_XY_VEL_MAX`, 1.5).
    pub xy_vel_max_m_s: f64,
    /// Body rate below which the vehicle may be landed [rad/s] (`LNDMC_ROT_MAX`, 20 °/s).
    pub rot_max_rad_s: f64,
    /// Time through the three stages to "landed" [s] (`LNDMC_TRIG_TIME`, 1.0).
    pub trigger_time_s: f64,
}

impl Default for LandDetectorParams {
    fn default() -> Self {
        Self {
            z_vel_max_m_s: 0.25,
            xy_vel_max_m_s: 1.5,
            rot_max_rad_s: 20f64.to_radians(),
            trigger_time_s: 1.0,
        }
    }
}

/// What the flight controller asks of the vehicle this tick, as the detector needs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LandInput {
    /// Armed.
    pub armed: bool,
    /// The setpoint asks to go down (or to stay below where the vehicle is).
    pub descent_commanded: bool,
    /// Collective thrust of the last tick over the believed weight m g [-].
    pub thrust_over_weight: f64,
}

/// A change the detector declared this tick.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LandTransition {
    /// Touch-down: the vehicle is on the ground.
    Landed,
    /// Lift-off: the vehicle left the ground.
    Airborne,
}

/// The detector's stage.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LandStage {
    /// Flying.
    InAir,
    /// Pushed against the ground (descent commanded, not moving).
    GroundContact,
    /// Ground contact with low thrust and no rotation.
    MaybeLanded,
    /// On the ground.
    Landed,
}

/// The land detector of one vehicle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LandDetector {
    stage: LandStage,
    /// z of the ground under the vehicle, NED [m] (where it last rested).
    ground_z_m: Option<f64>,
    /// Since when ground contact has held [s].
    contact_since_s: Option<f64>,
    /// Since when ground contact with low thrust has held [s].
    low_thrust_since_s: Option<f64>,
    /// When the vehicle last touched down [s].
    landed_at_s: Option<f64>,
}

impl Default for LandDetector {
    /// Landed (a vehicle boots on the ground).
    fn default() -> Self {
        Self {
            stage: LandStage::Landed,
            ground_z_m: None,
            contact_since_s: None,
            low_thrust_since_s: None,
            landed_at_s: None,
        }
    }
}

impl LandDetector {
    /// The current stage.
    pub fn stage(&self) -> LandStage {
        self.stage
    }

    /// On the ground.
    pub fn landed(&self) -> bool {
        self.stage == LandStage::Landed
    }

    /// Pushed against the ground, not yet declared landed (the commander cuts thrust).
    pub fn touching_down(&self) -> bool {
        matches!(self.stage, LandStage::GroundContact | LandStage::MaybeLanded)
    }

    /// Simulated time of the last touch-down [s] (`None` before any, or while flying).
    pub fn landed_at_s(&self) -> Option<f64> {
        self.landed_at_s.filter(|_| self.landed())
    }

    /// The ground's z, local NED [m], once known (where the vehicle last rested).
    pub fn ground_z_m(&self) -> Option<f64> {
        self.ground_z_m
    }

    /// `x` is close enough to the ground for ground contact.
    pub fn near_ground(&self, x: &VehicleState) -> bool {
        self.height_m(x) < GROUND_CONTACT_HEIGHT_M
    }

    /// Height of `x` above the ground under it [m] (0 before the ground is known).
    pub fn height_m(&self, x: &VehicleState) -> f64 {
        self.ground_z_m.map_or(0.0, |g| g - x.pos_w.z)
    }

    /// One tick at `t_s` [s] for state `x`: the transition declared, if any.
    pub fn update(
        &mut self,
        p: &LandDetectorParams,
        input: &LandInput,
        x: &VehicleState,
        t_s: f64,
    ) -> Option<LandTransition> {
        let ground_z = *self.ground_z_m.get_or_insert(x.pos_w.z);
        let height = ground_z - x.pos_w.z;
        if !input.armed {
            if x.vel_w.norm() < RESTING_SPEED_M_S {
                self.ground_z_m = Some(x.pos_w.z);
            }
            self.contact_since_s = None;
            self.low_thrust_since_s = None;
            let was = self.stage;
            self.stage = LandStage::Landed;
            self.landed_at_s.get_or_insert(t_s);
            return (was != LandStage::Landed).then_some(LandTransition::Landed);
        }
        if self.stage == LandStage::Landed {
            let climbing = -x.vel_w.z > p.z_vel_max_m_s;
            if climbing || height > LIFT_OFF_HEIGHT_M {
                self.stage = LandStage::InAir;
                self.landed_at_s = None;
                self.contact_since_s = None;
                self.low_thrust_since_s = None;
                return Some(LandTransition::Airborne);
            }
            return None;
        }
        let contact = input.descent_commanded
            && x.vel_w.z.abs() < p.z_vel_max_m_s
            && x.vel_w.xy().norm() < p.xy_vel_max_m_s
            && height < GROUND_CONTACT_HEIGHT_M;
        let low_thrust =
            contact && input.thrust_over_weight < LOW_THRUST_OF_HOVER && x.omega_b.amax() < p.rot_max_rad_s;
        let contact_for = held_for(&mut self.contact_since_s, contact, t_s);
        let low_for = held_for(&mut self.low_thrust_since_s, low_thrust, t_s);
        let stage_s = p.trigger_time_s / 3.0;
        self.stage = if low_thrust && contact_for >= stage_s && low_for >= 2.0 * stage_s {
            LandStage::Landed
        } else if low_thrust && contact_for >= stage_s {
            LandStage::MaybeLanded
        } else if contact && contact_for >= stage_s {
            LandStage::GroundContact
        } else if contact {
            // Contact not yet confirmed: keep a stage already reached, else still flying.
            match self.stage {
                LandStage::MaybeLanded => LandStage::GroundContact,
                s => s,
            }
        } else {
            LandStage::InAir
        };
        if self.stage == LandStage::Landed {
            self.ground_z_m = Some(x.pos_w.z);
            self.landed_at_s = Some(t_s);
            return Some(LandTransition::Landed);
        }
        None
    }
}

/// Seconds a condition has held at `t_s` [s], keeping its start in `since` (0 when it does not).
fn held_for(since: &mut Option<f64>, holds: bool, t_s: f64) -> f64 {
    if holds {
        t_s - *since.get_or_insert(t_s)
    } else {
        *since = None;
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Mat3, Vec3};

    const DT: f64 = 0.001;

    fn at(z: f64, vz: f64) -> VehicleState {
        VehicleState {
            t_s: 0.0,
            pos_w: Vec3::new(0.0, 0.0, z),
            vel_w: Vec3::new(0.0, 0.0, vz),
            r_wb: Mat3::identity(),
            omega_b: Vec3::zeros(),
        }
    }

    fn input(descent: bool, thrust: f64) -> LandInput {
        LandInput {
            armed: true,
            descent_commanded: descent,
            thrust_over_weight: thrust,
        }
    }

    /// Runs `d` for `seconds` from `t0`, returning the transitions with their times.
    fn run(d: &mut LandDetector, t0: f64, seconds: f64, i: LandInput, x: VehicleState) -> Vec<(f64, LandTransition)> {
        let p = LandDetectorParams::default();
        let n = (seconds / DT).round() as usize;
        (0..n)
            .filter_map(|k| {
                let t = t0 + k as f64 * DT;
                d.update(&p, &i, &x, t).map(|tr| (t, tr))
            })
            .collect()
    }

    #[test]
    fn boots_landed_and_disarmed_means_landed() {
        let mut d = LandDetector::default();
        assert!(d.landed());
        let mut i = input(false, 0.0);
        i.armed = false;
        assert!(run(&mut d, 0.0, 1.0, i, at(-0.1, 0.0)).is_empty());
        assert!(d.landed());
        assert_eq!(d.height_m(&at(-0.1, 0.0)), 0.0);
    }

    #[test]
    fn lift_off_by_climb_rate_or_height_whoever_commands_it() {
        let mut d = LandDetector::default();
        run(&mut d, 0.0, 0.1, input(false, 0.0), at(-0.1, 0.0));
        // Idle thrust, no command: a gust lifts the vehicle 0.4 m: airborne.
        let tr = run(&mut d, 0.1, 0.01, input(false, 0.0), at(-0.5, 0.0));
        assert_eq!(tr, vec![(0.1, LandTransition::Airborne)]);
        assert_eq!(d.stage(), LandStage::InAir);
        let mut d = LandDetector::default();
        run(&mut d, 0.0, 0.1, input(false, 0.0), at(-0.1, 0.0));
        assert_eq!(run(&mut d, 0.1, 0.01, input(false, 1.2), at(-0.15, -0.3)).len(), 1);
    }

    #[test]
    fn touch_down_takes_the_trigger_time_in_three_stages() {
        let mut d = LandDetector::default();
        run(&mut d, 0.0, 0.01, input(false, 1.0), at(-0.1, 0.0));
        run(&mut d, 0.01, 0.01, input(false, 1.0), at(-3.0, -1.0));
        assert_eq!(d.stage(), LandStage::InAir);
        // Descending in the air at 0.7 m/s: never ground contact.
        assert!(run(&mut d, 1.0, 5.0, input(true, 0.8), at(-2.0, 0.7)).is_empty());
        assert_eq!(d.stage(), LandStage::InAir);
        // Stopped by the ground with thrust still high: ground contact only.
        assert!(run(&mut d, 6.0, 2.0, input(true, 0.9), at(-0.1, 0.0)).is_empty());
        assert_eq!(d.stage(), LandStage::GroundContact);
        assert!(d.touching_down());
        // Thrust cut: landed 2/3 of the trigger time later.
        let tr = run(&mut d, 8.0, 2.0, input(true, 0.05), at(-0.1, 0.0));
        assert_eq!(tr.len(), 1);
        assert!((tr[0].0 - 8.0 - 2.0 / 3.0).abs() < 2.0 * DT, "{tr:?}");
        assert_eq!(d.landed_at_s(), Some(tr[0].0));
    }

    #[test]
    fn a_hover_is_never_a_landing() {
        // Stationary with low thrust, but nothing commands a descent (a light vehicle hovering).
        let mut d = LandDetector::default();
        run(&mut d, 0.0, 0.01, input(false, 1.0), at(-0.1, 0.0));
        run(&mut d, 0.01, 0.01, input(false, 1.0), at(-0.6, 0.0));
        assert!(run(&mut d, 1.0, 10.0, input(false, 0.1), at(-0.6, 0.0)).is_empty());
        // Commanded down but high above the ground (stuck reference): no contact either.
        assert!(run(&mut d, 11.0, 10.0, input(true, 0.1), at(-19.0, 0.0)).is_empty());
        assert_eq!(d.stage(), LandStage::InAir);
        // Sliding sideways faster than LNDMC_XY_VEL_MAX on the ground: not landed.
        let mut x = at(-0.1, 0.0);
        x.vel_w.x = 2.0;
        assert!(run(&mut d, 21.0, 5.0, input(true, 0.0), x).is_empty());
    }
}
