//! Control allocation for n ≥ 4 coplanar rotors (docs/allocation.md): G_q from the FC's airframe,
//! its minimum-norm inverse, and the saturation policy.
//!
//! The hot path ([`Allocator::allocate`]) works on fixed-size arrays and never allocates.

mod effectiveness;
mod failure;
mod inverse;
mod saturation;

pub use effectiveness::effectiveness_matrix;
pub use failure::FailedRotors;
pub use inverse::{closed_form_ring_inverse, min_norm_inverse, MAX_CONDITION};
pub use saturation::{Airmode, Saturation};

use nalgebra::DMatrix;
use saturation::{RotorArray, SpeedBox};
use thiserror::Error;

use crate::airframe::{Airframe, MAX_ROTORS};
use crate::math::Vec3;

/// An airframe the allocation cannot serve.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AllocationError {
    /// `G_q G_qᵀ` is (nearly) singular: the rotors cannot produce independent thrust and torques.
    #[error("allocation matrix is ill-conditioned (condition number {condition:.3e} > {MAX_CONDITION:.0e}): the rotors cannot produce independent thrust, roll, pitch and yaw")]
    Singular {
        /// Condition number of the row-normalised `G_q G_qᵀ`.
        condition: f64,
    },
}

/// Collective thrust and body torque.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wrench {
    /// Collective thrust u_T along −z_b [N].
    pub thrust_n: f64,
    /// Body torque τ_b (FRD) [N·m].
    pub torque_b: Vec3,
}

impl Wrench {
    fn as_array(&self) -> [f64; 4] {
        [self.thrust_n, self.torque_b.x, self.torque_b.y, self.torque_b.z]
    }
}

/// Result of one allocation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Allocation {
    n: usize,
    omega_sq: RotorArray,
    /// Wrench the commanded speeds produce, `G_q ω²` (what the estimator must use,
    /// docs/allocation.md §4).
    pub applied: Wrench,
    /// What was given up to stay within the speed limits.
    pub saturation: Saturation,
}

impl Allocation {
    /// Commanded squared speeds [(rad/s)²].
    pub fn omega_sq(&self) -> &[f64] {
        &self.omega_sq[..self.n]
    }

    /// Commanded speeds [rad/s].
    pub fn omega(&self) -> RotorSpeeds {
        let mut speeds = [0.0; MAX_ROTORS];
        for (s, w2) in speeds.iter_mut().zip(self.omega_sq()) {
            *s = w2.sqrt();
        }
        RotorSpeeds { n: self.n, speeds }
    }
}

/// Rotor speeds without heap allocation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotorSpeeds {
    n: usize,
    speeds: RotorArray,
}

impl RotorSpeeds {
    /// `n` rotors stopped (motors off); at most [`MAX_ROTORS`].
    pub fn idle(n: usize) -> Self {
        Self {
            n: n.min(MAX_ROTORS),
            speeds: [0.0; MAX_ROTORS],
        }
    }

    /// Speeds [rad/s].
    pub fn as_slice(&self) -> &[f64] {
        &self.speeds[..self.n]
    }
}

/// Maps a wrench to rotor speeds for one airframe.
#[derive(Debug, Clone)]
pub struct Allocator {
    g: DMatrix<f64>,
    a: DMatrix<f64>,
    g_rows: [RotorArray; 4],
    a_cols: [RotorArray; 4],
    bounds: SpeedBox,
    thrust_max_n: f64,
    airmode: Airmode,
}

impl Allocator {
    /// Builds G_q and its min-norm inverse from the FC's airframe.
    ///
    /// ```
    /// use rotorpilot::airframe::{Airframe, AirframeSource};
    /// use rotorpilot::allocation::{Allocator, Wrench};
    /// use nalgebra::Vector3;
    /// let af = Airframe::from_source(&AirframeSource::resolve("quad_x").unwrap()).unwrap();
    /// let alloc = Allocator::new(&af).unwrap();
    /// let out = alloc.allocate(&Wrench { thrust_n: 14.715, torque_b: Vector3::new(0.1, 0.0, 0.01) });
    /// assert!(!out.saturation.is_saturated());
    /// assert!((out.applied.torque_b.x - 0.1).abs() < 1e-9);
    /// ```
    pub fn new(af: &Airframe) -> Result<Self, AllocationError> {
        let g = effectiveness_matrix(af);
        let a = min_norm_inverse(&g)?;
        Ok(Self::from_parts(
            g,
            a,
            af.omega_min_rad_s.powi(2),
            af.omega_max_rad_s.powi(2),
        ))
    }

    /// An allocator for `g` (4 × n) with inverse `a` (n × 4) and squared-speed bounds.
    pub(super) fn from_parts(g: DMatrix<f64>, a: DMatrix<f64>, lo: f64, hi: f64) -> Self {
        let n = g.ncols();
        let mut g_rows = [[0.0; MAX_ROTORS]; 4];
        let mut a_cols = [[0.0; MAX_ROTORS]; 4];
        for k in 0..4 {
            for i in 0..n {
                g_rows[k][i] = g[(k, i)];
                a_cols[k][i] = a[(i, k)];
            }
        }
        Self {
            thrust_max_n: g.row(0).sum() * hi,
            g,
            a,
            g_rows,
            a_cols,
            bounds: SpeedBox { n, lo, hi },
            airmode: Airmode::default(),
        }
    }

    /// The same allocator with saturation policy `airmode` (docs/allocation.md §4).
    pub fn with_airmode(mut self, airmode: Airmode) -> Self {
        self.airmode = airmode;
        self
    }

    /// The saturation policy in force.
    pub fn airmode(&self) -> Airmode {
        self.airmode
    }

    /// G_q (4 × n), rows [u_T, τx, τy, τz].
    pub fn effectiveness(&self) -> &DMatrix<f64> {
        &self.g
    }

    /// The min-norm inverse A (n × 4).
    pub fn inverse(&self) -> &DMatrix<f64> {
        &self.a
    }

    /// Squared-speed bounds (lo, hi) [(rad/s)²].
    pub(super) fn squared_speed_bounds(&self) -> (f64, f64) {
        (self.bounds.lo, self.bounds.hi)
    }

    /// Number of rotors.
    pub fn rotor_count(&self) -> usize {
        self.bounds.n
    }

    /// Collective thrust with every rotor at full speed [N].
    pub fn thrust_max_n(&self) -> f64 {
        self.thrust_max_n
    }

    /// `G_q ω²` for squared speeds `omega_sq` [(rad/s)²].
    pub fn wrench_of(&self, omega_sq: &[f64]) -> Wrench {
        let row = |k: usize| self.g_rows[k].iter().zip(omega_sq).map(|(g, w)| g * w).sum::<f64>();
        Wrench {
            thrust_n: row(0),
            torque_b: Vec3::new(row(1), row(2), row(3)),
        }
    }

    /// Min-norm allocation of `w` with the saturation policy of docs/allocation.md §4. A non-finite
    /// wrench allocates zero thrust and torque and reports full saturation.
    pub fn allocate(&self, w: &Wrench) -> Allocation {
        let mut omega_sq = [0.0; MAX_ROTORS];
        let request = w.as_array();
        let saturation = if request.iter().all(|x| x.is_finite()) {
            saturation::allocate(
                &self.a_cols,
                self.bounds,
                self.thrust_max_n,
                self.airmode,
                request,
                &mut omega_sq,
            )
        } else {
            saturation::allocate(
                &self.a_cols,
                self.bounds,
                self.thrust_max_n,
                self.airmode,
                [0.0; 4],
                &mut omega_sq,
            );
            Saturation {
                yaw_scale: 0.0,
                thrust_shift_n: 0.0,
                roll_pitch_scale: 0.0,
                clipped: u32::MAX >> (32 - self.bounds.n),
            }
        };
        let n = self.bounds.n;
        Allocation {
            n,
            omega_sq,
            applied: self.wrench_of(&omega_sq[..n]),
            saturation,
        }
    }
}
