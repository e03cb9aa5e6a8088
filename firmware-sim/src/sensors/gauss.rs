//! Random draws shared by every sensor model: standard normals and uniforms from a ChaCha8
//! stream, bit-identical on every platform (docs/model.md §6).
//!
//! Normal variates use the Box–Muller transform (cosine branch) on 53-bit uniforms; each call
//! consumes exactly two 64-bit words, so a stream's position depends only on how many draws were
//! made, never on their values.

use nalgebra::Vector3;
use rand_chacha::rand_core::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Three independent N(0, sd²) values; draws from the RNG even when sd is 0 so the stream
/// position does not depend on which channels are noisy.
pub(crate) fn gaussian3(rng: &mut ChaCha8Rng, sd: f64) -> Vector3<f64> {
    Vector3::new(gaussian(rng), gaussian(rng), gaussian(rng)) * sd
}

/// One standard normal variate (Box–Muller, cosine branch).
pub(crate) fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    let u1 = 1.0 - uniform(rng); // (0, 1]: the logarithm stays finite
    let u2 = uniform(rng);
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// Uniform in [0, 1) from the top 53 bits of a u64.
pub(crate) fn uniform(rng: &mut ChaCha8Rng) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// Uniform in [lo, hi).
pub(crate) fn uniform_in(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * uniform(rng)
}

/// Three independent uniforms in [−half_width, half_width).
pub(crate) fn uniform3(rng: &mut ChaCha8Rng, half_width: f64) -> Vector3<f64> {
    Vector3::new(
        uniform_in(rng, -half_width, half_width),
        uniform_in(rng, -half_width, half_width),
        uniform_in(rng, -half_width, half_width),
    )
}

/// ChaCha8 seeded from `seed` on stream `stream`. Stream 0 is what [`crate::rand_chacha_seed`]
/// gives (the state sensor's generator); the sensor suite uses streams from 1 up, so the same
/// seed never makes two generators share draws.
pub(crate) fn seeded_stream(seed: u64, stream: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(stream);
    rng
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stream_zero_is_the_plain_seeded_generator_and_streams_differ() {
        let mut plain = crate::rand_chacha_seed(9);
        let mut zero = seeded_stream(9, 0);
        let mut one = seeded_stream(9, 1);
        let a = plain.next_u64();
        assert_eq!(a, zero.next_u64());
        assert_ne!(a, one.next_u64());
    }

    #[test]
    fn uniforms_are_flat_on_their_interval() {
        let mut rng = seeded_stream(3, 4);
        let n = 100_000;
        let xs: Vec<f64> = (0..n).map(|_| uniform_in(&mut rng, -2.0, 6.0)).collect();
        assert!(xs.iter().all(|x| (-2.0..6.0).contains(x)));
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        // Uniform on [a, b): mean (a+b)/2 = 2, variance (b−a)²/12 = 16/3. Standard errors for
        // n = 1e5: mean √(16/3/n) ≈ 0.0073; relative variance √((9/5 − 1)/n) ≈ 0.28 %.
        assert!((mean - 2.0).abs() < 0.04, "mean {mean}");
        assert!((var / (16.0 / 3.0) - 1.0).abs() < 0.02, "var {var}");
    }
}
