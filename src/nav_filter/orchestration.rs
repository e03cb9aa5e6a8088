//! The filter's steps per reading: which part runs, with which values, in which order. The
//! arithmetic lives in the parts (`error_state` and the aids); the order of their calls here is
//! the order of the fusions (docs/navigation_filter.md §2, §4, §6–§12, §18, §20).

use crate::math::{UnitQuat, Vec3};

use super::aiding::Aiding;
use super::alignment::initial_covariance;
use super::fuse_baro::BaroAid;
use super::fuse_mag::MagHeading;
use super::fusion::{Fusion, GpsFusion, SkipReason};
use super::nav_params::HeightSource;
use super::readings::{BaroReading, GpsReading, ImuReading, MagReading};
use super::state::Nominal;
use super::NavFilter;

impl NavFilter {
    /// Takes one IMU sample: feeds the alignment until it is done, then integrates the nominal
    /// state from the previous sample, records it in the state history and, once `predict_period_s`
    /// has accumulated, predicts the covariance and runs the time-driven checks (height-source
    /// time-outs, position hold, gravity vector) (docs/navigation_filter.md §2, eqs. (2.2)–(2.3);
    /// docs/navigation_filter.md §4, eq. (4.2); docs/navigation_filter.md §9;
    /// docs/navigation_filter.md §12, eq. (12.2); docs/navigation_filter.md §20). Non-finite,
    /// repeated or out-of-order samples are dropped and counted.
    pub fn predict(&mut self, imu: &ImuReading) {
        let Some(prev) = self.core.accept_imu(imu) else {
            return;
        };
        if !self.alignment.aligned {
            if self.alignment.aligner.add_imu(imu, self.params.align_time_s) {
                self.finish_alignment();
            }
            return;
        }
        let Some(interval) = self.core.propagate(prev, imu, self.params.output_tau_s) else {
            return;
        };
        self.heading_aid.add(&interval);
        let f_b = imu.accel_b - self.core.x.accel_bias_b;
        self.gravity.add(&f_b, interval.dt_s);
        self.gravity.add_rest(&self.core.omega_b, &f_b, interval.dt_s);
        if self.core.prediction_due(self.params.predict_period_s) {
            self.core.flush_covariance(&self.params, self.height.active);
            self.update_height_source();
            self.aiding
                .update_position_hold(&mut self.core, &self.params, self.gravity.at_rest());
            self.fuse_gravity(&f_b);
        }
    }

    /// Ends the alignment and hands what it found to the aids (docs/navigation_filter.md §11).
    fn finish_alignment(&mut self) {
        let decl = self.declination_rad();
        let found = self
            .alignment
            .finish(&mut self.core, &self.params, decl, self.height.active);
        self.mag.yaw_aligned = found.yaw_aligned;
        self.mag.tan_inclination = found.tan_inclination;
        self.baro.origin_m = found.baro_origin_m;
        self.height.active_since_s = self.core.t_s;
    }

    /// Starts the filter aligned at a known state instead of aligning at rest: position `pos_w`
    /// [m] and velocity `vel_w` [m/s] in the GPS readings' NED frame, attitude `q_wb`, at
    /// `t_s` [s], biases unknown (zero, with their initial uncertainty) — a vehicle whose filter
    /// converged before a headless run starts it in the air (docs/navigation_filter.md §11).
    /// The first barometer sample then sets the origin's barometric altitude, as after an
    /// alignment, and the GPS fixes are fused from the first one (the known state counts as
    /// aided at `t_s`).
    pub fn align_at(&mut self, t_s: f64, pos_w: Vec3, vel_w: Vec3, q_wb: UnitQuat) {
        self.core.t_s = t_s;
        let x = Nominal {
            pos_w,
            vel_w,
            q_wb,
            ..Nominal::default()
        };
        let p = initial_covariance(&self.params, self.height.active, &q_wb, 1.0);
        self.core.restart(x, p);
        self.mag.yaw_aligned = true;
        self.mag.tan_inclination = None;
        self.gnss.origin_w = Some(Vec3::zeros());
        self.baro.origin_m = None;
        self.aiding.known_state_at(t_s);
        self.height.mark_fused(self.height.active, t_s);
        self.alignment.aligned = true;
        self.height.active_since_s = t_s;
    }

    /// The time-driven height-source rules, with each source's availability
    /// (docs/navigation_filter.md §9).
    fn update_height_source(&mut self) {
        let (now, timeout) = (self.core.t_s, self.params.sensor_timeout_s);
        let (baro, gnss) = (&self.baro, &self.gnss);
        let available = |s: HeightSource| match s {
            HeightSource::Baro => baro.available(now, timeout),
            HeightSource::Gps => gnss.available(now, timeout),
        };
        self.height
            .update(available, &mut self.core, &self.params, &mut self.report.resets);
    }

    /// Fuses the direction of the bias-corrected specific force `f_b` [m/s²] while nothing aids
    /// horizontally (docs/navigation_filter.md §20, eqs. (20.1)–(20.3)).
    pub(super) fn fuse_gravity(&mut self, f_b: &Vec3) -> Fusion {
        let aided = self
            .aiding
            .horizontal_aiding_active(self.core.t_s, self.params.gps_ctrl);
        self.gravity
            .fuse(f_b, aided, &mut self.core, &self.params, self.height.active)
    }

    /// Fuses one GNSS fix arriving at `gps.t_s`, valid at `t_s − gps_delay_s`: velocity (3 axes),
    /// horizontal position and, while GNSS is the active height source, height, each gated on its
    /// own; between velocity and position the yaw estimator takes the velocity
    /// (docs/navigation_filter.md §6, eqs. (6.1)–(6.4);
    /// docs/navigation_filter.md §7, eqs. (7.1)–(7.3); docs/navigation_filter.md §18).
    pub fn fuse_gps(&mut self, gps: &GpsReading) -> GpsFusion {
        let result = self.fuse_gps_parts(gps);
        self.gnss.record(self.core.t_s, &result);
        result
    }

    fn fuse_gps_parts(&mut self, gps: &GpsReading) -> GpsFusion {
        let aligned = self.alignment.aligned;
        let prepared = self
            .gnss
            .prepare(gps, aligned, &mut self.core, &self.params, self.height.active);
        let mut fix = match prepared {
            Ok(fix) => fix,
            Err(reason) => return GpsFusion::all(Fusion::skipped(reason)),
        };
        let p = &self.params;
        let now = self.core.t_s;
        let reset = Aiding::timed_out(self.aiding.last_vel_s, now, p.noaid_timeout_s);
        let velocity = fix.fuse_velocity(reset, &mut self.core, p, &mut self.report);
        let may_reset_yaw = self.mag.yaw_aligned && self.mag.lost(now, p.sensor_timeout_s);
        if self
            .heading_aid
            .aid(&fix.vel_w, fix.var_vel, may_reset_yaw, &mut self.core, p)
        {
            self.report.resets.yaw = self.report.resets.yaw.saturating_add(1);
        }
        self.aiding.note_velocity(&velocity, now);
        let reset = Aiding::timed_out(self.aiding.last_pos_s, now, p.noaid_timeout_s);
        let horizontal = fix.fuse_horizontal(reset, &mut self.core, p, &mut self.report);
        self.aiding.note_horizontal(&horizontal, now);
        let vertical = fix.fuse_height(&mut self.core, p, &mut self.height, &mut self.report);
        GpsFusion {
            velocity,
            horizontal,
            vertical,
        }
    }

    /// Fuses one barometer sample (docs/navigation_filter.md §8, eqs. (8.1)–(8.3);
    /// docs/navigation_filter.md §9); before the alignment it feeds the alignment.
    pub fn fuse_baro(&mut self, baro: &BaroReading) -> Fusion {
        let f = match BaroAid::altitude_m(baro) {
            None => Fusion::skipped(SkipReason::Invalid),
            Some(altitude_m) if !self.alignment.aligned => {
                self.alignment.aligner.add_baro(altitude_m);
                Fusion::skipped(SkipReason::NotAligned)
            }
            Some(altitude_m) => self.baro.fuse(
                altitude_m,
                baro.t_s,
                &mut self.core,
                &self.params,
                &mut self.height,
                &mut self.report,
            ),
        };
        self.baro.track.record(self.core.t_s, f.outcome);
        f
    }

    /// Fuses one magnetometer sample as a heading
    /// (docs/navigation_filter.md §10, eqs. (10.1)–(10.4)); before the alignment it feeds the
    /// alignment, and the first sample after an alignment without one sets the yaw
    /// (docs/navigation_filter.md §11, eq. (11.4)).
    pub fn fuse_mag(&mut self, mag: &MagReading) -> Fusion {
        let f = if let Some(reason) = MagHeading::unusable(mag, &self.params) {
            Fusion::skipped(reason)
        } else if !self.alignment.aligned {
            self.alignment.aligner.add_mag(&mag.field_b);
            Fusion::skipped(SkipReason::NotAligned)
        } else {
            let decl = self.declination_rad();
            let height = self.height.active;
            self.mag
                .fuse(mag, &mut self.core, &self.params, decl, height, &mut self.report)
        };
        self.mag.track.record(self.core.t_s, f.outcome);
        f
    }
}
