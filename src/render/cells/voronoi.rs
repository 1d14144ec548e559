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
//! [`raster`](super::raster) finds the owners of every pixel of an output image.
//! [`VoronoiCells::border_gradient`] gives the first-order distance
//! from a point to its cell's border, which lets looks supersample only the pixels a border
//! crosses. Positions and distances are `f64` (sites carry `f64` metrics);
//! the per-point record is `f32`, enough for shading.

use crate::field::Tensor;
use crate::sampling::AnisotropicDelaunay;
use glam::DVec2;
use rayon::prelude::*;

use super::cellmap::CellMap;
pub use super::cellmap::NONE;
pub use super::colour_term::ColourTerm;

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
    /// [`Scene`](crate::render::Scene) has measured it (infinite otherwise, and when farther than
    /// [`BORDER_EXACT_PX`]).
    pub border_px: f32,
}

/// Where the cell map's borders cross the lines from a pixel's centre to its neighbours
/// ([`VoronoiCells::map_crossings`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapCrossings {
    /// The cell across the nearest crossing.
    pub second: u32,
    /// Its `D` at the pixel's centre.
    pub delta2: f32,
    /// The nearest crossing along x, in pixels (infinite where none).
    pub along_x: f64,
    /// The nearest crossing along y, in pixels (infinite where none).
    pub along_y: f64,
}

impl Owner {
    /// No owner: no site, no candidate, infinitely far.
    pub const NOBODY: Owner = Owner {
        site: NONE,
        second: NONE,
        delta: f32::INFINITY,
        delta2: f32::INFINITY,
        triangle: NONE,
        border_px: f32::INFINITY,
    };

    /// How much of this point is border ink: 1 within half the `width` of the border between
    /// its owner and the runner-up, falling to 0 over one pixel. Uses the distance the scene
    /// measured ([`Owner::border_px`]); exact for borders up to twice [`BORDER_EXACT_PX`] wide.
    #[must_use]
    pub fn border_coverage(&self, width: f32) -> f32 {
        (0.5 * width - self.border_px + 0.5).clamp(0.0, 1.0)
    }
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
/// triangulation, the paper's six candidates; optionally a [`ColourTerm`].
pub struct VoronoiCells<'a> {
    positions: &'a [DVec2],
    metrics: &'a [Tensor],
    inverses: Vec<Tensor>,
    quads: Vec<SiteQuad>,
    /// `1 / b` per site (`b` the short semi-axis): the largest `|∇δ|` can be.
    steepest: Vec<f64>,
    mesh: &'a AnisotropicDelaunay,
    candidates: Vec<[u32; 6]>,
    colour: Option<&'a ColourTerm>,
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
                // A missing neighbour (on the hull) repeats a corner, which the searches
                // ignore, so every search reads six candidates without a test.
                let mut c = [own[0], own[1], own[2], own[0], own[0], own[0]];
                for i in 0..3 {
                    if let Some(n) = mesh.neighbour(t, i) {
                        c[3 + i] = mesh
                            .triangle(n)
                            .into_iter()
                            .find(|v| !own.contains(v))
                            .unwrap_or(own[0]);
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
            colour: None,
        }
    }

    /// The same cells with `term`'s colour term in the owner (its `means` one per site).
    #[must_use]
    pub fn with_colour(mut self, term: &'a ColourTerm) -> Self {
        debug_assert_eq!(term.means.len(), self.positions.len());
        self.colour = Some(term);
        self
    }

    /// The colour term, if the cells have one.
    #[must_use]
    pub fn colour(&self) -> Option<&ColourTerm> {
        self.colour
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

    /// The anisotropic Delaunay triangulation the candidates come from.
    #[must_use]
    pub fn mesh(&self) -> &AnisotropicDelaunay {
        self.mesh
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

    /// `δ_i(p)²`, from the packed quadratic form the owner search uses.
    #[inline]
    #[must_use]
    pub fn delta_squared(&self, i: u32, p: DVec2) -> f64 {
        self.quads[i as usize].delta_squared(p)
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

    /// The owner of `p` among the candidates of triangle `t`. Where the colour term's cell map
    /// settles the owner
    /// ([`CellMap::settled_owner`](super::cellmap::CellMap::settled_owner): a pixel centre
    /// inside its cell), only its `D` is computed; the result is
    /// [`Self::owner_searched`]'s.
    #[inline]
    #[must_use]
    pub fn owner_in_triangle(&self, t: usize, p: DVec2) -> Owner {
        if let Some(term) = self.colour {
            if let Some(site) = term.map.as_ref().and_then(|map| map.settled_owner(p)) {
                return self.settled_owner(term, site, p, t as u32).1;
            }
        }
        self.owner_searched(t, p)
    }

    /// The owner of `p`, a pixel centre the colour term's cell map settles to `site`, in
    /// triangle `t`: `D` alone, no runner-up and no border (what [`Self::owner_in_triangle`]
    /// gives there), with `site`'s `δ²` at `p`, which `D` is made from.
    #[inline]
    #[must_use]
    pub fn settled_owner(&self, term: &ColourTerm, site: u32, p: DVec2, t: u32) -> (f64, Owner) {
        let delta_squared = self.quads[site as usize].delta_squared(p);
        let d1 = delta_squared + term.cost(term.colour_only_at(p), site);
        let owner = Owner {
            site,
            second: NONE,
            delta: d1.sqrt() as f32,
            delta2: f32::INFINITY,
            triangle: t,
            border_px: f32::INFINITY,
        };
        (delta_squared, owner)
    }

    /// The owner of `p` among the candidates of triangle `t`, every candidate searched.
    #[inline]
    #[must_use]
    pub fn owner_searched(&self, t: usize, p: DVec2) -> Owner {
        let candidates = self.candidates[t].iter();
        let ((site, d1), (second, d2)) = match self.colour {
            None => nearest_two(candidates.map(|&c| (c, self.quads[c as usize].delta_squared(p)))),
            Some(term) => {
                let colour = term.colour_only_at(p);
                let costs = self.colour_distances(term, &self.candidates[t], p, colour);
                let two = nearest_two(self.candidates[t].into_iter().zip(costs));
                as_mapped(term, p, two, |c| {
                    self.quads[c as usize].delta_squared(p) + term.cost(colour, c)
                })
            }
        };
        Owner {
            site,
            second,
            delta: d1.sqrt() as f32,
            delta2: d2.sqrt() as f32,
            triangle: t as u32,
            border_px: f32::INFINITY,
        }
    }

    /// The owning site of `p` among the candidates of triangle `t`: [`Self::owner_in_triangle`]'s
    /// site, the same one, without the runner-up, its distance or a square root (what owner
    /// maps and per-cell sums need).
    #[inline]
    #[must_use]
    pub fn site_in_triangle(&self, t: usize, p: DVec2) -> u32 {
        let candidates = &self.candidates[t];
        let Some(term) = self.colour else {
            return nearest(
                candidates
                    .iter()
                    .map(|&c| (c, self.quads[c as usize].delta_squared(p))),
            );
        };
        let map = term.map.as_ref();
        if let Some(site) = map.and_then(|map| map.settled_owner(p)) {
            return site;
        }
        let colour = term.colour_only_at(p);
        let site = self.nearest_by_colour(term, candidates, p, colour);
        // As `as_mapped`: an absorbed pixel belongs to its new cell.
        map.and_then(|map| map.absorbed_into(p)).unwrap_or(site)
    }

    /// The nearest of `candidates` at `p` by `D²` ([`Self::colour_distances`]'s, the first of
    /// equals), the colour term measured only for a candidate whose `δ²` alone is under the
    /// nearest `D²` so far: `D² ≥ δ²`, so the others cannot be nearer, nor first of equals.
    #[inline]
    fn nearest_by_colour(
        &self,
        term: &ColourTerm,
        candidates: &[u32; 6],
        p: DVec2,
        colour: [f32; 3],
    ) -> u32 {
        let (squared, limit) = self.within_reach(term, candidates, p);
        let mut best = (NONE, f64::INFINITY);
        for (&d2, &c) in squared.iter().zip(candidates) {
            if d2 <= limit && d2 < best.1 {
                let d = d2 + term.cost(colour, c);
                if d < best.1 {
                    best = (c, d);
                }
            }
        }
        best.0
    }

    /// `D² = δ² + w·|c − c_i|²` of each of `candidates` at `p` (`colour` the photo's there),
    /// infinite for a candidate farther than the nearest plus the reach, which is out
    /// ([`Self::within_reach`]). Plain loops over the six: the
    /// owner searches run them at every pixel.
    #[inline]
    fn colour_distances(
        &self,
        term: &ColourTerm,
        candidates: &[u32; 6],
        p: DVec2,
        colour: [f32; 3],
    ) -> [f64; 6] {
        let (mut squared, limit) = self.within_reach(term, candidates, p);
        for (d2, &c) in squared.iter_mut().zip(candidates) {
            *d2 = if *d2 <= limit {
                *d2 + term.cost(colour, c)
            } else {
                f64::INFINITY
            };
        }
        squared
    }

    /// `δ²` of each of `candidates` at `p`, and the largest `δ²` within the colour term's
    /// reach of the nearest (`(δ_min + reach)²`, compared squared: one square root per point,
    /// not six).
    #[inline]
    fn within_reach(&self, term: &ColourTerm, candidates: &[u32; 6], p: DVec2) -> ([f64; 6], f64) {
        let mut squared = [0.0f64; 6];
        let mut nearest = f64::INFINITY;
        for (d2, &c) in squared.iter_mut().zip(candidates) {
            *d2 = self.quads[c as usize].delta_squared(p);
            nearest = nearest.min(*d2);
        }
        let limit = nearest.sqrt() + term.reach;
        // Never under the nearest's own δ² (the square of its root can round below).
        (squared, (limit * limit).max(nearest))
    }

    /// `∇δ_j − ∇δ_i` at `p` for the owner `i` and runner-up `j` of `o` (zero without one):
    /// the gradient of `f = δ_j − δ_i`, which is zero on the border. With a colour term, the
    /// same for `f = D_j − D_i`: `∇D_i = (Q_i (p − p_i) + w Jᵀ(c − c_i)) / D_i`, `J` the
    /// photo's colour derivatives at `p`.
    #[must_use]
    pub fn border_gradient(&self, p: DVec2, o: &Owner) -> DVec2 {
        if o.second == NONE || o.delta <= 0.0 || o.delta2 <= 0.0 {
            return DVec2::ZERO;
        }
        let half_gradient = |i: u32| {
            let q = &self.quads[i as usize];
            let (dx, dy) = (p.x - q.x, p.y - q.y);
            DVec2::new(q.qxx * dx + q.qxy * dy, q.qxy * dx + q.qyy * dy)
        };
        let Some(term) = self.colour else {
            let grad = |i: u32, delta: f32| half_gradient(i) / f64::from(delta);
            return grad(o.second, o.delta2) - grad(o.site, o.delta);
        };
        let [c, dcx, dcy] = term.colour_at(p);
        let grad = |i: u32, big_d: f32| {
            let m = term.means[i as usize];
            let mut g = half_gradient(i);
            for k in 0..3 {
                let diff = f64::from(c[k] - m[k]) * term.weight;
                g += DVec2::new(diff * f64::from(dcx[k]), diff * f64::from(dcy[k]));
            }
            g / f64::from(big_d)
        };
        grad(o.second, o.delta2) - grad(o.site, o.delta)
    }

    /// Where the cell map's borders beside pixel (`x`, `y`) cross the lines to its four
    /// neighbours (the map is the colour term's, its pixels the picture's; `o` is the owner of
    /// the pixel's centre `p`): for each neighbour `q` of another cell `k`, the border of
    /// `f = D_k − D_i` lies a fraction `t = f(p) / (f(p) − f(q))` of the way to `q` (a secant
    /// through both centres: the photo's colour bends `D` too much for the tangent `f / |∇f|`
    /// to be trusted a pixel away), or halfway where `f` does not change sign between them (a
    /// piece absorbed against `D`). Gives the nearest crossing's cell `k`, its `D_k(p)`, and
    /// the nearest crossings along x and along y (infinite where none), in pixels; `None`
    /// where the four neighbours are all the owner's.
    #[must_use]
    pub fn map_crossings(
        &self,
        map: &CellMap,
        (x, y): (usize, usize),
        o: &Owner,
    ) -> Option<MapCrossings> {
        let term = self.colour?;
        let (w, h) = map.size();
        let p = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
        let big_d = |site: u32, q: DVec2, c: [f32; 3]| {
            (self.quads[site as usize].delta_squared(q) + term.cost(c, site)).sqrt()
        };
        let colour_p = term.colour_only_at(p);
        let own_p = big_d(o.site, p, colour_p);
        let mut found: Option<MapCrossings> = None;
        let neighbours = [
            (x.checked_sub(1), Some(y), true),
            ((x + 1 < w).then_some(x + 1), Some(y), true),
            (Some(x), y.checked_sub(1), false),
            (Some(x), (y + 1 < h).then_some(y + 1), false),
        ];
        for (nx, ny, along_x) in neighbours {
            let (Some(nx), Some(ny)) = (nx, ny) else {
                continue;
            };
            let k = map.cell(ny * w + nx);
            if k == o.site || k == NONE {
                continue;
            }
            let q = DVec2::new(nx as f64 + 0.5, ny as f64 + 0.5);
            let colour_q = term.colour_only_at(q);
            let k_p = big_d(k, p, colour_p);
            let (f_p, f_q) = (
                k_p - own_p,
                big_d(k, q, colour_q) - big_d(o.site, q, colour_q),
            );
            let t = if f_p >= 0.0 && f_q < 0.0 {
                f_p / (f_p - f_q)
            } else {
                0.5
            };
            let c = found.get_or_insert(MapCrossings {
                second: k,
                delta2: k_p as f32,
                along_x: f64::INFINITY,
                along_y: f64::INFINITY,
            });
            if t < c.along_x.min(c.along_y) {
                (c.second, c.delta2) = (k, k_p as f32);
            }
            if along_x {
                c.along_x = c.along_x.min(t);
            } else {
                c.along_y = c.along_y.min(t);
            }
        }
        found
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
        if self.colour.is_some() {
            return 0.0; // the photo's colour can change at any rate: always measure
        }
        f64::from(o.delta2 - o.delta) / (self.steepest(o.site) + self.steepest(o.second))
    }

    /// The owner of `p` by brute force over every site (the reference the tests use).
    #[must_use]
    pub fn owner_brute_force(&self, p: DVec2) -> Owner {
        // δ from the inverse metrics, not the packed quadratics the search uses, so the
        // reference stays independent of them.
        let sites = 0..self.positions.len() as u32;
        let ((site, d1), (second, d2)) = match self.colour {
            None => nearest_two(sites.map(|i| (i, self.delta(i, p)))),
            Some(term) => {
                let colour = term.colour_only_at(p);
                let nearest = sites
                    .clone()
                    .map(|i| self.delta(i, p))
                    .fold(f64::INFINITY, f64::min);
                let two = nearest_two(
                    sites
                        .map(|i| (i, self.delta(i, p)))
                        .filter(|&(_, d)| d <= nearest + term.reach)
                        .map(|(i, d)| (i, d * d + term.cost(colour, i))),
                );
                let ((s1, c1), (s2, c2)) = as_mapped(term, p, two, |i| {
                    self.delta(i, p).powi(2) + term.cost(colour, i)
                });
                ((s1, c1.sqrt()), (s2, c2.sqrt()))
            }
        };
        Owner {
            site,
            second,
            delta: d1 as f32,
            delta2: d2 as f32,
            triangle: NONE,
            border_px: f32::INFINITY,
        }
    }
}

/// The owner and runner-up `(site, D²)` at `p` as `term`'s
/// [`CellMap`](super::cellmap::CellMap) has them: an absorbed
/// pixel goes to its new cell with no runner-up (a border beside it is the map's, which the
/// shading reads: [`CellMap::border_distance_at`](super::cellmap::CellMap::border_distance_at)),
/// and a runner-up that
/// owns none of the pixels around `p` (the piece that was there was absorbed) is dropped, so
/// no border is drawn round a piece that is gone.
#[inline]
fn as_mapped(
    term: &ColourTerm,
    p: DVec2,
    two: ((u32, f64), (u32, f64)),
    cost: impl Fn(u32) -> f64,
) -> ((u32, f64), (u32, f64)) {
    let Some(map) = &term.map else {
        return two;
    };
    let ((site, d1), (second, _)) = two;
    if let Some(owner) = map.absorbed_into(p) {
        return ((owner, cost(owner)), (NONE, f64::INFINITY));
    }
    if second != NONE && !map.near(p, second) {
        return ((site, d1), (NONE, f64::INFINITY));
    }
    two
}

/// The nearest of `(site, distance)` pairs, the first of equals ([`nearest_two`]'s nearest);
/// `NONE` if there are none.
#[inline]
fn nearest(sites: impl Iterator<Item = (u32, f64)>) -> u32 {
    let mut best = (NONE, f64::INFINITY);
    for (c, d) in sites {
        if d < best.1 {
            best = (c, d);
        }
    }
    best.0
}

/// The nearest and second-nearest of `(site, distance)` pairs (`NONE` and infinity where
/// there are fewer). A site listed twice (a neighbour's opposite corner can repeat) has the
/// same distance both times: `<` keeps the first, and it never takes second place beside
/// itself.
#[inline]
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
