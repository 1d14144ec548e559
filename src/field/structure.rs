//! The colour structure tensor of a photo (paper section 4 and Figure 5: the metric is derived
//! from "the image gradient and its orthogonal vector field").
//!
//! `J = G_ρ * Σ_c ∇(G_σ * I_c) ∇(G_σ * I_c)ᵀ` over the three channels in linear light, with
//! pre-smoothing σ (noise scale) and integration ρ. The photo is first box-averaged, in linear
//! light, to an *analysis resolution* whose diagonal is at most a set number of pixels: every
//! scale of the metric is a fraction of the image diagonal, so a 12 MP photo and its 512 px
//! thumbnail give the same field, and the cost stays flat as photos grow.

use super::blur::gaussian_blur_parallel_mut;
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
/// smoothed in place: no copy of the image is made). Gradients are kornia's Scharr operator
/// (parallel, replicated border), whose 3x3 weights are optimised for rotation invariance:
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
    gaussian_blur_parallel_mut(&mut smooth, w, h, 3, noise_sigma);
    let (gx, gy) = scharr_gradients(smooth, w, h);
    let mut j = vec![[0.0f32; 3]; w * h];
    j.par_chunks_mut(w)
        .zip(gx.par_chunks(w * 3).zip(gy.par_chunks(w * 3)))
        .for_each(|(out, (gx, gy))| {
            for ((o, gx), gy) in out
                .iter_mut()
                .zip(gx.chunks_exact(3))
                .zip(gy.chunks_exact(3))
            {
                let mut t = [0.0f32; 3];
                for c in 0..3 {
                    t[0] += gx[c] * gx[c];
                    t[1] += gx[c] * gy[c];
                    t[2] += gy[c] * gy[c];
                }
                *o = t;
            }
        });
    drop((gx, gy));
    gaussian_blur_parallel_mut(j.as_flattened_mut(), w, h, 3, integration_sigma);
    j
}

/// Per-channel x and y derivatives (per pixel) of an interleaved RGB image, by kornia's
/// parallel Scharr operator. The buffer moves into kornia's image without a copy.
fn scharr_gradients(rgb: Vec<f32>, w: usize, h: usize) -> (Vec<f32>, Vec<f32>) {
    use kornia_image::{Image, ImageSize};
    let size = ImageSize {
        width: w,
        height: h,
    };
    let src = Image::<f32, 3>::new(size, rgb).expect("buffer is w·h·3");
    let mut dx = Image::<f32, 3>::from_size_val(size, 0.0).expect("non-empty size");
    let mut dy = Image::<f32, 3>::from_size_val(size, 0.0).expect("non-empty size");
    kornia_imgproc::filter::scharr_spatial_gradient_float(&src, &mut dx, &mut dy)
        .expect("images have the same size");
    (dx.into_vec(), dy.into_vec())
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
