//! The GNSS height datum: where the filter's z = 0 sits among the GNSS heights
//! (docs/navigation_filter.md §6, eq. (6.5)). PX4 takes it from the one fix at which the GNSS
//! height starts, so a vehicle resting on the ground reads that fix's error as its height for as
//! long as it rests. Here, until the first arming, the datum is the mean of every fix since the
//! first (the vehicle has not moved: its height is still the one it aligned at), so the resting
//! height is the receiver's averaged error, not one sample's; the first arming freezes it, and so
//! does the first sign of motion (an estimated speed above 0.3 m/s or a height 0.3 m from the
//! first fix's), so a filter that is never told of an arming cannot average a flight in.

/// Estimated speed that ends the averaging [m/s].
const MOVING_SPEED_M_S: f64 = 0.3;
/// Estimated height change from the first fix that ends the averaging [m].
const MOVED_HEIGHT_M: f64 = 0.3;

/// The vertical datum's state.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct GnssDatum {
    /// The estimate's height [m] at the first fix (the filter's z there, ≈ 0 after alignment).
    z_first_m: Option<f64>,
    /// Σ of the fixes' heights in the readings' frame [m], and their number.
    sum_z_m: f64,
    count: u32,
    frozen: bool,
}

impl GnssDatum {
    /// Takes a fix of height `gps_z_m` [m, readings' frame, down] whose estimate was `est_z_m`
    /// [m] at estimated speed `speed_m_s` [m/s]; the datum's z in the readings' frame [m]
    /// (docs/navigation_filter.md §6, eq. (6.5)): `z_datum = mean(z_gps) − z_first` until frozen, then as it was.
    pub fn observe(&mut self, gps_z_m: f64, est_z_m: f64, speed_m_s: f64) -> f64 {
        let z_first = *self.z_first_m.get_or_insert(est_z_m);
        if speed_m_s > MOVING_SPEED_M_S || (est_z_m - z_first).abs() > MOVED_HEIGHT_M {
            self.frozen = true;
        }
        if !self.frozen || self.count == 0 {
            self.sum_z_m += gps_z_m;
            self.count += 1;
        }
        self.sum_z_m / f64::from(self.count) - z_first
    }

    /// Stops the averaging: the vehicle armed (it may leave its height from now on).
    pub fn freeze(&mut self) {
        self.frozen = true;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_datum_is_the_mean_until_frozen() {
        let mut d = GnssDatum::default();
        assert_eq!(d.observe(-0.2, 0.0, 0.0), -0.2);
        assert_eq!(
            d.observe(0.0, 0.1, 0.0),
            -0.1,
            "the first fix's estimate stays the reference"
        );
        d.freeze();
        assert_eq!(d.observe(-5.0, -4.9, 0.0), -0.1);
        let mut late = GnssDatum::default();
        late.freeze();
        assert_eq!(
            late.observe(-0.3, 0.1, 0.0),
            -0.4,
            "frozen before any fix: the first fix sets it"
        );
    }

    #[test]
    fn motion_freezes_the_datum_without_an_arming() {
        let mut d = GnssDatum::default();
        assert_eq!(d.observe(-0.2, 0.0, 0.0), -0.2);
        assert_eq!(d.observe(-1.0, -0.1, 1.0), -0.2, "moving");
        assert_eq!(d.observe(0.0, 0.0, 0.0), -0.2, "stays frozen");
        let mut climbed = GnssDatum::default();
        assert_eq!(climbed.observe(0.0, 0.0, 0.0), 0.0);
        assert_eq!(climbed.observe(-2.0, -0.5, 0.1), 0.0, "0.5 m up");
    }
}
