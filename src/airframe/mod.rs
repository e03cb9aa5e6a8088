//! The flight controller's view of an airframe: what it believes the vehicle's mass, inertia and
//! rotors are. Parsed with the FC's own types (docs/architecture.md §2); the plant reads the same file
//! with its own. Mass and inertia come from `[fc]` when it gives them (a believed vehicle that
//! differs from the true one), else from `[vehicle]`.

mod presets;
mod schema;
mod source;

pub use presets::{preset_names, preset_text, PRESETS};
pub use source::AirframeSource;

use schema::{AirframeFile, RotorsTable};
use thiserror::Error;

use crate::math::Vec3;

/// Fewest rotors the allocation can serve (four inputs: u_T, τx, τy, τz).
pub const MIN_ROTORS: usize = 4;
/// Most rotors the allocation serves.
pub const MAX_ROTORS: usize = 16;

/// A refused airframe: file (or preset), field and reason.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{origin}: {}{reason}", if field.is_empty() { String::new() } else { format!("{field}: ") })]
pub struct AirframeError {
    /// Preset name or file path.
    pub origin: String,
    /// Dotted path of the field at fault (empty when the whole file or name is at fault).
    pub field: String,
    /// What is wrong.
    pub reason: String,
}

impl AirframeError {
    pub(crate) fn new(origin: &str, field: &str, reason: String) -> Self {
        Self {
            origin: origin.to_string(),
            field: field.to_string(),
            reason,
        }
    }
}

/// Propeller turning direction seen from above.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Spin {
    /// Clockwise seen from above: reaction torque −c_Q ω² about +z_b (FRD).
    Clockwise,
    /// Counter-clockwise seen from above: reaction torque +c_Q ω² about +z_b.
    CounterClockwise,
}

impl Spin {
    /// Sign of the yaw-row entry of this rotor's column of G_q (docs/allocation.md §1, eq. (1.3)).
    pub fn yaw_sign(self) -> f64 {
        match self {
            Self::Clockwise => -1.0,
            Self::CounterClockwise => 1.0,
        }
    }

    fn parse(s: &str) -> Option<Self> {
        match s {
            "cw" => Some(Self::Clockwise),
            "ccw" => Some(Self::CounterClockwise),
            _ => None,
        }
    }
}

/// One rotor as the FC knows it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotorDef {
    /// Angle α counter-clockwise seen from above from body +x [rad].
    pub angle_rad: f64,
    /// Hub distance from the centre of mass [m].
    pub arm_m: f64,
    /// Rotor plane offset along body z (FRD) [m].
    pub z_m: f64,
    /// Turning direction.
    pub spin: Spin,
}

/// Airframe as believed by the flight controller.
#[derive(Debug, Clone, PartialEq)]
pub struct Airframe {
    /// Name (file `name`, else the origin).
    pub name: String,
    /// Believed mass [kg].
    pub mass_kg: f64,
    /// Believed principal inertia Ixx, Iyy, Izz [kg·m²].
    pub inertia_kg_m2: Vec3,
    /// Propeller radius [m].
    pub rotor_radius_m: f64,
    /// Thrust coefficient c_T [N/(rad/s)²].
    pub c_t: f64,
    /// Drag-torque coefficient c_Q [N·m/(rad/s)²].
    pub c_q: f64,
    /// Lowest motor speed [rad/s].
    pub omega_min_rad_s: f64,
    /// Highest motor speed [rad/s].
    pub omega_max_rad_s: f64,
    /// Rotors in homework order.
    pub rotors: Vec<RotorDef>,
}

impl Airframe {
    /// Parses and validates the FC's view of an airframe file.
    ///
    /// ```
    /// use rotorpilot::airframe::{Airframe, AirframeSource};
    /// let src = AirframeSource::resolve("octo").unwrap();
    /// let af = Airframe::from_source(&src).unwrap();
    /// assert_eq!(af.rotors.len(), 8);
    /// ```
    pub fn from_source(src: &AirframeSource) -> Result<Self, AirframeError> {
        Self::from_toml_str(&src.text, &src.origin)
    }

    /// Parses `text`; `origin` names it in errors.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Self, AirframeError> {
        let f = FieldErrors(origin);
        let file: AirframeFile = toml::from_str(text).map_err(|e| f.syntax(text, &e))?;
        let vehicle = file.vehicle.ok_or_else(|| f.missing("vehicle"))?;
        let belief = file.fc.unwrap_or(schema::BeliefTable {
            mass: None,
            inertia: None,
        });
        let (mass, mass_field) = match belief.mass {
            Some(m) => (m, "fc.mass"),
            None => (vehicle.mass.ok_or_else(|| f.missing("vehicle.mass"))?, "vehicle.mass"),
        };
        let (inertia, inertia_field) = match belief.inertia {
            Some(i) => (i, "fc.inertia"),
            None => (
                vehicle.inertia.ok_or_else(|| f.missing("vehicle.inertia"))?,
                "vehicle.inertia",
            ),
        };
        let rotors = file.rotors.ok_or_else(|| f.missing("rotors"))?;
        let rotor_radius_m = f.positive(rotors.radius, "rotors.radius")?;
        let omega_min_rad_s = f.non_negative(rotors.omega_min.unwrap_or(0.0), "rotors.omega_min")?;
        let omega_max_rad_s = f.positive(rotors.omega_max, "rotors.omega_max")?;
        if omega_min_rad_s >= omega_max_rad_s {
            return Err(f.bad(
                "rotors.omega_min",
                format!("{omega_min_rad_s} rad/s is not below omega_max"),
            ));
        }
        let airframe = Self {
            name: file.name.unwrap_or_else(|| origin.to_string()),
            mass_kg: f.positive(Some(mass), mass_field)?,
            inertia_kg_m2: f.inertia(&inertia, inertia_field)?,
            rotor_radius_m,
            c_t: f.positive(rotors.c_t, "rotors.c_t")?,
            c_q: f.positive(rotors.c_q, "rotors.c_q")?,
            omega_min_rad_s,
            omega_max_rad_s,
            rotors: rotor_defs(&f, &rotors)?,
        };
        airframe.check_geometry(&f)?;
        Ok(airframe)
    }

    /// Distance from the centre of mass to the rotor hubs [m] (the largest if they differ).
    pub fn arm_length_m(&self) -> f64 {
        self.rotors.iter().map(|r| r.arm_m).fold(0.0, f64::max)
    }

    /// Hover speed of each rotor for the believed mass [rad/s].
    pub fn hover_speed_rad_s(&self) -> f64 {
        (self.mass_kg * crate::math::GRAVITY_M_S2 / (self.rotors.len() as f64 * self.c_t)).sqrt()
    }

    /// Collective thrust that holds the believed mass, as a fraction of the maximum:
    /// m g / (n c_T ω_max²) = (ω_hover / ω_max)² [-].
    pub fn hover_thrust_fraction(&self) -> f64 {
        (self.hover_speed_rad_s() / self.omega_max_rad_s).powi(2)
    }

    /// Coplanar rotor planes and no two propeller discs overlapping.
    fn check_geometry(&self, f: &FieldErrors) -> Result<(), AirframeError> {
        let z0 = self.rotors.first().map_or(0.0, |r| r.z_m);
        let hub = |r: &RotorDef| (r.arm_m * r.angle_rad.cos(), r.arm_m * r.angle_rad.sin());
        for (i, a) in self.rotors.iter().enumerate() {
            if (a.z_m - z0).abs() > 1e-6 {
                return Err(f.bad(
                    "rotors",
                    format!(
                        "rotor {} is not coplanar with rotor 1 (z = {} m vs {z0} m); allocation needs coplanar rotors",
                        i + 1,
                        a.z_m
                    ),
                ));
            }
            for (j, b) in self.rotors.iter().enumerate().skip(i + 1) {
                let (pa, pb) = (hub(a), hub(b));
                let gap = (pa.0 - pb.0).hypot(pa.1 - pb.1);
                if gap < 2.0 * self.rotor_radius_m {
                    return Err(f.bad(
                        "rotors",
                        format!(
                            "rotors {} and {} overlap: hubs {gap:.4} m apart, less than two propeller radii ({:.4} m)",
                            i + 1,
                            j + 1,
                            2.0 * self.rotor_radius_m
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

/// Rotor angles, arms and spins from a ring or a list (docs/allocation.md §1, eqs. (1.1)–(1.3):
/// α_i = α_0 + 2π(i−1)/n, spins alternating from rotor 1).
fn rotor_defs(f: &FieldErrors, r: &RotorsTable) -> Result<Vec<RotorDef>, AirframeError> {
    let defs = match (&r.ring, &r.rotor) {
        (Some(_), Some(_)) => {
            return Err(f.bad(
                "rotors",
                "give either [rotors.ring] or [[rotors.rotor]], not both".into(),
            ))
        }
        (None, None) => return Err(f.bad("rotors", "missing field: give [rotors.ring] or [[rotors.rotor]]".into())),
        (Some(ring), None) => {
            let count = ring.count.ok_or_else(|| f.missing("rotors.ring.count"))?;
            f.count(count, "rotors.ring.count")?;
            let n = count as usize;
            let arm = f.positive(ring.arm, "rotors.ring.arm")?;
            let first = f
                .finite(ring.first_angle.unwrap_or(0.0), "rotors.ring.first_angle")?
                .to_radians();
            let first_spin = f.spin(ring.first_spin.as_deref().unwrap_or("cw"), "rotors.ring.first_spin")?;
            let other = match first_spin {
                Spin::Clockwise => Spin::CounterClockwise,
                Spin::CounterClockwise => Spin::Clockwise,
            };
            let z = f.finite(ring.z.unwrap_or(0.0), "rotors.ring.z")?;
            (0..n)
                .map(|i| RotorDef {
                    angle_rad: first + std::f64::consts::TAU * i as f64 / n as f64,
                    arm_m: arm,
                    z_m: z,
                    spin: if i % 2 == 0 { first_spin } else { other },
                })
                .collect()
        }
        (None, Some(list)) => {
            f.count(list.len() as i64, "rotors.rotor")?;
            let mut defs = Vec::with_capacity(list.len());
            for (i, e) in list.iter().enumerate() {
                let field = |s: &str| format!("rotors.rotor[{i}].{s}");
                let angle = e.angle.ok_or_else(|| f.missing(&field("angle")))?;
                let arm = e.arm.ok_or_else(|| f.missing(&field("arm")))?;
                let spin = e.spin.as_deref().ok_or_else(|| f.missing(&field("spin")))?;
                defs.push(RotorDef {
                    angle_rad: f.finite(angle, &field("angle"))?.to_radians(),
                    arm_m: f.non_negative(arm, &field("arm"))?,
                    z_m: f.finite(e.z.unwrap_or(0.0), &field("z"))?,
                    spin: f.spin(spin, &field("spin"))?,
                });
            }
            defs
        }
    };
    Ok(defs)
}

/// Error builders for one file.
struct FieldErrors<'a>(&'a str);

impl FieldErrors<'_> {
    fn bad(&self, field: &str, reason: String) -> AirframeError {
        AirframeError::new(self.0, field, reason)
    }

    fn missing(&self, field: &str) -> AirframeError {
        self.bad(field, "missing field".into())
    }

    fn syntax(&self, text: &str, e: &toml::de::Error) -> AirframeError {
        let (place, reason) = crate::suggest::toml_error(text, e);
        self.bad(&place, reason)
    }

    fn finite(&self, v: f64, field: &str) -> Result<f64, AirframeError> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.bad(field, format!("{v} is not a finite number")))
        }
    }

    fn positive(&self, v: Option<f64>, field: &str) -> Result<f64, AirframeError> {
        let v = self.finite(v.ok_or_else(|| self.missing(field))?, field)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(self.bad(field, format!("{v} must be positive")))
        }
    }

    fn non_negative(&self, v: f64, field: &str) -> Result<f64, AirframeError> {
        if self.finite(v, field)? >= 0.0 {
            Ok(v)
        } else {
            Err(self.bad(field, format!("{v} must not be negative")))
        }
    }

    fn inertia(&self, v: &[f64], field: &str) -> Result<Vec3, AirframeError> {
        if v.len() != 3 {
            return Err(self.bad(field, format!("expected 3 principal moments, found {}", v.len())));
        }
        for (i, x) in v.iter().enumerate() {
            self.positive(Some(*x), &format!("{field}[{i}]"))?;
        }
        Ok(Vec3::new(v[0], v[1], v[2]))
    }

    fn count(&self, n: i64, field: &str) -> Result<(), AirframeError> {
        if n < MIN_ROTORS as i64 {
            Err(self.bad(
                field,
                format!("{n} rotors: fewer than {MIN_ROTORS} cannot produce thrust and three torques"),
            ))
        } else if n > MAX_ROTORS as i64 {
            Err(self.bad(field, format!("{n} rotors: more than the supported {MAX_ROTORS}")))
        } else {
            Ok(())
        }
    }

    fn spin(&self, s: &str, field: &str) -> Result<Spin, AirframeError> {
        Spin::parse(s).ok_or_else(|| self.bad(field, format!("unknown spin \"{s}\"; expected \"cw\" or \"ccw\"")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_preset_loads() {
        for (name, text) in PRESETS {
            let af = Airframe::from_toml_str(text, name).unwrap();
            assert_eq!(&af.name, name);
            assert!(af.rotors.len() >= 4);
        }
    }

    #[test]
    fn fc_belief_overrides_true_mass() {
        let text = format!(
            "{}\n[fc]\nmass = 1.5\n",
            preset_text("fsr_quad").unwrap().replace("mass = 1.5 ", "mass = 1.7 ")
        );
        let af = Airframe::from_toml_str(&text, "x").unwrap();
        assert_eq!(af.mass_kg, 1.5);
    }
}
