//! Local NED ↔ geodetic about home (docs/mavlink.md §4, eq. (4.1)): equirectangular with R = 6 371 000 m,
//! `lat = lat0 + x/R`, `lon = lon0 + y/(R cos lat0)`, `alt = alt0 − z`.

use crate::math::Vec3;

/// Mean Earth radius [m].
pub const EARTH_RADIUS_M: f64 = 6_371_000.0;

/// Geodetic home, the origin of local NED.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Home {
    /// Latitude [deg].
    pub lat_deg: f64,
    /// Longitude [deg].
    pub lon_deg: f64,
    /// Altitude above mean sea level [m].
    pub alt_amsl_m: f64,
}

impl Default for Home {
    /// PX4 SITL's default home (Zürich, 488 m AMSL).
    fn default() -> Self {
        Self {
            lat_deg: 47.397742,
            lon_deg: 8.545594,
            alt_amsl_m: 488.0,
        }
    }
}

impl Home {
    /// Latitude [deg], longitude [deg] and AMSL altitude [m] of local NED point `pos_w` [m].
    pub fn to_global(&self, pos_w: &Vec3) -> (f64, f64, f64) {
        let lat0 = self.lat_deg.to_radians();
        (
            self.lat_deg + (pos_w.x / EARTH_RADIUS_M).to_degrees(),
            self.lon_deg + (pos_w.y / (EARTH_RADIUS_M * lat0.cos())).to_degrees(),
            self.alt_amsl_m - pos_w.z,
        )
    }

    /// Local NED point [m] of latitude, longitude [deg] and AMSL altitude [m].
    pub fn to_local(&self, lat_deg: f64, lon_deg: f64, alt_amsl_m: f64) -> Vec3 {
        let lat0 = self.lat_deg.to_radians();
        Vec3::new(
            (lat_deg - self.lat_deg).to_radians() * EARTH_RADIUS_M,
            (lon_deg - self.lon_deg).to_radians() * EARTH_RADIUS_M * lat0.cos(),
            self.alt_amsl_m - alt_amsl_m,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_scale() {
        let home = Home::default();
        let p = Vec3::new(120.0, -35.5, -12.0);
        let (lat, lon, alt) = home.to_global(&p);
        assert!((home.to_local(lat, lon, alt) - p).norm() < 1e-9);
        assert!((alt - 500.0).abs() < 1e-12);
        // 1 m north is 1/R rad of latitude.
        let (lat1, _, _) = home.to_global(&Vec3::new(1.0, 0.0, 0.0));
        assert!(((lat1 - home.lat_deg).to_radians() * EARTH_RADIUS_M - 1.0).abs() < 1e-9);
    }
}
