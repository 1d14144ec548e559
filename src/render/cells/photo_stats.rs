//! What the edge-following cells' colour term reads of a photo to adapt to it
//! ([`cells`](super)): the range of its colours, over which colour differences weigh,
//! and its grain, which the colour term's photo is blurred against. Both from sRGB bytes,
//! every channel on its own, counted in integer histograms summed over parallel chunks (the
//! same figures at any thread count).

use image::RgbImage;
use rayon::prelude::*;

/// The range of `photo`'s colours: per channel the spread between its 1st and 99th
/// percentiles (of every fourth pixel), the largest over the channels, in [0, 1].
#[must_use]
pub(crate) fn colour_spread(photo: &RgbImage) -> f64 {
    let counts = photo
        .as_raw()
        .par_chunks(3 * 4 * 4096)
        .fold(
            || histograms(256),
            |mut counts, chunk| {
                for px in chunk.chunks_exact(3).step_by(4) {
                    for (histogram, &v) in counts.iter_mut().zip(px) {
                        histogram[usize::from(v)] += 1;
                    }
                }
                counts
            },
        )
        .reduce(|| histograms(256), summed);
    counts
        .iter()
        .map(|c| (quantile(c, 0.99) as f64 - quantile(c, 0.01) as f64) / 255.0)
        .fold(0.0, f64::max)
}

/// Three empty histograms of `bins` values, one per channel.
fn histograms(bins: usize) -> [Vec<u32>; 3] {
    [0; 3].map(|_| vec![0u32; bins])
}

/// Per channel, the counts of `a` and `b` together.
fn summed(mut a: [Vec<u32>; 3], b: [Vec<u32>; 3]) -> [Vec<u32>; 3] {
    for (a, b) in a.iter_mut().zip(&b) {
        for (a, b) in a.iter_mut().zip(b) {
            *a += b;
        }
    }
    a
}

/// The first value of `histogram` at or past share `q` of its counts (0 for none).
fn quantile(histogram: &[u32], q: f64) -> usize {
    let total: u64 = histogram.iter().map(|&n| u64::from(n)).sum();
    let want = ((q * total as f64).ceil() as u64).max(1);
    let mut seen = 0u64;
    histogram
        .iter()
        .position(|&n| {
            seen += u64::from(n);
            seen >= want
        })
        .unwrap_or(0)
}

/// The grain of `photo` in levels: Immerkær's robust noise estimate (*Fast Noise Variance
/// Estimation*, 1996, as the metric's [`noise`](crate::field::noise) takes it in linear
/// light), the median of `|N * I|` with `N = [1 −2 1; −2 4 −2; 1 −2 1]` over every fourth row
/// and column of the interior ([`GRAIN_STRIDE`]), divided by `0.6745·6` (white noise of
/// deviation σ gives σ), the largest over the channels. Smooth shading and edges covering
/// under half the picture give 0. 0 for photos under 3 × 3.
#[must_use]
pub(crate) fn grain_sigma(photo: &RgbImage) -> f64 {
    let (w, h) = (photo.width() as usize, photo.height() as usize);
    if w < 3 || h < 3 {
        return 0.0;
    }
    let raw = photo.as_raw();
    let row = |y: usize| &raw[3 * y * w..3 * (y + 1) * w];
    let empty = || histograms(MAX_RESPONSE + 1);
    let counts = (1..h - 1)
        .into_par_iter()
        .step_by(GRAIN_STRIDE)
        .with_min_len(16)
        .fold(empty, |mut counts, y| {
            let (above, here, below) = (row(y - 1), row(y), row(y + 1));
            for x in (1..w - 1).step_by(GRAIN_STRIDE) {
                let (l, m, r) = (3 * (x - 1), 3 * x, 3 * (x + 1));
                for (c, histogram) in counts.iter_mut().enumerate() {
                    let v = |line: &[u8], i: usize| i32::from(line[i + c]);
                    let corners = v(above, l) + v(above, r) + v(below, l) + v(below, r);
                    let sides = v(above, m) + v(here, l) + v(here, r) + v(below, m);
                    let response = corners - 2 * sides + 4 * v(here, m);
                    histogram[response.unsigned_abs() as usize] += 1;
                }
            }
            counts
        })
        .reduce(empty, summed);
    counts
        .iter()
        .map(|histogram| quantile(histogram, 0.5) as f64 / (0.6745 * 6.0))
        .fold(0.0, f64::max)
}

/// [`grain_sigma`] reads every this many rows and columns: a sixteenth of the pixels, plenty
/// for a median (a 12 MP photo took 17–30 ms at every other row and column beside the
/// sampler, 7 ms now).
const GRAIN_STRIDE: usize = 4;

/// The largest `|N * I|` of 8-bit values: 16 × 255.
const MAX_RESPONSE: usize = 16 * 255;

#[cfg(test)]
mod tests {
    use super::*;

    /// A smooth ramp with a hard edge through it, plus `noise(x, y)` levels.
    fn ramp(noise: impl Fn(u32, u32) -> f64) -> RgbImage {
        RgbImage::from_fn(120, 90, |x, y| {
            let base = if x < 60 { 40.0 } else { 200.0 } + f64::from(y) * 0.3;
            let v = (base + noise(x, y)).round().clamp(0.0, 255.0) as u8;
            image::Rgb([v, v / 2, 255 - v])
        })
    }

    #[test]
    fn grain_is_the_noise_and_not_the_edges_or_shading() {
        // Without grain the edge and the ramp give none.
        assert_eq!(grain_sigma(&ramp(|_, _| 0.0)), 0.0);
        // Gaussian-like noise of deviation 4 (a sum of twelve hashed uniforms): within 20 %.
        let noisy = ramp(|x, y| {
            let sum: f64 = (0..12u64)
                .map(|k| {
                    // SplitMix64 of the point and the draw.
                    let mut z = (u64::from(x) << 40 | u64::from(y) << 20 | k)
                        .wrapping_add(0x9E37_79B9_7F4A_7C15);
                    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
                    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
                    z ^= z >> 31;
                    (z >> 11) as f64 / (1u64 << 53) as f64
                })
                .sum();
            4.0 * (sum - 6.0)
        });
        let sigma = grain_sigma(&noisy);
        assert!(
            (3.2..4.8).contains(&sigma),
            "grain {sigma:.2} for noise of 4"
        );
        // Tiny photos have none to measure.
        assert_eq!(grain_sigma(&RgbImage::new(2, 2)), 0.0);
    }

    #[test]
    fn the_spread_is_the_widest_channels_middle_98_percent() {
        // Red spans 0..=255 evenly, green 100..=150, blue one value.
        let photo = RgbImage::from_fn(256, 64, |x, y| {
            image::Rgb([x as u8, 100 + ((x + y) % 51) as u8, 7])
        });
        let spread = colour_spread(&photo);
        assert!((spread - 252.0 / 255.0).abs() < 0.02, "spread {spread:.3}");
        let flat = RgbImage::from_pixel(64, 64, image::Rgb([9, 9, 9]));
        assert_eq!(colour_spread(&flat), 0.0);
    }
}
