//! Fabric textures (paper section 7.3) and plain tensor LIC. A sparse noise image holds a small
//! dot per sample; line integral convolution along each of the metric's two eigenvector fields
//! smears the dots into threads, and the two are blended into a weave. Thread thickness follows
//! the ellipse: threads along the long axis are as thick as a fraction of the short semi-axis
//! and the other way round (for photos: thin threads along edges, thicker across). With white
//! noise and one direction it is the classic tensor LIC, for comparison. The kernel reaches at
//! least the samples' long axes, so dots join into fibres (paper Figure 7); without a photo the
//! threads span the colour map from dark to light.
//!
//! The LIC runs on the output's pixels up to a one-megapixel photo's diagonal and on a grid of
//! that size beyond (`lic_grid.rs`, read bilinearly): the look's lengths are in that grid's
//! pixels, so a 12 MP painting shows the weave a 1 MP one shows, not specks, and the LIC costs
//! the same at any larger size.
//!
//! The LIC is the fast kind (Stalling and Hege): a long streamline is traced once from every
//! pixel that no earlier streamline has crossed, and a box filter slides along it, giving
//! every pixel it passes a value; the per-pixel cost no longer grows with the kernel length.
//! Bands of rows are processed in parallel, each depositing into its own rows plus a margin;
//! the band buffers are then added in band order, so the result does not depend on threads.
//! Streamlines step through a table of the long axis's direction at every pixel (one byte,
//! 0.7° steps, shared by both passes), computed once from the field, instead of sampling the
//! tensor field at every step: this halved the look's time at 12 MP (4.4 s → 2.4 s).
//! Values are `f32`; the noise and the first pass are kept as bytes to hold memory down.

use super::colour::{anisotropy_colour, linear_of, salt, Linear};
use super::lic_grid::LicGrid;
use super::rounding::round;
use super::scene::Scene;
use crate::field::TensorField;
use glam::DVec2;
use image::RgbImage;
use rayon::prelude::*;

/// The noise the LIC smears.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Noise {
    /// A small dot per sample (the paper's fabric).
    #[default]
    Samples,
    /// Per-pixel white noise (plain LIC).
    White,
}

/// Parameters of the fabric and LIC looks.
#[derive(Clone, Debug, PartialEq)]
pub struct FabricParams {
    /// The noise.
    pub noise: Noise,
    /// Shortest half-length of the convolution kernel, in pixels of the LIC's grid (the
    /// output's own up to a one-megapixel photo's size, see `lic_grid.rs`); the kernel
    /// reaches at least 1.2 median long semi-axes of the samples (see `kernel_px`).
    pub kernel_px: f32,
    /// Weight of the LIC along the short axes (the cross threads), 0 to 1.
    pub cross_weight: f32,
    /// Thread thickness as a fraction of the ellipse's other semi-axis.
    pub thickness: f32,
    /// Contrast of the threads over the colour, 0 to 1.
    pub contrast: f32,
}

impl Default for FabricParams {
    fn default() -> Self {
        FabricParams {
            noise: Noise::Samples,
            kernel_px: 10.0,
            cross_weight: 0.45,
            thickness: 0.35,
            contrast: 0.8,
        }
    }
}

/// Renders the fabric (or LIC) look of `scene`.
#[must_use]
pub fn fabric(scene: &Scene, params: &FabricParams) -> RgbImage {
    let r = scene.raster;
    let (w, h) = (r.width, r.height);
    let to_domain = DVec2::new(r.domain.x / w as f64, r.domain.y / h as f64);
    let grid = LicGrid::for_output(w, h, r.domain);
    let directions = Directions::new(scene.field, &grid);
    let along = lic(scene, params, Axis::Long, &directions, &grid);
    let across = if params.cross_weight > 0.0 {
        Some(lic(scene, params, Axis::Short, &directions, &grid))
    } else {
        None
    };
    let photo = scene.photo.map(super::colour::rgb8);
    let mut out = vec![0u8; 3 * w * h];
    out.par_chunks_mut(3 * w).enumerate().for_each(|(y, row)| {
        let rows = grid.rows_for(y, h);
        for (x, px) in row.chunks_exact_mut(3).enumerate() {
            let a = grid.read(&along, x, w, rows);
            let v = match &across {
                Some(c) => {
                    let b = grid.read(c, x, w, rows);
                    a * (1.0 - params.cross_weight) + b * params.cross_weight
                }
                None => a,
            };
            let p = (DVec2::new(x as f64, y as f64) + 0.5) * to_domain;
            let base = base_colour(scene, photo.as_deref(), p);
            let c = if photo.is_some() {
                let k = 1.0 - 0.5 * params.contrast + params.contrast * v;
                base.map(|c| (c * k).clamp(0.0, 1.0))
            } else {
                // A field has no picture to keep: threads run from the colour darkened (the
                // gaps between them) to the colour lightened (their crests), the paper's
                // Figure 7 fabric of clearly visible fibres.
                let s = FIELD_THREAD_SPAN * params.contrast;
                base.map(|c| {
                    let (dark, light) = (c * (1.0 - s), c + (1.0 - c) * s);
                    dark + (light - dark) * v
                })
            };
            px.copy_from_slice(&c.map(super::colour::to_srgb));
        }
    });
    RgbImage::from_raw(w as u32, h as u32, out).expect("w·h RGB pixels")
}

/// How far the threads of a field (no photo) reach from its colour map towards black and
/// white, at full contrast.
const FIELD_THREAD_SPAN: f32 = 0.85;

/// The colour under the threads: the photo's pixel, or the anisotropy colour map.
fn base_colour(scene: &Scene, photo: Option<&image::RgbImage>, p: DVec2) -> Linear {
    match photo {
        Some(img) => {
            let x = (p.x as u32).min(img.width() - 1);
            let y = (p.y as u32).min(img.height() - 1);
            linear_of(img.get_pixel(x, y).0)
        }
        None => anisotropy_colour(&scene.field.sample(p)),
    }
}

/// Which eigenvector field a LIC pass follows.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Axis {
    Long,
    Short,
}

/// Unit direction of the long axis at output point `p` (pixels), up to sign. From the tensor
/// `[[a, b], [b, c]]` directly: the long axis is at half the angle of `(a − c, 2b)`, and the
/// half-angle formulas give it without `atan2` or an eigen decomposition.
fn long_direction(field: &TensorField, p: DVec2, to_domain: DVec2) -> DVec2 {
    let t = field.sample(p * to_domain);
    let (c2, s2) = (t.xx - t.yy, 2.0 * t.xy);
    let n = (c2 * c2 + s2 * s2).sqrt();
    let d = if n > 0.0 {
        let c = c2 / n;
        let cos = (0.5 * (1.0 + c)).max(0.0).sqrt();
        let sin = (0.5 * (1.0 - c)).max(0.0).sqrt().copysign(s2);
        DVec2::new(cos, sin)
    } else {
        // Isotropic: any direction; keep x so streamlines stay straight.
        DVec2::X
    };
    // Back to output pixels (non-square scaling bends directions).
    (d / to_domain).normalize_or_zero()
}

/// `atan2(y, x)` in [−π, π] by a minimax polynomial for `atan` on [0, 1] after folding into
/// one octant (error under 2·10⁻⁵ rad, a 600th of an [`ANGLE_STEPS`] step, and far cheaper
/// than libm's `atan2` at every output pixel); 0 at the origin.
fn fast_atan2(y: f64, x: f64) -> f64 {
    use std::f64::consts::{FRAC_PI_2, PI};
    let (ax, ay) = (x.abs(), y.abs());
    if ax == 0.0 && ay == 0.0 {
        return 0.0;
    }
    let (z, steep) = if ay > ax {
        (ax / ay, true)
    } else {
        (ay / ax, false)
    };
    let z2 = z * z;
    let atan_z = z
        * (0.999_977_26
            + z2 * (-0.332_623_47
                + z2 * (0.193_543_46
                    + z2 * (-0.116_432_87 + z2 * (0.052_653_32 + z2 * -0.011_721_20)))));
    // The first quadrant's angle, mirrored into the quadrant of (x, y).
    let first = if steep { FRAC_PI_2 - atan_z } else { atan_z };
    let upper = if x < 0.0 { PI - first } else { first };
    if y < 0.0 {
        -upper
    } else {
        upper
    }
}

/// The angle in [0, π] of the axis along `d` (`d` and `−d` alike).
fn half_turn_angle(d: DVec2) -> f64 {
    let a = fast_atan2(d.y, d.x);
    if a < 0.0 {
        a + std::f64::consts::PI
    } else {
        a
    }
}

/// Steps of the quantised direction angle over half a turn (0.7° each).
const ANGLE_STEPS: usize = 256;

/// The long axis's direction at every output pixel centre, as an angle in [0, π) quantised
/// to [`ANGLE_STEPS`]: one byte per pixel serves both passes (the short axis is a quarter turn
/// away). Streamlines look directions up here, at the pixel they are in, instead of sampling
/// the tensor field at every step (a streamline step is then a table look-up; the field is
/// smooth at the scale of the ellipses, many pixels).
struct Directions {
    /// Quantised angles, one per pixel, row-major.
    angle: Vec<u8>,
    table: Vec<DVec2>,
}

impl Directions {
    fn new(field: &TensorField, grid: &LicGrid) -> Self {
        let (w, to_domain) = (grid.w, grid.to_domain);
        let step = std::f64::consts::PI / ANGLE_STEPS as f64;
        let mut angle = vec![0u8; w * grid.h];
        // Output pixels are square in the domain (the usual case): directions need no rescaling.
        let square = to_domain.x == to_domain.y;
        angle.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
            for (x, a) in row.iter_mut().enumerate() {
                let p = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                let theta = if square {
                    // The long axis lies at half the angle of (a − c, 2b): no square roots.
                    let t = field.sample(p * to_domain);
                    let half = 0.5 * fast_atan2(2.0 * t.xy, t.xx - t.yy);
                    if half < 0.0 {
                        half + std::f64::consts::PI
                    } else {
                        half
                    }
                } else {
                    half_turn_angle(long_direction(field, p, to_domain))
                };
                // θ ≥ 0: `+ 0.5` and truncation round (no libm call per pixel).
                *a = ((theta / step + 0.5) as usize % ANGLE_STEPS) as u8;
            }
        });
        let table = (0..ANGLE_STEPS)
            .map(|k| DVec2::from_angle(k as f64 * step))
            .collect();
        Directions { angle, table }
    }

    /// Unit direction of `axis` at pixel `i` (row-major), up to sign.
    #[inline]
    fn at_pixel(&self, i: usize, axis: Axis) -> DVec2 {
        let d = self.table[usize::from(self.angle[i])];
        if axis == Axis::Long {
            d
        } else {
            d.perp()
        }
    }
}

/// The kernel's half-length in pixels of the LIC's `grid`: `kernel_px`, or more, so that it
/// reaches [`FIELD_KERNEL_AXES`] median long semi-axes of the samples, the distance between
/// neighbouring dots along a thread; the dots then join into continuous fibres (paper Figure
/// 7) instead of stitches, at any size. Photos at 512 px read 7–11 px here, about
/// `kernel_px` (10); a one-megapixel photo's ellipses are twice as long, and with a fixed
/// kernel its threads broke into blobs.
fn kernel_px(scene: &Scene, params: &FabricParams, grid: &LicGrid) -> f32 {
    let mut long: Vec<f64> = scene
        .cells
        .metrics()
        .iter()
        .map(|m| m.eigen().l1.abs())
        .collect();
    if long.is_empty() {
        return params.kernel_px;
    }
    let mid = long.len() / 2;
    let (_, median, _) = long.select_nth_unstable_by(mid, f64::total_cmp);
    params
        .kernel_px
        .max((FIELD_KERNEL_AXES * *median * grid.pixels_per_unit()) as f32)
}

/// The kernel's least half-length in long semi-axes (see [`kernel_px`]).
const FIELD_KERNEL_AXES: f64 = 1.2;

/// One LIC pass along `axis` over the noise of `params`, as bytes (0..255, mid-grey 128).
fn lic(
    scene: &Scene,
    params: &FabricParams,
    axis: Axis,
    directions: &Directions,
    grid: &LicGrid,
) -> Vec<u8> {
    let (w, h) = (grid.w, grid.h);
    let noise = noise_image(scene, params, axis, grid);
    let kernel = kernel_px(scene, params, grid).max(1.0).round() as usize;
    // A streamline is traced this many kernel half-lengths each way from its seed.
    let reach = 2 * kernel;
    let margin = reach + 1;
    let bands = h.div_ceil(LIC_BAND_ROWS).max(1);
    // The bands add into these: filled by writing (see `buffer`).
    let mut total = super::buffer::filled(w * h, 0.0f32);
    let mut hits = super::buffer::filled(w * h, 0u16);
    // A few bands at a time, so band buffers (with their margins) never hold the whole image;
    // the buffers are made once and cleared for every group (fresh ones cost page faults and
    // the kernel's unmapping every time).
    let group: Vec<usize> = (0..bands).collect();
    let rows_most = (LIC_BAND_ROWS + 2 * margin).min(h);
    let mut buffers: Vec<(usize, Vec<f32>, Vec<u16>)> = (0..LIC_BANDS_AT_ONCE.min(bands))
        .map(|_| (0, vec![0.0f32; rows_most * w], vec![0u16; rows_most * w]))
        .collect();
    for bands_now in group.chunks(LIC_BANDS_AT_ONCE) {
        buffers
            .par_iter_mut()
            .zip(bands_now.par_iter())
            .for_each(|((top, sum, count), &band)| {
                let y0 = band * LIC_BAND_ROWS;
                let y1 = (y0 + LIC_BAND_ROWS).min(h);
                *top = y0.saturating_sub(margin);
                let bottom = (y1 + margin).min(h);
                let rows = bottom - *top;
                sum.clear();
                sum.resize(rows * w, 0.0);
                count.clear();
                count.resize(rows * w, 0);
                let mut line = Vec::with_capacity(2 * reach + 1);
                let mut scratch = Vec::with_capacity(reach + 1);
                let tracer = Tracer {
                    directions,
                    noise: &noise,
                    w,
                    h,
                    axis,
                };
                for y in y0..y1 {
                    for x in 0..w {
                        if count[(y - *top) * w + x] > 0 {
                            continue;
                        }
                        tracer.trace(x, y, reach, &mut line, &mut scratch);
                        deposit(&line, kernel, w, *top, bottom, sum, count);
                    }
                }
            });
        // Added in band order: the same sums at any thread count.
        for (top, sum, count) in &buffers[..bands_now.len()] {
            let start = top * w;
            for (i, (s, c)) in sum.iter().zip(count).enumerate() {
                total[start + i] += s;
                hits[start + i] = hits[start + i].saturating_add(*c);
            }
        }
    }
    // The mean convolved value of every pixel, in place of its sum.
    let mut values = total;
    values
        .par_iter_mut()
        .zip(hits.par_iter())
        .for_each(|(s, &c)| *s = if c > 0 { *s / f32::from(c) } else { 0.0 });
    // Normalised to the image's own spread, so threads show whatever the noise density. The
    // sums run over fixed chunks added in order: the same at any thread count.
    let n = values.len().max(1) as f64;
    let chunked_sum = |term: &(dyn Fn(f32) -> f64 + Sync)| -> f64 {
        let sums: Vec<f64> = values
            .par_chunks(LIC_SUM_CHUNK)
            .map(|chunk| chunk.iter().map(|&v| term(v)).sum::<f64>())
            .collect();
        sums.iter().sum()
    };
    let mean = chunked_sum(&f64::from) / n;
    let var = chunked_sum(&|v| (f64::from(v) - mean).powi(2)) / n;
    let spread = (LIC_SPREAD * var.sqrt()).max(1e-6);
    values
        .par_iter()
        .map(|&v| {
            let z = ((f64::from(v) - mean) / spread).clamp(-1.0, 1.0);
            round(128.0 + 127.0 * z) as u8
        })
        .collect()
}

/// Values per chunk of the LIC's mean and variance sums.
const LIC_SUM_CHUNK: usize = 1 << 16;

/// Rows per LIC band.
const LIC_BAND_ROWS: usize = 32;

/// Bands traced at once (then added into the image).
const LIC_BANDS_AT_ONCE: usize = 8;

/// The convolved values are mapped to bytes over this many standard deviations either side
/// of their mean.
const LIC_SPREAD: f64 = 2.0;

/// What a streamline needs to know.
struct Tracer<'a> {
    directions: &'a Directions,
    noise: &'a [i8],
    w: usize,
    h: usize,
    axis: Axis,
}

impl Tracer<'_> {
    fn inside(&self, p: DVec2) -> bool {
        p.x >= 0.0 && p.y >= 0.0 && p.x < self.w as f64 && p.y < self.h as f64
    }

    /// The noise at pixel `i` (row-major).
    #[inline]
    fn value(&self, i: usize) -> f32 {
        f32::from(self.noise[i]) / 127.0
    }

    /// Traces the streamline through pixel (`x`, `y`) both ways, `reach` unit steps each
    /// (eigenvectors have no sign, so each step keeps the direction of the previous one), into
    /// `line` as the pixels it steps on, with their noise, in order. `scratch` holds the
    /// backward half meanwhile. Each point's pixel is found once: the direction of the next
    /// step and the noise are read there, and the deposit adds there.
    fn trace(
        &self,
        x: usize,
        y: usize,
        reach: usize,
        line: &mut Vec<LinePoint>,
        scratch: &mut Vec<LinePoint>,
    ) {
        let start = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
        let start_pixel = y * self.w + x;
        let d0 = self.directions.at_pixel(start_pixel, self.axis);
        line.clear();
        scratch.clear();
        for (sign, out) in [(-1.0, &mut *scratch), (1.0, &mut *line)] {
            let mut p = start;
            let mut pixel = start_pixel;
            let mut prev = d0 * sign;
            for _ in 0..reach {
                // Unit Euler steps: the field is smooth at the scale of a pixel (it is smoothed
                // at the scale of the ellipses).
                let d = aligned(self.directions.at_pixel(pixel, self.axis), prev);
                let next = p + d;
                if !self.inside(next) || d == DVec2::ZERO {
                    break;
                }
                p = next;
                prev = d;
                let (px, py) = (p.x as usize, p.y as usize);
                pixel = py * self.w + px;
                out.push(LinePoint {
                    x: px as u32,
                    y: py as u32,
                    value: self.value(pixel),
                });
            }
        }
        // scratch: backward half from the seed outwards; line: forward half.
        scratch.reverse();
        scratch.push(LinePoint {
            x: x as u32,
            y: y as u32,
            value: self.value(start_pixel),
        });
        scratch.append(line);
        std::mem::swap(line, scratch);
    }
}

/// A streamline's point: the pixel it is in and the noise there.
#[derive(Clone, Copy)]
struct LinePoint {
    x: u32,
    y: u32,
    value: f32,
}

/// `d` or `−d`, whichever points along `prev`.
fn aligned(d: DVec2, prev: DVec2) -> DVec2 {
    if d.dot(prev) < 0.0 {
        -d
    } else {
        d
    }
}

/// Slides a box filter of half-length `kernel` along `line` and adds each window's mean to
/// the pixel at the window's centre, if it lies in rows `top..bottom`.
fn deposit(
    line: &[LinePoint],
    kernel: usize,
    w: usize,
    top: usize,
    bottom: usize,
    sum: &mut [f32],
    count: &mut [u16],
) {
    let n = line.len();
    let mut window = 0.0f32;
    let (mut lo, mut hi) = (0usize, 0usize);
    for k in 0..n {
        // Window [k − kernel, k + kernel], clipped to the line.
        let want_lo = k.saturating_sub(kernel);
        let want_hi = (k + kernel + 1).min(n);
        while hi < want_hi {
            window += line[hi].value;
            hi += 1;
        }
        while lo < want_lo {
            window -= line[lo].value;
            lo += 1;
        }
        let (px, py) = (line[k].x as usize, line[k].y as usize);
        if py < top || py >= bottom || px >= w {
            continue;
        }
        let i = (py - top) * w + px;
        sum[i] += window / (hi - lo) as f32;
        count[i] = count[i].saturating_add(1);
    }
}

/// The noise of one pass, as signed bytes (±127 = ±1), one per pixel of the LIC's `grid`.
fn noise_image(scene: &Scene, params: &FabricParams, axis: Axis, grid: &LicGrid) -> Vec<i8> {
    let (w, h) = (grid.w, grid.h);
    match params.noise {
        Noise::White => (0..w * h)
            .into_par_iter()
            .map(|i| {
                if super::colour::site_hash(i as u32, salt::LIC_NOISE) < 0.5 {
                    -127
                } else {
                    127
                }
            })
            .collect(),
        Noise::Samples => {
            // Dark ground, bright dots: the convolution draws bright threads through them.
            let mut img = vec![-127i8; w * h];
            let scale = DVec2::new(w as f64 / grid.domain.x, h as f64 / grid.domain.y);
            let cells = &scene.cells;
            for (i, (p, m)) in cells.positions().iter().zip(cells.metrics()).enumerate() {
                let e = m.eigen();
                // Thread thickness: a fraction of the other semi-axis, in output pixels.
                let other = if axis == Axis::Long { e.l2 } else { e.l1 };
                let radius = (other.abs() * f64::from(params.thickness) * scale.x.min(scale.y))
                    .clamp(0.6, 6.0);
                // Threads of slightly different brightness.
                let v = (60.0
                    + 67.0 * super::colour::site_hash(i as u32, salt::FABRIC_THREAD + axis as u64))
                    as i8;
                let c = *p * scale;
                let (x0, x1) = (
                    (c.x - radius).floor().max(0.0) as usize,
                    (c.x + radius).ceil(),
                );
                let (y0, y1) = (
                    (c.y - radius).floor().max(0.0) as usize,
                    (c.y + radius).ceil(),
                );
                for y in y0..(y1.max(0.0) as usize).min(h) {
                    for x in x0..(x1.max(0.0) as usize).min(w) {
                        let q = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                        if (q - c).length() <= radius {
                            img[y * w + x] = v;
                        }
                    }
                }
            }
            img
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_turn_angle_is_the_axis_angle() {
        for k in 0..3600 {
            let a = f64::from(k) * std::f64::consts::TAU / 3600.0;
            let d = DVec2::from_angle(a) * 3.0;
            let want = d.y.atan2(d.x).rem_euclid(std::f64::consts::PI);
            let got = half_turn_angle(d);
            // Equal up to the error bound, or at both ends of the half turn (one axis).
            let err = (got - want).abs();
            assert!(
                err < 2e-5 || (err - std::f64::consts::PI).abs() < 2e-5,
                "{a}: {got} vs {want}"
            );
        }
        assert_eq!(half_turn_angle(DVec2::ZERO), 0.0);
        for k in 0..=3600 {
            let a = f64::from(k) * std::f64::consts::TAU / 3600.0 - std::f64::consts::PI;
            let (y, x) = (2.5 * a.sin(), 2.5 * a.cos());
            assert!((fast_atan2(y, x) - y.atan2(x)).abs() < 2e-5, "{a}");
        }
    }
}
