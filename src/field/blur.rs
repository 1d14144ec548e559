//! Separable Gaussian blur of interleaved `f32` images (and of 8-bit ones, in bands of rows,
//! for the photo the edge-following cells read), parallel over rows with rayon, with
//! replicated (clamp-to-edge) borders and the kernel truncated at 3σ.
//!
//! This is the smoothing behind the structure tensor (pre-smoothing and integration, paper
//! section 4's metric from the image gradient). `benches/field.rs` measures it against
//! `kornia-imgproc`'s `gaussian_blur` and `imageproc`'s `gaussian_blur_f32`: both of those run on
//! one thread, kornia pads with zeros (a dark frame that the structure tensor would read as an
//! edge along every border) and imageproc truncates at 2σ, so neither is a drop-in here.

use rayon::prelude::*;

/// Normalised 1-D Gaussian weights for `sigma` (pixels), radius `ceil(3σ)`.
#[must_use]
pub fn gaussian_kernel(sigma: f32) -> Vec<f32> {
    let radius = (3.0 * sigma).ceil().max(1.0) as usize;
    let two_s2 = 2.0 * sigma * sigma;
    let mut k: Vec<f32> = (0..=2 * radius)
        .map(|i| {
            let x = i as f32 - radius as f32;
            (-x * x / two_s2).exp()
        })
        .collect();
    let sum: f32 = k.iter().sum();
    k.iter_mut().for_each(|w| *w /= sum);
    k
}

/// Gaussian blur of a `width × height` image with `channels` interleaved channels, into a
/// new buffer. A non-positive or non-finite `sigma` returns a copy.
///
/// # Panics
/// If `data.len() != width·height·channels`.
#[must_use]
pub fn gaussian_blur_parallel(
    data: &[f32],
    width: usize,
    height: usize,
    channels: usize,
    sigma: f32,
) -> Vec<f32> {
    let mut out = data.to_vec();
    gaussian_blur_parallel_mut(&mut out, width, height, channels, sigma);
    out
}

/// [`gaussian_blur_parallel`] in place: the horizontal pass reads the image row by row into
/// one scratch buffer and the vertical pass reads that back into the image, so a blur touches
/// one fresh buffer instead of two (on a VM, first touches of fresh pages were a third of the
/// metric stage's time) and copies no image.
/// Results are bit-identical to [`gaussian_blur_parallel`].
///
/// # Panics
/// If `data.len() != width·height·channels`.
pub fn gaussian_blur_parallel_mut(
    data: &mut [f32],
    width: usize,
    height: usize,
    channels: usize,
    sigma: f32,
) {
    assert_eq!(data.len(), width * height * channels, "image buffer size");
    if !(sigma > 0.0 && sigma.is_finite()) || data.is_empty() {
        return;
    }
    let mut copy = vec![0.0; data.len()];
    gaussian_blur_parallel_using(data, width, height, channels, sigma, &mut copy);
}

/// [`gaussian_blur_parallel_mut`] with the vertical pass's copy of the image in `scratch`
/// (overwritten; at least as long as `data`), so a caller with a spare buffer of that size
/// (a structure tensor blurs two images of one size) touches no fresh one.
///
/// # Panics
/// If `data.len() != width·height·channels` or `scratch` is shorter than `data`.
pub fn gaussian_blur_parallel_using(
    data: &mut [f32],
    width: usize,
    height: usize,
    channels: usize,
    sigma: f32,
    scratch: &mut [f32],
) {
    assert_eq!(data.len(), width * height * channels, "image buffer size");
    assert!(scratch.len() >= data.len(), "scratch buffer size");
    if !(sigma > 0.0 && sigma.is_finite()) || data.is_empty() {
        return;
    }
    let kernel = gaussian_kernel(sigma);
    let radius = kernel.len() / 2;
    let stride = width * channels;
    let shifts: Vec<usize> = (0..kernel.len()).map(|j| j * channels).collect();

    // Horizontal pass, into `scratch`: pad each row by replication into a buffer (one per
    // rayon job, not per pixel), then sum the taps block by block ([`weighted_rows`]).
    let horizontal = &mut scratch[..data.len()];
    horizontal
        .par_chunks_mut(stride)
        .zip(data.par_chunks(stride))
        .for_each_init(Vec::new, |padded: &mut Vec<f32>, (out, row)| {
            padded.clear();
            for _ in 0..radius {
                padded.extend_from_slice(&row[..channels]);
            }
            padded.extend_from_slice(row);
            for _ in 0..radius {
                padded.extend_from_slice(&row[stride - channels..]);
            }
            weighted_rows(out, &kernel, padded, &shifts);
        });

    // Vertical pass, back into `data`: each output row is a weighted sum of whole input rows,
    // read in order.
    let horizontal = &*horizontal;
    data.par_chunks_mut(stride).enumerate().for_each_init(
        Vec::new,
        |offsets: &mut Vec<usize>, (y, out_row)| {
            offsets.clear();
            offsets.extend(
                (0..kernel.len()).map(|j| (y + j).saturating_sub(radius).min(height - 1) * stride),
            );
            weighted_rows(out_row, &kernel, horizontal, offsets);
        },
    );
}

/// `out[i] = Σ_j kernel[j]·src[offsets[j] + i]`, the taps added in order from zero (the same
/// bits as adding tap by tap over the whole row), computed [`BLOCK`] values at a time so the
/// sums stay in registers: one write per value instead of one read and write per tap.
#[inline]
fn weighted_rows(out: &mut [f32], kernel: &[f32], src: &[f32], offsets: &[usize]) {
    let n = out.len();
    let whole = n - n % BLOCK;
    for (b, block) in out[..whole].chunks_exact_mut(BLOCK).enumerate() {
        let start = b * BLOCK;
        let mut acc = [0.0f32; BLOCK];
        for (&w, &off) in kernel.iter().zip(offsets) {
            let taps: &[f32; BLOCK] = src[off + start..off + start + BLOCK]
                .try_into()
                .expect("a block of the row");
            for (a, s) in acc.iter_mut().zip(taps) {
                *a += w * s;
            }
        }
        block.copy_from_slice(&acc);
    }
    let tail = &mut out[whole..];
    tail.fill(0.0);
    for (&w, &off) in kernel.iter().zip(offsets) {
        for (o, s) in tail.iter_mut().zip(&src[off + whole..off + n]) {
            *o += w * s;
        }
    }
}

/// A band's scratch in [`gaussian_blur_u8_parallel`]: a padded row, the band's rows blurred
/// along x, one row of vertical sums and the vertical taps' offsets.
type Scratch = (Vec<f32>, Vec<f32>, Vec<f32>, Vec<usize>);

/// Values per register block of [`weighted_rows`].
const BLOCK: usize = 16;

/// Gaussian blur of a `width × height` image of 8-bit samples with `channels` interleaved
/// channels, into a new buffer: the same arithmetic as converting to `f32`,
/// [`gaussian_blur_parallel_mut`] and rounding to the nearest byte (bit-identical results),
/// but in parallel bands of rows that each blur their rows and a margin of the kernel's radius
/// in a few rows of scratch, so no full-size `f32` plane is made and every pass runs on all
/// cores. A non-positive or non-finite
/// `sigma` returns a copy.
///
/// # Panics
/// If `data.len() != width·height·channels`.
#[must_use]
pub fn gaussian_blur_u8_parallel(
    data: &[u8],
    width: usize,
    height: usize,
    channels: usize,
    sigma: f32,
) -> Vec<u8> {
    assert_eq!(data.len(), width * height * channels, "image buffer size");
    if !(sigma > 0.0 && sigma.is_finite()) || data.is_empty() {
        return data.to_vec();
    }
    let kernel = gaussian_kernel(sigma);
    let radius = kernel.len() / 2;
    let stride = width * channels;
    let shifts: Vec<usize> = (0..kernel.len()).map(|j| j * channels).collect();
    let mut out = vec![0u8; data.len()];
    out.par_chunks_mut(stride * U8_BAND_ROWS)
        .enumerate()
        .for_each_init(
            || (Vec::new(), Vec::new(), Vec::new(), Vec::new()),
            |(padded, rows, acc, offsets): &mut Scratch, (band, chunk)| {
                let first = band * U8_BAND_ROWS;
                let end = first + chunk.len() / stride;
                // The rows this band's vertical pass reads, blurred along x.
                let (lo, hi) = (first.saturating_sub(radius), (end + radius).min(height));
                rows.clear();
                rows.resize((hi - lo) * stride, 0.0);
                acc.clear();
                acc.resize(stride, 0.0);
                for (y, row) in (lo..hi).zip(rows.chunks_exact_mut(stride)) {
                    let src = &data[y * stride..(y + 1) * stride];
                    padded.clear();
                    for _ in 0..radius {
                        padded.extend(src[..channels].iter().map(|&v| f32::from(v)));
                    }
                    padded.extend(src.iter().map(|&v| f32::from(v)));
                    for _ in 0..radius {
                        padded.extend(src[stride - channels..].iter().map(|&v| f32::from(v)));
                    }
                    weighted_rows(row, &kernel, padded, &shifts);
                }
                for (y, out_row) in (first..end).zip(chunk.chunks_exact_mut(stride)) {
                    offsets.clear();
                    offsets.extend(
                        (0..kernel.len()).map(|j| {
                            ((y + j).saturating_sub(radius).min(height - 1) - lo) * stride
                        }),
                    );
                    weighted_rows(acc, &kernel, rows, offsets);
                    for (o, &v) in out_row.iter_mut().zip(acc.iter()) {
                        *o = round_to_byte(v);
                    }
                }
            },
        );
    out
}

/// `v.round().clamp(0.0, 255.0) as u8` for a value meant as a byte (a blurred one, an inked
/// one), without the libm `roundf` call that baseline x86-64 makes for `round` (a tenth of
/// the blur's time): truncation and the exact fraction give the same rounding, half away from
/// zero.
#[inline]
#[must_use]
pub fn round_to_byte(v: f32) -> u8 {
    // Blurred bytes lie in [0, 255] up to rounding; the clamp keeps `as i32` in range and
    // NaN (never produced) at 0.
    let c = v.clamp(-1.0, 256.0);
    let t = c as i32;
    let frac = c - t as f32;
    let r = if frac >= 0.5 {
        t + 1
    } else if frac <= -0.5 {
        t - 1
    } else {
        t
    };
    r.clamp(0, 255) as u8
}

/// Rows per parallel band of [`gaussian_blur_u8_parallel`]: each band blurs `2·radius` rows
/// more than it writes along x, a sixth more work at σ = 1.
const U8_BAND_ROWS: usize = 32;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_to_byte_is_round_then_clamp() {
        let reference = |v: f32| v.round().clamp(0.0, 255.0) as u8;
        // Every f32 from -2 to 258 in steps of 1/1024, the halves and their neighbours, and
        // the specials.
        let mut values: Vec<f32> = (-2048..=264_192).map(|i| i as f32 / 1024.0).collect();
        for k in -2..=258 {
            let half = k as f32 + 0.5;
            values.extend([half, half.next_down(), half.next_up()]);
        }
        values.extend([
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            -0.0,
            1e30,
            -1e30,
        ]);
        for v in values {
            assert_eq!(round_to_byte(v), reference(v), "{v}");
        }
    }

    /// Brute-force 2-D convolution with clamped borders: the reference.
    fn reference(data: &[f32], w: usize, h: usize, sigma: f32) -> Vec<f32> {
        let k = gaussian_kernel(sigma);
        let r = (k.len() / 2) as isize;
        let mut out = vec![0.0; w * h];
        for y in 0..h as isize {
            for x in 0..w as isize {
                let mut acc = 0.0f64;
                for dy in -r..=r {
                    for dx in -r..=r {
                        let sx = (x + dx).clamp(0, w as isize - 1) as usize;
                        let sy = (y + dy).clamp(0, h as isize - 1) as usize;
                        acc += f64::from(k[(dx + r) as usize] * k[(dy + r) as usize])
                            * f64::from(data[sy * w + sx]);
                    }
                }
                out[y as usize * w + x as usize] = acc as f32;
            }
        }
        out
    }

    #[test]
    fn matches_brute_force_convolution() {
        let (w, h) = (23, 17);
        let data: Vec<f32> = (0..w * h)
            .map(|i| ((i * 7919) % 101) as f32 / 100.0)
            .collect();
        for sigma in [0.6, 1.5, 4.0] {
            let got = gaussian_blur_parallel(&data, w, h, 1, sigma);
            let want = reference(&data, w, h, sigma);
            for (g, r) in got.iter().zip(&want) {
                assert!((g - r).abs() < 1e-5, "sigma {sigma}: {g} vs {r}");
            }
        }
    }

    #[test]
    fn in_place_is_the_same_blur() {
        let (w, h) = (31, 9);
        let data: Vec<f32> = (0..w * h * 3).map(|i| ((i * 31) % 17) as f32).collect();
        let want = reference(
            &data.iter().step_by(3).copied().collect::<Vec<_>>(),
            w,
            h,
            2.0,
        );
        let mut got = data.clone();
        gaussian_blur_parallel_mut(&mut got, w, h, 3, 2.0);
        for (g, r) in got.iter().step_by(3).zip(&want) {
            assert!((g - r).abs() < 1e-4, "{g} vs {r}");
        }
        assert_eq!(got, gaussian_blur_parallel(&data, w, h, 3, 2.0));
    }

    #[test]
    fn constant_image_stays_constant_including_borders() {
        let data = vec![0.25f32; 9 * 5 * 3];
        let out = gaussian_blur_parallel(&data, 9, 5, 3, 3.0);
        assert!(out.iter().all(|v| (v - 0.25).abs() < 1e-6));
    }

    #[test]
    fn channels_are_independent_and_tiny_images_work() {
        let data = vec![1.0, 0.0, 2.0, 0.0];
        let out = gaussian_blur_parallel(&data, 1, 2, 2, 1.0);
        assert!((out[0] + out[2] - 3.0).abs() < 1e-5);
        assert!(out[1].abs() < 1e-7 && out[3].abs() < 1e-7);
        assert!((gaussian_blur_parallel(&[5.0], 1, 1, 1, 2.0)[0] - 5.0).abs() < 1e-5);
    }

    #[test]
    fn byte_blur_is_the_float_blur_rounded() {
        for (w, h, c, sigma) in [
            (37, 70, 3, 1.0),
            (5, 3, 1, 2.5),
            (1, 1, 3, 1.0),
            (64, 33, 2, 0.7),
        ] {
            let data: Vec<u8> = (0..w * h * c)
                .map(|i| ((i * 7919 + i / 7) % 256) as u8)
                .collect();
            let mut float: Vec<f32> = data.iter().map(|&v| f32::from(v)).collect();
            gaussian_blur_parallel_mut(&mut float, w, h, c, sigma);
            let want: Vec<u8> = float
                .iter()
                .map(|v| v.round().clamp(0.0, 255.0) as u8)
                .collect();
            assert_eq!(
                gaussian_blur_u8_parallel(&data, w, h, c, sigma),
                want,
                "{w}x{h}x{c}"
            );
        }
        assert_eq!(
            gaussian_blur_u8_parallel(&[9, 8, 7], 1, 1, 3, 0.0),
            vec![9, 8, 7]
        );
    }
}
