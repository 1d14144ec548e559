//! What every look draws from: a [`Scene`] (the generalized Voronoi cells of paper section 6,
//! their colours, the field, the output size). Cell looks shade raster points through
//! [`Scene::shade`], which averages `supersample²` points per pixel in linear light or, for
//! ink on paper, in the sRGB encoding ([`Average`]), or
//! [`Scene::shade_settled`], which shades the pixels the cell map settles inside their cells
//! without the owner search. The looks import this file; it imports none of them.

use super::cells::border_distance::BorderDistances;
use super::cells::cellmap::CellMap;
use super::cells::means::{cell_means, cell_means_and_widths};
use super::cells::raster::Raster;
use super::cells::voronoi::{Owner, VoronoiCells, BORDER_EXACT_PX, NONE};
use super::lines::outline_share::OutlineShare;
use super::support::colour::{anisotropy_colours, to_srgb, Linear};
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
    /// How much of the picture the outlines laid over the look will ink around each point,
    /// which the ink looks leave out of their own tone.
    pub outline_share: Option<&'a OutlineShare>,
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
            outline_share: None,
            pixels_per_unit: raster.pixels_per_unit(),
            raster,
        }
    }

    /// An image whose every pixel is the mean of `colour(point, owner)` over its raster points,
    /// in linear light or in the encoding (`average`), beside a border whose width is
    /// `border_px`.
    ///
    /// The owner is found at the pixel's centre, with the distance to the border between it
    /// and the runner-up ([`Owner::border_px`], from the first-order border function
    /// `f = δ_j − δ_i`, or `D_j − D_i` with a colour term, whose zero is the border). When
    /// `colour` draws borders (`border_px`, their widest, above 0) and the colour term's cell
    /// map has the picture's pixels, the borders drawn are the map's: beside a pixel of
    /// another cell, that cell is the runner-up and the distance comes from secants of `f`
    /// between the pixel centres ([`VoronoiCells::map_crossings`]); with another cell only
    /// diagonally, from the map ([`CellMap::border_distance_at`]).
    /// Supersampling is adaptive: only a pixel that
    /// a border may cross (centre less than [`BORDER_MARGIN_PX`] from it) is shaded at all
    /// `supersample²` points, each owned by whichever side of the linearised border it lies
    /// on. Inside a cell one evaluation suffices: the textures anti-alias themselves over the
    /// pixel's footprint.
    #[must_use]
    pub fn shade<F>(&self, (border_px, average): (f32, Average), colour: F) -> RgbImage
    where
        F: Fn(DVec2, &Owner) -> Linear + Sync,
    {
        let r = self.raster;
        let mut out = vec![0u8; 3 * r.width * r.height];
        let centres = Raster {
            supersample: 1,
            ..r
        };
        let steps = (r.step(), centres.step());
        let aligned = self.aligned_map().filter(|_| border_px > 0.0);
        self.cells
            .shade_rows(&centres, &mut out, 3 * r.width, |y, owners, row| {
                for (x, (px, o)) in row.chunks_exact_mut(3).zip(owners).enumerate() {
                    self.shade_pixel((x, y), o, (aligned, average), &colour, steps, px);
                }
            });
        RgbImage::from_raw(r.width as u32, r.height as u32, out).expect("w·h RGB pixels")
    }

    /// The colour term's cell map when its pixels are the picture's (a picture at the photo's
    /// own size): the shading draws its borders.
    fn aligned_map(&self) -> Option<&CellMap> {
        let r = self.raster;
        let centres = Raster {
            supersample: 1,
            ..r
        };
        self.cells
            .colour()
            .and_then(|term| term.map.as_ref())
            .filter(|map| map.size() == (r.width, r.height) && centres.step() == DVec2::ONE)
    }

    /// A border width given in pixels of a picture of
    /// [`REFERENCE_DIAGONAL`](super::cells::raster::REFERENCE_DIAGONAL), in this picture's pixels
    /// ([`Raster::length_scale`]): the mosaic's leading keeps its share of the cells at any
    /// size.
    #[must_use]
    pub fn border_px(&self, width: f32) -> f32 {
        (f64::from(width) * self.raster.length_scale()) as f32
    }

    /// [`Self::shade`], with `inside(p, δ², owner)` shading the pixels whose owner the colour
    /// term's cell map settles (a picture at the photo's own size): those are inside their
    /// cell, at least [`SETTLED_CLEAR_PX`] from a border, so `inside` must give what `colour`
    /// gives for an owner whose [`Owner::border_px`] is infinite. It is handed the site's `δ²`
    /// at `p`, which `D` was made from, and the owner the search would have found (but for its
    /// triangle, `NONE`), found without the search ([`VoronoiCells::settled_owner`]).
    ///
    /// `border_px` is the widest border `colour` draws. When its ink reaches settled pixels
    /// (wider than 1.5 px), those within its reach are shaded by `colour`, their
    /// [`Owner::border_px`] the distance to the map's borders ([`BorderDistances`]).
    #[must_use]
    pub fn shade_settled<F, I>(&self, border: (f32, Average), colour: F, inside: I) -> RgbImage
    where
        F: Fn(DVec2, &Owner) -> Linear + Sync,
        I: Fn(DVec2, f64, &Owner) -> Linear + Sync,
    {
        let Some(term) = self.cells.colour() else {
            return self.shade(border, colour);
        };
        self.shade_settled_with(border, &colour, |p, site| {
            let (delta_squared, o) = self.cells.settled_owner(term, site, p, NONE);
            inside(p, delta_squared, &o)
        })
    }

    /// [`Self::shade_settled`] for a look whose colour inside a cell needs only the point and
    /// the cell (`inside(p, site)`, what `colour` gives there for an owner without a border
    /// near): the owner's distances are not measured at the settled pixels.
    #[must_use]
    pub fn shade_settled_by_site<F, I>(
        &self,
        border: (f32, Average),
        colour: F,
        inside: I,
    ) -> RgbImage
    where
        F: Fn(DVec2, &Owner) -> Linear + Sync,
        I: Fn(DVec2, u32) -> Linear + Sync,
    {
        if self.cells.colour().is_none() {
            return self.shade(border, colour);
        }
        self.shade_settled_with(border, &colour, inside)
    }

    /// The shading of [`Self::shade_settled`] and [`Self::shade_settled_by_site`]:
    /// `inside(p, site)` colours a settled pixel clear of the borders' ink.
    fn shade_settled_with<F, I>(
        &self,
        (border_px, average): (f32, Average),
        colour: &F,
        inside: I,
    ) -> RgbImage
    where
        F: Fn(DVec2, &Owner) -> Linear + Sync,
        I: Fn(DVec2, u32) -> Linear + Sync,
    {
        let term = self.cells.colour().expect("callers check the colour term");
        let r = self.raster;
        let mut out = vec![0u8; 3 * r.width * r.height];
        let centres = Raster {
            supersample: 1,
            ..r
        };
        let step = centres.step();
        let steps = (r.step(), step);
        // How far from a border its ink reaches (half the width, and half a pixel of
        // anti-aliasing), where that is past the settled pixels' clearance.
        let ink_reach = 0.5 * border_px + 0.5;
        let aligned = self.aligned_map();
        let distances = aligned
            .filter(|_| ink_reach > SETTLED_CLEAR_PX)
            .map(|map| BorderDistances::new(map, ink_reach));
        // The borders drawn are the map's (see `Self::shade`).
        let aligned = aligned.filter(|_| border_px > 0.0);
        self.cells.shade_rows_settled(
            &centres,
            &mut out,
            3 * r.width,
            aligned.is_some(),
            |y, owners, settled, row| {
                let py = (y as f64 + 0.5) * step.y;
                for (x, (px, o)) in row.chunks_exact_mut(3).zip(owners).enumerate() {
                    match settled.get(x) {
                        Some(&site) if site != NONE => {
                            let p = DVec2::new((x as f64 + 0.5) * step.x, py);
                            let c = match distances.as_ref().and_then(|d| d.within(x, y)) {
                                Some(d) => {
                                    let (_, mut o) = self.cells.settled_owner(term, site, p, NONE);
                                    o.border_px = d + MAP_BORDER_OFFSET_PX;
                                    colour(p, &o)
                                }
                                None => inside(p, site),
                            };
                            for k in 0..3 {
                                px[k] = to_srgb(c[k]);
                            }
                        }
                        _ => {
                            self.shade_pixel((x, y), o, (aligned, average), colour, steps, px);
                        }
                    }
                }
            },
        );
        RgbImage::from_raw(r.width as u32, r.height as u32, out).expect("w·h RGB pixels")
    }

    /// One pixel (`x`, `y`) of [`Self::shade`] whose centre's owner is `o`, into `px`; `map` is
    /// the cell map whose borders are drawn ([`Self::shade`]), if any; `steps` are the raster's
    /// points' and the pixel centres' steps.
    #[inline]
    #[allow(clippy::too_many_arguments)] // one pixel's whole context, in the hot loop
    fn shade_pixel<F>(
        &self,
        (x, y): (usize, usize),
        o: &Owner,
        (map, average): (Option<&CellMap>, Average),
        colour: &F,
        steps: (DVec2, DVec2),
        px: &mut [u8],
    ) where
        F: Fn(DVec2, &Owner) -> Linear,
    {
        if o.site == NONE {
            return;
        }
        let (step, centre_step) = steps;
        let ss = self.raster.supersample;
        let ppu = self.pixels_per_unit;
        // `centres.point(x, y)`, with the step divided out once.
        let centre = DVec2::new(
            (x as f64 + 0.5) * centre_step.x,
            (y as f64 + 0.5) * centre_step.y,
        );
        let mut o = *o;
        // At the photo's own size the borders drawn are the cell map's: beside a pixel of
        // another cell, that cell is the runner-up, and the border lies where the map's
        // secants put it.
        let crossings = map.and_then(|m| self.cells.map_crossings(m, (x, y), &o));
        if let Some(c) = &crossings {
            (o.second, o.delta2) = (c.second, c.delta2);
        }
        // The border: f = δ_j − δ_i ≥ 0 on the owner's side, linear to first order.
        let mut gradient = DVec2::ZERO;
        if self.cells.border_distance_at_least(&o) * ppu < BORDER_EXACT_PX {
            gradient = self.cells.border_gradient(centre, &o);
            let len = gradient.length();
            if len > 0.0 {
                o.border_px = (f64::from(o.delta2 - o.delta) / len * ppu) as f32;
            }
        }
        // The secants' distance, across the border: where it crosses both axes, to the line
        // through both crossings; where it crosses one, along the gradient's direction.
        let mut f0 = f64::from(o.delta2 - o.delta);
        if let Some(c) = &crossings {
            let len = gradient.length();
            let d = if c.along_x.is_finite() && c.along_y.is_finite() {
                c.along_x * c.along_y / c.along_x.hypot(c.along_y)
            } else if len > 0.0 {
                let (t, cos) = if c.along_x.is_finite() {
                    (c.along_x, gradient.x.abs() / len)
                } else {
                    (c.along_y, gradient.y.abs() / len)
                };
                t * cos
            } else {
                c.along_x.min(c.along_y)
            };
            o.border_px = (d * ppu) as f32;
            f0 = d * len;
        }
        // The cell map's distance where the map has no neighbour of another cell beside the
        // pixel but one diagonally, and the search kept no runner-up: every border of the
        // map is inked.
        let map_distance = map
            .filter(|_| o.border_px == f32::INFINITY)
            .map(|m| m.border_distance_at(x, y))
            .filter(|d| d.is_finite());
        if let Some(d) = map_distance {
            o.border_px = d;
        }
        // Supersampled where the border with the runner-up may cross the pixel (without one,
        // or without a direction across it, every point has the same owner and distance).
        let len = gradient.length();
        let c =
            if ss > 1 && o.second != NONE && len > 0.0 && f64::from(o.border_px) < BORDER_MARGIN_PX
            {
                let weight = 1.0 / (ss * ss) as f32;
                let mut sum = [0.0f32; 3];
                for j in 0..ss {
                    for i in 0..ss {
                        let q =
                            DVec2::new((x * ss + i) as f64 + 0.5, (y * ss + j) as f64 + 0.5) * step;
                        let f = f0 + gradient.dot(q - centre);
                        let mut oq = o;
                        if f < 0.0 {
                            // Across the border: the runner-up owns this point.
                            std::mem::swap(&mut oq.site, &mut oq.second);
                            std::mem::swap(&mut oq.delta, &mut oq.delta2);
                        }
                        oq.border_px = (f.abs() / len * ppu) as f32;
                        if let Some(d) = map_distance {
                            oq.border_px = oq.border_px.min(d);
                        }
                        let c = colour(q, &oq);
                        for k in 0..3 {
                            sum[k] += match average {
                                Average::Linear => c[k],
                                Average::Encoded => f32::from(to_srgb(c[k])),
                            };
                        }
                    }
                }
                if average == Average::Encoded {
                    for k in 0..3 {
                        // Round half up of a mean of codes, in [0, 255].
                        px[k] = (sum[k] * weight + 0.5) as u8;
                    }
                    return;
                }
                sum.map(|v| v * weight)
            } else {
                colour(centre, &o)
            };
        for k in 0..3 {
            px[k] = to_srgb(c[k]);
        }
    }
}

/// How [`Scene::shade`] averages the points of a supersampled pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Average {
    /// In linear light, as light from the colours meeting at a border mixes.
    Linear,
    /// In the sRGB encoding, as the ink looks mix ink and paper in a partly inked pixel (so
    /// that the picture seen from afar has the photo's tones): averaged in linear light, a
    /// border pixel whose points fall on ink and on paper came out lighter than its share of
    /// ink, and a hatching over a textured photo, with its many small cells, 3 to 4 levels
    /// lighter than the photo.
    Encoded,
}

/// Added to a settled pixel's distance to the cell map's borders: they run through the
/// midpoints of pixel edges, on average nearer than the border itself (with it the leading of
/// a mosaic twice as large as a one-megapixel photo covers 1.12 times the share of the
/// picture the 1.5 px one does there, without it 1.24 times).
const MAP_BORDER_OFFSET_PX: f32 = 0.25;

/// How far, in pixels, a pixel the cell map settles (its eight neighbours in its own cell) is
/// taken to lie from a border: the 1.5 px leading of the mosaic, whose ink reaches 1.25 px, has
/// always been drawn as if none of them were nearer.
pub const SETTLED_CLEAR_PX: f32 = 1.25;

/// A pixel whose centre is closer than this to a cell border (in output pixels) is
/// supersampled: half the pixel's diagonal plus a margin for the first-order distance.
pub const BORDER_MARGIN_PX: f64 = 0.75;
