//! The points of a sweep: its axes combined into a full grid, random draws or a Latin hypercube
//! (docs/sweep.md §2, eqs. (2.1)–(2.3)); deterministic in the design's seed. Pure.

use rand_chacha::rand_core::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::SweepError;

/// Where an axis's values come from.
#[derive(Debug, Clone, PartialEq)]
pub enum AxisValues {
    /// Explicit values.
    List(Vec<toml::Value>),
    /// `[lo, hi]` drawn uniformly (random and Latin-hypercube designs).
    Uniform {
        /// Lower bound.
        lo: f64,
        /// Upper bound.
        hi: f64,
        /// Rounded to integers.
        integer: bool,
    },
}

/// One swept scenario field.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// Dotted path of the field (`estimator.order`, `initial.position[2]`); it names the
    /// axis's column.
    pub field: String,
    /// Further fields that take the same value.
    pub also: Vec<String>,
    /// Its values.
    pub values: AxisValues,
}

impl Axis {
    /// Every field the axis sets: its own, then those of `also`.
    pub fn fields(&self) -> impl Iterator<Item = &String> {
        std::iter::once(&self.field).chain(&self.also)
    }
}

/// How the axes combine.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Design {
    /// Every combination of the listed values, the last axis varying fastest (2.1).
    Grid,
    /// `samples` independent draws of every axis (2.2).
    Random {
        /// Points drawn.
        samples: usize,
        /// Seed of the draws.
        seed: u64,
    },
    /// `samples` points with every axis's range cut in `samples` strata, each stratum used once
    /// per axis (2.3).
    LatinHypercube {
        /// Points drawn.
        samples: usize,
        /// Seed of the draws.
        seed: u64,
    },
}

/// One point: a value for every axis, in axis order.
pub type Point = Vec<toml::Value>;

/// The `lo..=hi` range in `steps` evenly spaced values [-], rounded when `integer`.
pub fn range_values(lo: f64, hi: f64, steps: usize, integer: bool) -> Vec<toml::Value> {
    (0..steps)
        .map(|i| {
            let x = lo + (hi - lo) * i as f64 / (steps - 1) as f64;
            number(x, integer)
        })
        .collect()
}

fn number(x: f64, integer: bool) -> toml::Value {
    if integer {
        toml::Value::Integer(x.round() as i64)
    } else {
        toml::Value::Float(x)
    }
}

/// A number uniform in [0, 1) from the top 53 bits of one `u64` (the Monte Carlo draws too).
pub(crate) fn unit(rng: &mut ChaCha8Rng) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// The first value an axis takes: its first listed value, or the low end of its interval.
pub fn first_value(values: &AxisValues) -> toml::Value {
    match values {
        AxisValues::List(v) => v.first().cloned().unwrap_or(toml::Value::Boolean(false)),
        AxisValues::Uniform { lo, integer, .. } => number(*lo, *integer),
    }
}

/// The value of `axis` at quantile `u` ∈ [0, 1).
fn at_quantile(axis: &Axis, u: f64) -> toml::Value {
    match &axis.values {
        AxisValues::List(values) => values[((u * values.len() as f64) as usize).min(values.len() - 1)].clone(),
        AxisValues::Uniform { lo, hi, integer } => number(lo + (hi - lo) * u, *integer),
    }
}

/// Every point of `axes` combined by `design`, in a fixed order.
pub fn points(axes: &[Axis], design: Design) -> Result<Vec<Point>, SweepError> {
    match design {
        Design::Grid => grid(axes),
        Design::Random { samples, seed } => {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            Ok((0..samples)
                .map(|_| axes.iter().map(|a| at_quantile(a, unit(&mut rng))).collect())
                .collect())
        }
        Design::LatinHypercube { samples, seed } => {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let mut columns = Vec::with_capacity(axes.len());
            for axis in axes {
                let mut strata: Vec<usize> = (0..samples).collect();
                // Fisher–Yates with the design's stream: each stratum once per axis.
                for i in (1..samples).rev() {
                    let j = (rng.next_u64() % (i as u64 + 1)) as usize;
                    strata.swap(i, j);
                }
                let column: Vec<toml::Value> = strata
                    .iter()
                    .map(|&k| at_quantile(axis, (k as f64 + unit(&mut rng)) / samples as f64))
                    .collect();
                columns.push(column);
            }
            Ok((0..samples)
                .map(|i| columns.iter().map(|c| c[i].clone()).collect())
                .collect())
        }
    }
}

/// Whether `axes` can be combined by `design`: a grid takes only listed values.
pub fn check(axes: &[Axis], design: Design) -> Result<(), SweepError> {
    match (
        design,
        axes.iter().find(|a| matches!(a.values, AxisValues::Uniform { .. })),
    ) {
        (Design::Grid, Some(axis)) => Err(SweepError::Invalid(format!(
            "axis `{}`: `uniform` needs a random or latin_hypercube design; a grid takes `values` or `range`",
            axis.field
        ))),
        _ => Ok(()),
    }
}

/// The full grid of list axes, the last one varying fastest (2.1).
fn grid(axes: &[Axis]) -> Result<Vec<Point>, SweepError> {
    check(axes, Design::Grid)?;
    let lists: Vec<&Vec<toml::Value>> = axes
        .iter()
        .filter_map(|a| match &a.values {
            AxisValues::List(values) => Some(values),
            AxisValues::Uniform { .. } => None,
        })
        .collect();
    let mut out: Vec<Point> = vec![Vec::new()];
    for values in lists {
        out = out
            .into_iter()
            .flat_map(|p| {
                values.iter().map(move |v| {
                    let mut q = p.clone();
                    q.push(v.clone());
                    q
                })
            })
            .collect();
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn list(field: &str, values: &[i64]) -> Axis {
        Axis {
            field: field.into(),
            also: Vec::new(),
            values: AxisValues::List(values.iter().map(|v| toml::Value::Integer(*v)).collect()),
        }
    }

    fn uniform(field: &str, lo: f64, hi: f64) -> Axis {
        Axis {
            field: field.into(),
            also: Vec::new(),
            values: AxisValues::Uniform { lo, hi, integer: false },
        }
    }

    #[test]
    fn a_grid_is_every_combination_with_the_last_axis_fastest() {
        let p = points(&[list("a", &[1, 2]), list("b", &[10, 20, 30])], Design::Grid).unwrap();
        let ints: Vec<Vec<i64>> = p
            .iter()
            .map(|q| q.iter().map(|v| v.as_integer().unwrap()).collect())
            .collect();
        assert_eq!(
            ints,
            vec![
                vec![1, 10],
                vec![1, 20],
                vec![1, 30],
                vec![2, 10],
                vec![2, 20],
                vec![2, 30]
            ]
        );
        assert_eq!(points(&[], Design::Grid).unwrap(), vec![Vec::<toml::Value>::new()]);
        assert!(points(&[uniform("c", 0.0, 1.0)], Design::Grid).is_err());
    }

    #[test]
    fn ranges_include_both_ends() {
        let v = range_values(1.0, 13.0, 7, true);
        let ints: Vec<i64> = v.iter().map(|x| x.as_integer().unwrap()).collect();
        assert_eq!(ints, vec![1, 3, 5, 7, 9, 11, 13]);
        let f = range_values(0.5, 1.0, 3, false);
        assert_eq!(f[1].as_float(), Some(0.75));
    }

    #[test]
    fn random_draws_are_in_range_and_repeat_with_the_seed() {
        let axes = [uniform("x", -2.0, 3.0), list("k", &[4, 5])];
        let a = points(&axes, Design::Random { samples: 200, seed: 7 }).unwrap();
        assert_eq!(a, points(&axes, Design::Random { samples: 200, seed: 7 }).unwrap());
        assert_ne!(a, points(&axes, Design::Random { samples: 200, seed: 8 }).unwrap());
        assert!(a.iter().all(|p| (-2.0..3.0).contains(&p[0].as_float().unwrap())));
        let fours = a.iter().filter(|p| p[1].as_integer() == Some(4)).count();
        assert!((60..140).contains(&fours), "both values drawn: {fours}");
    }

    #[test]
    fn a_latin_hypercube_uses_every_stratum_of_every_axis_once() {
        let n = 50;
        let axes = [uniform("x", 0.0, 1.0), uniform("y", 10.0, 20.0)];
        let p = points(&axes, Design::LatinHypercube { samples: n, seed: 3 }).unwrap();
        for (j, (lo, hi)) in [(0.0, 1.0), (10.0, 20.0)].iter().enumerate() {
            let mut strata: Vec<usize> = p
                .iter()
                .map(|q| ((q[j].as_float().unwrap() - lo) / (hi - lo) * n as f64) as usize)
                .collect();
            strata.sort_unstable();
            assert_eq!(strata, (0..n).collect::<Vec<_>>(), "axis {j}");
        }
    }
}
