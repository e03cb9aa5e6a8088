//! The Earth's main magnetic field at any place: NOAA's World Magnetic Model (WMM2025), evaluated
//! at a fixed date so that runs are deterministic (docs/model.md §10.5, eqs. (10.12), (10.19)).
//!
//! Pure: a place in, the field out. The spherical-harmonic synthesis (degree 12, WMM2025
//! coefficients, the WMM2025 technical report's equations) is the `world_magnetic_model` crate's;
//! this module fixes the date, checks the place and turns its components (north, east, down, in
//! nanotesla) into gauss.
//!
//! Accuracy: the model's own error budget (the WMM2025 technical report's error model: RMS
//! 0.3°–0.4° in declination away from the magnetic poles, 0.2° in inclination, about 150 nT in
//! total intensity) plus the field's secular change since [`FIELD_EPOCH_YEAR`] (about 0.1° a year
//! in declination); local crustal anomalies are not modelled.

use nalgebra::Vector3;
use thiserror::Error;
use world_magnetic_model::time::{Date, Month};
use world_magnetic_model::uom::si::angle::degree;
use world_magnetic_model::uom::si::f32::{Angle, Length};
use world_magnetic_model::uom::si::length::meter;
use world_magnetic_model::uom::si::magnetic_flux_density::nanotesla;
use world_magnetic_model::GeomagneticField;

/// The field is evaluated on 1 January of this year: 2025.0, WMM2025's epoch (its coefficients
/// without secular change).
pub const FIELD_EPOCH_YEAR: i32 = 2025;

/// Gauss per nanotesla (1 G = 10⁻⁴ T = 10⁵ nT) [G/nT].
const GAUSS_PER_NT: f64 = 1e-5;

/// Heights the model covers, above the WGS-84 ellipsoid [m] (the WMM2025 technical report's
/// validity range).
pub const FIELD_HEIGHT_RANGE_M: (f64, f64) = (-1_000.0, 850_000.0);

/// A place on the Earth: WGS-84 geodetic latitude and longitude, and height.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GeoSite {
    /// Latitude, north positive [deg], within [−90, 90].
    pub lat_deg: f64,
    /// Longitude, east positive [deg], within [−180, 180].
    pub lon_deg: f64,
    /// Height [m] within [`FIELD_HEIGHT_RANGE_M`]; the model reads it above the WGS-84 ellipsoid
    /// (an AMSL altitude read as such is off by the geoid, at most about 100 m: a few nanotesla).
    pub alt_m: f64,
}

impl GeoSite {
    /// PX4 SITL's default home near Zurich: 47.397742° N, 8.545594° E, 488 m.
    pub const PX4_DEFAULT_HOME: Self = Self {
        lat_deg: 47.397742,
        lon_deg: 8.545594,
        alt_m: 488.0,
    };
}

/// The model cannot give the field at this place.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum EarthFieldError {
    /// Latitude not finite or outside [−90°, 90°].
    #[error("latitude {0}° is outside [-90, 90]")]
    Latitude(f64),
    /// Longitude not finite or outside [−180°, 180°].
    #[error("longitude {0}° is outside [-180, 180]")]
    Longitude(f64),
    /// Height not finite or outside [`FIELD_HEIGHT_RANGE_M`].
    #[error("height {0} m is outside the World Magnetic Model's [-1 km, 850 km]")]
    Height(f64),
    /// The model refused the place or the date (its own message).
    #[error("World Magnetic Model: {0}")]
    Model(String),
}

/// The Earth's field at one place: strength, declination and inclination
/// (docs/model.md §10.5, eq. (10.14)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EarthField {
    /// Total intensity F [gauss].
    pub strength_gauss: f64,
    /// Declination D, east of true north positive [rad].
    pub declination_rad: f64,
    /// Inclination I, below the horizontal positive (negative in the southern magnetic
    /// hemisphere) [rad].
    pub inclination_rad: f64,
}

impl EarthField {
    /// The World Magnetic Model's field at `site` on [`FIELD_EPOCH_YEAR`]
    /// (docs/model.md §10.5, eq. (10.19)).
    pub fn at(site: &GeoSite) -> Result<Self, EarthFieldError> {
        let date = Date::from_calendar_date(FIELD_EPOCH_YEAR, Month::January, 1)
            .map_err(|e| EarthFieldError::Model(e.to_string()))?;
        Self::on(site, date)
    }

    /// The field at `site` on `date` (the model covers 2020-01-01 to 2029-12-31).
    pub(crate) fn on(site: &GeoSite, date: Date) -> Result<Self, EarthFieldError> {
        let (lo, hi) = FIELD_HEIGHT_RANGE_M;
        if !(site.lat_deg.is_finite() && site.lat_deg.abs() <= 90.0) {
            return Err(EarthFieldError::Latitude(site.lat_deg));
        }
        if !(site.lon_deg.is_finite() && site.lon_deg.abs() <= 180.0) {
            return Err(EarthFieldError::Longitude(site.lon_deg));
        }
        if !(site.alt_m.is_finite() && (lo..=hi).contains(&site.alt_m)) {
            return Err(EarthFieldError::Height(site.alt_m));
        }
        // The model computes in f32 (about 1e-7 relative, far below its accuracy).
        let field = GeomagneticField::new(
            Length::new::<meter>(site.alt_m as f32),
            Angle::new::<degree>(site.lat_deg as f32),
            Angle::new::<degree>(site.lon_deg as f32),
            date,
        )
        .map_err(|e| EarthFieldError::Model(e.to_string()))?;
        let ned_nt = [field.x(), field.y(), field.z()].map(|c| f64::from(c.get::<nanotesla>()));
        Ok(Self::from_ned(&(Vector3::from(ned_nt) * GAUSS_PER_NT)))
    }

    /// The field of NED vector `m_w` [gauss] (docs/model.md §10.5, eq. (10.14)).
    pub fn from_ned(m_w: &Vector3<f64>) -> Self {
        Self {
            strength_gauss: m_w.norm(),
            declination_rad: m_w.y.atan2(m_w.x),
            inclination_rad: m_w.z.atan2(m_w.xy().norm()),
        }
    }

    /// The field as a vector in world NED [gauss] (docs/model.md §10.5, eq. (10.12)).
    pub fn field_w(&self) -> Vector3<f64> {
        let (si, ci) = self.inclination_rad.sin_cos();
        let (sd, cd) = self.declination_rad.sin_cos();
        Vector3::new(ci * cd, ci * sd, si) * self.strength_gauss
    }
}

#[cfg(test)]
#[path = "earth_field_tests.rs"]
mod tests;
