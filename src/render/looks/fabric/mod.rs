//! Fabric textures (paper section 7.3) and plain tensor LIC. A sparse noise image holds a small
//! dot per sample; line integral convolution along each of the metric's two eigenvector fields
//! smears the dots into threads, and the two are blended into a weave. Thread thickness follows
//! the ellipse: threads along the long axis are as thick as a fraction of the short semi-axis
//! and the other way round (for photos: thin threads along edges, thicker across). With white
//! noise and one direction it is the classic tensor LIC, for comparison. The kernel reaches at
//! least the long axes of the ellipses where it runs, so dots join into fibres (paper Figure
//! 7) in small cells and in a sky's large ones alike; without a photo the threads span the
//! colour map from dark to light. A photo's streamlines follow its calm line field (the
//! engraving's, `line_field.rs`): its edges' directions where they hold, level across flat
//! areas, where the metric's own axes only follow the grain.
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
//! Streamlines step through a table of the long axis's direction and the kernel at every pixel
//! (`lic_field.rs`), computed once from the field, instead of sampling the tensor field at
//! every step: this halved the look's time at 12 MP (4.4 s → 2.4 s).
//! Values are `f32`; the noise and the first pass are kept as bytes to hold memory down.

mod lic_field;
mod lic_grid;

use crate::render::lines::line_field::Directions;
use crate::render::scene::Scene;
use crate::render::support::colour::anisotropy_colour;
use crate::render::support::hash::salt;
use crate::render::support::rounding::round;
use glam::DVec2;
use image::RgbImage;
use lic_field::{Axis, Kernel, LicField};
use lic_grid::LicGrid;
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
    /// reaches at least 1.2 long semi-axes, of the ellipse where it runs for the samples'
    /// noise (up to three times the median sample's), of the median sample for white noise
    /// (see `kernel`).
    pub kernel_px: f32,
    /// Weight of the LIC along the short axes (the cross threads), 0 to 1.
    pub cross_weight: f32,
    /// Thread thickness as a fraction of the ellipse's other semi-axis.
    pub thickness: f32,
    /// Contrast of the threads over the colour, 0 to 1.
    pub contrast: f32,
    /// The direction (degrees, 0 level) a photo's threads and streaks take where it has none:
    /// a flat sky, a plain wall (see `fabric`).
    pub flat_angle: f32,
}

impl Default for FabricParams {
    fn default() -> Self {
        FabricParams {
            noise: Noise::Samples,
            kernel_px: 10.0,
            cross_weight: 0.45,
            thickness: 0.35,
            contrast: 0.8,
            flat_angle: 0.0,
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
    // A photo's streamlines follow its calm line field (`line_field.rs`, the engraving's and
    // the strokes'), a field's its own long axes: they cross a photo's flat areas in long calm
    // runs at `flat_angle` and follow its forms where its direction holds; along the metric's
    // own axes they would swirl round every faint gradient, a structure the photo does not have
    // (a night sky in loops). The wide field crosses soft edges (a motion-blurred ball).
    let lines = scene.photo.map(|_| {
        let angle = f64::from(params.flat_angle).to_radians();
        Directions::at_cell_scale(scene.field, angle, scene.cells.positions().len())
    });
    let angles = lines.as_ref().map_or(scene.field, Directions::tensors);
    let kernel = kernel(scene, params, &grid);
    let table = LicField::new((angles, scene.field), &grid, kernel);
    let along = lic(scene, params, Axis::Long, &table, &grid);
    let across = if params.cross_weight > 0.0 {
        Some(lic(scene, params, Axis::Short, &table, &grid))
    } else {
        None
    };
    let photo = scene.photo.map(crate::render::support::colour::rgb8);
    let weave = Weave::new(params.contrast);
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
            match photo.as_deref() {
                Some(img) => {
                    let px_photo = img.get_pixel(
                        (p.x as u32).min(img.width() - 1),
                        (p.y as u32).min(img.height() - 1),
                    );
                    px.copy_from_slice(&weave.over(px_photo.0, v));
                }
                None => {
                    // A field has no picture to keep: threads run from the colour darkened
                    // (the gaps between them) to the colour lightened (their crests), the
                    // paper's Figure 7 fabric of clearly visible fibres.
                    let base = anisotropy_colour(&scene.field.sample(p));
                    let s = FIELD_THREAD_SPAN * params.contrast;
                    let c = base.map(|c| {
                        let (dark, light) = (c * (1.0 - s), c + (1.0 - c) * s);
                        dark + (light - dark) * v
                    });
                    px.copy_from_slice(&c.map(crate::render::support::colour::to_srgb));
                }
            }
        }
    });
    RgbImage::from_raw(w as u32, h as u32, out).expect("w·h RGB pixels")
}

/// How far the threads of a field (no photo) reach from its colour map towards black and
/// white, at full contrast.
const FIELD_THREAD_SPAN: f32 = 0.85;

/// How the threads move a photo's pixel (sRGB codes): its luma `Y'` by `±contrast ·
/// min(THREAD_SWING, max(THREAD_FLOOR, Y', 255 − Y'))` codes, the colour drawn towards white
/// on a crest and towards black in a gap (each channel the same share of its way there, so the
/// luma moves by that much; only the floor's few codes clip, in black and white, which keep a
/// faint weave). The threads read alike in every tone, as a weave's do, and average to the
/// photo. Scaled in linear light instead (the colour times `1 ± contrast/2`), they swung ±35
/// codes in a light sky, where a tower of the camera man's skyline was lost in the weave, and
/// ±6 in a dark coat, which showed no weave at all. Tabulated by the luma's whole code, so a
/// pixel costs no division.
struct Weave {
    /// Per luma code, the share of each channel's way to white at a full crest.
    up: [f32; 256],
    /// Per luma code, the share of each channel's way to black in a full gap.
    down: [f32; 256],
}

impl Weave {
    fn new(contrast: f32) -> Self {
        let swing = |y: f32| contrast * THREAD_SWING.min(THREAD_FLOOR.max(y.min(255.0 - y)));
        Weave {
            up: std::array::from_fn(|y| swing(y as f32) / (255.0 - y as f32).max(1.0)),
            down: std::array::from_fn(|y| swing(y as f32) / (y as f32).max(1.0)),
        }
    }

    /// `rgb` under threads of LIC value `v` (0 a gap, 1 a crest, ½ the mean).
    fn over(&self, rgb: [u8; 3], v: f32) -> [u8; 3] {
        // Luma, Rec. 601 weights in 1/256ths, rounded.
        let [r, g, b] = rgb.map(u32::from);
        let y = ((77 * r + 150 * g + 29 * b + 128) >> 8) as usize;
        let t = (2.0 * v - 1.0).clamp(-1.0, 1.0);
        // One of the two is 0.
        let (up, down) = (t.max(0.0) * self.up[y], (-t).max(0.0) * self.down[y]);
        rgb.map(|c| {
            let c = f32::from(c);
            let moved = c + (255.0 - c) * up - c * down;
            // Round half up of a value in [0, 255].
            (moved.clamp(0.0, 255.0) + 0.5) as u8
        })
    }
}

/// The largest swing of a photo's luma under the threads at full contrast, in sRGB codes.
const THREAD_SWING: f32 = 25.0;

/// The swing of black and white under the threads at full contrast, in sRGB codes: without it
/// a black-and-white picture (a silhouette, a page of text) came out as the photo, unwoven.
const THREAD_FLOOR: f32 = 8.0;

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

/// The kernel of a pass: for white noise [`kernel_px`]'s everywhere; for the samples' dots
/// [`FIELD_KERNEL_AXES`] of the long semi-axes at each pixel, from `kernel_px` (the params')
/// up to [`LOCAL_KERNEL_MOST`] times [`kernel_px`]'s. With the median's kernel everywhere, a
/// sky's cells (larger than most) would leave their dots apart: a lattice of soft crosses, a
/// dot per cell. White noise keeps one kernel: there it is the grain's length, not the dots'
/// spacing.
fn kernel(scene: &Scene, params: &FabricParams, grid: &LicGrid) -> Kernel {
    let median = kernel_px(scene, params, grid).max(1.0).round().min(255.0) as u8;
    match params.noise {
        Noise::White => Kernel::Fixed(median),
        Noise::Samples => Kernel::Local {
            axes: FIELD_KERNEL_AXES,
            least: params.kernel_px.clamp(1.0, 255.0).round() as u8,
            most: (f64::from(median) * LOCAL_KERNEL_MOST).min(255.0) as u8,
        },
    }
}

/// The longest local kernel of the samples' noise, in [`kernel_px`]'s (the median cell's): the
/// bands' margins, and so their buffers, grow with the longest kernel in the picture. On the
/// photos measured the look's time and memory did not change (12 MP fabric: 0.54 s and 106 MB
/// before and after).
const LOCAL_KERNEL_MOST: f64 = 3.0;

/// One LIC pass along `axis` over the noise of `params`, as bytes (0..255, mid-grey 128).
fn lic(
    scene: &Scene,
    params: &FabricParams,
    axis: Axis,
    table: &LicField,
    grid: &LicGrid,
) -> Vec<u8> {
    let (w, h) = (grid.w, grid.h);
    let noise = noise_image(scene, params, axis, grid);
    // A streamline is traced two of its kernel's half-lengths each way from its seed.
    let reach_most = 2 * table.kernel_most();
    let margin = reach_most + 1;
    let bands = h.div_ceil(LIC_BAND_ROWS).max(1);
    // The bands add into these: filled by writing (see `buffer`).
    let mut total = crate::render::support::buffer::filled(w * h, 0.0f32);
    let mut hits = crate::render::support::buffer::filled(w * h, 0u16);
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
                let mut line = Vec::with_capacity(2 * reach_most + 1);
                let mut scratch = Vec::with_capacity(reach_most + 1);
                let tracer = Tracer {
                    table,
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
                        let kernel = table.kernel_at(y * w + x);
                        tracer.trace(x, y, 2 * kernel, &mut line, &mut scratch);
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
    table: &'a LicField,
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
        let d0 = self.table.at_pixel(start_pixel, self.axis);
        line.clear();
        scratch.clear();
        for (sign, out) in [(-1.0, &mut *scratch), (1.0, &mut *line)] {
            let mut p = start;
            let mut pixel = start_pixel;
            let mut prev = d0 * sign;
            for _ in 0..reach {
                // Unit Euler steps: the field is smooth at the scale of a pixel (it is smoothed
                // at the scale of the ellipses).
                let d = aligned(self.table.at_pixel(pixel, self.axis), prev);
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
                if crate::render::support::hash::site_hash(i as u32, salt::LIC_NOISE) < 0.5 {
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
                    + 67.0
                        * crate::render::support::hash::site_hash(
                            i as u32,
                            salt::FABRIC_THREAD + axis as u64,
                        )) as i8;
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
