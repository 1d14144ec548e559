//! The generalized Voronoi diagram of paper section 6: every point `p` belongs to the site `i`
//! minimising `δ_i(p) = |m_i⁻¹ (p − p_i)|`, the distance under which site `i`'s own ellipse is
//! the unit circle (the paper's eq. 7 prints `m`; `m⁻¹` is the choice consistent with eq. 3 and
//! with the sampler's conventions).
//!
//! Owners are found as the paper does: the candidates for `p` are the three corners of the
//! anisotropic Delaunay triangle containing `p` and the opposite corners of its three
//! neighbours. The triangle of every raster point comes from rasterising the triangulation
//! scanline by scanline in parallel bands of rows, not from a search per point. Where the
//! true owner is not among the candidates (a far, large ellipse reaching past its neighbours:
//! the paper's "orphans") the result differs from a brute-force search over all sites; tests
//! measure how often.
//!
//! A [`Raster`] places `supersample²` points in every output pixel; [`VoronoiCells::shade_rows`]
//! hands each output row its points' [`Owner`]s, band by band, so memory stays a few rows deep
//! whatever the image size. [`VoronoiCells::border_gradient`] gives the first-order distance
//! from a point to its cell's border, which lets looks supersample only the pixels a border
//! crosses. Positions and distances are `f64` (sites carry `f64` metrics);
//! the per-point record is `f32`, enough for shading.

use crate::field::Tensor;
use crate::sampling::AnisotropicDelaunay;
use glam::DVec2;
use rayon::prelude::*;

/// No site / no triangle.
pub const NONE: u32 = u32::MAX;

/// Where the raster points of an output image lie in the field's domain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Raster {
    /// Output width in pixels.
    pub width: usize,
    /// Output height in pixels.
    pub height: usize,
    /// Raster points per pixel along each axis (1 = pixel centres only).
    pub supersample: usize,
    /// Size of the domain the sites live in (pixels of the input).
    pub domain: DVec2,
}

impl Raster {
    /// Raster points per row.
    #[must_use]
    pub fn points_per_row(&self) -> usize {
        self.width * self.supersample
    }

    /// Raster point rows.
    #[must_use]
    pub fn point_rows(&self) -> usize {
        self.height * self.supersample
    }

    /// Domain units per raster point along x and y.
    #[must_use]
    pub fn step(&self) -> DVec2 {
        DVec2::new(
            self.domain.x / self.points_per_row() as f64,
            self.domain.y / self.point_rows() as f64,
        )
    }

    /// The domain position of raster point (`gx`, `gy`).
    #[must_use]
    pub fn point(&self, gx: usize, gy: usize) -> DVec2 {
        let s = self.step();
        DVec2::new((gx as f64 + 0.5) * s.x, (gy as f64 + 0.5) * s.y)
    }

    /// Output pixels per domain unit (the geometric mean of x and y).
    #[must_use]
    pub fn pixels_per_unit(&self) -> f64 {
        ((self.width as f64 / self.domain.x) * (self.height as f64 / self.domain.y)).sqrt()
    }
}

/// The owner of one raster point: the nearest site and the runner-up among the candidates,
/// with their distances `δ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Owner {
    /// The owning site.
    pub site: u32,
    /// The second-nearest candidate (`NONE` if there was only one).
    pub second: u32,
    /// `δ` of the owner.
    pub delta: f32,
    /// `δ` of the second (infinite when there is none).
    pub delta2: f32,
    /// The triangle whose candidates were searched (`NONE` after a brute-force search).
    pub triangle: u32,
    /// Distance to the border between `site` and `second` in output pixels, when a look's
    /// [`Scene`](super::Scene) has measured it (infinite otherwise, and when farther than
    /// [`BORDER_EXACT_PX`]).
    pub border_px: f32,
}

/// Border distances up to this many output pixels are measured to first order; farther ones
/// are only known to be at least this far (enough for borders up to twice as wide).
pub const BORDER_EXACT_PX: f64 = 8.0;

/// What the owner search reads of a site, packed in one cache line: its position and
/// `Q = m⁻ᵀm⁻¹` (so `δ² = yᵀQy`, no square root per candidate).
#[derive(Clone, Copy, Debug, Default)]
struct SiteQuad {
    x: f64,
    y: f64,
    qxx: f64,
    qxy: f64,
    qyy: f64,
}

impl SiteQuad {
    #[inline]
    fn delta_squared(&self, p: DVec2) -> f64 {
        let (dx, dy) = (p.x - self.x, p.y - self.y);
        self.qxx * dx * dx + 2.0 * self.qxy * dx * dy + self.qyy * dy * dy
    }
}

/// Sites with their inverse metrics and, per triangle of their anisotropic Delaunay
/// triangulation, the paper's six candidates.
pub struct VoronoiCells<'a> {
    positions: &'a [DVec2],
    metrics: &'a [Tensor],
    inverses: Vec<Tensor>,
    quads: Vec<SiteQuad>,
    /// `1 / b` per site (`b` the short semi-axis): the largest `|∇δ|` can be.
    steepest: Vec<f64>,
    mesh: &'a AnisotropicDelaunay,
    candidates: Vec<[u32; 6]>,
}

impl<'a> VoronoiCells<'a> {
    /// Cells of the sites at `positions` with `metrics`, triangulated by `mesh`.
    #[must_use]
    pub fn new(
        positions: &'a [DVec2],
        metrics: &'a [Tensor],
        mesh: &'a AnisotropicDelaunay,
    ) -> Self {
        let inverses: Vec<Tensor> = metrics
            .par_iter()
            .map(|m| m.inverse().unwrap_or_default())
            .collect();
        let quads = inverses
            .iter()
            .zip(positions)
            .map(|(inv, p)| SiteQuad {
                x: p.x,
                y: p.y,
                qxx: inv.xx * inv.xx + inv.xy * inv.xy,
                qxy: inv.xy * (inv.xx + inv.yy),
                qyy: inv.yy * inv.yy + inv.xy * inv.xy,
            })
            .collect();
        let steepest = metrics
            .iter()
            .map(|m| 1.0 / m.eigen().l2.abs().max(1e-12))
            .collect();
        let candidates = (0..mesh.num_triangles())
            .into_par_iter()
            .map(|t| {
                let own = mesh.triangle(t);
                let mut c = [own[0], own[1], own[2], NONE, NONE, NONE];
                for i in 0..3 {
                    if let Some(n) = mesh.neighbour(t, i) {
                        c[3 + i] = mesh
                            .triangle(n)
                            .into_iter()
                            .find(|v| !own.contains(v))
                            .unwrap_or(NONE);
                    }
                }
                c
            })
            .collect();
        VoronoiCells {
            positions,
            metrics,
            inverses,
            quads,
            steepest,
            mesh,
            candidates,
        }
    }

    /// The largest slope `|∇δ_i|` anywhere: `1/b_i`.
    #[must_use]
    pub fn steepest(&self, i: u32) -> f64 {
        self.steepest[i as usize]
    }

    /// The sites' positions.
    #[must_use]
    pub fn positions(&self) -> &[DVec2] {
        self.positions
    }

    /// The sites' metrics.
    #[must_use]
    pub fn metrics(&self) -> &[Tensor] {
        self.metrics
    }

    /// `δ_i(p)`.
    #[inline]
    #[must_use]
    pub fn delta(&self, i: u32, p: DVec2) -> f64 {
        let i = i as usize;
        self.inverses[i].mul_vec(p - self.positions[i]).length()
    }

    /// Gradient of `δ_i` at `p`: `m⁻ᵀ m⁻¹ (p − p_i) / δ_i` (`m⁻¹` is symmetric).
    #[inline]
    #[must_use]
    pub fn delta_gradient(&self, i: u32, p: DVec2) -> DVec2 {
        let inv = &self.inverses[i as usize];
        let u = inv.mul_vec(p - self.positions[i as usize]);
        let len = u.length();
        if len > 0.0 {
            inv.mul_vec(u) / len
        } else {
            DVec2::ZERO
        }
    }

    /// The owner of `p` among the candidates of triangle `t`.
    #[inline]
    #[must_use]
    pub fn owner_in_triangle(&self, t: usize, p: DVec2) -> Owner {
        let candidates = self.candidates[t].iter().filter(|&&c| c != NONE);
        let ((site, d1), (second, d2)) =
            nearest_two(candidates.map(|&c| (c, self.quads[c as usize].delta_squared(p))));
        Owner {
            site,
            second,
            delta: d1.sqrt() as f32,
            delta2: d2.sqrt() as f32,
            triangle: t as u32,
            border_px: f32::INFINITY,
        }
    }

    /// `∇δ_j − ∇δ_i` at `p` for the owner `i` and runner-up `j` of `o` (zero without one):
    /// the gradient of `f = δ_j − δ_i`, which is zero on the border.
    #[must_use]
    pub fn border_gradient(&self, p: DVec2, o: &Owner) -> DVec2 {
        if o.second == NONE || o.delta <= 0.0 || o.delta2 <= 0.0 {
            return DVec2::ZERO;
        }
        let grad = |i: u32, delta: f32| {
            let q = &self.quads[i as usize];
            let (dx, dy) = (p.x - q.x, p.y - q.y);
            DVec2::new(q.qxx * dx + q.qxy * dy, q.qxy * dx + q.qyy * dy) / f64::from(delta)
        };
        grad(o.second, o.delta2) - grad(o.site, o.delta)
    }

    /// A lower bound of the distance from a point to the border between its owner and the
    /// runner-up, `(δ_j − δ_i) / |∇δ_j − ∇δ_i|` to first order, without gradients:
    /// `|∇δ| ≤ 1/b`.
    #[inline]
    #[must_use]
    pub fn border_distance_at_least(&self, o: &Owner) -> f64 {
        if o.second == NONE {
            return f64::INFINITY;
        }
        f64::from(o.delta2 - o.delta) / (self.steepest(o.site) + self.steepest(o.second))
    }

    /// The owner of `p` by brute force over every site (the reference the tests use).
    #[must_use]
    pub fn owner_brute_force(&self, p: DVec2) -> Owner {
        // δ from the inverse metrics, not the packed quadratics the search uses, so the
        // reference stays independent of them.
        let sites = 0..self.positions.len() as u32;
        let ((site, d1), (second, d2)) = nearest_two(sites.map(|i| (i, self.delta(i, p))));
        Owner {
            site,
            second,
            delta: d1 as f32,
            delta2: d2 as f32,
            triangle: NONE,
            border_px: f32::INFINITY,
        }
    }

    /// Calls `shade(y, owners, row)` for every output row `y` of `out` (rows of `row_len`
    /// values, `raster.height` of them), in parallel bands. `owners` holds the row's
    /// `supersample` rows of raster points, `raster.points_per_row()` each.
    pub fn shade_rows<P, F>(&self, raster: &Raster, out: &mut [P], row_len: usize, shade: F)
    where
        P: Send,
        F: Fn(usize, &[Owner], &mut [P]) + Sync,
    {
        let ss = raster.supersample.max(1);
        let band_rows = BAND_ROWS;
        let bands = raster.height.div_ceil(band_rows).max(1);
        let lists = self.band_lists(raster, band_rows * ss, bands);
        out.par_chunks_mut(row_len * band_rows)
            .zip(lists.par_iter())
            .enumerate()
            .for_each(|(band, (chunk, list))| {
                let first_point_row = band * band_rows * ss;
                let rows_here = chunk.len() / row_len.max(1);
                let mut tri = vec![NONE; rows_here * ss * raster.points_per_row()];
                self.rasterise(raster, list, first_point_row, &mut tri);
                let mut owners = vec![
                    Owner {
                        site: NONE,
                        second: NONE,
                        delta: f32::INFINITY,
                        delta2: f32::INFINITY,
                        triangle: NONE,
                        border_px: f32::INFINITY,
                    };
                    ss * raster.points_per_row()
                ];
                for (k, row) in chunk.chunks_mut(row_len).enumerate() {
                    let per_row = ss * raster.points_per_row();
                    let tris = &tri[k * per_row..(k + 1) * per_row];
                    for (j, o) in owners.iter_mut().enumerate() {
                        let gy = first_point_row + k * ss + j / raster.points_per_row();
                        let gx = j % raster.points_per_row();
                        let p = raster.point(gx, gy);
                        *o = match self.triangle_near(tris, j, raster.points_per_row()) {
                            Some(t) => self.owner_in_triangle(t, p),
                            None => self.owner_brute_force(p),
                        };
                    }
                    shade(band * band_rows + k, &owners, row);
                }
            });
    }

    /// The triangle at point `j` of a row block, or the nearest one found on its own point
    /// row (a point can fall between two triangles by rounding); `None` if the row has none.
    fn triangle_near(&self, tris: &[u32], j: usize, per_row: usize) -> Option<usize> {
        if tris[j] != NONE {
            return Some(tris[j] as usize);
        }
        let start = j - j % per_row;
        let row = &tris[start..start + per_row];
        let x = j - start;
        (1..per_row)
            .flat_map(|d| [x.checked_sub(d), Some(x + d)])
            .flatten()
            .filter(|&i| i < per_row)
            .map(|i| row[i])
            .find(|&t| t != NONE)
            .map(|t| t as usize)
    }

    /// For every band of `rows_per_band` raster point rows, the triangles that reach it.
    fn band_lists(&self, raster: &Raster, rows_per_band: usize, bands: usize) -> Vec<Vec<u32>> {
        let step = raster.step();
        let mut lists = vec![Vec::new(); bands];
        for (t, [a, b, c]) in self.mesh.triangles().enumerate() {
            let ys = [a, b, c].map(|v| self.positions[v as usize].y / step.y - 0.5);
            let lo = ys
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min)
                .floor()
                .max(0.0);
            let hi = ys.iter().copied().fold(f64::NEG_INFINITY, f64::max).ceil();
            if hi < 0.0 {
                continue;
            }
            let first = (lo as usize) / rows_per_band;
            let last = ((hi as usize) / rows_per_band).min(bands - 1);
            for list in &mut lists[first.min(bands - 1)..=last] {
                list.push(t as u32);
            }
        }
        lists
    }

    /// Writes each triangle of `list` into the raster points it covers, for the point rows
    /// `first_row..` that `tri` (whole rows of points) holds.
    fn rasterise(&self, raster: &Raster, list: &[u32], first_row: usize, tri: &mut [u32]) {
        let per_row = raster.points_per_row();
        let rows = tri.len() / per_row.max(1);
        let step = raster.step();
        for &t in list {
            let [a, b, c] = self.mesh.triangle(t as usize);
            // In raster point units, where point (gx, gy) sits at (gx + ½, gy + ½).
            let v = [a, b, c].map(|i| self.positions[i as usize] / step - DVec2::splat(0.5));
            let y_lo = v.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
            let y_hi = v.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max);
            let r0 = (y_lo.ceil().max(first_row as f64)) as usize;
            let r1 = (y_hi.floor() as i64).min((first_row + rows) as i64 - 1);
            for gy in r0 as i64..=r1 {
                let y = gy as f64;
                let Some((x0, x1)) = span(&v, y) else {
                    continue;
                };
                // A hair wider than the exact span, so shared edges leave no gaps.
                let lo = (x0 - 1e-9).ceil().max(0.0) as usize;
                let hi = (x1 + 1e-9).floor().min(per_row as f64 - 1.0);
                if hi < 0.0 || (lo as f64) > hi {
                    continue;
                }
                let row = (gy as usize - first_row) * per_row;
                tri[row + lo..=row + hi as usize].fill(t);
            }
        }
    }
}

/// The nearest and second-nearest of `(site, distance)` pairs (`NONE` and infinity where
/// there are fewer). A site listed twice (a neighbour's opposite corner can repeat) has the
/// same distance both times: `<` keeps the first, and it never takes second place beside
/// itself.
fn nearest_two(sites: impl Iterator<Item = (u32, f64)>) -> ((u32, f64), (u32, f64)) {
    let mut best = (NONE, f64::INFINITY);
    let mut second = (NONE, f64::INFINITY);
    for (c, d) in sites {
        if d < best.1 {
            second = best;
            best = (c, d);
        } else if d < second.1 && c != best.0 {
            second = (c, d);
        }
    }
    (best, second)
}

/// Rows of output pixels per parallel band.
const BAND_ROWS: usize = 16;

/// The x-interval where the horizontal line at `y` crosses the triangle `v`.
fn span(v: &[DVec2; 3], y: f64) -> Option<(f64, f64)> {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for i in 0..3 {
        let (p, q) = (v[i], v[(i + 1) % 3]);
        if !((p.y <= y && y <= q.y) || (q.y <= y && y <= p.y)) {
            continue;
        }
        let (a, b) = if p.y == q.y {
            (p.x, q.x)
        } else {
            let x = p.x + (q.x - p.x) * (y - p.y) / (q.y - p.y);
            (x, x)
        };
        lo = lo.min(a.min(b));
        hi = hi.max(a.max(b));
    }
    (lo <= hi).then_some((lo, hi))
}

/// The label map: the owning site of every pixel centre (`raster.supersample` is ignored),
/// row-major, as `i32` for export (`.npy`).
#[must_use]
pub fn label_map(cells: &VoronoiCells, raster: &Raster) -> Vec<i32> {
    let raster = Raster {
        supersample: 1,
        ..*raster
    };
    let mut labels = vec![-1i32; raster.width * raster.height];
    cells.shade_rows(&raster, &mut labels, raster.width, |_, owners, row| {
        for (l, o) in row.iter_mut().zip(owners) {
            *l = if o.site == NONE { -1 } else { o.site as i32 };
        }
    });
    labels
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::AnalyticField;
    use crate::sampling::{self, SamplerParams};

    #[test]
    fn spans_of_a_triangle() {
        let v = [
            DVec2::new(0.0, 0.0),
            DVec2::new(4.0, 0.0),
            DVec2::new(0.0, 4.0),
        ];
        assert_eq!(span(&v, 2.0), Some((0.0, 2.0)));
        assert_eq!(span(&v, 5.0), None);
        assert_eq!(span(&v, 0.0), Some((0.0, 4.0)));
    }

    #[test]
    fn label_map_matches_brute_force_on_a_constant_field() {
        let field = AnalyticField::parse("constant:angle=30,anisotropy=3,size=0.02")
            .unwrap()
            .field(120, 90);
        let s = sampling::sample(&field, &SamplerParams::default()).unwrap();
        let cells = VoronoiCells::new(&s.positions, &s.metrics, &s.mesh);
        for (w, h) in [(120, 90), (61, 47), (1, 9), (9, 1)] {
            let raster = Raster {
                width: w,
                height: h,
                supersample: 1,
                domain: field.domain(),
            };
            let labels = label_map(&cells, &raster);
            let mut agree = 0;
            for y in 0..h {
                for x in 0..w {
                    let o = cells.owner_brute_force(raster.point(x, y));
                    agree += usize::from(labels[y * w + x] == o.site as i32);
                }
            }
            let rate = agree as f64 / (w * h) as f64;
            assert!(rate >= 0.995, "{w}x{h}: {rate}");
        }
    }
}
