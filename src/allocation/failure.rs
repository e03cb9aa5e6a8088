//! Allocation after rotor failures (issue 6): the columns of the stopped rotors leave G_q and the
//! min-norm inverse is taken of what is left (docs/allocation.md §5, eqs. (5.1)–(5.3)).

use nalgebra::DMatrix;

use super::inverse::min_norm_inverse;
use super::{AllocationError, Allocator, Wrench};
use crate::math::Vec3;

/// What the allocator can still control after rotor failures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FailedRotors {
    /// Thrust and all three torques (e.g. a hexa- or octocopter without one rotor).
    FullControl,
    /// Thrust, roll and pitch; the yaw torque is whatever the remaining rotors give.
    YawUncontrolled,
}

impl Allocator {
    /// The allocator after the rotors marked in `failed` stopped (docs/allocation.md §5: their
    /// columns of G_q set to zero): the min-norm inverse of what is left when it still spans
    /// thrust and all three torques with room to stabilise around hover; otherwise (a
    /// quadrotor, or a PNPNPN hexacopter, that lost a rotor) thrust, roll and pitch only, giving
    /// up yaw ([`FailedRotors::YawUncontrolled`]): the vehicle spins but stays level. A failed
    /// rotor is always commanded zero.
    pub fn with_failed_rotors(&self, failed: &[bool]) -> Result<(Self, FailedRotors), AllocationError> {
        let mut g = self.g.clone();
        let n = g.ncols();
        for (i, _) in failed.iter().enumerate().filter(|(i, f)| **f && *i < n) {
            g.column_mut(i).fill(0.0);
        }
        let (lo, hi) = self.squared_speed_bounds();
        if let Ok(a) = min_norm_inverse(&g) {
            let full = Self::from_parts(g.clone(), a, lo, hi).with_airmode(self.airmode());
            if full.holds_roll_and_pitch() {
                return Ok((full, FailedRotors::FullControl));
            }
        }
        let g3 = g.rows(0, 3).into_owned();
        let a3 = min_norm_inverse(&g3)?;
        let mut a = DMatrix::zeros(g.ncols(), 4);
        a.columns_mut(0, 3).copy_from(&a3);
        Ok((
            Self::from_parts(g, a, lo, hi).with_airmode(self.airmode()),
            FailedRotors::YawUncontrolled,
        ))
    }
}

impl Allocator {
    /// The rotor (0-based) mounted opposite rotor `i` across the centre of mass: the same thrust
    /// column with the roll and pitch arms reversed (on `hexa_x` rotor i+3, on `octo` rotor
    /// i+4); `None` when there is none (an odd or asymmetric frame, or `i` out of range).
    pub fn opposite_rotor(&self, i: usize) -> Option<usize> {
        let g = &self.g;
        if i >= g.ncols() {
            return None;
        }
        let arm = g[(1, i)].hypot(g[(2, i)]);
        let tol = 1e-6 * arm.max(g[(0, i)].abs());
        (0..g.ncols()).find(|&j| {
            j != i
                && (g[(0, j)] - g[(0, i)]).abs() <= tol
                && (g[(1, j)] + g[(1, i)]).abs() <= tol
                && (g[(2, j)] + g[(2, i)]).abs() <= tol
        })
    }

    /// [`Self::opposite_rotor`] when it turns the other way from rotor `i`: leaving both out
    /// keeps as many rotors turning each way as before (a hexacopter with alternating spins).
    /// `None` where the opposite rotor turns the same way (a quadrotor, an octocopter), whose
    /// removal would unbalance the yaw torque instead.
    pub fn counter_rotating_opposite(&self, i: usize) -> Option<usize> {
        self.opposite_rotor(i)
            .filter(|&j| self.g[(3, i)] * self.g[(3, j)] < 0.0)
    }
}

impl Allocator {
    /// True when a mid collective with ±5 % of the full roll and pitch torque, each sign, is
    /// allocated exactly: the allocation can hover and stabilise. A PNPNPN hexacopter that lost
    /// a rotor cannot (it must idle the opposite rotor to balance yaw, and then the min-norm
    /// roll/pitch columns need that rotor below zero one way).
    fn holds_roll_and_pitch(&self) -> bool {
        let (_, hi) = self.squared_speed_bounds();
        let g = self.effectiveness();
        let full = |row: usize| g.row(row).iter().map(|x| x.abs()).sum::<f64>() * hi;
        let thrust_n = 0.5 * self.thrust_max_n();
        [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)].iter().all(|(x, y)| {
            let torque_b = Vec3::new(0.05 * x * full(1), 0.05 * y * full(2), 0.0);
            let out = self.allocate(&Wrench { thrust_n, torque_b });
            (out.applied.thrust_n - thrust_n).abs() <= 1e-6 * thrust_n
                && (out.applied.torque_b - torque_b).norm() <= 1e-6 * (full(1) + full(2))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::airframe::{Airframe, AirframeSource};
    use crate::allocation::Wrench;
    use crate::math::Vec3;

    fn allocator(preset: &str) -> Allocator {
        Allocator::new(&Airframe::from_source(&AirframeSource::resolve(preset).unwrap()).unwrap()).unwrap()
    }

    #[test]
    fn an_octocopter_without_one_rotor_keeps_full_control() {
        let nominal = allocator("octo");
        let mut failed = vec![false; 8];
        failed[2] = true;
        let (alloc, mode) = nominal.with_failed_rotors(&failed).unwrap();
        assert_eq!(mode, FailedRotors::FullControl);
        let hover = Wrench {
            thrust_n: 0.5 * alloc.thrust_max_n(),
            torque_b: Vec3::new(0.05, -0.05, 0.02),
        };
        let out = alloc.allocate(&hover);
        assert_eq!(out.omega_sq()[2], 0.0, "the failed rotor is commanded zero");
        assert!((out.applied.thrust_n - hover.thrust_n).abs() < 1e-6);
        assert!((out.applied.torque_b - hover.torque_b).norm() < 1e-6);
        assert!(alloc.thrust_max_n() < nominal.thrust_max_n());
        let identity = alloc.effectiveness() * alloc.inverse();
        assert!((identity - nalgebra::DMatrix::<f64>::identity(4, 4)).amax() < 1e-9);
    }

    #[test]
    fn a_pnpnpn_hexacopter_without_one_rotor_gives_up_yaw_but_holds_roll_and_pitch() {
        let (alloc, mode) = allocator("hexa_x")
            .with_failed_rotors(&[true, false, false, false, false, false])
            .unwrap();
        assert_eq!(mode, FailedRotors::YawUncontrolled);
        for torque in [
            Vec3::new(0.05, 0.0, 0.0),
            Vec3::new(-0.05, 0.0, 0.0),
            Vec3::new(0.0, 0.05, 0.0),
            Vec3::new(0.0, -0.05, 0.0),
        ] {
            let out = alloc.allocate(&Wrench {
                thrust_n: 14.7,
                torque_b: torque,
            });
            assert_eq!(out.omega_sq()[0], 0.0);
            assert!((out.applied.thrust_n - 14.7).abs() < 1e-6);
            assert!(
                (out.applied.torque_b.xy() - torque.xy()).norm() < 1e-6,
                "{torque:?}: {:?}",
                out.saturation
            );
        }
    }

    #[test]
    fn a_quadrotor_without_one_rotor_gives_up_yaw() {
        let nominal = allocator("quad_x");
        let (alloc, mode) = nominal.with_failed_rotors(&[false, false, true, false]).unwrap();
        assert_eq!(mode, FailedRotors::YawUncontrolled);
        let w = Wrench {
            thrust_n: 12.0,
            torque_b: Vec3::new(0.02, 0.01, 0.3),
        };
        let out = alloc.allocate(&w);
        assert_eq!(out.omega_sq()[2], 0.0);
        assert!((out.applied.thrust_n - 12.0).abs() < 1e-6 && (out.applied.torque_b.x - 0.02).abs() < 1e-6);
        assert!((out.applied.torque_b.y - 0.01).abs() < 1e-6);
        assert!((out.applied.torque_b.z - 0.3).abs() > 0.1, "yaw is not controlled");
    }

    #[test]
    fn opposite_rotors_sit_across_the_centre_of_mass() {
        let hexa = allocator("hexa_x");
        assert_eq!(
            (0..6).map(|i| hexa.opposite_rotor(i)).collect::<Vec<_>>(),
            [3, 4, 5, 0, 1, 2].map(Some)
        );
        assert_eq!(allocator("octo").opposite_rotor(1), Some(5));
        assert_eq!(allocator("quad_x").opposite_rotor(0), Some(2));
        assert_eq!(hexa.opposite_rotor(6), None);
        assert_eq!(hexa.counter_rotating_opposite(0), Some(3));
        assert_eq!(allocator("octo").counter_rotating_opposite(1), None, "same spin");
        assert_eq!(allocator("quad_x").counter_rotating_opposite(0), None, "same spin");
    }

    #[test]
    fn a_pnpnpn_hexacopter_without_a_rotor_and_its_opposite_hovers_without_yaw_torque() {
        // Rotors 2, 3, 5, 6 are left, two of each spin: hover balances yaw, but the yaw torque
        // can only come with roll and pitch torque (rank 3), so yaw is given up.
        let (alloc, mode) = allocator("hexa_x")
            .with_failed_rotors(&[true, false, false, true, false, false])
            .unwrap();
        assert_eq!(mode, FailedRotors::YawUncontrolled);
        let hover = alloc.allocate(&Wrench {
            thrust_n: 14.7,
            torque_b: Vec3::zeros(),
        });
        assert_eq!((hover.omega_sq()[0], hover.omega_sq()[3]), (0.0, 0.0));
        assert!((hover.applied.thrust_n - 14.7).abs() < 1e-6);
        assert!(hover.applied.torque_b.norm() < 1e-9, "{:?}", hover.applied);
        assert!(!hover.saturation.is_saturated());
    }

    #[test]
    fn two_adjacent_quad_rotors_cannot_be_allocated() {
        assert!(allocator("quad_x")
            .with_failed_rotors(&[true, true, false, false])
            .is_err());
    }
}
