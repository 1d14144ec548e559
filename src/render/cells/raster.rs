//! Rasterising the generalized Voronoi cells (paper section 6) onto an output image: a
//! [`Raster`] says where pixels lie in the field's domain; the anisotropic Delaunay triangles
//! are scan-converted in parallel bands of rows, so every pixel centre gets its containing
//! triangle without a search, and [`VoronoiCells::shade_rows`] hands each output row its
//! pixels' [`Owner`]s, band by band, so memory stays a few rows deep whatever the image size;
//! [`VoronoiCells::shade_rows_settled`] leaves out the search where the cell map settles the
//! owner. [`VoronoiCells::site_rows`] hands out the owning sites alone; [`owner_map`] and
//! [`label_map`] keep them. Per-cell sums of a photo's pixels are in
//! [`sums`](super::sums). Positions are `f64`.

use super::cellmap::CellMap;
use super::voronoi::{Owner, VoronoiCells, NONE};
use crate::render::support::rounding::{ceil, floor};
use glam::DVec2;
use rayon::prelude::*;

/// The diagonal, in pixels, of the pictures the looks' lengths in pixels were chosen on (a
/// one-megapixel photo's). A larger picture draws those lengths scaled with its diagonal
/// ([`Raster::length_scale`]), so it shows the same look, finer, instead of lines that thin
/// to hairlines, gone when the picture is seen whole.
pub const REFERENCE_DIAGONAL: f64 = 1500.0;

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

    /// Output pixels per domain unit along x and y (what the vector forms scale by).
    #[must_use]
    pub fn pixels_per_domain_unit(&self) -> DVec2 {
        DVec2::new(
            self.width as f64 / self.domain.x,
            self.height as f64 / self.domain.y,
        )
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

    /// How many of this picture's pixels a length of one pixel at [`REFERENCE_DIAGONAL`]
    /// takes: the picture's diagonal over that one, and never under 1.
    #[must_use]
    pub fn length_scale(&self) -> f64 {
        let (w, h) = (self.width as f64, self.height as f64);
        ((w * w + h * h).sqrt() / REFERENCE_DIAGONAL).max(1.0)
    }

    /// Output pixels per domain unit (the geometric mean of x and y).
    #[must_use]
    pub fn pixels_per_unit(&self) -> f64 {
        let s = self.pixels_per_domain_unit();
        (s.x * s.y).sqrt()
    }
}

impl VoronoiCells<'_> {
    /// Calls `shade(y, owners, row)` for every output row `y` of `out` (rows of `row_len`
    /// values, `raster.height` of them), in parallel bands, with `owners` the owners of the
    /// row's pixel centres (`raster.supersample` is not read: looks that supersample do it
    /// themselves, on the border the centres' owners give).
    pub fn shade_rows<P, F>(&self, raster: &Raster, out: &mut [P], row_len: usize, shade: F)
    where
        P: Send,
        F: Fn(usize, &[Owner], &mut [P]) + Sync,
    {
        self.owner_rows(raster, out, row_len, None, None, |y, owners, _, row| {
            shade(y, owners, row);
        });
    }

    /// [`Self::shade_rows`] without the owner search where the colour term's cell map settles
    /// the owner ([`CellMap::settled_at`]): `shade(y, owners, settled, row)` gets those pixels'
    /// sites in `settled` ([`NONE`] elsewhere) and [`Owner::NOBODY`] in `owners`, and finds
    /// their owners itself ([`VoronoiCells::settled_owner`]). The map is read only when the
    /// raster's points are its pixels' centres (a picture at the photo's own size); otherwise
    /// `settled` is empty and every pixel is searched as by [`Self::shade_rows`].
    ///
    /// With `crossings` (the shading takes the runner-up beside another cell's pixel from the
    /// map's crossings, [`VoronoiCells::map_crossings`]), such a pixel's owner is not searched
    /// either (`owner_beside`).
    pub fn shade_rows_settled<P, F>(
        &self,
        raster: &Raster,
        out: &mut [P],
        row_len: usize,
        crossings: bool,
        shade: F,
    ) where
        P: Send,
        F: Fn(usize, &[Owner], &[u32], &mut [P]) + Sync,
    {
        let map = self.aligned_map(raster);
        let beside = map.filter(|_| crossings);
        self.owner_rows(raster, out, row_len, map, beside, shade);
    }

    /// The owner of pixel centre `p` in triangle `t` beside a pixel of another cell of the
    /// colour term's cell `map` ([`CellMap::beside_another`]), but for its runner-up: the map's
    /// cell (which the owner search found there, or absorbed the pixel into) with its `D`,
    /// the same expression the search evaluates. The shading replaces the runner-up with the
    /// crossings' ([`VoronoiCells::map_crossings`]), so it needs no search. `None` elsewhere.
    fn owner_beside(&self, map: &CellMap, t: usize, p: DVec2) -> Option<Owner> {
        let term = self.colour()?;
        let site = map.beside_another(p)?;
        let (_, owner) = self.settled_owner(term, site, p, t as u32);
        Some(owner)
    }

    /// The colour term's cell map when its pixels are the raster's points (a picture at the
    /// photo's own size).
    fn aligned_map(&self, raster: &Raster) -> Option<&CellMap> {
        let centres = Raster {
            supersample: 1,
            ..*raster
        };
        self.colour()
            .and_then(|term| term.map.as_ref())
            .filter(|map| {
                map.size() == (centres.width, centres.height) && centres.step() == DVec2::ONE
            })
    }

    /// The owner search of [`Self::shade_rows`] and [`Self::shade_rows_settled`] through
    /// [`Self::rows_of`], leaving out the pixels `settle` settles, and taking the owners of
    /// the pixels beside another cell's off `beside` (`owner_beside`).
    fn owner_rows<P, F>(
        &self,
        raster: &Raster,
        out: &mut [P],
        row_len: usize,
        settle: Option<&CellMap>,
        beside: Option<&CellMap>,
        shade: F,
    ) where
        P: Send,
        F: Fn(usize, &[Owner], &[u32], &mut [P]) + Sync,
    {
        self.rows_of(
            raster,
            out,
            row_len,
            Owner::NOBODY,
            |t, p| match t {
                Some(t) => beside
                    .and_then(|map| self.owner_beside(map, t, p))
                    .unwrap_or_else(|| self.owner_in_triangle(t, p)),
                None => self.owner_brute_force(p),
            },
            settle,
            shade,
        );
    }

    /// [`Self::shade_rows`] with only the owning sites ([`VoronoiCells::site_in_triangle`]),
    /// for callers that need no runner-up or distance.
    pub fn site_rows<P, F>(&self, raster: &Raster, out: &mut [P], row_len: usize, shade: F)
    where
        P: Send,
        F: Fn(usize, &[u32], &mut [P]) + Sync,
    {
        // The cell map holds every pixel's owner (what the search below finds, absorbed pixels
        // given to their new cells): at its own size the rows are read off it.
        if let Some(map) = self.aligned_map(raster) {
            let width = map.size().0;
            out.par_chunks_mut(row_len * BAND_ROWS)
                .enumerate()
                .for_each(|(band, chunk)| {
                    let mut sites = vec![NONE; width];
                    for (k, row) in chunk.chunks_mut(row_len).enumerate() {
                        let y = band * BAND_ROWS + k;
                        for (x, site) in sites.iter_mut().enumerate() {
                            *site = map.cell(y * width + x);
                        }
                        shade(y, &sites, row);
                    }
                });
            return;
        }
        self.rows_of(
            raster,
            out,
            row_len,
            NONE,
            |t, p| match t {
                Some(t) => self.site_in_triangle(t, p),
                None => self.owner_brute_force(p).site,
            },
            None,
            |y, sites, _, row| shade(y, sites, row),
        );
    }

    /// The driver of [`Self::shade_rows`], [`Self::shade_rows_settled`] and
    /// [`Self::site_rows`]: `at(triangle, p)` is what a pixel centre `p` gets, its triangle
    /// `None` where no triangle covers its row; where `settle` (a map of the raster's own
    /// pixels) settles a pixel, it gets `none` and its site goes to `shade`'s third slice.
    #[allow(clippy::too_many_arguments)]
    fn rows_of<T, P, A, F>(
        &self,
        raster: &Raster,
        out: &mut [P],
        row_len: usize,
        none: T,
        at: A,
        settle: Option<&CellMap>,
        shade: F,
    ) where
        T: Copy + Send + Sync,
        P: Send,
        A: Fn(Option<usize>, DVec2) -> T + Sync,
        F: Fn(usize, &[T], &[u32], &mut [P]) + Sync,
    {
        let raster = Raster {
            supersample: 1,
            ..*raster
        };
        let width = raster.width;
        let bands = raster.height.div_ceil(BAND_ROWS).max(1);
        let lists = self.band_lists(&raster, BAND_ROWS, bands);
        // One job per band: bands differ in cost (a band of edge-following borders takes many
        // times one of settled pixels), and rayon's adaptive split stops halving a thread's
        // share after a few levels, so the last share ran on alone (a 12 MP pointillist: one
        // core idle for its last 0.09 s of shading).
        out.par_chunks_mut(row_len * BAND_ROWS)
            .zip(lists.par_iter())
            .with_max_len(1)
            .enumerate()
            .for_each(|(band, (chunk, list))| {
                let first_row = band * BAND_ROWS;
                let rows_here = chunk.len() / row_len.max(1);
                let mut tri = vec![NONE; rows_here * width];
                self.rasterise(&raster, list, first_row, &mut tri);
                let mut values = vec![none; width];
                let mut settled = vec![NONE; if settle.is_some() { width } else { 0 }];
                let step = raster.step();
                for (k, row) in chunk.chunks_mut(row_len).enumerate() {
                    let tris = &tri[k * width..(k + 1) * width];
                    let y = (((first_row + k) as f64) + 0.5) * step.y;
                    if let Some(map) = settle {
                        map.settled_row(first_row + k, &mut settled);
                    }
                    for (x, v) in values.iter_mut().enumerate() {
                        if settled.get(x).is_some_and(|&s| s != NONE) {
                            *v = none;
                            continue;
                        }
                        // `raster.point(x, first_row + k)`, with the step divided out once.
                        let p = DVec2::new((x as f64 + 0.5) * step.x, y);
                        *v = at(triangle_near(tris, x), p);
                    }
                    shade(first_row + k, &values, &settled, row);
                }
            });
    }

    /// For every band of `rows_per_band` raster point rows, the triangles that reach it.
    fn band_lists(&self, raster: &Raster, rows_per_band: usize, bands: usize) -> Vec<Vec<u32>> {
        let step = raster.step();
        let mut lists = vec![Vec::new(); bands];
        for (t, [a, b, c]) in self.mesh().triangles().enumerate() {
            let ys = [a, b, c].map(|v| self.positions()[v as usize].y / step.y - 0.5);
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
            let [a, b, c] = self.mesh().triangle(t as usize);
            // In raster point units, where point (gx, gy) sits at (gx + ½, gy + ½).
            let v = [a, b, c].map(|i| self.positions()[i as usize] / step - DVec2::splat(0.5));
            let y_lo = v.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
            let y_hi = v.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max);
            // floor and ceil without libm calls (baseline x86-64 has no rounding instruction).
            let r0 = (ceil(y_lo).max(first_row as f64)) as usize;
            let r1 = (floor(y_hi) as i64).min((first_row + rows) as i64 - 1);
            for gy in r0 as i64..=r1 {
                let y = gy as f64;
                let Some((x0, x1)) = span(&v, y) else {
                    continue;
                };
                // A hair wider than the exact span, so shared edges leave no gaps.
                let lo = ceil(x0 - 1e-9).max(0.0) as usize;
                let hi = floor(x1 + 1e-9).min(per_row as f64 - 1.0);
                if hi < 0.0 || (lo as f64) > hi {
                    continue;
                }
                let row = (gy as usize - first_row) * per_row;
                tri[row + lo..=row + hi as usize].fill(t);
            }
        }
    }
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

/// The triangle at pixel `x` of a row, or the nearest one found on the row (a point can fall
/// between two triangles by rounding); `None` if the row has none.
fn triangle_near(row: &[u32], x: usize) -> Option<usize> {
    if row[x] != NONE {
        return Some(row[x] as usize);
    }
    (1..row.len())
        .flat_map(|d| [x.checked_sub(d), Some(x + d)])
        .flatten()
        .filter(|&i| i < row.len())
        .map(|i| row[i])
        .find(|&t| t != NONE)
        .map(|t| t as usize)
}

/// The owning site of every pixel centre of `raster` (`raster.supersample` is not read),
/// row-major, [`NONE`] where no site owns it.
#[must_use]
pub fn owner_map(cells: &VoronoiCells, raster: &Raster) -> Vec<u32> {
    let mut owners = vec![NONE; raster.width * raster.height];
    cells.site_rows(raster, &mut owners, raster.width, |_, sites, row| {
        row.copy_from_slice(sites);
    });
    owners
}

/// The label map: [`owner_map`] as `i32` for export (`.npy`), -1 where no site owns a pixel.
#[must_use]
pub fn label_map(cells: &VoronoiCells, raster: &Raster) -> Vec<i32> {
    owner_map(cells, raster)
        .into_iter()
        .map(|site| if site == NONE { -1 } else { site as i32 })
        .collect()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::field::{AnalyticField, TensorField};
    use crate::render::VoronoiCells;
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

    /// Samples of a constant 3:1 field at 30° on a `w × h` domain, ellipses of `size`
    /// diagonals.
    pub(crate) fn constant_samples(
        w: usize,
        h: usize,
        size: f64,
    ) -> (TensorField, sampling::Sampling) {
        let field = AnalyticField::parse(&format!("constant:angle=30,anisotropy=3,size={size}"))
            .unwrap()
            .field(w, h);
        let s = sampling::sample(&field, &SamplerParams::default()).unwrap();
        (field, s)
    }

    /// Edge-following cells of a photo (a dark disc and fine stripes: borders carved by colour,
    /// pieces absorbed), made as [`CellSites`](super::super::CellSites) makes them (owners searched
    /// with the colour term, then one piece per cell), with the photo's raster: the samples, the
    /// colour term with its cell map, and the raster.
    fn edge_cells_at_photo_size() -> (
        sampling::Sampling,
        super::super::colour_term::ColourTerm,
        Raster,
    ) {
        let (w, h) = (120usize, 90usize);
        let (field, s) = constant_samples(w, h, 0.05);
        let photo = image::RgbImage::from_fn(w as u32, h as u32, |x, y| {
            let (dx, dy) = (f64::from(x) - 50.0, f64::from(y) - 40.0);
            let disc = dx.hypot(dy) < 22.0;
            let stripe = (x / 3 + y / 7) % 2 == 0;
            let v: u8 = if disc {
                30
            } else if stripe {
                200
            } else {
                150
            };
            image::Rgb([v, v / 2 + 40, 255 - v])
        });
        let mut term = super::super::colour_term::ColourTerm::new(photo.clone(), 300.0);
        term.reach = 1.0;
        term.means = s
            .positions
            .iter()
            .map(|&p| term.colour_only_at(p))
            .collect();
        let raster = Raster {
            width: w,
            height: h,
            supersample: 1,
            domain: field.domain(),
        };
        let searched_once = {
            let cells = VoronoiCells::new(&s.positions, &s.metrics, &s.mesh).with_colour(&term);
            owner_map(&cells, &raster)
        };
        let unit = |v: u8| f32::from(v) / 255.0;
        term.map = Some(super::super::pieces::one_piece(
            searched_once,
            w,
            h,
            &term.means,
            |x, y| photo.get_pixel(x as u32, y as u32).0.map(unit),
        ));
        (s, term, raster)
    }

    #[test]
    fn site_rows_at_the_photos_size_read_the_cell_map_as_the_search_finds() {
        // At the photo's size the rows come off the cell map, and they are what the full
        // owner search (`D²` of every candidate, then the nearest two) finds at every pixel:
        // the map's own search (`site_in_triangle`, its colour term measured only where `δ²`
        // can still win) found the same owners.
        let (s, term, raster) = edge_cells_at_photo_size();
        let w = raster.width;
        let cells = VoronoiCells::new(&s.positions, &s.metrics, &s.mesh).with_colour(&term);
        assert!(cells.aligned_map(&raster).is_some());
        let mapped = owner_map(&cells, &raster);
        let mut searched = vec![NONE; mapped.len()];
        cells.rows_of(
            &raster,
            &mut searched,
            w,
            NONE,
            |t, p| match t {
                Some(t) => cells.owner_in_triangle(t, p).site,
                None => cells.owner_brute_force(p).site,
            },
            None,
            |_, sites, _, row| row.copy_from_slice(sites),
        );
        let differ = mapped.iter().zip(&searched).filter(|(a, b)| a != b).count();
        assert_eq!(differ, 0, "{differ} of {} pixels", mapped.len());
    }

    #[test]
    fn owners_beside_another_cell_are_the_searched_ones_but_for_the_runner_up() {
        // Where the shading takes the runner-up from the map's crossings, the owners come off
        // the map: the same site and `D`, bit for bit, as the search at every pixel, the
        // runner-up left to the crossings, which every such pixel has.
        let (s, term, raster) = edge_cells_at_photo_size();
        let cells = VoronoiCells::new(&s.positions, &s.metrics, &s.mesh).with_colour(&term);
        let map = cells.aligned_map(&raster).expect("the photo's size");
        let owners = |crossings: bool| {
            let mut out = vec![Owner::NOBODY; raster.width * raster.height];
            cells.shade_rows_settled(
                &raster,
                &mut out,
                raster.width,
                crossings,
                |_, o, _, row| {
                    row.copy_from_slice(o);
                },
            );
            out
        };
        let (taken, searched) = (owners(true), owners(false));
        let mut beside = 0;
        for (k, (a, b)) in taken.iter().zip(&searched).enumerate() {
            assert_eq!(
                (a.site, a.delta.to_bits()),
                (b.site, b.delta.to_bits()),
                "pixel {k}"
            );
            let (x, y) = (k % raster.width, k / raster.width);
            if map.beside_another(raster.point(x, y)).is_some() {
                beside += 1;
                assert!(cells.map_crossings(map, (x, y), a).is_some(), "pixel {k}");
            } else {
                assert_eq!(a, b, "pixel {k}");
            }
        }
        assert!(beside > 1000, "{beside} pixels beside another cell");
    }

    #[test]
    fn label_map_matches_brute_force_on_a_constant_field() {
        let (field, s) = constant_samples(120, 90, 0.02);
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
