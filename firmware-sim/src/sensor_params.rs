//! `[plant.sensors]` validated into a [`SensorSuiteConfig`] (docs/model.md §10.7).
//!
//! Each field overrides the corresponding value of the base set (`base`: `"sitl"`, the default,
//! [`SensorSuiteConfig::typical`]; `"hardware"`, [`SensorSuiteConfig::hardware`]); a bad value is
//! refused with its dotted path, e.g. `plant.sensors.gps.latency`.

use crate::file_sensors::{FileBaro, FileGps, FileImu, FileMag, FileSensors};
use crate::params::ParamsError;
use crate::sensors::{BaroConfig, GpsConfig, ImuConfig, MagConfig, SensorSuiteConfig, MAX_GPS_LATENCY_S};
use crate::validate::{finite, non_negative, positive, vec3, Checker};

/// Highest sensor rate: one sample per plant tick at 1 kHz [Hz].
const MAX_RATE_HZ: f64 = 1000.0;
/// Most satellites the file may claim, as PX4's SIM_GPS_USED [-].
const MAX_SATELLITES: i64 = 50;
/// Origin altitudes the ISA troposphere model covers [m].
const ORIGIN_ALT_RANGE_M: (f64, f64) = (-500.0, 11_000.0);

/// The suite configuration of `[plant.sensors]`, or the base set's values where it says nothing.
pub(crate) fn sensor_suite_config(
    check: &Checker,
    file: Option<&FileSensors>,
) -> Result<SensorSuiteConfig, ParamsError> {
    let default = FileSensors::default();
    let f = file.unwrap_or(&default);
    let base = match f.base.as_deref() {
        None | Some("sitl") => SensorSuiteConfig::typical(),
        Some("hardware") => SensorSuiteConfig::hardware(),
        Some(other) => {
            return Err(check.error(
                "plant.sensors.base",
                format!("unknown set {other:?}: \"sitl\" (PX4 SITL's sensors, the default) or \"hardware\""),
            ))
        }
    };
    Ok(SensorSuiteConfig {
        imu: imu(check, f.imu.as_ref(), base.imu)?,
        gps: gps(check, f.gps.as_ref(), base.gps)?,
        baro: baro(check, f.baro.as_ref(), base.baro)?,
        mag: mag(check, f.mag.as_ref(), base.mag)?,
    })
}

/// `v` when given, else `default`; checked by `rule` under `plant.sensors.<field>`.
fn value(
    check: &Checker,
    v: Option<f64>,
    default: f64,
    field: &str,
    rule: fn(&Checker, f64, &str) -> Result<f64, ParamsError>,
) -> Result<f64, ParamsError> {
    match v {
        Some(x) => rule(check, x, &format!("plant.sensors.{field}")),
        None => Ok(default),
    }
}

/// `v` when given (checked to lie in [lo, hi]), else `default`.
fn within(check: &Checker, v: Option<f64>, default: f64, field: &str, lo: f64, hi: f64) -> Result<f64, ParamsError> {
    let Some(x) = v else { return Ok(default) };
    let path = format!("plant.sensors.{field}");
    let x = finite(check, x, &path)?;
    if (lo..=hi).contains(&x) {
        Ok(x)
    } else {
        Err(check.error(&path, format!("{x} is outside [{lo}, {hi}]")))
    }
}

fn imu(check: &Checker, f: Option<&FileImu>, d: ImuConfig) -> Result<ImuConfig, ParamsError> {
    let Some(f) = f else { return Ok(d) };
    let sd = |v, default, field| value(check, v, default, field, non_negative);
    Ok(ImuConfig {
        accel_noise_m_s2: sd(f.accel_noise, d.accel_noise_m_s2, "imu.accel_noise")?,
        accel_bias_walk_m_s2_sqrt_s: sd(f.accel_bias_walk, d.accel_bias_walk_m_s2_sqrt_s, "imu.accel_bias_walk")?,
        accel_turn_on_bias_m_s2: sd(
            f.accel_turn_on_bias,
            d.accel_turn_on_bias_m_s2,
            "imu.accel_turn_on_bias",
        )?,
        gyro_noise_rad_s: sd(f.gyro_noise, d.gyro_noise_rad_s, "imu.gyro_noise")?,
        gyro_bias_walk_rad_s_sqrt_s: sd(f.gyro_bias_walk, d.gyro_bias_walk_rad_s_sqrt_s, "imu.gyro_bias_walk")?,
        gyro_turn_on_bias_rad_s: sd(f.gyro_turn_on_bias, d.gyro_turn_on_bias_rad_s, "imu.gyro_turn_on_bias")?,
    })
}

fn gps(check: &Checker, f: Option<&FileGps>, d: GpsConfig) -> Result<GpsConfig, ParamsError> {
    let Some(f) = f else { return Ok(d) };
    let sd = |v, default, field| value(check, v, default, field, non_negative);
    let satellites = match f.satellites {
        Some(n) if (0..=MAX_SATELLITES).contains(&n) => n as u8,
        Some(n) => {
            return Err(check.error(
                "plant.sensors.gps.satellites",
                format!("{n} is outside [0, {MAX_SATELLITES}]"),
            ))
        }
        None => d.satellites,
    };
    Ok(GpsConfig {
        rate_hz: within(check, f.rate, d.rate_hz, "gps.rate", f64::MIN_POSITIVE, MAX_RATE_HZ)?,
        latency_s: within(check, f.latency, d.latency_s, "gps.latency", 0.0, MAX_GPS_LATENCY_S)?,
        h_noise_m: sd(f.h_noise, d.h_noise_m, "gps.h_noise")?,
        v_noise_m: sd(f.v_noise, d.v_noise_m, "gps.v_noise")?,
        h_wander_m: sd(f.h_wander, d.h_wander_m, "gps.h_wander")?,
        v_wander_m: sd(f.v_wander, d.v_wander_m, "gps.v_wander")?,
        wander_tau_s: value(check, f.wander_tau, d.wander_tau_s, "gps.wander_tau", positive)?,
        vel_noise_m_s: sd(f.vel_noise, d.vel_noise_m_s, "gps.vel_noise")?,
        satellites,
        h_acc_m: sd(f.h_acc, d.h_acc_m, "gps.h_acc")?,
        v_acc_m: sd(f.v_acc, d.v_acc_m, "gps.v_acc")?,
        speed_acc_m_s: sd(f.speed_acc, d.speed_acc_m_s, "gps.speed_acc")?,
    })
}

fn baro(check: &Checker, f: Option<&FileBaro>, d: BaroConfig) -> Result<BaroConfig, ParamsError> {
    let Some(f) = f else { return Ok(d) };
    let (lo, hi) = ORIGIN_ALT_RANGE_M;
    Ok(BaroConfig {
        rate_hz: within(check, f.rate, d.rate_hz, "baro.rate", f64::MIN_POSITIVE, MAX_RATE_HZ)?,
        origin_alt_m: match f.origin_altitude {
            None => d.origin_alt_m,
            given => Some(within(check, given, 0.0, "baro.origin_altitude", lo, hi)?),
        },
        noise_m: value(check, f.noise, d.noise_m, "baro.noise", non_negative)?,
        drift_m_sqrt_s: value(check, f.drift, d.drift_m_sqrt_s, "baro.drift", non_negative)?,
    })
}

fn mag(check: &Checker, f: Option<&FileMag>, d: MagConfig) -> Result<MagConfig, ParamsError> {
    let Some(f) = f else { return Ok(d) };
    // A part the file gives replaces the World Magnetic Model's at home (docs/model.md §10.5).
    let angle = |v: Option<f64>, default_rad: Option<f64>, field: &str, limit: f64| match v {
        Some(_) => within(check, v, 0.0, field, -limit, limit).map(|deg| Some(deg.to_radians())),
        None => Ok(default_rad),
    };
    let declination_rad = angle(f.declination, d.declination_rad, "mag.declination", 180.0)?;
    let inclination_rad = angle(f.inclination, d.inclination_rad, "mag.inclination", 90.0)?;
    let strength_gauss = match f.strength {
        Some(x) => Some(positive(check, x, "plant.sensors.mag.strength")?),
        None => d.strength_gauss,
    };
    let bias_b_gauss = match f.bias.clone() {
        Some(v) => vec3(check, v, "plant.sensors.mag.bias")?,
        None => d.bias_b_gauss,
    };
    Ok(MagConfig {
        rate_hz: within(check, f.rate, d.rate_hz, "mag.rate", f64::MIN_POSITIVE, MAX_RATE_HZ)?,
        strength_gauss,
        declination_rad,
        inclination_rad,
        noise_gauss: value(check, f.noise, d.noise_gauss, "mag.noise", non_negative)?,
        bias_b_gauss,
    })
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;

    use crate::{PlantParams, SensorSuiteConfig};

    const BASE: &str = include_str!("../../airframes/quad_x.toml");

    fn parse(extra: &str) -> Result<PlantParams, crate::ParamsError> {
        PlantParams::from_toml_str(&format!("{BASE}\n{extra}"), "test")
    }

    fn refused(extra: &str) -> (String, String) {
        let e = parse(extra).unwrap_err();
        (e.field, e.reason)
    }

    #[test]
    fn no_sensors_table_gives_the_typical_suite() {
        assert_eq!(parse("").unwrap().sensors, SensorSuiteConfig::typical());
        assert_eq!(parse("[plant.sensors]").unwrap().sensors, SensorSuiteConfig::typical());
    }

    #[test]
    fn the_hardware_base_takes_a_real_receivers_errors_and_fields_still_override_it() {
        let p = parse("[plant.sensors]\nbase = \"hardware\"\n[plant.sensors.gps]\nlatency = 0.2\n")
            .unwrap()
            .sensors;
        let h = SensorSuiteConfig::hardware();
        assert_eq!(p.gps.latency_s, 0.2);
        assert_eq!(
            (p.gps.v_wander_m, p.baro.drift_m_sqrt_s),
            (h.gps.v_wander_m, h.baro.drift_m_sqrt_s)
        );
        assert_ne!(h.gps.v_wander_m, SensorSuiteConfig::typical().gps.v_wander_m);
        assert_eq!(
            parse("[plant.sensors]\nbase = \"sitl\"").unwrap().sensors,
            SensorSuiteConfig::typical()
        );
        let (field, reason) = refused("[plant.sensors]\nbase = \"rtk\"");
        assert_eq!(field, "plant.sensors.base");
        assert!(reason.contains("\"rtk\"") && reason.contains("hardware"), "{reason}");
    }

    #[test]
    fn each_field_overrides_only_itself() {
        let p = parse(
            "[plant.sensors.gps]\nlatency = 0.2\nsatellites = 3\n\
             [plant.sensors.mag]\ndeclination = -10.0\nbias = [0.01, 0.0, -0.02]\n\
             [plant.sensors.imu]\ngyro_noise = 0.0\n[plant.sensors.baro]\norigin_altitude = 0.0\n",
        )
        .unwrap()
        .sensors;
        let t = SensorSuiteConfig::typical();
        assert_eq!(
            (p.gps.latency_s, p.gps.satellites, p.gps.rate_hz),
            (0.2, 3, t.gps.rate_hz)
        );
        assert_eq!(p.mag.declination_rad, Some((-10.0f64).to_radians()));
        assert_eq!(
            (p.mag.inclination_rad, p.mag.strength_gauss),
            (None, None),
            "the model's at home"
        );
        assert_eq!(p.mag.bias_b_gauss, Vector3::new(0.01, 0.0, -0.02));
        assert_eq!(
            (p.imu.gyro_noise_rad_s, p.imu.accel_noise_m_s2),
            (0.0, t.imu.accel_noise_m_s2)
        );
        assert_eq!((p.baro.origin_alt_m, p.baro.rate_hz), (Some(0.0), t.baro.rate_hz));
    }

    #[test]
    fn bad_values_are_refused_with_their_field_path() {
        let cases = [
            ("[plant.sensors.imu]\ngyro_noise = -0.1", "plant.sensors.imu.gyro_noise"),
            ("[plant.sensors.gps]\nlatency = 1.5", "plant.sensors.gps.latency"),
            ("[plant.sensors.gps]\nrate = 0.0", "plant.sensors.gps.rate"),
            ("[plant.sensors.gps]\nsatellites = 51", "plant.sensors.gps.satellites"),
            ("[plant.sensors.gps]\nwander_tau = 0.0", "plant.sensors.gps.wander_tau"),
            ("[plant.sensors.baro]\nrate = 2000.0", "plant.sensors.baro.rate"),
            (
                "[plant.sensors.baro]\norigin_altitude = 20000.0",
                "plant.sensors.baro.origin_altitude",
            ),
            (
                "[plant.sensors.mag]\ninclination = 95.0",
                "plant.sensors.mag.inclination",
            ),
            ("[plant.sensors.mag]\nstrength = 0.0", "plant.sensors.mag.strength"),
            ("[plant.sensors.mag]\nbias = [0.1, 0.2]", "plant.sensors.mag.bias"),
            ("[plant.sensors.mag]\nnoise = nan", "plant.sensors.mag.noise"),
        ];
        for (extra, field) in cases {
            assert_eq!(refused(extra).0, field, "{extra}");
        }
    }

    #[test]
    fn unknown_fields_are_refused_with_their_line() {
        let (field, reason) = refused("[plant.sensors.gps]\nrate = 5.0\nlatncy = 0.1");
        assert!(field.starts_with("line "), "{field}");
        assert!(reason.contains("latncy"), "{reason}");
        let (_, reason) = refused("[plant.sensors.lidar]\nrate = 5.0");
        assert!(reason.contains("lidar"), "{reason}");
    }
}
