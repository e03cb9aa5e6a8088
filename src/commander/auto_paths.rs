//! [`AutoPaths`]: the AUTO modes' paths, climbs and descents from the settings, the cruise speed
//! (`MPC_XY_CRUISE` or DO_CHANGE_SPEED's) and the ground height, capped at `MPC_XY_VEL_MAX`.
//! A read-only view the commander builds for each use; every concern that flies a path (take-off,
//! return, mission, GOTO, orbit, follow-me) asks it for its limits and guidance.

use crate::control::VehicleState;
use crate::guidance::{DescentProfile, Guidance, MotionLimits, Track, TrackLeg};
use crate::math::{euler_zyx, Vec3};

use super::CommanderParams;

/// The settings and speeds an AUTO path is planned with.
#[derive(Debug, Clone, Copy)]
pub(super) struct AutoPaths<'a> {
    /// Settings.
    params: &'a CommanderParams,
    /// DO_CHANGE_SPEED's speed, when one is set [m/s].
    speed_override: Option<f64>,
    /// DO_CHANGE_SPEED's climb and descent speeds, when set [m/s].
    vertical_speeds: (Option<f64>, Option<f64>),
    /// Where the land detector last touched the ground (z, NED), if it did [m].
    ground_z_m: Option<f64>,
    /// Home's z (NED) [m].
    home_z_m: f64,
}

impl<'a> AutoPaths<'a> {
    /// Paths under `params` with DO_CHANGE_SPEED's horizontal `speed_override` and
    /// `vertical_speeds` (climb, descent) [m/s], the ground last touched at `ground_z_m` [m] and
    /// home at `home_z_m` [m].
    pub fn new(
        params: &'a CommanderParams,
        (speed_override, vertical_speeds): (Option<f64>, (Option<f64>, Option<f64>)),
        ground_z_m: Option<f64>,
        home_z_m: f64,
    ) -> Self {
        Self {
            params,
            speed_override,
            vertical_speeds,
            ground_z_m,
            home_z_m,
        }
    }

    /// The settings.
    pub fn params(&self) -> &'a CommanderParams {
        self.params
    }

    /// Home's z (NED) [m]: mission heights above home are read from it.
    pub fn home_z_m(&self) -> f64 {
        self.home_z_m
    }

    /// Horizontal speed of the AUTO modes [m/s]: DO_CHANGE_SPEED's, else `MPC_XY_CRUISE`.
    pub fn cruise_speed(&self) -> f64 {
        self.speed_override.unwrap_or(self.params.cruise_speed_m_s)
    }

    /// AUTO path limits for a horizontal speed of `horizontal_m_s` [m/s], capped at
    /// `MPC_XY_VEL_MAX`; vertical speeds DO_CHANGE_SPEED's, else `MPC_Z_V_AUTO_UP` / `_DN`,
    /// within `MPC_Z_VEL_MAX_UP` / `_DN`; every other limit as set.
    pub fn limits(&self, horizontal_m_s: f64) -> MotionLimits {
        let (m, auto) = (&self.params.motion, &self.params.auto_vertical);
        let (up, down) = self.vertical_speeds;
        MotionLimits {
            horizontal_m_s: horizontal_m_s.min(m.horizontal_m_s),
            up_m_s: up.unwrap_or(auto.up_m_s).min(m.up_m_s),
            down_m_s: down.unwrap_or(auto.down_m_s).min(m.down_m_s),
            ..*m
        }
    }

    /// The limits of a take-off climb at `height_m` [m] above the ground, as PX4's AUTO
    /// take-off: below `MPC_LAND_ALT1` at `MPC_TKO_SPEED`, reached in `MPC_TKO_RAMP_T`; above it
    /// as any AUTO path.
    pub fn takeoff_limits(&self, height_m: f64) -> MotionLimits {
        let limits = self.limits(self.cruise_speed());
        let auto = &self.params.auto_vertical;
        if height_m >= self.params.land_alt1_m {
            return limits;
        }
        let speed = auto.takeoff_m_s.min(limits.up_m_s);
        MotionLimits {
            up_m_s: speed,
            // A ramp time of 0 turns the ramp off (PX4).
            acc_up_m_s2: match auto.takeoff_ramp_s {
                ramp if ramp > 0.0 => limits.acc_up_m_s2.min(speed / ramp),
                _ => limits.acc_up_m_s2,
            },
            ..limits
        }
    }

    /// A take-off climb from where the vehicle is to `to_w` [m] at heading `yaw` [rad] (PX4's
    /// AUTO take-off speeds, [`Self::takeoff_limits`], kept as it climbs by
    /// [`Self::climb_limits`]).
    pub fn climb_to(&self, x: &VehicleState, to_w: Vec3, yaw: f64, t_s: f64) -> Guidance {
        let leg = TrackLeg {
            target_w: to_w,
            next_w: None,
            accept_m: self.params.mission.accept_m,
            yaw_rad: yaw,
            cruise_m_s: self.cruise_speed(),
            corner_gain: self.params.mission.corner_gain,
        };
        let limits = self.climb_limits(x);
        Guidance::Track(Track::new(x.pos_w, x.vel_w, yaw, t_s, leg, limits))
    }

    /// A take-off climb's limits at the height of `x` (below or above `MPC_LAND_ALT1`).
    pub fn climb_limits(&self, x: &VehicleState) -> MotionLimits {
        self.takeoff_limits(self.height_above_ground(x))
    }

    /// Height of `x` above the ground the land detector last touched, else above home [m].
    fn height_above_ground(&self, x: &VehicleState) -> f64 {
        self.ground_z_m.unwrap_or(self.home_z_m) - x.pos_w.z
    }

    /// A path at `speed_m_s` [m/s] from where the vehicle is to `to_w` [m], ending at heading
    /// `to_yaw_rad` [rad] (turned the short way within `MPC_YAWRAUTO_MAX`).
    pub fn path_to(&self, x: &VehicleState, to_w: Vec3, to_yaw_rad: f64, speed_m_s: f64, t_s: f64) -> Guidance {
        let yaw = euler_zyx(&x.r_wb).z;
        Guidance::path(x.pos_w, to_w, yaw, to_yaw_rad, &self.limits(speed_m_s), t_s)
    }

    /// A landing descent from where the vehicle is, at heading `yaw` [rad]: `MPC_Z_V_AUTO_DN`
    /// above `MPC_LAND_ALT1`, slowing to `MPC_LAND_SPEED` below `MPC_LAND_ALT2`.
    pub fn descend(&self, x: &VehicleState, yaw: f64, t_s: f64) -> Guidance {
        Guidance::Descend {
            xy_w: x.pos_w,
            yaw_rad: yaw,
            z_start_m: x.pos_w.z,
            start_s: t_s,
            start_down_m_s: x.vel_w.z,
            profile: DescentProfile {
                fast_m_s: self.limits(0.0).down_m_s,
                land_m_s: self.params.land_speed_m_s,
                slow_from_m: self.params.land_alt1_m,
                land_from_m: self.params.land_alt2_m,
                acc_m_s2: self.params.motion.acc_down_m_s2,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(z: f64) -> VehicleState {
        VehicleState::at_rest(0.0, Vec3::new(0.0, 0.0, z))
    }

    #[test]
    fn the_cruise_speed_is_do_change_speeds_else_mpc_xy_cruise_within_mpc_xy_vel_max() {
        let p = CommanderParams::default();
        let paths = AutoPaths::new(&p, (None, (None, None)), None, 0.0);
        assert_eq!(paths.cruise_speed(), p.cruise_speed_m_s);
        let fast = AutoPaths::new(&p, (Some(100.0), (None, None)), None, 0.0);
        assert_eq!(fast.cruise_speed(), 100.0);
        assert_eq!(fast.limits(fast.cruise_speed()).horizontal_m_s, p.motion.horizontal_m_s);
        let slow_climb = AutoPaths::new(&p, (None, (Some(0.5), Some(100.0))), None, 0.0);
        assert_eq!(slow_climb.limits(1.0).up_m_s, 0.5, "DO_CHANGE_SPEED's climb");
        assert_eq!(
            slow_climb.limits(1.0).down_m_s,
            p.motion.down_m_s,
            "within MPC_Z_VEL_MAX_DN"
        );
    }

    #[test]
    fn the_climb_is_paced_by_the_height_above_the_ground_touched_else_home() {
        let p = CommanderParams::default();
        let low = p.auto_vertical.takeoff_m_s.min(p.auto_vertical.up_m_s);
        // 5 m above home: below MPC_LAND_ALT1, at MPC_TKO_SPEED.
        let over_home = AutoPaths::new(&p, (None, (None, None)), None, 0.0);
        assert_eq!(over_home.climb_limits(&at(-5.0)).up_m_s, low);
        // The ground touched 20 m lower: above MPC_LAND_ALT1, at the AUTO climb speed.
        let over_ground = AutoPaths::new(&p, (None, (None, None)), Some(20.0), 0.0);
        assert_eq!(
            over_ground.climb_limits(&at(-5.0)).up_m_s,
            over_ground.limits(0.0).up_m_s
        );
    }

    #[test]
    fn a_descent_starts_where_the_vehicle_is_with_the_landing_profile() {
        let p = CommanderParams::default();
        let paths = AutoPaths::new(&p, (None, (None, None)), None, 0.0);
        let Guidance::Descend {
            xy_w,
            z_start_m,
            profile,
            ..
        } = paths.descend(&at(-8.0), 0.3, 2.0)
        else {
            panic!("a descent");
        };
        assert_eq!((xy_w, z_start_m), (Vec3::new(0.0, 0.0, -8.0), -8.0));
        assert_eq!(profile.land_m_s, p.land_speed_m_s);
        assert_eq!(profile.fast_m_s, paths.limits(0.0).down_m_s);
    }
}
