//! The grid the LIC of the fabric and LIC looks ([`fabric`](super), paper section 7.3)
//! runs on: the output's own pixels up to a one-megapixel photo's diagonal, a coarser grid of
//! the same aspect beyond, read back bilinearly at the output's pixels. Coordinates `f64`,
//! values bytes read as `f32` in [0, 1].

use glam::DVec2;

/// The grid the LIC runs on: the output's own pixels up to [`LIC_MAX_DIAGONAL`], a coarser grid
/// of the same aspect beyond it, whose values the output reads bilinearly. Every length of the
/// look (the kernel, the threads' thickness, the grain of white noise) is in this grid's
/// pixels, so a painting larger than that shows the same texture, only finer, instead of
/// threads that shrink to specks as the pixel count grows (a 12 MP fabric read as a blurred
/// photo with a cross at every sample), and the LIC's cost stops growing with the output.
pub(crate) struct LicGrid {
    /// Width and height in grid pixels.
    pub(crate) w: usize,
    pub(crate) h: usize,
    /// Domain units per grid pixel along x and y.
    pub(crate) to_domain: DVec2,
    /// The domain's size.
    pub(crate) domain: DVec2,
}

/// Largest diagonal, in pixels, of the grid the LIC runs on: the one the looks' lengths were
/// chosen at.
const LIC_MAX_DIAGONAL: f64 = crate::render::cells::raster::REFERENCE_DIAGONAL;

impl LicGrid {
    pub(crate) fn for_output(w: usize, h: usize, domain: DVec2) -> Self {
        let diagonal = ((w * w + h * h) as f64).sqrt();
        let (gw, gh) = if diagonal > LIC_MAX_DIAGONAL {
            let f = diagonal / LIC_MAX_DIAGONAL;
            let shrunk = |n: usize| ((n as f64 / f).round() as usize).max(1);
            (shrunk(w), shrunk(h))
        } else {
            (w, h)
        };
        LicGrid {
            w: gw,
            h: gh,
            to_domain: DVec2::new(domain.x / gw as f64, domain.y / gh as f64),
            domain,
        }
    }

    /// Grid pixels per domain unit (the geometric mean of the two axes').
    pub(crate) fn pixels_per_unit(&self) -> f64 {
        ((self.w as f64 / self.domain.x) * (self.h as f64 / self.domain.y)).sqrt()
    }

    /// The two grid rows output row `y` reads and the weight of the lower one.
    pub(crate) fn rows_for(&self, y: usize, h: usize) -> (usize, usize, f32) {
        if self.h == h {
            return (y, y, 0.0);
        }
        axis_pair((y as f64 + 0.5) * self.h as f64 / h as f64 - 0.5, self.h)
    }

    /// The value (0 to 1) of grid image `img` at output pixel `x` of a row `w` wide, between
    /// grid `rows` (from [`Self::rows_for`]).
    #[inline]
    pub(crate) fn read(
        &self,
        img: &[u8],
        x: usize,
        w: usize,
        (r0, r1, ty): (usize, usize, f32),
    ) -> f32 {
        let byte = |i: usize| f32::from(img[i]) / 255.0;
        if self.w == w && ty == 0.0 {
            return byte(r0 * w + x);
        }
        let (c0, c1, tx) = axis_pair((x as f64 + 0.5) * self.w as f64 / w as f64 - 0.5, self.w);
        let upper = byte(r0 * self.w + c0) * (1.0 - tx) + byte(r0 * self.w + c1) * tx;
        let lower = byte(r1 * self.w + c0) * (1.0 - tx) + byte(r1 * self.w + c1) * tx;
        upper * (1.0 - ty) + lower * ty
    }
}

/// The two grid nodes around coordinate `t` (in nodes, clamped to `0..n`) and the weight of
/// the second.
fn axis_pair(t: f64, n: usize) -> (usize, usize, f32) {
    let t = t.clamp(0.0, (n - 1) as f64);
    let i0 = t as usize;
    let i1 = (i0 + 1).min(n - 1);
    (i0, i1, (t - i0 as f64) as f32)
}
