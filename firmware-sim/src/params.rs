//! The plant's view of an airframe file, validated into typed parameters.
//!
//! The plant parses the file with its own types and derives rotor positions with its own
//! code (docs/architecture.md §2: no constants shared with the flight controller). A bad file is
//! refused with a [`ParamsError`] naming the file, the field and the reason.

use nalgebra::Vector3;
use thiserror::Error;

use crate::disturbance::{Disturbance, DisturbanceKind};
use crate::file_schema::{FileAirframe, FileGround, FilePlant, FileRotors};
use crate::proximity::{ProximityError, ProximityLaw, ProximityModel};
use crate::sensor_params::sensor_suite_config;
use crate::sensors::{NoiseParams, SensorSuiteConfig};
use crate::validate::{finite, non_negative, positive, required, vec3, Checker};
use crate::wind::WindSettings;

/// A refused airframe file: which file, which field, and why.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{origin}: {field}: {reason}")]
pub struct ParamsError {
    /// File path or preset name the text came from.
    pub origin: String,
    /// Dotted path of the offending field, e.g. `vehicle.mass`.
    pub field: String,
    /// What is wrong with it.
    pub reason: String,
}

/// Motor and propeller constants shared by every rotor (docs/model.md §4).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotorConstants {
    /// Propeller radius ρ [m].
    pub radius_m: f64,
    /// Thrust coefficient c_T [N/(rad/s)²].
    pub c_t: f64,
    /// Drag-torque coefficient c_Q [N·m/(rad/s)²].
    pub c_q: f64,
    /// Lowest speed a motor turns at [rad/s].
    pub omega_min_rad_s: f64,
    /// Highest speed a motor turns at [rad/s].
    pub omega_max_rad_s: f64,
    /// Spin-up time constant [s]; 0 means no lag.
    pub tau_up_s: f64,
    /// Spin-down time constant [s]; 0 means no lag.
    pub tau_down_s: f64,
}

/// Where a rotor sits and which way it turns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotorGeometry {
    /// Hub position in the body frame (FRD) [m].
    pub hub_b: Vector3<f64>,
    /// Sign of the reaction torque about +z_b: −1 for a propeller turning clockwise seen from
    /// above, +1 for counter-clockwise (docs/allocation.md §1, eq. (1.3)).
    pub reaction_sign: f64,
}

/// Ground plane and the ground-effect law.
#[derive(Debug, Clone, PartialEq)]
pub struct GroundSettings {
    /// Ground plane height as a NED z coordinate [m].
    pub plane_z_m: f64,
    /// Thrust factor law; `None` keeps contact but no aerodynamic effect.
    pub effect: Option<ProximityModel>,
}

/// Ceiling plane and the ceiling-effect law (docs/ground_ceiling.md §4).
#[derive(Debug, Clone, PartialEq)]
pub struct CeilingSettings {
    /// Ceiling plane height as a NED z coordinate [m] (above the vehicle: more negative).
    pub plane_z_m: f64,
    /// Thrust factor law.
    pub effect: ProximityModel,
    /// True while k1, k2 are the unconfirmed placeholders of docs/ground_ceiling.md §4.
    pub unconfirmed: bool,
}

/// Initial pose; by default the vehicle rests on the ground at the origin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitialState {
    /// Initial position (NED) [m]; `None` places the vehicle on the ground below the origin.
    pub pos_w: Option<Vector3<f64>>,
    /// Initial heading [rad].
    pub yaw_rad: f64,
}

/// Validated plant parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct PlantParams {
    /// Airframe name.
    pub name: String,
    /// True mass [kg].
    pub mass_kg: f64,
    /// Principal moments of inertia Ixx, Iyy, Izz in FRD [kg·m²].
    pub inertia_kg_m2: Vector3<f64>,
    /// Height of the centre of mass above the ground when resting level [m].
    pub gear_height_m: f64,
    /// Constants shared by every rotor.
    pub rotor: RotorConstants,
    /// Geometry of each rotor, in file order.
    pub rotors: Vec<RotorGeometry>,
    /// Ground plane; always present (contact), its aerodynamic effect optional.
    pub ground: GroundSettings,
    /// Ceiling, when configured.
    pub ceiling: Option<CeilingSettings>,
    /// Linear drag coefficients along the body axes [N·s/m] (docs/model.md §5.1, eq. (5.2)).
    pub linear_drag_n_s_m: Vector3<f64>,
    /// Quadratic drag coefficients along the body axes [N·s²/m²] (docs/model.md §5.1, eq. (5.2)).
    pub quadratic_drag_n_s2_m2: Vector3<f64>,
    /// Mean wind, gusts and turbulence (docs/model.md §5.2).
    pub wind: WindSettings,
    /// Noise of the state sensor (`[plant.noise]`, docs/model.md §6).
    pub noise: NoiseParams,
    /// The sensor suite (`[plant.sensors]`, docs/model.md §10.7): typical values unless the file
    /// overrides them.
    pub sensors: SensorSuiteConfig,
    /// Scripted external wrench components, summed.
    pub disturbances: Vec<Disturbance>,
    /// Initial pose.
    pub initial: InitialState,
}

impl PlantParams {
    /// Parses and validates an airframe file's text; `origin` names it in errors.
    ///
    /// ```
    /// let text = include_str!("../../airframes/quad_x.toml");
    /// let params = firmware_sim::PlantParams::from_toml_str(text, "quad_x").unwrap();
    /// assert_eq!(params.rotors.len(), 4);
    /// ```
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Self, ParamsError> {
        let check = Checker::new(origin);
        let file: FileAirframe = toml::from_str(text).map_err(|e| check.syntax(text, &e))?;
        let vehicle = required(&check, file.vehicle, "vehicle")?;
        let mass_kg = positive(&check, required(&check, vehicle.mass, "vehicle.mass")?, "vehicle.mass")?;
        let inertia = vec3(
            &check,
            required(&check, vehicle.inertia, "vehicle.inertia")?,
            "vehicle.inertia",
        )?;
        let inertia_kg_m2 = check_inertia(&check, inertia)?;
        let gear_height_m = non_negative(&check, vehicle.gear_height.unwrap_or(0.0), "vehicle.gear_height")?;
        let rotors_file = required(&check, file.rotors, "rotors")?;
        let rotor = rotor_constants(&check, &rotors_file)?;
        let rotors = crate::layout::rotor_geometry(&check, &rotors_file, rotor.radius_m)?;
        let plant = file.plant.unwrap_or_default();
        let ground = ground_settings(&check, plant.ground.as_ref(), &rotors, rotor.radius_m)?;
        let ceiling = ceiling_settings(&check, &plant, rotor.radius_m)?;
        let drag = plant.drag.as_ref();
        let linear_drag_n_s_m = drag_coefficients(&check, drag.and_then(|d| d.linear.clone()), "plant.drag.linear")?;
        let quadratic_drag_n_s2_m2 =
            drag_coefficients(&check, drag.and_then(|d| d.quadratic.clone()), "plant.drag.quadratic")?;
        let wind = crate::wind::wind_settings(&check, plant.wind.as_ref())?;
        let noise = noise_params(&check, &plant)?;
        let sensors = sensor_suite_config(&check, plant.sensors.as_ref())?;
        let disturbances = disturbances(&check, &plant)?;
        let initial = initial_state(&check, &plant)?;
        Ok(Self {
            name: file.name.unwrap_or_else(|| origin.to_string()),
            mass_kg,
            inertia_kg_m2,
            gear_height_m,
            rotor,
            rotors,
            ground,
            ceiling,
            linear_drag_n_s_m,
            quadratic_drag_n_s2_m2,
            wind,
            noise,
            sensors,
            disturbances,
            initial,
        })
    }

    /// Warnings worth logging at start-up (e.g. unconfirmed ceiling constants).
    pub fn warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        let no_drag = self.linear_drag_n_s_m == Vector3::zeros() && self.quadratic_drag_n_s2_m2 == Vector3::zeros();
        if !self.wind.is_calm() && no_drag {
            out.push(format!(
                "{}: wind is set but plant.drag is zero: the wind exerts no force (docs/model.md §5.1)",
                self.name
            ));
        }
        if self.ceiling.as_ref().is_some_and(|c| c.unconfirmed) {
            out.push(format!(
                "{}: ceiling effect uses the unconfirmed placeholder k1 = 16, k2 = 0 (docs/ground_ceiling.md §4)",
                self.name
            ));
        }
        out
    }

    /// Hover speed of every rotor for the true mass out of ground effect [rad/s].
    pub fn hover_speed_rad_s(&self) -> f64 {
        (self.mass_kg * crate::GRAVITY_M_S2 / (self.rotors.len() as f64 * self.rotor.c_t)).sqrt()
    }
}

/// Drag coefficients along the body axes from `field`: three non-negative numbers, zero when
/// absent.
fn drag_coefficients(check: &Checker, v: Option<Vec<f64>>, field: &str) -> Result<Vector3<f64>, ParamsError> {
    let Some(v) = v else {
        return Ok(Vector3::zeros());
    };
    let d = vec3(check, v, field)?;
    for (i, c) in d.iter().enumerate() {
        non_negative(check, *c, &format!("{field}[{i}]"))?;
    }
    Ok(d)
}

fn check_inertia(check: &Checker, i: Vector3<f64>) -> Result<Vector3<f64>, ParamsError> {
    for (k, v) in i.iter().enumerate() {
        positive(check, *v, &format!("vehicle.inertia[{k}]"))?;
    }
    Ok(i)
}

fn rotor_constants(check: &Checker, r: &FileRotors) -> Result<RotorConstants, ParamsError> {
    let get = |v: Option<f64>, f: &str| required(check, v, f).and_then(|x| finite(check, x, f));
    let c = RotorConstants {
        radius_m: positive(check, get(r.radius, "rotors.radius")?, "rotors.radius")?,
        c_t: positive(check, get(r.c_t, "rotors.c_t")?, "rotors.c_t")?,
        c_q: positive(check, get(r.c_q, "rotors.c_q")?, "rotors.c_q")?,
        omega_min_rad_s: non_negative(check, r.omega_min.unwrap_or(0.0), "rotors.omega_min")?,
        omega_max_rad_s: positive(check, get(r.omega_max, "rotors.omega_max")?, "rotors.omega_max")?,
        tau_up_s: non_negative(check, r.tau_up.unwrap_or(0.0), "rotors.tau_up")?,
        tau_down_s: non_negative(check, r.tau_down.unwrap_or(0.0), "rotors.tau_down")?,
    };
    if c.omega_min_rad_s >= c.omega_max_rad_s {
        return Err(check.error(
            "rotors.omega_min",
            format!(
                "{} rad/s is not below omega_max = {} rad/s",
                c.omega_min_rad_s, c.omega_max_rad_s
            ),
        ));
    }
    Ok(c)
}

fn ground_settings(
    check: &Checker,
    g: Option<&FileGround>,
    rotors: &[RotorGeometry],
    radius_m: f64,
) -> Result<GroundSettings, ParamsError> {
    let Some(g) = g else {
        return Ok(GroundSettings {
            plane_z_m: 0.0,
            effect: None,
        });
    };
    let plane_z_m = finite(check, g.height.unwrap_or(0.0), "plant.ground.height")?;
    let cap = g.cap.unwrap_or(ProximityModel::DEFAULT_CAP);
    let law = match g.model.as_deref().unwrap_or("off") {
        "off" => None,
        "cheeseman_bennett" => Some(ProximityLaw::CheesemanBennett),
        "multirotor" => {
            let arm = rotors.iter().map(|r| r.hub_b.xy().norm()).fold(0.0, f64::max);
            let spacing = match g.spacing {
                Some(d) => positive(check, d, "plant.ground.spacing")?,
                None => crate::layout::smallest_hub_spacing(rotors),
            };
            let body_distance = positive(check, g.body_distance.unwrap_or(arm), "plant.ground.body_distance")?;
            let body_gain = non_negative(check, g.body_gain.unwrap_or(0.0), "plant.ground.body_gain")?;
            Some(ProximityLaw::Multirotor {
                spacing_m: spacing,
                body_distance_m: body_distance,
                body_gain,
            })
        }
        other => {
            return Err(check.error(
                "plant.ground.model",
                format!("unknown model \"{other}\"; expected \"off\", \"cheeseman_bennett\" or \"multirotor\""),
            ))
        }
    };
    let effect = match law {
        Some(law) => Some(
            ProximityModel::new(law, radius_m, cap, g.cutoff).map_err(|e| proximity_error(check, "plant.ground", e))?,
        ),
        None => None,
    };
    Ok(GroundSettings { plane_z_m, effect })
}

fn ceiling_settings(check: &Checker, plant: &FilePlant, radius_m: f64) -> Result<Option<CeilingSettings>, ParamsError> {
    let Some(c) = plant.ceiling.as_ref() else {
        return Ok(None);
    };
    if !c.enabled.unwrap_or(true) {
        return Ok(None);
    }
    let plane_z_m = finite(
        check,
        required(check, c.height, "plant.ceiling.height")?,
        "plant.ceiling.height",
    )?;
    let unconfirmed = c.k1.is_none() && c.k2.is_none();
    let k1 = positive(check, c.k1.unwrap_or(16.0), "plant.ceiling.k1")?;
    let k2 = non_negative(check, c.k2.unwrap_or(0.0), "plant.ceiling.k2")?;
    let cap = c.cap.unwrap_or(ProximityModel::DEFAULT_CAP);
    let effect = ProximityModel::new(ProximityLaw::Ceiling { k1, k2_m: k2 }, radius_m, cap, c.cutoff)
        .map_err(|e| proximity_error(check, "plant.ceiling", e))?;
    Ok(Some(CeilingSettings {
        plane_z_m,
        effect,
        unconfirmed,
    }))
}

fn proximity_error(check: &Checker, table: &str, e: ProximityError) -> ParamsError {
    check.error(&format!("{table}.{}", e.field()), e.to_string())
}

fn noise_params(check: &Checker, plant: &FilePlant) -> Result<NoiseParams, ParamsError> {
    let Some(n) = plant.noise.as_ref() else {
        return Ok(NoiseParams::default());
    };
    let sd = |v: Option<f64>, f: &str| non_negative(check, v.unwrap_or(0.0), f);
    Ok(NoiseParams {
        position_m: sd(n.position, "plant.noise.position")?,
        velocity_m_s: sd(n.velocity, "plant.noise.velocity")?,
        attitude_rad: sd(n.attitude, "plant.noise.attitude")?,
        gyro_rad_s: sd(n.gyro, "plant.noise.gyro")?,
        accel_m_s2: sd(n.accel, "plant.noise.accel")?,
    })
}

fn disturbances(check: &Checker, plant: &FilePlant) -> Result<Vec<Disturbance>, ParamsError> {
    let Some(list) = plant.disturbance.as_ref() else {
        return Ok(Vec::new());
    };
    let mut out = Vec::with_capacity(list.len());
    for (i, d) in list.iter().enumerate() {
        let field = |f: &str| format!("plant.disturbance[{i}].{f}");
        let v3 = |v: &Option<Vec<f64>>, f: &str| match v {
            Some(v) => vec3(check, v.clone(), &field(f)),
            None => Ok(Vector3::zeros()),
        };
        let force_w = v3(&d.force, "force")?;
        let torque_b = v3(&d.torque, "torque")?;
        let kind = match d.kind.as_deref() {
            Some("constant") => DisturbanceKind::Constant,
            Some("step") => DisturbanceKind::Step {
                start_s: finite(check, required(check, d.start, &field("start"))?, &field("start"))?,
            },
            Some("sinusoid") => DisturbanceKind::Sinusoid {
                frequency_hz: positive(
                    check,
                    required(check, d.frequency, &field("frequency"))?,
                    &field("frequency"),
                )?,
                phase_rad: finite(check, d.phase.unwrap_or(0.0), &field("phase"))?,
            },
            Some(other) => {
                return Err(check.error(
                    &field("kind"),
                    format!("unknown kind \"{other}\"; expected \"constant\", \"step\" or \"sinusoid\""),
                ))
            }
            None => return Err(check.error(&field("kind"), "missing field".to_string())),
        };
        out.push(Disturbance {
            kind,
            force_w,
            torque_b,
        });
    }
    Ok(out)
}

fn initial_state(check: &Checker, plant: &FilePlant) -> Result<InitialState, ParamsError> {
    let Some(i) = plant.initial.as_ref() else {
        return Ok(InitialState {
            pos_w: None,
            yaw_rad: 0.0,
        });
    };
    let pos_w = match i.position.clone() {
        Some(p) => Some(vec3(check, p, "plant.initial.position")?),
        None => None,
    };
    let yaw_deg = finite(check, i.yaw.unwrap_or(0.0), "plant.initial.yaw")?;
    Ok(InitialState {
        pos_w,
        yaw_rad: yaw_deg.to_radians(),
    })
}
