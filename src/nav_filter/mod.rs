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
//! - `predict`: nominal integration per IMU sample, increments, covariance prediction timing.
//! - `covariance`: Φ, Q, the gated sequential scalar update, variance limits, resets.
//! - `delay_buffer`: the fixed-size state history for delayed measurements.
//! - `alignment`: roll and pitch from the accelerometer, yaw from the magnetometer, initial P.
//! - `fuse_gps`, `fuse_baro`, `fuse_mag`: the measurement models and their fusion.
//! - `datum`: the GNSS height datum, averaged until the first arming.
//! - `height`: which height source is active, fall-back and return.
//! - `aiding`: dead reckoning, validity, the position-hold pseudo-measurement.
//! - `fusion`, `status`, `estimate`: what the filter returns.
//! - `preflight`: the pre-flight checks on the low-passed innovations.
//! - `isa`: ISA pressure altitude.
//! - `yaw_estimator`, `heading_aid`: the heading from GNSS velocity (a Gaussian sum of heading
//!   hypotheses) and its fusion while the magnetometer is lost.

mod aiding;
mod alignment;
mod covariance;
mod datum;
mod delay_buffer;
mod estimate;
mod fuse_baro;
mod fuse_gps;
mod fuse_gravity;
mod fuse_mag;
mod fusion;
mod heading_aid;
mod height;
pub mod isa;
mod output;
mod params;
mod predict;
mod preflight;
mod readings;
mod state;
mod status;
mod yaw_estimator;

#[cfg(test)]
mod tests;

pub use aiding::DEAD_RECKONING_AFTER_S;
pub use estimate::NavEstimate;
pub use fusion::{Fusion, FusionOutcome, GpsFusion, SkipReason};
pub use output::NavOutput;
pub use params::{
    HeightSource, NavParams, NavParamsError, GPS_CTRL_FUSED, IMU_CTRL_GRAVITY, MAG_TYPE_NONE, MAX_DELAY_S,
};
pub use preflight::PreflightFailure;
pub use readings::{BaroReading, GpsReading, ImuReading, MagReading};
pub use state::{
    Covariance, ErrorVector, ERR_ACCEL_BIAS, ERR_ATT, ERR_BARO_OFFSET, ERR_GYRO_BIAS, ERR_POS, ERR_VEL, STATE_DIM,
};
pub use status::{Innovations, NavStatus, ResetCounters, SourceHealth, SourceStatus, TestRatios};

use crate::math::Vec3;

use aiding::Aiding;
use alignment::Aligner;
use covariance::Increments;
use datum::GnssDatum;
use delay_buffer::DelayBuffer;
use fuse_gravity::GravityAid;
use heading_aid::HeadingAidIncrements;
use height::HeightSelection;
use output::OutputLag;
use preflight::PreflightChecks;
use state::{part, Nominal};
use status::SourceTrack;
use yaw_estimator::YawEstimator;

/// The navigation filter (docs/navigation_filter.md).
#[derive(Debug, Clone)]
pub struct NavFilter {
    params: NavParams,
    x: Nominal,
    p: Covariance,
    /// Time of the latest IMU sample [s].
    t_s: f64,
    last_imu: Option<ImuReading>,
    omega_b: Vec3,
    increments: Increments,
    buffer: DelayBuffer,
    aligner: Aligner,
    aligned: bool,
    yaw_aligned: bool,
    /// tan of the field's inclination, taken when the yaw is set from the magnetometer.
    mag_tan_inclination: Option<f64>,
    origin_w: Option<Vec3>,
    /// The vertical part of `origin_w` (docs/navigation_filter.md §6, eq. (6.5)).
    datum: GnssDatum,
    baro_origin_m: Option<f64>,
    height: HeightSelection,
    aiding: Aiding,
    gps: SourceTrack,
    baro: SourceTrack,
    mag: SourceTrack,
    ratios: TestRatios,
    innovations: Innovations,
    /// The low-passed innovations the pre-flight checks read (docs/navigation_filter.md §19).
    preflight: PreflightChecks,
    resets: ResetCounters,
    imu_dropped: u32,
    /// The corrections not yet blended into the output (docs/navigation_filter.md §16).
    output_lag: OutputLag,
    /// The heading from GNSS velocity (docs/navigation_filter.md §18).
    yaw_gsf: YawEstimator,
    /// IMU increments since the last GNSS fix, for `yaw_gsf`.
    heading_aid: HeadingAidIncrements,
    gravity: GravityAid,
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
            x: Nominal::default(),
            p: Covariance::zeros(),
            t_s: 0.0,
            last_imu: None,
            omega_b: Vec3::zeros(),
            increments: Increments::default(),
            buffer: DelayBuffer::new(),
            aligner: Aligner::default(),
            aligned: false,
            yaw_aligned: false,
            mag_tan_inclination: None,
            origin_w: None,
            datum: GnssDatum::default(),
            baro_origin_m: None,
            height: HeightSelection::new(params.height_ref),
            aiding: Aiding::default(),
            gps: SourceTrack::default(),
            baro: SourceTrack::default(),
            mag: SourceTrack::default(),
            ratios: TestRatios::default(),
            innovations: Innovations::default(),
            preflight: PreflightChecks::default(),
            resets: ResetCounters::default(),
            imu_dropped: 0,
            output_lag: OutputLag::default(),
            yaw_gsf: YawEstimator::default(),
            heading_aid: HeadingAidIncrements::default(),
            gravity: GravityAid::default(),
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
                self.switch_height_source(params.height_ref);
            }
        }
        Ok(())
    }

    /// The parameters in use.
    pub fn params(&self) -> &NavParams {
        &self.params
    }

    /// The current navigation solution (docs/navigation_filter.md §1, eqs. (1.1)–(1.2)).
    pub fn estimate(&self) -> NavEstimate {
        let std = |i: usize| Vec3::new(self.p[(i, i)], self.p[(i + 1, i + 1)], self.p[(i + 2, i + 2)]).map(f64::sqrt);
        NavEstimate {
            t_s: self.t_s,
            pos_w: self.x.pos_w,
            vel_w: self.x.vel_w,
            q_wb: self.x.q_wb,
            omega_b: self.omega_b,
            accel_bias_b: self.x.accel_bias_b,
            gyro_bias_b: self.x.gyro_bias_b,
            baro_offset_m: self.x.baro_offset_m,
            pos_std_w: std(ERR_POS),
            vel_std_w: std(ERR_VEL),
            att_std_w: std(ERR_ATT),
        }
    }

    /// The output the controllers fly on: the nominal state with the corrections blended in
    /// over `output_tau_s` (docs/navigation_filter.md §16, eqs. (16.1)–(16.2)).
    pub fn output(&self) -> NavOutput {
        let (pos_w, vel_w, q_wb) = self.output_lag.apply(&self.x);
        NavOutput {
            t_s: self.t_s,
            pos_w,
            vel_w,
            q_wb,
            omega_b: self.omega_b,
        }
    }

    /// The filter's origin in the GNSS readings' NED frame [m], once the first fix set it.
    pub fn origin_w(&self) -> Option<Vec3> {
        self.origin_w
    }

    /// Freezes the GNSS height datum: the vehicle armed and may leave the height it rested at
    /// (docs/navigation_filter.md §6, eq. (6.5)).
    pub fn freeze_height_datum(&mut self) {
        self.datum.freeze();
    }

    /// The filter's report on itself (docs/navigation_filter.md §12–§13).
    pub fn status(&self) -> NavStatus {
        let now = self.t_s;
        let timeout = self.params.sensor_timeout_s;
        let since_aiding = self.aiding.last_aiding_s.map(|t| (now - t).max(0.0));
        let aided = self.aligned && since_aiding.is_some_and(|s| s <= self.params.noaid_timeout_s);
        NavStatus {
            t_s: now,
            attitude_valid: self.aligned,
            yaw_aligned: self.yaw_aligned,
            horizontal_position_valid: aided && self.origin_w.is_some(),
            vertical_position_valid: self.aligned && self.height_fused_recently(),
            velocity_valid: aided,
            dead_reckoning: self.aligned && since_aiding.is_some_and(|s| s > DEAD_RECKONING_AFTER_S),
            position_hold: self.aligned && self.aiding.hold_pos_w.is_some(),
            time_since_aiding_s: since_aiding,
            height_ref: self.height.reference,
            active_height: self.height.active,
            gps: self.gps.status(now, timeout),
            baro: self.baro.status(now, timeout),
            mag: self.mag.status(now, timeout),
            test_ratios: self.ratios,
            innovations: self.innovations,
            preflight: if self.aligned {
                self.preflight.failure(now, self.yaw_aligned)
            } else {
                Some(PreflightFailure::Heading)
            },
            resets: self.resets,
            origin_w: self.origin_w,
            baro_origin_m: self.baro_origin_m,
            imu_dropped: self.imu_dropped,
        }
    }

    /// The error-state covariance P, ordered as the `ERR_*` indices
    /// (docs/navigation_filter.md §1, eq. (1.2)).
    pub fn covariance(&self) -> &Covariance {
        &self.p
    }

    /// Oldest time a future measurement can refer to: now minus the longest configured delay,
    /// with a margin of two IMU periods [s] (docs/navigation_filter.md §7, eq. (7.3)).
    fn history_start_s(&self) -> f64 {
        let p = &self.params;
        self.t_s - p.gps_delay_s.max(p.baro_delay_s).max(p.mag_delay_s) - 0.002
    }

    /// Injects an error estimate into the nominal state and the state history
    /// (docs/navigation_filter.md §5, eq. (5.7); docs/navigation_filter.md §7, eq. (7.3)).
    fn apply(&mut self, dx: &ErrorVector) {
        self.x.inject(dx);
        self.output_lag
            .corrected(&part(dx, ERR_POS), &part(dx, ERR_VEL), &part(dx, ERR_ATT));
        self.buffer.correct(
            self.history_start_s(),
            &part(dx, ERR_POS),
            &part(dx, ERR_VEL),
            &part(dx, ERR_ATT),
        );
    }
}
