//! Colour in the line drawings' edge responses: an edge between two colours of about the same
//! lightness (a red apple on green leaves) gives the lightness' difference of Gaussians
//! ([`super::outline`]) almost nothing, so neither the outlines nor the highlights draw it,
//! though the eye sees it at once. Here the chroma's own difference across the edge (Grundland
//! and Dodgson's opponent channels `P`, `Q`, see [`super::node_grid::colour_grid`]) stands in
//! for the lightness' where it is the larger: `|y| → max(|y|, c)`, `y` the lightness' response
//! above a flat area's and `c` the chroma's, on the side the lightness says is dark or light.
//! Where the lightness hardly differs, the chroma decides the side (yellow reads lighter than
//! blue, as in *Decolorize*), so a line does not hop from side to side along an edge. A grey
//! photo is unchanged. (Adding the two as a vector, `√(y² + c²)`, would also thicken the
//! lines of edges the lightness already draws: a white rim on green and orange would become a
//! heavy black ring.) `f32`.

use super::edge_dog::{across_edges, difference_of_gaussians, RHO};
use rayon::prelude::*;

/// How much a chroma difference counts against the same difference of lightness. `P` and
/// `Q` span twice the lightness' range; at 0.5 a saturated red against a grey of its luma reads
/// as a lightness step of 0.56. Since the chroma only stands in where it is the larger, edges
/// the lightness draws are drawn as they would be without it.
const CHROMA_WEIGHT: f32 = 0.5;

/// Where the lightness' response is under this share of the chroma's, the chroma's
/// yellow–blue response decides the side.
const SIDE_FROM_CHROMA: f32 = 0.25;

/// Lets the chroma `chroma` = [`P`, `Q`] stand in for the lightness `light` in the responses
/// `dog` (the difference of Gaussians of [`super::outline::dog_kernel`] across `normals`,
/// σ_c = `sigma_c` nodes) where its own difference across the same normals is the larger (see
/// the module's doc).
pub(crate) fn with_chroma_mut(
    dog: &mut [f32],
    light: &[f32],
    chroma: &[Vec<f32>; 2],
    normals: &[[f32; 2]],
    dims: (usize, usize),
    sigma_c: f32,
) {
    // A plain difference (ρ = 1): a flat colour gives 0, whatever its chroma.
    let kernel = difference_of_gaussians(sigma_c, 1.0);
    if chroma.iter().all(|c| c.iter().all(|&v| v == 0.0)) {
        return;
    }
    let yellow = across_edges(&chroma[0], normals, dims, &kernel);
    let red = across_edges(&chroma[1], normals, dims, &kernel);
    dog.par_iter_mut()
        .zip(light.par_iter())
        .zip(yellow.par_iter().zip(red.par_iter()))
        .for_each(|((d, &l), (&p, &q))| {
            let c = CHROMA_WEIGHT * p.hypot(q);
            let flat = (1.0 - RHO) * l;
            let y = *d - flat;
            if c > y.abs() {
                let side = if y.abs() >= SIDE_FROM_CHROMA * c {
                    y
                } else {
                    p
                };
                *d = flat + if side >= 0.0 { c } else { -c };
            }
        });
}
