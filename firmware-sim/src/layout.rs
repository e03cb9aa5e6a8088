//! Rotor hub positions and spins from a ring or an explicit list
//! (docs/allocation.md §1, eqs. (1.1)–(1.3)).
//!
//! Rotor i sits at angle α_i counted counter-clockwise seen from above from body +x, which in
//! FRD runs from +x towards −y: hub `r_i = l [cos α_i, −sin α_i, 0]ᵀ + z e3`.

use nalgebra::Vector3;

use crate::file_schema::FileRotors;
use crate::params::{ParamsError, RotorGeometry};
use crate::validate::{finite, non_negative, positive, required, Checker};

/// Fewest rotors a vehicle may have: four inputs are needed for [u_T, τx, τy, τz].
pub const MIN_ROTORS: usize = 4;
/// Most rotors a vehicle may have.
pub const MAX_ROTORS: usize = 16;
/// Largest difference in rotor-plane height still called coplanar [m].
const COPLANAR_TOLERANCE_M: f64 = 1e-6;

/// Hub positions and spins from `[rotors.ring]` or `[[rotors.rotor]]`, checked for count,
/// coplanarity and overlap.
pub(crate) fn rotor_geometry(
    check: &Checker,
    r: &FileRotors,
    radius_m: f64,
) -> Result<Vec<RotorGeometry>, ParamsError> {
    let (rotors, base) = match (&r.ring, &r.rotor) {
        (Some(_), Some(_)) => {
            return Err(check.error(
                "rotors",
                "give either [rotors.ring] or [[rotors.rotor]], not both".to_string(),
            ))
        }
        (None, None) => {
            return Err(check.error(
                "rotors",
                "missing field: give [rotors.ring] or [[rotors.rotor]]".to_string(),
            ))
        }
        (Some(ring), None) => {
            let count = required(check, ring.count, "rotors.ring.count")?;
            check_count(check, count, "rotors.ring.count")?;
            let n = count as usize;
            let arm = positive(check, required(check, ring.arm, "rotors.ring.arm")?, "rotors.ring.arm")?;
            let first = finite(check, ring.first_angle.unwrap_or(0.0), "rotors.ring.first_angle")?.to_radians();
            let first_sign = spin_sign(
                check,
                ring.first_spin.as_deref().unwrap_or("cw"),
                "rotors.ring.first_spin",
            )?;
            let z = finite(check, ring.z.unwrap_or(0.0), "rotors.ring.z")?;
            let rotors = (0..n)
                .map(|k| {
                    let alpha = first + std::f64::consts::TAU * k as f64 / n as f64;
                    let sign = if k % 2 == 0 { first_sign } else { -first_sign };
                    RotorGeometry {
                        hub_b: hub(arm, alpha, z),
                        reaction_sign: sign,
                    }
                })
                .collect::<Vec<_>>();
            (rotors, "rotors.ring.arm".to_string())
        }
        (None, Some(list)) => {
            check_count(check, list.len() as i64, "rotors.rotor")?;
            let mut rotors = Vec::with_capacity(list.len());
            for (i, f) in list.iter().enumerate() {
                let field = |s: &str| format!("rotors.rotor[{i}].{s}");
                let angle = finite(check, required(check, f.angle, &field("angle"))?, &field("angle"))?;
                let arm = non_negative(check, required(check, f.arm, &field("arm"))?, &field("arm"))?;
                let z = finite(check, f.z.unwrap_or(0.0), &field("z"))?;
                let spin = required(check, f.spin.as_deref(), &field("spin"))?;
                let sign = spin_sign(check, spin, &field("spin"))?;
                rotors.push(RotorGeometry {
                    hub_b: hub(arm, angle.to_radians(), z),
                    reaction_sign: sign,
                });
            }
            (rotors, "rotors.rotor".to_string())
        }
    };
    check_coplanar(check, &rotors, &base)?;
    check_overlap(check, &rotors, radius_m, &base)?;
    Ok(rotors)
}

/// Smallest distance between two hubs [m].
pub(crate) fn smallest_hub_spacing(rotors: &[RotorGeometry]) -> f64 {
    let mut best = f64::INFINITY;
    for (i, a) in rotors.iter().enumerate() {
        for b in &rotors[i + 1..] {
            best = best.min((a.hub_b - b.hub_b).norm());
        }
    }
    best
}

fn hub(arm: f64, alpha: f64, z: f64) -> Vector3<f64> {
    Vector3::new(arm * alpha.cos(), -arm * alpha.sin(), z)
}

fn check_count(check: &Checker, count: i64, field: &str) -> Result<(), ParamsError> {
    if count < MIN_ROTORS as i64 {
        return Err(check.error(
            field,
            format!("{count} rotors: fewer than {MIN_ROTORS} cannot control thrust and three torques"),
        ));
    }
    if count > MAX_ROTORS as i64 {
        return Err(check.error(field, format!("{count} rotors: more than the supported {MAX_ROTORS}")));
    }
    Ok(())
}

fn spin_sign(check: &Checker, spin: &str, field: &str) -> Result<f64, ParamsError> {
    match spin {
        "cw" => Ok(-1.0),
        "ccw" => Ok(1.0),
        other => Err(check.error(
            field,
            format!("unknown spin \"{other}\"; expected \"cw\" or \"ccw\" (seen from above)"),
        )),
    }
}

fn check_coplanar(check: &Checker, rotors: &[RotorGeometry], base: &str) -> Result<(), ParamsError> {
    let z0 = rotors.first().map_or(0.0, |r| r.hub_b.z);
    for (i, r) in rotors.iter().enumerate() {
        if (r.hub_b.z - z0).abs() > COPLANAR_TOLERANCE_M {
            return Err(check.error(
                &format!("{base}[{i}].z"),
                format!(
                    "rotor {} is not coplanar: z = {} m, rotor 1 has z = {z0} m",
                    i + 1,
                    r.hub_b.z
                ),
            ));
        }
    }
    Ok(())
}

fn check_overlap(check: &Checker, rotors: &[RotorGeometry], radius_m: f64, base: &str) -> Result<(), ParamsError> {
    for (i, a) in rotors.iter().enumerate() {
        for (j, b) in rotors.iter().enumerate().skip(i + 1) {
            let gap = (a.hub_b - b.hub_b).norm();
            if gap < 2.0 * radius_m {
                let field = if base.ends_with("arm") {
                    base.to_string()
                } else {
                    format!("{base}[{j}]")
                };
                return Err(check.error(
                    &field,
                    format!(
                        "rotors {} and {} overlap: hubs {gap:.4} m apart, less than two radii ({:.4} m)",
                        i + 1,
                        j + 1,
                        2.0 * radius_m
                    ),
                ));
            }
        }
    }
    Ok(())
}
