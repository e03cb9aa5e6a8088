//! AUTO.RTL's phases: climb to `RTL_RETURN_ALT` above home (or stay higher), fly over home at
//! that height, then descend and land there.

use crate::control::VehicleState;
use crate::math::Vec3;

use super::Commander;

/// Where a return is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum RtlPhase {
    /// Climbing to the return altitude.
    Climb,
    /// Flying over home.
    Return,
    /// Descending to land at home.
    Descend,
}

impl Commander {
    /// One AUTO.RTL tick: when a phase's path is flown, the next phase starts from here.
    pub(super) fn advance_rtl(&mut self, x: &VehicleState, yaw: f64, t_s: f64) {
        if !self.guidance.finished(t_s) {
            return;
        }
        match self.rtl_phase {
            RtlPhase::Climb => {
                self.rtl_phase = RtlPhase::Return;
                let home_at_alt = Vec3::new(self.home_w.x, self.home_w.y, x.pos_w.z);
                self.guidance = self.path_to(x, home_at_alt, yaw, self.cruise_speed(), t_s);
            }
            RtlPhase::Return => {
                self.rtl_phase = RtlPhase::Descend;
                self.guidance = self.descend(x, yaw, t_s);
            }
            RtlPhase::Descend => {}
        }
    }
}
