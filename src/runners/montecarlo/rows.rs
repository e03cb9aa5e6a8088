//! A campaign's runs as rows of a sweep's results table (docs/sweep.md §5): the law and the drawn
//! state are the axes, the trial's outcome the metrics, so `--out` writes the same Parquet
//! layout as `rotorpilot sweep`. Pure.

use crate::control::ControllerKind;
use crate::math::euler_zyx;
use crate::sweep::metrics::Scalar;
use crate::sweep::results::{RunRow, Status};
use crate::sweep::{Axis, AxisValues};

use super::envelope::{Draw, Envelope};
use super::stats::RunResult;

/// The drawn quantities, each a column of three: name, and its bound in `env` per element.
fn drawn(env: &Envelope) -> [(&'static str, [f64; 3]); 6] {
    let tilt = env.max_tilt_rad.to_degrees();
    [
        ("initial.position", [env.max_offset_m; 3]),
        ("initial.velocity", [env.max_speed_m_s; 3]),
        ("initial.attitude", [tilt, tilt, 180.0]),
        ("initial.rates", [env.max_rate_rad_s.to_degrees(); 3]),
        ("disturbance.force", [env.max_force_n; 3]),
        ("disturbance.torque", env.max_torque_n_m),
    ]
}

/// The axes of a campaign: the law, then every drawn element in the envelope's bounds
/// (position [m], velocity [m/s], roll/pitch/yaw [deg], body rates [deg/s], force world NED
/// [N], torque body FRD [N·m]).
pub fn axes(controllers: &[ControllerKind], env: &Envelope) -> Vec<Axis> {
    let law = Axis {
        field: "controller".into(),
        also: Vec::new(),
        values: AxisValues::List(
            controllers
                .iter()
                .map(|k| toml::Value::String(k.name().into()))
                .collect(),
        ),
    };
    let elements = drawn(env).into_iter().flat_map(|(name, bound)| {
        (0..3).map(move |k| Axis {
            field: format!("{name}[{k}]"),
            also: Vec::new(),
            values: AxisValues::Uniform {
                lo: -bound[k],
                hi: bound[k],
                integer: false,
            },
        })
    });
    std::iter::once(law).chain(elements).collect()
}

/// The values of `draw` in the order of [`axes`] after the law.
fn drawn_values(d: &Draw) -> Vec<toml::Value> {
    let rpy = euler_zyx(&d.q_wb.to_rotation_matrix().into_inner()).map(f64::to_degrees);
    let rates = d.omega_b.map(f64::to_degrees);
    [d.pos_w, d.vel_w, rpy, rates, d.force_w, d.torque_b]
        .iter()
        .flat_map(|v| v.iter().map(|x| toml::Value::Float(*x)).collect::<Vec<_>>())
        .collect()
}

/// One row per law and draw, the laws in order (`run` = law index × draws + draw index,
/// `point` = the draw's index, `seed` = the campaign's seed, which with `point` names the draw).
pub fn rows(controllers: &[ControllerKind], seed: u64, draws: &[Draw], results: &[Vec<RunResult>]) -> Vec<RunRow> {
    let mut out = Vec::with_capacity(controllers.len() * draws.len());
    for (l, (kind, runs)) in controllers.iter().zip(results).enumerate() {
        for (i, (draw, result)) in draws.iter().zip(runs).enumerate() {
            let mut values = vec![toml::Value::String(kind.name().into())];
            values.extend(drawn_values(draw));
            let (status, error, metrics) = match result {
                RunResult::Flew(o) => {
                    let mut m = vec![
                        ("exit".to_string(), Scalar::Text(o.end.name().into())),
                        ("converged".into(), Scalar::Bool(o.converged)),
                        ("final_position_error_m".into(), Scalar::Float(o.final_position_error_m)),
                        (
                            "final_attitude_error_deg".into(),
                            Scalar::Float(o.final_attitude_error_rad.to_degrees()),
                        ),
                        ("max_tilt_deg".into(), Scalar::Float(o.max_tilt_rad.to_degrees())),
                        ("non_finite".into(), Scalar::Bool(o.non_finite)),
                        ("fault_ticks".into(), Scalar::Int(o.fault_ticks as i64)),
                        ("saturated_ticks".into(), Scalar::Int(o.saturated_ticks as i64)),
                        ("ticks".into(), Scalar::Int(o.ticks as i64)),
                    ];
                    if let Some(t) = o.convergence_time_s {
                        m.push(("convergence_time_s".into(), Scalar::Float(t)));
                    }
                    (Status::Ok, None, m)
                }
                RunResult::Panicked(why) => (Status::Panicked, Some(why.clone()), Vec::new()),
            };
            out.push(RunRow {
                run: l * draws.len() + i,
                point: i,
                seed,
                values,
                status,
                error,
                metrics,
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lockstep::Exit;
    use crate::runners::montecarlo::envelope::draws;
    use crate::runners::montecarlo::TrialOutcome;
    use crate::sweep::results::{columns, ColumnKind};

    #[test]
    fn every_law_and_draw_is_a_row_with_its_state_and_outcome() {
        let env = Envelope::HOVER;
        let ds = draws(&env, 3, 2);
        let laws = [ControllerKind::Geometric, ControllerKind::Hierarchical];
        let flew = RunResult::Flew(TrialOutcome {
            end: Exit::Complete,
            converged: true,
            convergence_time_s: Some(1.5),
            final_position_error_m: 0.01,
            final_attitude_error_rad: 0.0,
            max_tilt_rad: 0.5,
            non_finite: false,
            fault_ticks: 0,
            saturated_ticks: 7,
            ticks: 6000,
        });
        let results = vec![vec![flew.clone(), flew], vec![RunResult::Panicked("boom".into()); 2]];
        let axes = axes(&laws, &env);
        let rows = rows(&laws, 3, &ds, &results);
        assert_eq!(rows.len(), 4);
        assert_eq!(
            (rows[3].run, rows[3].point, rows[3].seed, rows[3].status),
            (3, 1, 3, Status::Panicked)
        );
        let table = columns(&axes, &rows);
        let col = |name: &str| table.iter().find(|c| c.name == name).unwrap();
        assert_eq!(col("controller").cells[2], Some(Scalar::Text("hierarchical".into())));
        assert_eq!(col("initial.position[2]").kind, ColumnKind::Float);
        assert_eq!(col("initial.position[2]").cells[1], Some(Scalar::Float(ds[1].pos_w.z)));
        let tilt = ds[0].tilt_rad().to_degrees();
        let Some(Scalar::Float(roll)) = col("initial.attitude[0]").cells[0] else {
            panic!()
        };
        assert!(roll.abs() <= tilt + 1e-9);
        assert_eq!(
            col("convergence_time_s").cells,
            [Some(Scalar::Float(1.5)), Some(Scalar::Float(1.5)), None, None]
        );
        assert_eq!(col("saturated_ticks").cells[0], Some(Scalar::Int(7)));
        assert_eq!(col("error").cells[3], Some(Scalar::Text("boom".into())));
    }
}
