//! The colour structure tensor of a photo (paper section 4 and Figure 5: the metric is derived
//! from "the image gradient and its orthogonal vector field").
//!
//! `J = G_ρ * Σ_c ∇(G_σ * I_c) ∇(G_σ * I_c)ᵀ` over the three channels in linear light, with
//! pre-smoothing σ (noise scale) and integration ρ. The photo is first box-averaged, in linear
//! light, to an *analysis resolution* whose diagonal is at most a set number of pixels: every
//! scale of the metric is a fraction of the image diagonal, so a 12 MP photo and its 512 px
//! thumbnail give the same field, and the cost stays flat as photos grow.

use super::blur::gaussian_blur_parallel_using;
use image::DynamicImage;
use rayon::prelude::*;

/// A three-channel image in linear light, `f32`, interleaved RGB, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearImage {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// `width·height·3` values, nominally in `[0, 1]`.
    pub data: Vec<f32>,
}

/// sRGB transfer function decoded to linear light.
#[must_use]
pub fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear light encoded with the sRGB transfer function.
#[must_use]
pub fn linear_to_srgb(v: f32) -> f32 {
    let v = v.clamp(0.0, 1.0);
    if v <= 0.003_130_8 {
        v * 12.92
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// The integer downsampling factor that brings `width × height` to a diagonal of at most
/// `max_diagonal` pixels (1 = full resolution; `max_diagonal = 0` means no limit).
#[must_use]
pub fn analysis_factor(width: usize, height: usize, max_diagonal: usize) -> usize {
    if max_diagonal == 0 {
        return 1;
    }
    let diag = ((width * width + height * height) as f64).sqrt();
    (diag / max_diagonal as f64).ceil().max(1.0) as usize
}

/// The photo in linear light, box-averaged by `factor` (the last block of a row or column
/// averages the pixels it has). Alpha is composited over white, the paper colour.
#[must_use]
pub fn linear_analysis_image(photo: &DynamicImage, factor: usize) -> LinearImage {
    let (w, h) = (photo.width() as usize, photo.height() as usize);
    let factor = factor.max(1);
    let (aw, ah) = (w.div_ceil(factor), h.div_ceil(factor));
    let lut: Vec<f32> = (0..256).map(|i| srgb_to_linear(i as f32 / 255.0)).collect();
    let mut data = vec![0.0f32; aw * ah * 3];
    // One job per output row; each reads `factor` input rows in order.
    match photo {
        DynamicImage::ImageRgb8(rgb) => {
            let raw = rgb.as_raw();
            data.par_chunks_mut(aw * 3)
                .enumerate()
                .for_each(|(ar, out)| {
                    box_rows(out, ar, factor, w, h, |x, y| {
                        let i = (y * w + x) * 3;
                        [
                            lut[raw[i] as usize],
                            lut[raw[i + 1] as usize],
                            lut[raw[i + 2] as usize],
                        ]
                    });
                });
        }
        DynamicImage::ImageLuma8(grey) => {
            let raw = grey.as_raw();
            data.par_chunks_mut(aw * 3)
                .enumerate()
                .for_each(|(ar, out)| {
                    box_rows(out, ar, factor, w, h, |x, y| {
                        let v = lut[raw[y * w + x] as usize];
                        [v, v, v]
                    });
                });
        }
        other => {
            // Every other layout (alpha, 16-bit, float) goes through RGBA f32 once.
            let rgba = other.to_rgba32f();
            let raw = rgba.as_raw();
            data.par_chunks_mut(aw * 3)
                .enumerate()
                .for_each(|(ar, out)| {
                    box_rows(out, ar, factor, w, h, |x, y| {
                        let i = (y * w + x) * 4;
                        let a = raw[i + 3].clamp(0.0, 1.0);
                        let ch = |v: f32| srgb_to_linear(v.clamp(0.0, 1.0)) * a + (1.0 - a);
                        [ch(raw[i]), ch(raw[i + 1]), ch(raw[i + 2])]
                    });
                });
        }
    }
    LinearImage {
        width: aw,
        height: ah,
        data,
    }
}

/// Averages the `factor × factor` blocks of analysis row `ar` into `out` (RGB interleaved).
fn box_rows(
    out: &mut [f32],
    ar: usize,
    factor: usize,
    w: usize,
    h: usize,
    pixel: impl Fn(usize, usize) -> [f32; 3],
) {
    let y0 = ar * factor;
    let y1 = (y0 + factor).min(h);
    for (ac, o) in out.chunks_exact_mut(3).enumerate() {
        let x0 = ac * factor;
        let x1 = (x0 + factor).min(w);
        let mut acc = [0.0f32; 3];
        for y in y0..y1 {
            for x in x0..x1 {
                let p = pixel(x, y);
                acc[0] += p[0];
                acc[1] += p[1];
                acc[2] += p[2];
            }
        }
        let n = ((y1 - y0) * (x1 - x0)) as f32;
        o.copy_from_slice(&[acc[0] / n, acc[1] / n, acc[2] / n]);
    }
}

/// The colour structure tensor `(Jxx, Jxy, Jyy)` per pixel of `img`, with pre-smoothing
/// `noise_sigma` and integration `integration_sigma`, both in pixels of `img` (which is
/// smoothed in place: no copy of the image is made). Gradients are the normalised Scharr
/// operator (replicated border), whose 3x3 weights are optimised for rotation invariance:
/// central differences bias the direction of a 14 px stripe pattern by more than a degree,
/// Scharr by a few hundredths.
#[must_use]
pub fn structure_tensor(
    img: LinearImage,
    noise_sigma: f32,
    integration_sigma: f32,
) -> Vec<[f32; 3]> {
    let (w, h) = (img.width, img.height);
    let mut smooth = img.data;
    // Two buffers of the image's size in all: the tensor's is the first blur's scratch before
    // the gradients fill it, and the smoothed image the second blur's once they are taken.
    let mut j = vec![[0.0f32; 3]; w * h];
    gaussian_blur_parallel_using(&mut smooth, w, h, 3, noise_sigma, j.as_flattened_mut());
    gradient_products_into(&smooth, w, h, &mut j);
    gaussian_blur_parallel_using(
        j.as_flattened_mut(),
        w,
        h,
        3,
        integration_sigma,
        &mut smooth,
    );
    j
}

/// Kornia's normalised Scharr kernels (`kornia_imgproc::filter::kernels`): x, then y, rows top
/// to bottom.
const SCHARR_X: [[f32; 3]; 3] = [
    [-0.093_75, 0.0, 0.093_75],
    [-0.3125, 0.0, 0.3125],
    [-0.093_75, 0.0, 0.093_75],
];
const SCHARR_Y: [[f32; 3]; 3] = [
    [-0.093_75, -0.3125, -0.093_75],
    [0.0, 0.0, 0.0],
    [0.093_75, 0.3125, 0.093_75],
];

/// `Σ_c ∇I_c ∇I_cᵀ` per pixel of an interleaved RGB image (`w × h`), the gradients by the
/// normalised Scharr operator with replicated borders, in one parallel pass over rows that
/// keeps no gradient images: each row's gradients are accumulated tap by tap over the whole
/// row (a loop the compiler vectorises) in a scratch row, then multiplied out.
///
/// Every pixel's taps are added in the order kornia's `scharr_spatial_gradient_float` adds
/// them, so the result is bit-identical to its gradients multiplied out (tested); the taps
/// of weight zero are left out, which changes no bit (adding a zero product to a sum that
/// starts at +0 leaves it as it is, for finite pixels). Kornia's operator writes two full
/// gradient images (at a megapixel 24 MB of fresh pages, 25 ms with the products in a paint
/// on one thread); `benches/field.rs` measures both.
#[must_use]
pub fn gradient_products(img: &[f32], w: usize, h: usize) -> Vec<[f32; 3]> {
    let mut j = vec![[0.0f32; 3]; w * h];
    gradient_products_into(img, w, h, &mut j);
    j
}

/// [`gradient_products`] into `j` (`w·h` values, every one overwritten).
///
/// # Panics
/// If `img.len() != w·h·3` or `j.len() != w·h`.
pub fn gradient_products_into(img: &[f32], w: usize, h: usize, j: &mut [[f32; 3]]) {
    assert_eq!(img.len(), w * h * 3, "image buffer size");
    assert_eq!(j.len(), w * h, "tensor buffer size");
    if j.is_empty() {
        return;
    }
    let stride = 3 * w;
    // The non-zero taps in kornia's order: (row above/at/below, column left/at/right, weight).
    let taps = |kernel: &[[f32; 3]; 3]| -> Vec<(usize, usize, f32)> {
        (0..3)
            .flat_map(|k| (0..3).map(move |m| (k, m)))
            .map(|(k, m)| (k, m, kernel[k][m]))
            .filter(|&(_, _, weight)| weight != 0.0)
            .collect()
    };
    let (taps_x, taps_y) = (taps(&SCHARR_X), taps(&SCHARR_Y));
    j.par_chunks_mut(w).enumerate().for_each_init(
        || {
            (
                vec![Vec::new(); 3],
                vec![0.0f32; stride],
                vec![0.0f32; stride],
            )
        },
        |(padded, gx, gy), (r, out)| {
            // Rows above, at and below, each with one replicated pixel at either end.
            for (k, y) in [r.saturating_sub(1), r, (r + 1).min(h - 1)]
                .into_iter()
                .enumerate()
            {
                let src = &img[y * stride..(y + 1) * stride];
                let p = &mut padded[k];
                p.clear();
                p.extend_from_slice(&src[..3]);
                p.extend_from_slice(src);
                p.extend_from_slice(&src[stride - 3..]);
            }
            for (g, taps) in [(&mut *gx, &taps_x), (&mut *gy, &taps_y)] {
                g.fill(0.0);
                for &(k, m, weight) in taps {
                    for (o, v) in g.iter_mut().zip(&padded[k][3 * m..3 * m + stride]) {
                        *o += v * weight;
                    }
                }
            }
            for ((o, x), y) in out
                .iter_mut()
                .zip(gx.chunks_exact(3))
                .zip(gy.chunks_exact(3))
            {
                *o = channel_products(x, y);
            }
        },
    );
}

/// `Σ_c (gx_c², gx_c·gy_c, gy_c²)` over a pixel's three channels, summed in channel order: the
/// structure tensor of one pixel from its x and y derivatives.
#[inline]
#[must_use]
pub fn channel_products(gx: &[f32], gy: &[f32]) -> [f32; 3] {
    let mut t = [0.0f32; 3];
    for c in 0..3 {
        t[0] += gx[c] * gx[c];
        t[1] += gx[c] * gy[c];
        t[2] += gy[c] * gy[c];
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{Rgb, RgbImage};

    #[test]
    fn srgb_round_trip() {
        for i in 0..=255 {
            let v = i as f32 / 255.0;
            assert!((linear_to_srgb(srgb_to_linear(v)) - v).abs() < 1e-5);
        }
    }

    #[test]
    fn box_average_is_in_linear_light() {
        // A 2x1 block of black and white averages to linear 0.5, not sRGB 0.5.
        let mut img = RgbImage::new(2, 1);
        img.put_pixel(1, 0, Rgb([255, 255, 255]));
        let lin = linear_analysis_image(&DynamicImage::ImageRgb8(img), 2);
        assert_eq!((lin.width, lin.height), (1, 1));
        assert!((lin.data[0] - 0.5).abs() < 1e-6);
    }

    #[test]
    fn analysis_factor_caps_the_diagonal() {
        assert_eq!(analysis_factor(512, 512, 1536), 1);
        assert_eq!(analysis_factor(4000, 3000, 1536), 4);
        assert_eq!(analysis_factor(4000, 3000, 0), 1);
    }

    /// Kornia's Scharr gradients multiplied out as the structure tensor's sum over channels:
    /// the oracle of [`gradient_products`].
    fn kornia_products(rgb: &[f32], w: usize, h: usize) -> Vec<[f32; 3]> {
        use kornia_image::{Image, ImageSize};
        let size = ImageSize {
            width: w,
            height: h,
        };
        let src = Image::<f32, 3>::new(size, rgb.to_vec()).unwrap();
        let mut dx = Image::<f32, 3>::from_size_val(size, 0.0).unwrap();
        let mut dy = Image::<f32, 3>::from_size_val(size, 0.0).unwrap();
        kornia_imgproc::filter::scharr_spatial_gradient_float(&src, &mut dx, &mut dy).unwrap();
        dx.as_slice()
            .chunks_exact(3)
            .zip(dy.as_slice().chunks_exact(3))
            .map(|(gx, gy)| channel_products(gx, gy))
            .collect()
    }

    #[test]
    fn gradient_products_are_kornias_scharr_bit_for_bit() {
        for (w, h) in [(37, 23), (1, 5), (6, 1), (2, 2), (1, 1)] {
            let rgb: Vec<f32> = (0..w * h * 3)
                // Negative values too: their zero-weight products are −0.
                .map(|i| (((i * 7919 + i / 5) % 257) as f32 / 256.0).powi(2) - 0.25)
                .collect();
            let ours = gradient_products(&rgb, w, h);
            let theirs = kornia_products(&rgb, w, h);
            let bits = |v: &[[f32; 3]]| -> Vec<u32> {
                v.iter().flat_map(|t| t.map(f32::to_bits)).collect()
            };
            assert_eq!(bits(&ours), bits(&theirs), "{w}x{h}");
        }
    }

    #[test]
    fn vertical_edge_gives_horizontal_gradient() {
        let img = LinearImage {
            width: 8,
            height: 4,
            data: (0..32)
                .flat_map(|i| {
                    let v = if i % 8 < 4 { 0.0 } else { 1.0 };
                    [v, v, v]
                })
                .collect(),
        };
        let j = structure_tensor(img, 0.0, 0.0);
        let at = j[8 + 4];
        assert!(at[0] > 0.0 && at[1].abs() < 1e-7 && at[2].abs() < 1e-7);
    }
}
