//! `run.csv` of a scenario run: every signal the homework plots, one row per tick.
//!
//! Columns (SI units, NED world, FRD body, angles in rad):
//! `t, x,y,z, x_ref,y_ref,z_ref, ex,ey,ez, evx,evy,evz, roll,pitch,yaw, roll_ref,pitch_ref,yaw_ref,
//! eR_x,eR_y,eR_z, ew_x,ew_y,ew_z, thrust, tau_x,tau_y,tau_z, omega_1..omega_n,
//! fx_hat,fy_hat,fz_hat, tx_hat,ty_hat,tz_hat, fx_true,fy_true,fz_true, tx_true,ty_true,tz_true,
//! mass_hat, saturated, vx,vy,vz, p,q,r` (world velocity [m/s], body rates FRD [rad/s]). The
//! attitude errors are e_R, e_ω (geometric) or e_η, ė_η (RPY laws); thrust and torques are the
//! applied ones; `*_hat` are empty when the estimator is off.

use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;

use crate::lockstep::TickView;
use crate::math::euler_zyx;

/// Header of `run.csv` for `rotors` rotors.
pub fn header(rotors: usize) -> String {
    let mut h = String::from(
        "t,x,y,z,x_ref,y_ref,z_ref,ex,ey,ez,evx,evy,evz,roll,pitch,yaw,roll_ref,pitch_ref,yaw_ref,\
         eR_x,eR_y,eR_z,ew_x,ew_y,ew_z,thrust,tau_x,tau_y,tau_z",
    );
    for i in 1..=rotors {
        let _ = write!(h, ",omega_{i}");
    }
    h.push_str(
        ",fx_hat,fy_hat,fz_hat,tx_hat,ty_hat,tz_hat,fx_true,fy_true,fz_true,tx_true,ty_true,tz_true,mass_hat,saturated,\
         vx,vy,vz,p,q,r",
    );
    h
}

/// Buffered writer of `run.csv`.
pub struct RunCsv {
    out: std::io::BufWriter<std::fs::File>,
    line: String,
}

impl RunCsv {
    /// Creates `path` and writes the header.
    pub fn create(path: &Path, rotors: usize) -> std::io::Result<Self> {
        let mut out = std::io::BufWriter::with_capacity(1 << 16, std::fs::File::create(path)?);
        writeln!(out, "{}", header(rotors))?;
        Ok(Self {
            out,
            line: String::with_capacity(1024),
        })
    }

    /// Appends one row.
    pub fn row(&mut self, r: &TickView) -> std::io::Result<()> {
        let l = &mut self.line;
        l.clear();
        let eta = euler_zyx(&r.state.r_wb);
        let _ = write!(l, "{}", r.t_s);
        for v in [r.state.pos_w, r.ref_w] {
            let _ = write!(l, ",{},{},{}", v.x, v.y, v.z);
        }
        match r.step {
            Some(step) => {
                let c = &step.control;
                for v in [
                    c.errors.pos_w,
                    c.errors.vel_w,
                    eta,
                    c.eta_desired,
                    c.errors.attitude,
                    c.errors.rate,
                ] {
                    let _ = write!(l, ",{},{},{}", v.x, v.y, v.z);
                }
                let applied = &step.allocation.applied;
                let t = &applied.torque_b;
                let _ = write!(l, ",{},{},{},{}", applied.thrust_n, t.x, t.y, t.z);
            }
            None => {
                l.push_str(",,,,,,");
                let _ = write!(l, ",{},{},{}", eta.x, eta.y, eta.z);
                l.push_str(",,,,,,,,,,0,0,0,0");
            }
        }
        for w in r.motor_speeds {
            let _ = write!(l, ",{w}");
        }
        let estimate = r.step.and_then(|s| s.estimate);
        match &estimate {
            Some(e) => {
                let (f, tq) = (e.force_w, e.torque_b);
                let _ = write!(l, ",{},{},{},{},{},{}", f.x, f.y, f.z, tq.x, tq.y, tq.z);
            }
            None => l.push_str(",,,,,,"),
        }
        let (f, tq) = (r.truth.external_and_drag_force_w(), r.truth.external_torque_b);
        let _ = write!(l, ",{},{},{},{},{},{}", f.x, f.y, f.z, tq.x, tq.y, tq.z);
        match &estimate {
            Some(e) => {
                let _ = write!(l, ",{}", e.mass_kg);
            }
            None => l.push(','),
        }
        let saturated = r.step.is_some_and(|s| s.allocation.saturation.is_saturated());
        let _ = write!(l, ",{}", u8::from(saturated));
        let (v, w) = (r.state.vel_w, r.state.omega_b);
        let _ = writeln!(l, ",{},{},{},{},{},{}", v.x, v.y, v.z, w.x, w.y, w.z);
        self.out.write_all(l.as_bytes())
    }

    /// Flushes the buffer to the file.
    pub fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }

    /// Flushes the file.
    pub fn finish(mut self) -> std::io::Result<()> {
        self.out.flush()
    }
}
