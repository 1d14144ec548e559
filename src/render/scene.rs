//! What every look draws from: a [`Scene`] (the generalized Voronoi cells of paper section 6,
//! their colours, the field, the output size). Cell looks shade raster points through
//! [`Scene::shade`], which averages `supersample²` points per pixel in linear light. The looks
//! import this file; it imports none of them.

use super::colour::{anisotropy_colours, cell_means, cell_means_and_widths, to_srgb, Linear};
use super::raster::Raster;
use super::voronoi::{Owner, VoronoiCells, BORDER_EXACT_PX, NONE};
use crate::field::TensorField;
use glam::DVec2;
use image::{DynamicImage, RgbImage};

/// Everything a look draws from.
pub struct Scene<'a> {
    /// The generalized Voronoi cells of the samples.
    pub cells: VoronoiCells<'a>,
    /// Colour of every cell: the photo's mean under it, or a colour map of its ellipse.
    pub colours: Vec<Linear>,
    /// For edge-following cells, every cell's width across its narrowest direction (domain
    /// units): a cell carved down to a thin line by an edge is narrower than its ellipse, and
    /// textures too coarse for it give way to its flat tone.
    pub thin_widths: Option<Vec<f64>>,
    /// The metric field the samples came from.
    pub field: &'a TensorField,
    /// The photo, if the input was one.
    pub photo: Option<&'a DynamicImage>,
    /// Output size and supersampling.
    pub raster: Raster,
    /// Output pixels per domain unit.
    pub pixels_per_unit: f64,
}

impl<'a> Scene<'a> {
    /// A scene of `cells` rendered at `width × height` with `supersample²` points per pixel.
    #[must_use]
    pub fn new(
        cells: VoronoiCells<'a>,
        field: &'a TensorField,
        photo: Option<&'a DynamicImage>,
        width: usize,
        height: usize,
        supersample: usize,
    ) -> Self {
        // Widths only matter (and are only measured) for edge-following cells.
        let (colours, widths) = match (photo, cells.colour()) {
            (Some(p), Some(_)) => {
                let (colours, widths) = cell_means_and_widths(&cells, p);
                (colours, Some(widths))
            }
            (Some(p), None) => (cell_means(&cells, p), None),
            (None, _) => (anisotropy_colours(cells.metrics()), None),
        };
        let raster = Raster {
            width: width.max(1),
            height: height.max(1),
            supersample: supersample.max(1),
            domain: field.domain(),
        };
        Scene {
            cells,
            colours,
            thin_widths: widths,
            field,
            photo,
            pixels_per_unit: raster.pixels_per_unit(),
            raster,
        }
    }

    /// An image whose every pixel is the linear-light mean of `colour(point, owner)` over its
    /// raster points.
    ///
    /// The owner is found at the pixel's centre, with the distance to the border between it
    /// and the runner-up ([`Owner::border_px`], from the first-order border function
    /// `f = δ_j − δ_i`, or `D_j − D_i` with a colour term, whose zero is the border).
    /// Supersampling is adaptive: only a pixel that
    /// a border may cross (centre less than [`BORDER_MARGIN_PX`] from it) is shaded at all
    /// `supersample²` points, each owned by whichever side of the linearised border it lies
    /// on. Inside a cell one evaluation suffices: the textures anti-alias themselves over the
    /// pixel's footprint.
    #[must_use]
    pub fn shade<F>(&self, colour: F) -> RgbImage
    where
        F: Fn(DVec2, &Owner) -> Linear + Sync,
    {
        let r = self.raster;
        let ss = r.supersample;
        let centres = Raster {
            supersample: 1,
            ..r
        };
        let step = r.step();
        let centre_step = centres.step();
        let weight = 1.0 / (ss * ss) as f32;
        let mut out = vec![0u8; 3 * r.width * r.height];
        let ppu = self.pixels_per_unit;
        self.cells
            .shade_rows(&centres, &mut out, 3 * r.width, |y, owners, row| {
                for (x, (px, o)) in row.chunks_exact_mut(3).zip(owners).enumerate() {
                    if o.site == NONE {
                        continue;
                    }
                    // `centres.point(x, y)`, with the step divided out once.
                    let centre = DVec2::new(
                        (x as f64 + 0.5) * centre_step.x,
                        (y as f64 + 0.5) * centre_step.y,
                    );
                    let mut o = *o;
                    // The border: f = δ_j − δ_i ≥ 0 on the owner's side, linear to first order.
                    let mut gradient = DVec2::ZERO;
                    if self.cells.border_distance_at_least(&o) * ppu < BORDER_EXACT_PX {
                        gradient = self.cells.border_gradient(centre, &o);
                        let len = gradient.length();
                        if len > 0.0 {
                            o.border_px = (f64::from(o.delta2 - o.delta) / len * ppu) as f32;
                        }
                    }
                    let c = if ss > 1 && f64::from(o.border_px) < BORDER_MARGIN_PX {
                        let f0 = f64::from(o.delta2 - o.delta);
                        let len = gradient.length();
                        let mut sum = [0.0f32; 3];
                        for j in 0..ss {
                            for i in 0..ss {
                                let q = DVec2::new(
                                    (x * ss + i) as f64 + 0.5,
                                    (y * ss + j) as f64 + 0.5,
                                ) * step;
                                let f = f0 + gradient.dot(q - centre);
                                let mut oq = o;
                                if f < 0.0 {
                                    // Across the border: the runner-up owns this point.
                                    std::mem::swap(&mut oq.site, &mut oq.second);
                                    std::mem::swap(&mut oq.delta, &mut oq.delta2);
                                }
                                oq.border_px = (f.abs() / len * ppu) as f32;
                                let c = colour(q, &oq);
                                for k in 0..3 {
                                    sum[k] += c[k];
                                }
                            }
                        }
                        sum.map(|v| v * weight)
                    } else {
                        colour(centre, &o)
                    };
                    for k in 0..3 {
                        px[k] = to_srgb(c[k]);
                    }
                }
            });
        RgbImage::from_raw(r.width as u32, r.height as u32, out).expect("w·h RGB pixels")
    }
}

/// A pixel whose centre is closer than this to a cell border (in output pixels) is
/// supersampled: half the pixel's diagonal plus a margin for the first-order distance.
pub const BORDER_MARGIN_PX: f64 = 0.75;
