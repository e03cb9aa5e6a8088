//! International Standard Atmosphere (troposphere): pressure ↔ pressure altitude
//! (docs/navigation_filter.md §8, eq. (8.1)).

/// Sea-level standard pressure [Pa].
pub const ISA_P0_PA: f64 = 101_325.0;
/// Sea-level standard temperature [K].
const ISA_T0_K: f64 = 288.15;
/// Tropospheric temperature lapse rate [K/m].
const ISA_LAPSE_K_M: f64 = 0.0065;
/// Exponent R·L / (g₀·M) of the barometric formula [-].
const ISA_EXPONENT: f64 = 0.190_263;

/// Pressure altitude above mean sea level of static pressure `pressure_pa` [Pa] [m]
/// (docs/navigation_filter.md §8, eq. (8.1)); `None` for a pressure that is not a positive number.
pub fn pressure_altitude_m(pressure_pa: f64) -> Option<f64> {
    if !(pressure_pa.is_finite() && pressure_pa > 0.0) {
        return None;
    }
    Some(ISA_T0_K / ISA_LAPSE_K_M * (1.0 - (pressure_pa / ISA_P0_PA).powf(ISA_EXPONENT)))
}

/// Static pressure at pressure altitude `altitude_m` [m] [Pa]: the inverse of
/// [`pressure_altitude_m`] (docs/navigation_filter.md §8, eq. (8.1)).
pub fn pressure_at_altitude_pa(altitude_m: f64) -> f64 {
    ISA_P0_PA * (1.0 - ISA_LAPSE_K_M * altitude_m / ISA_T0_K).powf(1.0 / ISA_EXPONENT)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_reference_values() {
        assert!(pressure_altitude_m(ISA_P0_PA).unwrap().abs() < 1e-9);
        // ISA tables: 1000 m ↔ 89 875 Pa, 5000 m ↔ 54 020 Pa.
        assert!((pressure_at_altitude_pa(1000.0) - 89_875.0).abs() < 5.0);
        assert!((pressure_at_altitude_pa(5000.0) - 54_020.0).abs() < 10.0);
        for h in [-200.0, 0.0, 488.0, 3000.0] {
            let back = pressure_altitude_m(pressure_at_altitude_pa(h)).unwrap();
            assert!((back - h).abs() < 1e-6, "{h} -> {back}");
        }
        assert_eq!(pressure_altitude_m(0.0), None);
        assert_eq!(pressure_altitude_m(f64::NAN), None);
    }

    #[test]
    fn near_sea_level_one_metre_is_about_twelve_pascal() {
        let dp = pressure_at_altitude_pa(0.0) - pressure_at_altitude_pa(1.0);
        assert!((dp - 12.0).abs() < 0.2, "{dp}");
    }
}
