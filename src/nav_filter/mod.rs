//! Navigation filter: an error-state extended Kalman filter with PX4 EKF2's structure
//! (docs/navigation_filter.md): a nominal state integrated at every IMU sample, a 16-state
//! error covariance predicted at `predict_period_s` from accumulated increments, and sequential
//! scalar fusion of GNSS position and velocity (delayed), barometric height and magnetic
//! heading, each behind an innovation gate. Pure: readings (time included) in, values out; no
//! heap use after [`NavFilter::new`].
//!
//! # Layout
//!
//! - `params`: [`NavParams`] (PX4's `EKF2_*` values in SI units) and [`HeightSource`].
//! - `readings`: the FC-side sensor readings [`ImuReading`], [`GpsReading`], [`BaroReading`],
//!   [`MagReading`].
//! - `state`: nominal state, error-state layout (`ERR_*`), injection.
//! - `orchestration`: [`NavFilter`]'s per-reading steps: which part runs, in which order.
//! - `error_state`: the core filter (`ErrorStateFilter`): nominal state, covariance, the IMU
//!   step, the gated fusion of scalars, the state history, the output lag.
//! - `predict`: nominal integration per IMU sample and its increments.
//! - `covariance`: Φ, Q, the gated sequential scalar update, variance limits, resets.
//! - `delay_buffer`: the fixed-size state history for delayed measurements.
//! - `aligner`: the alignment window and its end (`Alignment`); `alignment`: its maths (roll and
//!   pitch from the accelerometer, yaw from the magnetometer, initial P).
//! - `fuse_gps` (`GnssAid`: origin, datum, the fix's three parts), `fuse_baro` (`BaroAid`:
//!   origin altitude), `fuse_mag` (`MagHeading`: inclination, yaw alignment), `fuse_gravity`
//!   (`GravityAid`): each aid owns its state and fuses into the core filter.
//! - `datum`: the GNSS height datum, averaged until the first arming.
//! - `height`: which height source is active, fall-back and return (`HeightSelection`).
//! - `aiding`: the aiding decision (`Aiding`): dead reckoning, resets, the position hold.
//! - `reporting`: what the fusions leave for the status (`FilterReport`): test ratios,
//!   innovations, pre-flight checks, reset counters.
//! - `fusion`, `status`, `estimate`: what the filter returns.
//! - `preflight`: the pre-flight checks on the low-passed innovations.
//! - `isa`: ISA pressure altitude.
//! - `yaw_estimator`, `heading_aid`: the heading from GNSS velocity (a Gaussian sum of heading
//!   hypotheses) and its fusion while the magnetometer is lost (`HeadingAid`).

mod aiding;
mod aligner;
mod alignment;
mod covariance;
mod datum;
mod delay_buffer;
mod error_state;
mod estimate;
mod fuse_baro;
mod fuse_gps;
mod fuse_gravity;
mod fuse_mag;
mod fusion;
mod heading_aid;
mod height;
pub mod isa;
mod nav_params;
mod orchestration;
mod output;
mod predict;
mod preflight;
mod readings;
mod reporting;
mod state;
mod status;
mod yaw_estimator;

#[cfg(test)]
mod tests;

pub use aiding::DEAD_RECKONING_AFTER_S;
pub use estimate::NavEstimate;
pub use fusion::{Fusion, FusionOutcome, GpsFusion, SkipReason};
pub use nav_params::{
    HeightSource, NavParams, NavParamsError, DECL_TYPE_USE_GEO, GPS_CTRL_FUSED, IMU_CTRL_GRAVITY, MAG_TYPE_NONE,
    MAX_DELAY_S,
};
pub use output::NavOutput;
pub use preflight::PreflightFailure;
pub use readings::{BaroReading, GpsReading, ImuReading, MagReading};
pub use state::{
    Covariance, ErrorVector, ERR_ACCEL_BIAS, ERR_ATT, ERR_BARO_OFFSET, ERR_GYRO_BIAS, ERR_POS, ERR_VEL, STATE_DIM,
};
pub use status::{Innovations, NavStatus, ResetCounters, SourceHealth, SourceStatus, TestRatios};

use crate::math::Vec3;

use aiding::Aiding;
use aligner::Alignment;
use error_state::ErrorStateFilter;
use fuse_baro::BaroAid;
use fuse_gps::GnssAid;
use fuse_gravity::GravityAid;
use fuse_mag::MagHeading;
use heading_aid::HeadingAid;
use height::HeightSelection;
use reporting::FilterReport;

/// The navigation filter (docs/navigation_filter.md): the core error-state filter and the
/// aids around it, each owning its state; [`NavFilter`] runs them in order for each reading.
#[derive(Debug, Clone)]
pub struct NavFilter {
    params: NavParams,
    /// The World Magnetic Model's declination at home [rad], once known (PX4's geo look-up).
    geo_declination_rad: Option<f64>,
    /// Nominal state, covariance, state history, output lag.
    core: ErrorStateFilter,
    /// The alignment at rest (docs/navigation_filter.md §11).
    alignment: Alignment,
    /// GNSS: origin, datum, counters (docs/navigation_filter.md §6).
    gnss: GnssAid,
    /// Barometer: origin altitude, counters (docs/navigation_filter.md §8).
    baro: BaroAid,
    /// Which height source is fused (docs/navigation_filter.md §9).
    height: HeightSelection,
    /// Magnetometer heading: inclination, yaw alignment, counters (docs/navigation_filter.md §10).
    mag: MagHeading,
    /// The heading from GNSS velocity (docs/navigation_filter.md §18).
    heading_aid: HeadingAid,
    /// Gravity-vector fusion (docs/navigation_filter.md §20).
    gravity: GravityAid,
    /// The aiding decision and the position hold (docs/navigation_filter.md §12).
    aiding: Aiding,
    /// Test ratios, innovations, pre-flight checks, resets (docs/navigation_filter.md §13).
    report: FilterReport,
}

/// A filter with PX4's defaults ([`NavParams::default`], valid by construction: tested).
impl Default for NavFilter {
    fn default() -> Self {
        Self::unchecked(NavParams::default())
    }
}

impl NavFilter {
    /// A filter waiting for its alignment at rest (docs/navigation_filter.md §11); the only
    /// allocation is the state history.
    pub fn new(params: NavParams) -> Result<Self, NavParamsError> {
        params.validate()?;
        Ok(Self::unchecked(params))
    }

    /// [`Self::new`] for parameters known to be valid.
    fn unchecked(params: NavParams) -> Self {
        Self {
            params,
            geo_declination_rad: None,
            core: ErrorStateFilter::new(),
            alignment: Alignment::default(),
            gnss: GnssAid::default(),
            baro: BaroAid::default(),
            height: HeightSelection::new(params.height_ref),
            mag: MagHeading::default(),
            heading_aid: HeadingAid::default(),
            gravity: GravityAid::default(),
            aiding: Aiding::default(),
            report: FilterReport::default(),
        }
    }

    /// Replaces the parameters, keeping the state; a new height reference becomes the active
    /// height source (docs/navigation_filter.md §9).
    pub fn set_params(&mut self, params: NavParams) -> Result<(), NavParamsError> {
        params.validate()?;
        let new_ref = params.height_ref != self.params.height_ref;
        self.params = params;
        if new_ref {
            self.height.reference = params.height_ref;
            if self.height.active != params.height_ref {
                self.height
                    .switch(params.height_ref, &mut self.core, &self.params, &mut self.report.resets);
            }
        }
        Ok(())
    }

    /// The parameters in use.
    pub fn params(&self) -> &NavParams {
        &self.params
    }

    /// Gives the World Magnetic Model's declination at home `declination_rad` [rad] (`None`:
    /// the model gives none there), as PX4's filter looks it up at its GNSS origin.
    pub fn set_geo_declination(&mut self, declination_rad: Option<f64>) {
        self.geo_declination_rad = declination_rad;
    }

    /// The declination the magnetometer's heading uses [rad]
    /// (docs/navigation_filter.md §10, eq. (10.5)): the World Magnetic Model's at home when `EKF2_DECL_TYPE` bit 0 asks for it and
    /// the model gives one, else `EKF2_MAG_DECL`, as PX4's `Ekf::getMagDeclination`.
    pub fn declination_rad(&self) -> f64 {
        match self.geo_declination_rad {
            Some(d) if self.params.decl_type & DECL_TYPE_USE_GEO != 0 => d,
            _ => self.params.mag_declination_rad,
        }
    }

    /// The current navigation solution (docs/navigation_filter.md §1, eqs. (1.1)–(1.2)).
    pub fn estimate(&self) -> NavEstimate {
        self.core.estimate()
    }

    /// The output the controllers fly on: the nominal state with the corrections blended in
    /// over `output_tau_s` (docs/navigation_filter.md §16, eqs. (16.1)–(16.2)).
    pub fn output(&self) -> NavOutput {
        self.core.output()
    }

    /// The filter's origin in the GNSS readings' NED frame [m], once the first fix set it.
    pub fn origin_w(&self) -> Option<Vec3> {
        self.gnss.origin_w
    }

    /// Freezes the GNSS height datum: the vehicle armed and may leave the height it rested at
    /// (docs/navigation_filter.md §6, eq. (6.5)).
    pub fn freeze_height_datum(&mut self) {
        self.gnss.freeze_datum();
    }

    /// The filter's report on itself (docs/navigation_filter.md §12–§13).
    pub fn status(&self) -> NavStatus {
        let now = self.core.t_s;
        let timeout = self.params.sensor_timeout_s;
        let aligned = self.alignment.aligned;
        let since_aiding = self.aiding.last_aiding_s.map(|t| (now - t).max(0.0));
        let aided = aligned && since_aiding.is_some_and(|s| s <= self.params.noaid_timeout_s);
        NavStatus {
            t_s: now,
            attitude_valid: aligned,
            yaw_aligned: self.mag.yaw_aligned,
            horizontal_position_valid: aided && self.gnss.origin_w.is_some(),
            vertical_position_valid: aligned && self.height.fused_recently(now, self.params.height_timeout_s),
            velocity_valid: aided,
            dead_reckoning: aligned && since_aiding.is_some_and(|s| s > DEAD_RECKONING_AFTER_S),
            position_hold: aligned && self.aiding.hold_pos_w.is_some(),
            time_since_aiding_s: since_aiding,
            height_ref: self.height.reference,
            active_height: self.height.active,
            gps: self.gnss.track.status(now, timeout),
            baro: self.baro.track.status(now, timeout),
            mag: self.mag.track.status(now, timeout),
            test_ratios: self.report.ratios,
            innovations: self.report.innovations,
            preflight: self.report.preflight_failure(now, aligned, self.mag.yaw_aligned),
            resets: self.report.resets,
            origin_w: self.gnss.origin_w,
            baro_origin_m: self.baro.origin_m,
            imu_dropped: self.core.imu_dropped,
        }
    }

    /// The error-state covariance P, ordered as the `ERR_*` indices
    /// (docs/navigation_filter.md §1, eq. (1.2)).
    pub fn covariance(&self) -> &Covariance {
        &self.core.p
    }
}
