//! Saturation policy (docs/allocation.md §4, eqs. (4.1)–(4.2)): keep thrust and roll/pitch, give
//! up yaw first.
//!
//! Every `ω_i²` is affine in any one scalar of the wrench, so each step intersects n intervals:
//! 1. clamp u_T to `[0, u_T,max]`;
//! 2. largest yaw scale `k_z ∈ [0, 1]` that fits: if any fits, done;
//! 3. otherwise drop yaw and shift the collective to the feasible u_T closest to the request
//!    (with air mode off never above `max(u_T, u_idle)`);
//! 4. if no collective fits, scale roll/pitch by the largest `s ∈ [0, 1]` that lets one fit
//!    (bisection on step 3);
//! 5. recover as much yaw as the remaining margin allows;
//! 6. clip to the box to absorb round-off.

use crate::airframe::MAX_ROTORS;

/// What the saturation policy gave up in one allocation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Saturation {
    /// Fraction of the requested yaw torque delivered [-].
    pub yaw_scale: f64,
    /// Delivered minus requested collective thrust [N].
    pub thrust_shift_n: f64,
    /// Fraction of the requested roll and pitch torque delivered [-].
    pub roll_pitch_scale: f64,
    /// Bit i set when rotor i's command sits on a speed limit.
    pub clipped: u32,
}

impl Saturation {
    /// Nothing given up.
    pub const NONE: Self = Self {
        yaw_scale: 1.0,
        thrust_shift_n: 0.0,
        roll_pitch_scale: 1.0,
        clipped: 0,
    };

    /// True when any part of the requested wrench was not delivered.
    pub fn is_saturated(&self) -> bool {
        self.yaw_scale < 1.0 || self.roll_pitch_scale < 1.0 || self.thrust_shift_n != 0.0
    }
}

/// Whether the saturation policy may raise the collective above the request to make room for
/// roll and pitch torque (PX4's `MC_AIRMODE`) (docs/allocation.md §4, eq. (4.3)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Airmode {
    /// The collective is never raised above the request (or above idle when the request is
    /// below it): roll and pitch are scaled down instead. A vehicle asked for no thrust never
    /// lifts off to make a torque. PX4's default (`MC_AIRMODE` = 0).
    Disabled,
    /// The collective moves to whatever value fits full roll and pitch, up as well as down
    /// (`MC_AIRMODE` = 1): full attitude authority at zero thrust request.
    #[default]
    RollPitch,
}

/// Fixed-size vector of per-rotor values.
pub(crate) type RotorArray = [f64; MAX_ROTORS];

/// The box `[lo, hi]` every `ω_i²` must stay in [(rad/s)²], and the n in use.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SpeedBox {
    pub n: usize,
    pub lo: f64,
    pub hi: f64,
}

impl SpeedBox {
    /// Round-off allowance when testing feasibility [(rad/s)²].
    fn tol(&self) -> f64 {
        1e-12 * self.hi
    }

    /// Interval of k for which `base + k dir` stays in the box, or None.
    fn interval(&self, base: &RotorArray, dir: &RotorArray) -> Option<(f64, f64)> {
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        let tol = self.tol();
        for (b, d) in base[..self.n].iter().zip(&dir[..self.n]) {
            if d.abs() <= f64::EPSILON * self.hi.max(1.0) * 1e-6 {
                if *b < self.lo - tol || *b > self.hi + tol {
                    return None;
                }
                continue;
            }
            let k1 = (self.lo - tol - b) / d;
            let k2 = (self.hi + tol - b) / d;
            lo = lo.max(k1.min(k2));
            hi = hi.min(k1.max(k2));
        }
        (lo <= hi).then_some((lo, hi))
    }

    /// Largest k in [0, 1] with `base + k dir` in the box.
    fn largest_fraction(&self, base: &RotorArray, dir: &RotorArray) -> Option<f64> {
        let (lo, hi) = self.interval(base, dir)?;
        (lo <= 1.0 && hi >= 0.0).then(|| hi.min(1.0))
    }
}

/// `a·x + b·y + …` over the first n entries.
fn combine(n: usize, terms: &[(&RotorArray, f64)]) -> RotorArray {
    let mut out = [0.0; MAX_ROTORS];
    for (col, k) in terms {
        for (o, c) in out[..n].iter_mut().zip(&col[..n]) {
            *o += c * k;
        }
    }
    out
}

/// Allocates `w = [u_T, τx, τy, τz]` through the columns `a` of the min-norm inverse with the
/// priority above; writes `ω²` into `out` and reports what was given up. `thrust_max_n` is
/// the collective at full speed [N].
pub(crate) fn allocate(
    a: &[RotorArray; 4],
    bounds: SpeedBox,
    thrust_max_n: f64,
    airmode: Airmode,
    w: [f64; 4],
    out: &mut RotorArray,
) -> Saturation {
    let n = bounds.n;
    let [col_t, col_x, col_y, col_z] = a;
    let [u_req, tx, ty, tz] = w;
    // 1. Collective within what the motors can give.
    let mut u = u_req.clamp(0.0, thrust_max_n);
    let roll_pitch = combine(n, &[(col_x, tx), (col_y, ty)]);
    let yaw = combine(n, &[(col_z, tz)]);
    let mut rp_scale = 1.0;

    // 2. Full roll/pitch and collective; as much yaw as fits.
    let base = combine(n, &[(col_t, u), (&roll_pitch, 1.0)]);
    let yaw_scale = match bounds.largest_fraction(&base, &yaw) {
        Some(k) => k,
        None => {
            // 3. Yaw dropped: shift the collective.
            // A collective that fits must also be one the motors can give, [0, u_max]: after a
            // rotor failure a rotor may have (almost) no thrust column, so no collective lifts it.
            // Without air mode it must also not exceed the request, or idle (4.3).
            let ceiling_n = match airmode {
                Airmode::RollPitch => thrust_max_n,
                Airmode::Disabled => {
                    let idle_n = bounds
                        .interval(&[0.0; MAX_ROTORS], col_t)
                        .map_or(thrust_max_n, |(lo, _)| lo.max(0.0));
                    u.max(idle_n).min(thrust_max_n)
                }
            };
            let fit_collective = |s: f64| {
                bounds
                    .interval(&combine(n, &[(&roll_pitch, s)]), col_t)
                    .filter(|(lo, hi)| *hi >= 0.0 && *lo <= ceiling_n)
            };
            let (lo, hi) = match fit_collective(1.0) {
                Some(range) => range,
                None => {
                    // 4. Scale roll/pitch down until some collective fits.
                    let (mut good, mut bad) = (0.0, 1.0);
                    for _ in 0..50 {
                        let mid = 0.5 * (good + bad);
                        if fit_collective(mid).is_some() {
                            good = mid;
                        } else {
                            bad = mid;
                        }
                    }
                    rp_scale = good;
                    fit_collective(good).unwrap_or((0.0, 0.0))
                }
            };
            u = u.clamp(lo.max(0.0), hi.clamp(0.0, thrust_max_n));
            // 5. Recover what yaw the margin allows.
            let base = combine(n, &[(col_t, u), (&roll_pitch, rp_scale)]);
            bounds.largest_fraction(&base, &yaw).unwrap_or(0.0)
        }
    };
    *out = combine(n, &[(col_t, u), (&roll_pitch, rp_scale), (&yaw, yaw_scale)]);
    // 6. Clip round-off and note rotors on a limit.
    let mut clipped = 0u32;
    let tol = bounds.tol();
    for (i, x) in out[..n].iter_mut().enumerate() {
        *x = x.clamp(bounds.lo, bounds.hi);
        if *x <= bounds.lo + tol || *x >= bounds.hi - tol {
            clipped |= 1 << i;
        }
    }
    Saturation {
        yaw_scale,
        thrust_shift_n: u - u_req,
        roll_pitch_scale: rp_scale,
        clipped,
    }
}
