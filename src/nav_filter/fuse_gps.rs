//! GNSS fusion: quality checks, the origin, delayed velocity and position observations, resets
//! at the start of aiding or after a long rejection, and GNSS height while it is the active
//! height source (docs/navigation_filter.md §6–§7, §9).

use crate::math::Vec3;

use super::aiding::Aiding;
use super::covariance::{fuse_group, innovation_variance, uncorrelate, ScalarObservation};
use super::fusion::{Fusion, FusionOutcome, GpsFusion, SkipReason};
use super::params::{HeightSource, GPS_CTRL_FUSED};
use super::readings::GpsReading;
use super::state::{ERR_POS, ERR_VEL};
use super::NavFilter;

impl NavFilter {
    /// Fuses one GNSS fix arriving at `gps.t_s`, valid at `t_s − gps_delay_s`: velocity (3 axes),
    /// horizontal position and, while GNSS is the active height source, height, each gated on its
    /// own (docs/navigation_filter.md §6, eqs. (6.1)–(6.4);
    /// docs/navigation_filter.md §7, eqs. (7.1)–(7.3)).
    pub fn fuse_gps(&mut self, gps: &GpsReading) -> GpsFusion {
        let result = self.fuse_gps_parts(gps);
        self.gps.record_parts(
            self.t_s,
            &[
                result.velocity.outcome,
                result.horizontal.outcome,
                result.vertical.outcome,
            ],
        );
        result
    }

    /// Whether the receiver's own figures allow the fix (PX4's `EKF2_GPS_CHECK` subset)
    /// (docs/navigation_filter.md §6).
    fn gps_quality_ok(&self, gps: &GpsReading) -> bool {
        let p = &self.params;
        gps.fix_3d
            && gps.satellites >= p.gps_min_satellites
            && gps.h_acc_m <= p.gps_max_h_acc_m
            && gps.v_acc_m <= p.gps_max_v_acc_m
            && gps.speed_acc_m_s <= p.gps_max_speed_acc_m_s
    }

    fn fuse_gps_parts(&mut self, gps: &GpsReading) -> GpsFusion {
        if !gps.is_finite() {
            return GpsFusion::all(Fusion::skipped(SkipReason::Invalid));
        }
        if !self.aligned {
            return GpsFusion::all(Fusion::skipped(SkipReason::NotAligned));
        }
        if self.params.gps_ctrl & GPS_CTRL_FUSED == 0 {
            return GpsFusion::all(Fusion::skipped(SkipReason::Inactive));
        }
        if !self.gps_quality_ok(gps) {
            return GpsFusion::all(Fusion::skipped(SkipReason::Quality));
        }
        self.flush_covariance();
        let t_meas = gps.t_s - self.params.gps_delay_s;
        let Some(past) = self.buffer.at(t_meas) else {
            return GpsFusion::all(Fusion::skipped(SkipReason::Stale));
        };
        let origin = self.origin_w.get_or_insert(gps.pos_w - past.pos_w);
        origin.z = self.datum.observe(gps.pos_w.z, past.pos_w.z, past.vel_w.norm());
        let origin = *origin;
        let z_w = gps.pos_w - origin;
        let p = self.params;
        let var_h = p.gps_pos_noise_m.max(gps.h_acc_m).powi(2);
        let var_v = (1.5 * p.gps_pos_noise_m).max(gps.v_acc_m).powi(2);
        let var_vel = p.gps_vel_noise_m_s.max(gps.speed_acc_m_s).powi(2);
        let now = self.t_s;

        // Velocity (6.1): ν = v_gps − v̂(t_m).
        let nu_vel = gps.vel_w - past.vel_w;
        let velocity = if Aiding::timed_out(self.aiding.last_vel_s, now, p.noaid_timeout_s) {
            self.x.vel_w += nu_vel;
            self.buffer
                .correct(self.history_start_s(), &Vec3::zeros(), &nu_vel, &Vec3::zeros());
            for i in 0..3 {
                uncorrelate(&mut self.p, ERR_VEL + i, var_vel);
            }
            self.resets.velocity = self.resets.velocity.saturating_add(1);
            Fusion {
                outcome: FusionOutcome::Reset,
                test_ratio: 0.0,
            }
        } else {
            let group = [0, 1, 2].map(|i| ScalarObservation::of_state(ERR_VEL + i, nu_vel[i], var_vel));
            let f = self.fuse_gated(&group, p.gps_vel_gate_sd, |s, v| s.innovations.gps_vel_var = v);
            self.ratios.gps_velocity = f.test_ratio;
            let var = self.innovations.gps_vel_var;
            self.preflight.velocity(now, &nu_vel, &var, p.gps_vel_gate_sd);
            f
        };
        self.innovations.gps_vel_w = nu_vel;
        self.aid_heading_from_gps(&gps.vel_w, var_vel);
        if velocity.accepted() {
            self.aiding.last_vel_s = Some(now);
            self.aiding.last_aiding_s = Some(now);
        }

        // Horizontal position (6.1), against the history as corrected by the velocity.
        let past = self.buffer.at(t_meas).unwrap_or(past);
        let nu_pos = z_w - past.pos_w;
        let horizontal = if Aiding::timed_out(self.aiding.last_pos_s, now, p.noaid_timeout_s) {
            let d = Vec3::new(nu_pos.x, nu_pos.y, 0.0);
            self.x.pos_w += d;
            self.buffer
                .correct(self.history_start_s(), &d, &Vec3::zeros(), &Vec3::zeros());
            uncorrelate(&mut self.p, ERR_POS, var_h);
            uncorrelate(&mut self.p, ERR_POS + 1, var_h);
            self.resets.horizontal_position = self.resets.horizontal_position.saturating_add(1);
            Fusion {
                outcome: FusionOutcome::Reset,
                test_ratio: 0.0,
            }
        } else {
            let group = [0, 1].map(|i| ScalarObservation::of_state(ERR_POS + i, nu_pos[i], var_h));
            let f = self.fuse_gated(&group, p.gps_pos_gate_sd, |s, v| {
                s.innovations.gps_pos_var.x = v.x;
                s.innovations.gps_pos_var.y = v.y;
            });
            self.ratios.gps_horizontal = f.test_ratio;
            let var = self.innovations.gps_pos_var;
            self.preflight
                .position(now, (nu_pos.x, nu_pos.y), (var.x, var.y), p.gps_pos_gate_sd);
            f
        };
        if horizontal.accepted() {
            self.aiding.last_pos_s = Some(now);
            self.aiding.last_aiding_s = Some(now);
        }

        // Height (6.1).
        let past = self.buffer.at(t_meas).unwrap_or(past);
        let nu_z = z_w.z - past.pos_w.z;
        self.innovations.gps_pos_w = Vec3::new(nu_pos.x, nu_pos.y, nu_z);
        let obs = ScalarObservation::of_state(ERR_POS + 2, nu_z, var_v);
        let s = innovation_variance(&self.p, &obs);
        self.innovations.gps_pos_var.z = s;
        self.preflight.gps_height(now, nu_z, s, p.gps_pos_gate_sd);
        let vertical = if self.height.active == HeightSource::Gps {
            self.fuse_active_height(HeightSource::Gps, &obs, p.gps_pos_gate_sd)
        } else {
            let ratio = nu_z * nu_z / (p.gps_pos_gate_sd.powi(2) * s);
            if self.height.reference == HeightSource::Gps {
                self.height.note_reference_test(ratio <= 1.0, now);
            }
            Fusion {
                outcome: FusionOutcome::Skipped(SkipReason::Inactive),
                test_ratio: ratio,
            }
        };
        self.ratios.gps_height = vertical.test_ratio;
        GpsFusion {
            velocity,
            horizontal,
            vertical,
        }
    }

    /// Gates and fuses a group of scalars, applying the correction; `store` receives the
    /// innovation variances (docs/navigation_filter.md §5, eqs. (5.2)–(5.7)).
    fn fuse_gated(&mut self, group: &[ScalarObservation], gate_sd: f64, store: impl FnOnce(&mut Self, Vec3)) -> Fusion {
        let update = fuse_group(&mut self.p, group, Some(gate_sd));
        let [a, b, c] = update.innovation_variance;
        store(self, Vec3::new(a, b, c));
        let outcome = match update.dx {
            Some(dx) => {
                self.apply(&dx);
                FusionOutcome::Fused
            }
            None => FusionOutcome::Rejected,
        };
        Fusion {
            outcome,
            test_ratio: update.test_ratio,
        }
    }
}
