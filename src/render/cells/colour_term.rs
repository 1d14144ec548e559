//! The colour term of edge-following cells (an anisotropic SLIC step over the generalized
//! Voronoi cells of paper section 6, see [`cells`](super)): the photo the owner search
//! reads, bilinear with derivatives, the cells' colours and the cost `w·|c − c_i|²` the owner
//! search adds to `δ²`. Colours are `f32` sRGB in [0, 1]; costs `f64`.

use super::cellmap::CellMap;
use glam::DVec2;

/// The colour term of edge-following cells: with it, the owner of `p` is the candidate
/// minimising `D_i(p)² = δ_i(p)² + w·|c(p) − c_i|²`, `c(p)` the photo's colour at `p`
/// (bilinear, sRGB in [0, 1] per channel, a roughly perceptual scale) and `c_i` cell `i`'s
/// colour: a pixel across a strong edge from its nearest site goes to the neighbour on its own
/// side (an anisotropic SLIC step, see [`cells`](super)). `w = 0` is the paper's cell.
#[derive(Clone, Debug)]
pub struct ColourTerm {
    /// The photo, one pixel per domain unit.
    photo: image::RgbImage,
    /// Each cell's colour, sRGB in [0, 1].
    pub means: Vec<[f32; 3]>,
    /// `w`: a colour difference of `1/√w` weighs as much as the whole ellipse radius.
    pub weight: f64,
    /// How far past the paper's border a cell may reach: a candidate `j` can own `p` only
    /// while `δ_j(p) ≤ δ_min(p) + reach`, so a cell grows across its border into a neighbour
    /// but never jumps over it, and its pieces stay joined to it.
    pub reach: f64,
    /// The owners of the photo's pixels once every cell is one piece
    /// ([`pieces`](super::pieces)); `None` while the cells are still being made.
    pub map: Option<CellMap>,
}

impl ColourTerm {
    /// The term of `photo` (domain units = its pixels) with no cell colours yet.
    #[must_use]
    pub fn new(photo: image::RgbImage, weight: f64) -> Self {
        ColourTerm {
            photo,
            means: Vec::new(),
            weight,
            reach: f64::INFINITY,
            map: None,
        }
    }

    /// The photo.
    #[must_use]
    pub fn photo(&self) -> &image::RgbImage {
        &self.photo
    }

    /// The photo's colour at `p` (bilinear between pixel centres, clamped at the edges) and
    /// its derivatives along x and y, sRGB in [0, 1].
    #[inline]
    #[must_use]
    pub fn colour_at(&self, p: DVec2) -> [[f32; 3]; 3] {
        let ([a, b, c, d], tx, ty) = self.corners(p);
        let mut out = [[0.0f32; 3]; 3];
        for k in 0..3 {
            let top = a[k] + (b[k] - a[k]) * tx;
            let bottom = c[k] + (d[k] - c[k]) * tx;
            out[0][k] = top + (bottom - top) * ty;
            out[1][k] = (b[k] - a[k]) + ((d[k] - c[k]) - (b[k] - a[k])) * ty;
            out[2][k] = bottom - top;
        }
        out
    }

    /// The blurred photo's colour at `p` (bilinear), `colour_at(p)[0]` without the derivatives:
    /// what the owner search needs at every pixel. At a pixel centre (every raster point of a
    /// picture at the photo's own size) that is the pixel's own texel, read alone.
    #[inline]
    #[must_use]
    pub fn colour_only_at(&self, p: DVec2) -> [f32; 3] {
        let (x, y) = self.texel_position(p);
        let (x0, y0) = (x as u32, y as u32);
        if f64::from(x0) == x && f64::from(y0) == y {
            return self.texel(x0, y0);
        }
        let ([a, b, c, d], tx, ty) = self.corners(p);
        std::array::from_fn(|k| {
            let top = a[k] + (b[k] - a[k]) * tx;
            let bottom = c[k] + (d[k] - c[k]) * tx;
            top + (bottom - top) * ty
        })
    }

    /// `p` in texel coordinates (texel centres at whole numbers), clamped to the photo.
    #[inline]
    fn texel_position(&self, p: DVec2) -> (f64, f64) {
        let (w, h) = (self.photo.width(), self.photo.height());
        (
            (p.x - 0.5).clamp(0.0, f64::from(w - 1)),
            (p.y - 0.5).clamp(0.0, f64::from(h - 1)),
        )
    }

    /// Texel (`x`, `y`), sRGB in [0, 1].
    #[inline]
    fn texel(&self, x: u32, y: u32) -> [f32; 3] {
        let i = 3 * (y as usize * self.photo.width() as usize + x as usize);
        let raw = &self.photo.as_raw()[i..i + 3];
        [raw[0], raw[1], raw[2]].map(|v| UNIT[usize::from(v)])
    }

    /// The four texels around `p` (top left, top right, bottom left, bottom right; sRGB in
    /// [0, 1]) and `p`'s weights across and down between them.
    #[inline]
    fn corners(&self, p: DVec2) -> ([[f32; 3]; 4], f32, f32) {
        let (w, h) = (self.photo.width(), self.photo.height());
        let (x, y) = self.texel_position(p);
        let (x0, y0) = (x as u32, y as u32);
        let (x1, y1) = ((x0 + 1).min(w - 1), (y0 + 1).min(h - 1));
        let (tx, ty) = ((x - f64::from(x0)) as f32, (y - f64::from(y0)) as f32);
        (
            [
                self.texel(x0, y0),
                self.texel(x1, y0),
                self.texel(x0, y1),
                self.texel(x1, y1),
            ],
            tx,
            ty,
        )
    }

    /// `w·|c − c_i|²`.
    #[inline]
    pub(crate) fn cost(&self, c: [f32; 3], i: u32) -> f64 {
        let m = self.means[i as usize];
        let d2: f32 = (0..3).map(|k| (c[k] - m[k]) * (c[k] - m[k])).sum();
        self.weight * f64::from(d2)
    }
}

/// `v / 255` for every byte `v`, the same `f32` as the division: texels in [0, 1] without a
/// division per read.
const UNIT: [f32; 256] = {
    let mut table = [0.0f32; 256];
    let mut v = 0;
    while v < 256 {
        table[v] = v as f32 / 255.0;
        v += 1;
    }
    table
};
