//! The battery gauge: coulomb counting of the rotors' electrical power against the pack's
//! capacity, as PX4 estimates the remaining charge from current and `BAT1_CAPACITY`. Pure.

/// Nominal cell voltage used to turn capacity into energy [V].
const NOMINAL_CELL_V: f64 = 3.7;
/// Cell voltage when full [V].
const FULL_CELL_V: f64 = 4.2;
/// Cell voltage when empty [V].
const EMPTY_CELL_V: f64 = 3.5;

/// Pack description.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BatteryParams {
    /// Capacity [mAh] (`BAT1_CAPACITY`, 5100: the iris pack).
    pub capacity_mah: f64,
    /// Cells in series (`BAT1_N_CELLS`, 3).
    pub cells: u32,
}

impl Default for BatteryParams {
    fn default() -> Self {
        Self {
            capacity_mah: 5100.0,
            cells: 3,
        }
    }
}

/// Energy drawn so far and what it leaves.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BatteryGauge {
    /// Energy drawn [J].
    used_j: f64,
    /// Latest draw [W].
    power_w: f64,
}

impl BatteryGauge {
    /// Pack energy [J]: capacity × cells × nominal cell voltage.
    pub fn capacity_j(p: &BatteryParams) -> f64 {
        p.capacity_mah * 1e-3 * 3600.0 * f64::from(p.cells) * NOMINAL_CELL_V
    }

    /// Draws `power_w` [W] for `dt_s` [s] (negative or non-finite power counts as zero).
    pub fn draw(&mut self, power_w: f64, dt_s: f64) {
        let power_w = if power_w.is_finite() { power_w.max(0.0) } else { 0.0 };
        self.power_w = power_w;
        self.used_j += power_w * dt_s;
    }

    /// Remaining fraction of the pack [0, 1].
    pub fn fraction(&self, p: &BatteryParams) -> f64 {
        let capacity = Self::capacity_j(p);
        if capacity <= 0.0 {
            return 0.0;
        }
        (1.0 - self.used_j / capacity).clamp(0.0, 1.0)
    }

    /// Cell voltage [V], linear from 4.2 V full to 3.5 V empty.
    pub fn cell_voltage_v(&self, p: &BatteryParams) -> f64 {
        EMPTY_CELL_V + (FULL_CELL_V - EMPTY_CELL_V) * self.fraction(p)
    }

    /// Current [A] at the latest draw.
    pub fn current_a(&self, p: &BatteryParams) -> f64 {
        self.power_w / (self.cell_voltage_v(p) * f64::from(p.cells.max(1)))
    }

    /// Charge drawn [mAh] at the nominal voltage.
    pub fn consumed_mah(&self, p: &BatteryParams) -> f64 {
        self.used_j / (f64::from(p.cells.max(1)) * NOMINAL_CELL_V) / 3.6
    }

    /// Energy drawn [J].
    pub fn used_j(&self) -> f64 {
        self.used_j
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pack_drains_linearly_with_energy() {
        let p = BatteryParams {
            capacity_mah: 1000.0,
            cells: 4,
        };
        let capacity = BatteryGauge::capacity_j(&p);
        assert!((capacity - 53_280.0).abs() < 1e-6, "1 Ah × 4 × 3.7 V = 14.8 Wh");
        let mut g = BatteryGauge::default();
        assert_eq!(g.fraction(&p), 1.0);
        assert!((g.cell_voltage_v(&p) - 4.2).abs() < 1e-12);
        g.draw(capacity / 4.0, 1.0);
        assert!((g.fraction(&p) - 0.75).abs() < 1e-12);
        assert!((g.consumed_mah(&p) - 250.0).abs() < 1e-9);
        assert!((g.current_a(&p) - capacity / 4.0 / (4.0 * 4.025)).abs() < 1e-9);
        g.draw(f64::NAN, 1.0);
        g.draw(-5.0, 1.0);
        assert!((g.fraction(&p) - 0.75).abs() < 1e-12, "bad power draws nothing");
        g.draw(capacity, 1.0);
        assert_eq!(g.fraction(&p), 0.0);
    }
}
