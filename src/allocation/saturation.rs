//! Saturation policy (docs/allocation.md §4, eqs. (4.1)–(4.2)): keep thrust and roll/pitch, give
//! up yaw first.
//!
//! Every `ω_i²` is affine in any one scalar of the wrench, so each step intersects n intervals:
//! 1. clamp u_T to `[0, u_T,max]`;
//! 2. largest yaw scale `k_z ∈ [0, 1]` that fits: if any fits, done (with yaw air mode, first
//!    move the collective, within the air-mode ceiling, to where the full yaw fits);
//! 3. otherwise drop yaw and shift the collective to the feasible u_T closest to the request
//!    (never more than the air-mode limit above `max(u_T, u_idle)`);
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

/// How far the saturation policy may raise the collective above the request to make room for
/// torque (PX4's `MC_AIRMODE_LIM` and `MC_AIRMODE_YAW`) (docs/allocation.md §4, eq. (4.3)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Airmode {
    /// Largest rise of the collective above the request (or above idle when the request is
    /// below it), as a fraction of the full collective [-] (`MC_AIRMODE_LIM`): 0 never raises it
    /// (roll and pitch are scaled down instead, so a vehicle asked for no thrust never lifts off
    /// to make a torque); 1 or more lets it move to whatever value fits full roll and pitch.
    pub raise_limit: f64,
    /// Yaw counts too (`MC_AIRMODE_YAW`): when the full yaw torque does not fit at the request,
    /// the collective moves (within `raise_limit` upwards) to fit it before yaw is scaled down.
    pub yaw: bool,
}

impl Airmode {
    /// Air mode off (PX4's default, `MC_AIRMODE_LIM` 0): the collective never rises.
    pub const DISABLED: Self = Self {
        raise_limit: 0.0,
        yaw: false,
    };
    /// Air mode for roll and pitch without a limit (PX4's legacy `MC_AIRMODE` 1): full
    /// attitude authority at zero thrust request. The bare control laws allocate this way.
    pub const ROLL_PITCH: Self = Self {
        raise_limit: 1.0,
        yaw: false,
    };

    /// The highest collective [N] the policy may choose for a request `u_n` [N], idle collective
    /// `idle_n` [N] and full collective `thrust_max_n` [N].
    fn ceiling_n(&self, u_n: f64, idle_n: f64, thrust_max_n: f64) -> f64 {
        if self.raise_limit >= 1.0 {
            return thrust_max_n;
        }
        (u_n.max(idle_n) + self.raise_limit.max(0.0) * thrust_max_n).min(thrust_max_n)
    }
}

impl Default for Airmode {
    fn default() -> Self {
        Self::ROLL_PITCH
    }
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
    let mut fitted = bounds.largest_fraction(&base, &yaw);
    // 2b. Yaw air mode: a collective (within the ceiling) that fits the full yaw as well.
    if airmode.yaw && fitted.is_none_or(|k| k < 1.0) {
        if let Some(shifted) = yaw_collective(a, bounds, thrust_max_n, airmode, u, &roll_pitch, &yaw) {
            u = shifted;
            fitted = Some(1.0);
        }
    }
    let yaw_scale = match fitted {
        Some(k) => k,
        None => {
            // 3. Yaw dropped: shift the collective.
            // A collective that fits must also be one the motors can give, [0, u_max]: after a
            // rotor failure a rotor may have (almost) no thrust column, so no collective lifts it.
            // It must also not rise above the request (or idle) by more than air mode allows (4.3).
            let idle_n = bounds
                .interval(&[0.0; MAX_ROTORS], col_t)
                .map_or(thrust_max_n, |(lo, _)| lo.max(0.0));
            let ceiling_n = airmode.ceiling_n(u, idle_n, thrust_max_n);
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

/// Yaw air mode (step 2b): the collective nearest the request `u` [N], within `[0, ceiling]`,
/// that fits full roll/pitch and full yaw; `None` when none does.
fn yaw_collective(
    a: &[RotorArray; 4],
    bounds: SpeedBox,
    thrust_max_n: f64,
    airmode: Airmode,
    u: f64,
    roll_pitch: &RotorArray,
    yaw: &RotorArray,
) -> Option<f64> {
    let n = bounds.n;
    let idle_n = bounds
        .interval(&[0.0; MAX_ROTORS], &a[0])
        .map_or(thrust_max_n, |(lo, _)| lo.max(0.0));
    let ceiling_n = airmode.ceiling_n(u, idle_n, thrust_max_n);
    let (lo, hi) = bounds.interval(&combine(n, &[(roll_pitch, 1.0), (yaw, 1.0)]), &a[0])?;
    let (lo, hi) = (lo.max(0.0), hi.min(ceiling_n));
    (lo <= hi).then(|| u.clamp(lo, hi))
}
