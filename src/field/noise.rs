//! How much of a photo's structure tensor is noise (paper section 4: the pre-smoothing σ is
//! "the noise scale"; this measures the noise itself).
//!
//! White noise of variance `σ_c²` in channel `c` adds, in expectation, `σ_c²·E` to the trace
//! of `J = G_ρ * Σ_c ∇(G_σ * I_c) ∇(G_σ * I_c)ᵀ` and no direction, where `E` is the energy
//! (sum of squares) of the impulse responses of pre-smoothing followed by the Scharr x and y
//! derivatives ([`response_energy`]). `σ_c` is estimated at the finest scale of the analysis
//! image with Immerkær's mask (*Fast Noise Variance Estimation*, 1996), taking the median
//! absolute response instead of the mean, so edges and texture covering under half the picture
//! do not count as noise ([`channel_sigma`]). The metric ([`super::metric`]) then reads detail
//! above this level only: a flat, grainy wall or sky gets the large round ellipses of a flat
//! area instead of small ones turned every way by the grain.
//! `f32` for the image and its responses, as in [`super::structure`]; `f64` for the energies.

use super::blur::gaussian_blur_parallel_mut;
use super::structure::{gradient_products, LinearImage};
use rayon::prelude::*;

/// The expected trace `Σ_c σ_c²·E` that the noise of `img` adds to its structure tensor
/// computed with pre-smoothing `noise_sigma` (analysis pixels). 0 for images under 3×3.
#[must_use]
pub fn noise_energy(img: &LinearImage, noise_sigma: f32) -> f64 {
    let variance: f64 = (0..3).map(|c| channel_sigma(img, c).powi(2)).sum();
    if variance == 0.0 {
        return 0.0;
    }
    variance * response_energy(noise_sigma)
}

/// Robust standard deviation of the noise of channel `c` (0, 1 or 2) of `img`: the median of
/// `|N * I|` over the interior, `N = [1 −2 1; −2 4 −2; 1 −2 1]`, which for white Gaussian noise
/// of deviation σ is `0.6745·6σ` (`|N|₂ = 6`), while smooth shading gives 0. Every other row
/// and column is read (a quarter of a megapixel analysis image is plenty for a median), rows
/// in parallel, each into its own slots.
#[must_use]
pub fn channel_sigma(img: &LinearImage, c: usize) -> f64 {
    let (w, h) = (img.width, img.height);
    if w < 3 || h < 3 {
        return 0.0;
    }
    let (cols, rows) = ((w - 1) / 2, (h - 1) / 2);
    let mut responses = vec![0.0f32; cols * rows];
    responses
        .par_chunks_mut(cols)
        .enumerate()
        .for_each(|(k, out)| {
            let y = 2 * k + 1;
            let row = |y: usize| &img.data[y * w * 3..(y + 1) * w * 3];
            let (above, at, below) = (row(y - 1), row(y), row(y + 1));
            for (i, o) in out.iter_mut().enumerate() {
                // Channel c of the pixels left of, at and right of column 2i + 1.
                let (l, m, r) = ((2 * i) * 3 + c, (2 * i + 1) * 3 + c, (2 * i + 2) * 3 + c);
                let corners = above[l] + above[r] + below[l] + below[r];
                let sides = above[m] + at[l] + at[r] + below[m];
                *o = (corners - 2.0 * sides + 4.0 * at[m]).abs();
            }
        });
    let middle = responses.len() / 2;
    let (_, median, _) = responses.select_nth_unstable_by(middle, f32::total_cmp);
    f64::from(*median) / (0.674_5 * 6.0)
}

/// Energy `Σ (h_x² + h_y²)` of the impulse responses `h_x`, `h_y` of a Gaussian blur of
/// `sigma` pixels followed by the normalised Scharr derivatives: what unit-variance white
/// noise adds to `J`'s trace per channel. Computed on an impulse with the blur and the
/// gradient products the structure tensor itself uses ([`gradient_products`]).
#[must_use]
pub fn response_energy(sigma: f32) -> f64 {
    let radius = (4.0 * sigma.max(0.0)).ceil() as usize + 2;
    let side = 2 * radius + 1;
    // One channel holds the impulse; the others are zero and add nothing.
    let mut impulse = vec![0.0f32; 3 * side * side];
    impulse[3 * (radius * side + radius)] = 1.0;
    if sigma > 0.0 {
        gaussian_blur_parallel_mut(&mut impulse, side, side, 3, sigma);
    }
    gradient_products(&impulse, side, side)
        .iter()
        .map(|t| f64::from(t[0]) + f64::from(t[2]))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::structure::structure_tensor;

    /// A `w × h` image: a ramp rising `2·slope` per pixel along x and `slope` along y, plus
    /// white Gaussian noise of deviation `sigma` in every channel (Box–Muller on a 64-bit
    /// linear congruential generator's top 53 bits).
    fn noisy_ramp(w: usize, h: usize, sigma: f64, slope: f64, seed: u64) -> LinearImage {
        let mut state = seed;
        let mut uniform = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut data = Vec::with_capacity(w * h * 3);
        for y in 0..h {
            for x in 0..w {
                for _ in 0..3 {
                    let (u, v) = (uniform().max(1e-12), uniform());
                    let gauss = (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos();
                    let ramp = 0.3 + slope * (2.0 * x as f64 + y as f64);
                    data.push((ramp + sigma * gauss) as f32);
                }
            }
        }
        LinearImage {
            width: w,
            height: h,
            data,
        }
    }

    #[test]
    fn the_noise_of_a_ramp_is_found_and_the_ramp_is_not() {
        for sigma in [0.0, 0.004, 0.02] {
            let img = noisy_ramp(200, 150, sigma, 1e-3, 3);
            for c in 0..3 {
                let found = channel_sigma(&img, c);
                assert!(
                    (found - sigma).abs() <= 0.05 * sigma + 1e-6,
                    "channel {c}: {found} for {sigma}"
                );
            }
        }
    }

    #[test]
    fn the_energy_is_what_noise_adds_to_the_structure_tensor() {
        // The truth: the mean trace of the structure tensor of pure noise over a constant.
        for pre in [0.0f32, 0.8, 2.0] {
            let sigma = 0.01;
            let img = noisy_ramp(240, 240, sigma, 0.0, 11);
            let predicted = noise_energy(&img, pre);
            let j = structure_tensor(img, pre, 3.0);
            let (mut sum, mut n) = (0.0, 0.0);
            for y in 20..220 {
                for x in 20..220 {
                    let t = j[y * 240 + x];
                    sum += f64::from(t[0] + t[2]);
                    n += 1.0;
                }
            }
            let measured = sum / n;
            assert!(
                (measured / predicted - 1.0).abs() < 0.08,
                "pre-smoothing {pre}: measured {measured:e}, predicted {predicted:e}"
            );
        }
    }

    #[test]
    fn small_images_have_no_noise_estimate() {
        let img = LinearImage {
            width: 2,
            height: 2,
            data: vec![0.5; 12],
        };
        assert_eq!(noise_energy(&img, 1.0), 0.0);
    }
}
