//! Outlines: a line drawing along the photo's edges, laid over any look, as pen and ink has
//! it. The lines come from a flow-based difference of Gaussians (Kang, Lee and Chui, *Coherent
//! Line Drawing*, 2007): across the edge, a difference of Gaussians of the lightness (σ_c and
//! σ_s = 1.6 σ_c) marks the dark side of every edge; along the edge, that response is
//! averaged over a Gaussian of σ_m following the tangent field, so lines run long and coherent
//! where the photo's edges do, and noise that follows no edge fades. The tangent field is the
//! photo's own structure tensor (the one its metric came from, paper section 3): its minor
//! eigenvector runs along edges. Drawn in the photo's own colour ([`OutlineInk::Pixel`]), the
//! lines are found on the light side of edges as well, by the same walk on the response above
//! what a flat area gives: a thin light line is drawn back like a dark one. Where two colours
//! of about one lightness meet, the chroma's difference across the edge stands in for the
//! lightness' (`chroma_edges.rs`).
//!
//! Everything runs on the structure tensor's grid, the analysis resolution (diagonal at most
//! 1536 px), so lines keep their width relative to the picture at any photo size; the line
//! map is then read bilinearly at every output pixel. Lightness and responses are `f32`.

use super::chroma_edges::with_chroma_mut;
use super::edge_dog::{across_edges, dog_kernel, RHO};
use super::node_grid::{
    bilinear_inside, blend, clamped_axis, colour_grid, major_axis, per_node, AxisWeights,
};
use super::outline_ink::{DarkerInk, OutlineInk, PhotoInk};
use super::outline_rigger::sparse_lines_whole_mut;
use crate::field::blur::round_to_byte;
use crate::field::TensorField;
use image::{DynamicImage, RgbImage};
use rayon::prelude::*;

/// How outlines are drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutlineParams {
    /// Ink of the lines, 0 (no outlines) to 1 (full ink on the strongest edges).
    pub strength: f32,
    /// Width of the lines relative to the default (σ_c of one analysis pixel).
    pub scale: f32,
    /// What the lines are drawn in: one ink, or the photo's colour under them.
    pub ink: OutlineInk,
    /// Paper laid along the photo's thin light lines
    /// ([`highlight_map`](super::highlights::highlight_map)), 0 (none) to 1, by
    /// the looks that lay one ink over paper.
    pub highlights: f32,
}

impl Default for OutlineParams {
    fn default() -> Self {
        OutlineParams {
            strength: 0.0,
            scale: 1.0,
            ink: OutlineInk::Colour([24, 20, 18]),
            highlights: 0.0,
        }
    }
}

/// σ_m / σ_c of the averaging along the edge.
const ALONG: f32 = 3.0;
/// Sharpness φ of the soft threshold `−tanh(φ·H)`, for lightness in [0, 1].
pub(crate) const SHARPNESS: f32 = 30.0;
/// Responses weaker than this (lightness units) draw nothing: the grain of fur or grass.
pub(crate) const FLOOR: f32 = 0.006;

/// What the outlines and the highlights ([`super::highlights`]) both read on the structure
/// tensor's grid, found once: the photo's lightness, the edges' normals (the tensor's major
/// eigenvectors) and step 1, the difference of Gaussians across the edges.
pub struct EdgeResponses {
    pub(crate) light: Vec<f32>,
    pub(crate) normals: Vec<[f32; 2]>,
    pub(crate) dog: Vec<f32>,
    pub(crate) cols: usize,
    pub(crate) rows: usize,
    /// σ_c in nodes.
    pub(crate) sigma_c: f32,
}

impl EdgeResponses {
    /// The responses of `photo` on `tensor`'s grid at the lines' width `params.scale`.
    #[must_use]
    pub fn new(photo: &DynamicImage, tensor: &TensorField, params: &OutlineParams) -> Self {
        let (cols, rows) = (tensor.cols(), tensor.rows());
        let (light, chroma) = colour_grid(photo, tensor);
        let normals = per_node(cols, rows, |c, r| major_axis(&tensor.node(c, r)));
        let sigma_c = params.scale.max(0.1);
        let mut dog = across_edges(&light, &normals, (cols, rows), &dog_kernel(sigma_c));
        with_chroma_mut(&mut dog, &light, &chroma, &normals, (cols, rows), sigma_c);
        EdgeResponses {
            light,
            normals,
            dog,
            cols,
            rows,
            sigma_c,
        }
    }
}

/// The line map on `tensor`'s grid: ink in [0, 1] per node, 1 on the dark side of strong
/// edges, 0 elsewhere; drawn in the photo's own colour ([`OutlineInk::Pixel`]), on the light
/// side of strong edges too, and sparse lines whole as a rigger lays them
/// ([`outline_rigger`](super::outline_rigger)).
#[must_use]
pub fn line_map(photo: &DynamicImage, tensor: &TensorField, params: &OutlineParams) -> Vec<f32> {
    lines_of(&EdgeResponses::new(photo, tensor, params), params.ink)
}

/// [`line_map`] from responses already found, for lines in `ink`.
#[must_use]
pub fn lines_of(responses: &EdgeResponses, ink: OutlineInk) -> Vec<f32> {
    let (light, normals) = (&responses.light, &responses.normals);
    let (cols, rows, sigma_c) = (responses.cols, responses.rows, responses.sigma_c);
    // In the photo's own colour, the light side too: a thin light line (a whisker, a wire
    // against a dark wall, a highlight on hair) that the broad strokes paint over comes back.
    // Its response is the difference of Gaussians above what a flat area of that lightness
    // gives, `(1 − ρ)·L`, negated so that the same walk and threshold find it; each node keeps
    // the stronger of its two sides before the walk (along an edge the side does not change,
    // so this is about the stronger of two walks, at the cost of one).
    let walked = if ink == OutlineInk::Pixel {
        let mut dog = responses.dog.clone();
        for (d, &l) in dog.iter_mut().zip(light) {
            *d = d.min((1.0 - RHO) * l - *d);
        }
        std::borrow::Cow::Owned(dog)
    } else {
        std::borrow::Cow::Borrowed(&responses.dog)
    };
    // Step 2: averaged along the flow, both ways from every node.
    let mut lines = along_flow(&walked, normals, cols, rows, sigma_c, true);
    if ink == OutlineInk::Pixel {
        sparse_lines_whole_mut(&mut lines, (cols, rows), sigma_c);
    }
    lines
}

/// Ink per node from the responses `dog` averaged along the flow of `normals` (a Gaussian of
/// σ_m = [`ALONG`]·`sigma_c`, both ways from every node), through the soft threshold. With
/// `skip_quiet`, nodes whose walk can only read responses of at least `−FLOOR` are not walked
/// ([`QuietTiles`]): the same result.
fn along_flow(
    dog: &[f32],
    normals: &[[f32; 2]],
    cols: usize,
    rows: usize,
    sigma_c: f32,
    skip_quiet: bool,
) -> Vec<f32> {
    let sigma_m = ALONG * sigma_c;
    let steps = (2.0 * sigma_m).ceil() as usize;
    let weights: Vec<f32> = (0..=steps)
        .map(|s| (-(s as f32).powi(2) / (2.0 * sigma_m * sigma_m)).exp())
        .collect();
    // A walk of `steps` unit steps reads nodes up to `steps + 1` away (a bilinear read takes
    // the next node on); one more for the rounding of the steps' length.
    let quiet = skip_quiet.then(|| QuietTiles::new(dog, cols, rows, steps + 2));
    per_node(cols, rows, |c, r| {
        if quiet.as_ref().is_some_and(|q| q.is_quiet(c, r)) {
            return 0.0;
        }
        let k = r * cols + c;
        let start = (c as f32, r as f32);
        let mut sum = weights[0] * dog[k];
        let mut total = weights[0];
        for direction in [1.0f32, -1.0] {
            let (mut x, mut y) = start;
            let [nx, ny] = normals[k];
            let mut tangent = [-ny * direction, nx * direction];
            for w in &weights[1..] {
                x += tangent[0];
                y += tangent[1];
                if x < 0.0 || y < 0.0 || x > (cols - 1) as f32 || y > (rows - 1) as f32 {
                    break;
                }
                sum += w * bilinear_inside(dog, cols, rows, x, y);
                total += w;
                // Follow the tangent there, keeping the direction of travel.
                // The nearest node (x, y ≥ 0 here: `+ 0.5` and truncation round, and
                // need no libm call; through `u32` as in `bilinear_inside`).
                let node = ((y + 0.5) as u32 as usize) * cols + (x + 0.5) as u32 as usize;
                let [mx, my] = normals[node];
                let next = [-my, mx];
                tangent = if next[0] * tangent[0] + next[1] * tangent[1] < 0.0 {
                    [-next[0], -next[1]]
                } else {
                    next
                };
            }
        }
        let h = sum / total;
        if h < -FLOOR {
            (-(SHARPNESS * (h + FLOOR)).tanh()).min(1.0)
        } else {
            0.0
        }
    })
}

/// Where the flow walk cannot ink: tiles of the grid whose surroundings hold no response
/// below the threshold. The walk from a node averages the responses it reads within `reach`
/// nodes of it (bilinear reads of nodes one step on), with positive weights, so where every
/// response it can read is at least `−FLOOR` (with a margin far above rounding), its average
/// is too and the node draws nothing: the walk is skipped, with the same result. On photos,
/// most nodes are far from an edge's dark side.
struct QuietTiles {
    /// Per tile, whether the lowest response over the tiles within `reach` nodes of it is
    /// at least `QUIET_ABOVE`.
    quiet: Vec<bool>,
    tiles_per_row: usize,
    side: usize,
}

/// Side of the quiet tiles in nodes: small tiles follow the responses closely (4 against
/// 8 skipped about a tenth more of the walks on photos), while the tiles' lows stay cheap to
/// compare.
const QUIET_TILE: usize = 4;

/// Responses at least this high cannot average to ink: `−FLOOR` with a margin of 10⁻⁵. A
/// response is a difference of Gaussians of lightness in [0, 1], under 1 in size, so the
/// `f32` average of the few dozen a walk reads rounds by about 10⁻⁶ at most: the margin is ten
/// times that.
const QUIET_ABOVE: f32 = -FLOOR + 1e-5;

impl QuietTiles {
    /// Tiles of [`QUIET_TILE`] nodes a side over the `cols × rows` responses `dog`, for walks
    /// that read nodes up to `reach` away: a tile is quiet when the tiles within `reach`
    /// nodes of it (`⌈reach / side⌉` tiles each way) hold no response under `QUIET_ABOVE`.
    fn new(dog: &[f32], cols: usize, rows: usize, reach: usize) -> Self {
        let side = QUIET_TILE;
        let span = reach.div_ceil(side);
        let (tx, ty) = (cols.div_ceil(side), rows.div_ceil(side));
        // The lowest response per tile, tile rows in parallel.
        let mut low = vec![f32::INFINITY; tx * ty];
        low.par_chunks_mut(tx).enumerate().for_each(|(j, tiles)| {
            for r in j * side..((j + 1) * side).min(rows) {
                for (i, t) in tiles.iter_mut().enumerate() {
                    let row = &dog[r * cols + i * side..r * cols + ((i + 1) * side).min(cols)];
                    *t = row.iter().fold(*t, |m, &v| m.min(v));
                }
            }
        });
        let quiet = per_node(tx, ty, |i, j| {
            (j.saturating_sub(span)..(j + span + 1).min(ty)).all(|n| {
                (i.saturating_sub(span)..(i + span + 1).min(tx))
                    .all(|m| low[n * tx + m] >= QUIET_ABOVE)
            })
        });
        QuietTiles {
            quiet,
            tiles_per_row: tx,
            side,
        }
    }

    /// Whether node (`c`, `r`)'s walk cannot ink.
    #[inline]
    fn is_quiet(&self, c: usize, r: usize) -> bool {
        self.quiet[(r / self.side) * self.tiles_per_row + c / self.side]
    }
}

/// Lays the outlines of `photo` over `image`, the painting at any size of `domain` (the
/// photo's size in domain units), in `params.ink` ([`OutlineInk`]): `lines`, their
/// [`line_map`] on `tensor`'s grid. One ink is no lighter than the photo under it: where the
/// photo is darker than the ink, the ink there is darkened to the photo's lightness (a black
/// silhouette on white kept a brown-black rim of the outlines' ink round it, where the looks
/// lay black).
pub fn draw_outlines(
    image: &mut RgbImage,
    photo: &DynamicImage,
    lines: (&TensorField, &[f32]),
    domain: glam::DVec2,
    params: &OutlineParams,
) {
    draw_lines(image, photo, lines, domain, params, true);
}

/// Lays the highlights' paper (`map`, [`super::highlights::highlight_map`] on `tensor`'s
/// grid) over `image` as [`draw_outlines`] lays lines, in `params.ink` as it is.
pub fn draw_highlights(
    image: &mut RgbImage,
    photo: &DynamicImage,
    map: (&TensorField, &[f32]),
    domain: glam::DVec2,
    params: &OutlineParams,
) {
    draw_lines(image, photo, map, domain, params, false);
}

/// [`draw_outlines`], with one ink darkened where the photo is darker (`no_lighter`) or not.
fn draw_lines(
    image: &mut RgbImage,
    photo: &DynamicImage,
    (tensor, lines): (&TensorField, &[f32]),
    domain: glam::DVec2,
    params: &OutlineParams,
    no_lighter: bool,
) {
    if params.strength <= 0.0 {
        return;
    }
    let (w, h) = (image.width() as usize, image.height() as usize);
    let map = PictureGrid::new(tensor, domain, (w, h));
    let photo_ink =
        (params.ink == OutlineInk::Pixel || no_lighter).then(|| PhotoInk::new(photo, (w, h)));
    let one_ink = match params.ink {
        OutlineInk::Colour(c) => c.map(f32::from),
        OutlineInk::Pixel => [0.0; 3],
    };
    let darker = match params.ink {
        OutlineInk::Colour(c) if no_lighter => Some(DarkerInk::new(c)),
        _ => None,
    };
    image
        .as_mut()
        .par_chunks_mut(3 * w)
        .enumerate()
        .for_each(|(y, row)| {
            let across = map.row(y);
            for (x, px) in row.chunks_exact_mut(3).enumerate() {
                let a = params.strength * map.value(lines, &across, x);
                if a > 0.0 {
                    let under = photo_ink.as_ref().map(|p| p.at(x, y));
                    let ink = match (params.ink, under) {
                        (OutlineInk::Pixel, Some(photo)) => photo,
                        (_, Some(photo)) => darker
                            .as_ref()
                            .and_then(|d| d.under(photo))
                            .unwrap_or(one_ink),
                        _ => one_ink,
                    };
                    for k in 0..3 {
                        let v = f32::from(px[k]);
                        px[k] = round_to_byte(v + (ink[k] - v) * a);
                    }
                }
            }
        });
}

/// Where the outlines of [`draw_outlines`] ink at least half a `width × height` picture's
/// pixel: 1 there, 0 elsewhere (row-major), for their vector form; `lines`, their
/// [`line_map`] on `tensor`'s grid.
#[must_use]
pub fn outline_mask(
    (tensor, lines): (&TensorField, &[f32]),
    domain: glam::DVec2,
    (w, h): (usize, usize),
    params: &OutlineParams,
) -> Vec<i32> {
    if params.strength <= 0.0 {
        return vec![0; w * h];
    }
    picture_values((tensor, lines), domain, (w, h))
        .iter()
        .map(|&v| i32::from(v >= 0.5))
        .collect()
}

/// `values` (a map on `tensor`'s grid: the outlines' [`line_map`] or the highlights') read at
/// every pixel of a `width × height` picture (row-major), as [`draw_outlines`] reads them.
#[must_use]
pub fn picture_values(
    (tensor, values): (&TensorField, &[f32]),
    domain: glam::DVec2,
    (w, h): (usize, usize),
) -> Vec<f32> {
    let map = PictureGrid::new(tensor, domain, (w, h));
    let mut out = vec![0.0; w * h];
    out.par_chunks_mut(w.max(1))
        .enumerate()
        .for_each(|(y, row)| {
            let across = map.row(y);
            for (x, v) in row.iter_mut().enumerate() {
                *v = map.value(values, &across, x);
            }
        });
    out
}

/// Where every pixel of a `width × height` picture reads the line map: per column the two
/// grid columns and the weight between them, per row the two grid rows and theirs, computed
/// once (each pixel's position took a division and the clamps of `node_grid::bilinear`, and a
/// 12 MP picture has 12 M of them). A value is `bilinear`'s at the pixel's centre, bit for bit.
struct PictureGrid {
    cols: usize,
    rows: usize,
    /// Per picture column: grid column, the next one (clamped) and the weight of the next.
    columns: Vec<(usize, usize, f32)>,
    /// Domain units per picture row, and per grid node.
    step_y: f64,
    spacing: f64,
}

impl PictureGrid {
    fn new(tensor: &TensorField, domain: glam::DVec2, (w, h): (usize, usize)) -> Self {
        let (cols, rows) = (tensor.cols(), tensor.rows());
        let spacing = tensor.spacing();
        let step_x = domain.x / w as f64;
        let columns = (0..w)
            .map(|x| clamped_axis((((x as f64 + 0.5) * step_x) / spacing - 0.5) as f32, cols))
            .collect();
        PictureGrid {
            cols,
            rows,
            columns,
            step_y: domain.y / h as f64,
            spacing,
        }
    }

    /// Picture row `y`'s two grid rows and the weight of the second.
    fn row(&self, y: usize) -> AxisWeights {
        let gy = (((y as f64 + 0.5) * self.step_y) / self.spacing - 0.5) as f32;
        clamped_axis(gy, self.rows)
    }

    /// The line map `values` at pixel (`x`, the row `across` was made for).
    #[inline]
    fn value(&self, values: &[f32], across: &AxisWeights, x: usize) -> f32 {
        blend(values, self.cols, self.columns[x], *across)
    }
}

#[cfg(test)]
mod tests {
    use super::super::node_grid::bilinear;
    use super::*;

    #[test]
    fn skipping_quiet_tiles_changes_no_node() {
        // Responses like a photo's: mostly small and positive, the dark side of a curved
        // edge, and a grain of values just under and over the threshold; normals that turn.
        let (cols, rows) = (150usize, 110usize);
        let mut dog = vec![0.002f32; cols * rows];
        let mut normals = vec![[1.0f32, 0.0]; cols * rows];
        for r in 0..rows {
            for c in 0..cols {
                let (x, y) = (c as f32, r as f32);
                let k = r * cols + c;
                let angle = 0.03 * x + 0.05 * y;
                normals[k] = [angle.cos(), angle.sin()];
                let ring = ((x - 40.0).hypot(y - 50.0) - 25.0).abs();
                // A thin, strong line: walks that cross it from several nodes away ink.
                if ring < 0.7 {
                    dog[k] = -1.0;
                } else if (c * 7 + r * 13) % 97 == 0 {
                    dog[k] = if c % 2 == 0 {
                        -FLOOR - 0.004
                    } else {
                        -FLOOR + 0.0005
                    };
                }
            }
        }
        for sigma_c in [0.5f32, 1.0, 2.0] {
            let all = along_flow(&dog, &normals, cols, rows, sigma_c, false);
            let skipped = along_flow(&dog, &normals, cols, rows, sigma_c, true);
            let inked = all.iter().filter(|&&v| v > 0.0).count();
            assert!(
                inked > 500 && inked < cols * rows / 2,
                "{inked} inked nodes"
            );
            for (k, (a, b)) in all.iter().zip(&skipped).enumerate() {
                assert_eq!(a.to_bits(), b.to_bits(), "node {k}, sigma_c {sigma_c}");
            }
        }
    }

    #[test]
    fn major_axis_matches_the_eigen_angle() {
        use crate::field::Tensor;
        let mut worst = 0.0f32;
        let mut check = |t: Tensor| {
            let a = t.eigen().angle;
            let want = [a.cos() as f32, a.sin() as f32];
            let got = major_axis(&t);
            for k in 0..2 {
                worst = worst.max((got[k] - want[k]).abs());
            }
            assert_eq!(
                got[1].is_sign_negative(),
                want[1].is_sign_negative(),
                "{t:?}"
            );
        };
        for i in 0..2000 {
            let angle = f64::from(i) * 0.0031 - 3.2;
            for (l1, l2) in [(1.0, 0.0), (5.0, 4.999), (1e-6, 1e-7), (3.0, -2.0)] {
                check(Tensor::from_eigen(angle, l1, l2));
            }
        }
        // Axis-aligned and degenerate tensors, signed zeros included.
        for (xx, xy, yy) in [
            (1.0, 0.0, 2.0),
            (1.0, -0.0, 2.0),
            (2.0, 0.0, 1.0),
            (2.0, -0.0, 1.0),
            (1.0, 0.0, 1.0),
            (0.0, 0.0, 0.0),
            (1.0, 1e-300, 1.0),
        ] {
            check(Tensor::new(xx, xy, yy));
        }
        assert!(worst <= 2.0 * f32::EPSILON, "largest difference {worst}");
    }

    #[test]
    fn grid_bilinear_matches_the_generic_one_with_clamped_texels() {
        let (cols, rows) = (7usize, 5usize);
        let values: Vec<f32> = (0..cols * rows)
            .map(|k| ((k * 37 % 11) as f32 - 4.0) * 0.37)
            .collect();
        let (last_col, last_row) = (cols as i64 - 1, rows as i64 - 1);
        let generic = |x: f32, y: f32| {
            crate::render::support::bilinear::bilinear(f64::from(x), f64::from(y), |i, j| {
                [values[j.clamp(0, last_row) as usize * cols + i.clamp(0, last_col) as usize]]
            })[0]
        };
        for a in -30..=100 {
            for b in -20..=80 {
                let (x, y) = (a as f32 * 0.0731 - 0.2, b as f32 * 0.0613 - 0.1);
                let (fast, slow) = (bilinear(&values, cols, rows, x, y), generic(x, y));
                assert_eq!(
                    fast.to_bits(),
                    slow.to_bits(),
                    "({x}, {y}): {fast} vs {slow}"
                );
            }
        }
    }
}
