//! Step 1 of the line drawings (outlines and highlights): the difference of Gaussians across
//! the edges (Kang, Lee and Chui, *Coherent Line Drawing*, 2007), σ_c and σ_s = 1.6 σ_c, read
//! along the normals of the structure tensor's grid at every node. It marks the dark side of an
//! edge below what a flat area gives and the light side above. `f32`.

use super::node_grid::{bilinear, bilinear_inside, per_node};

/// σ_s / σ_c of the difference of Gaussians (Kang et al. after Marr–Hildreth).
const SURROUND: f32 = 1.6;
/// Weight ρ of the surround: just under 1, so flat areas give a small positive response.
pub(crate) const RHO: f32 = 0.99;

/// The outlines' difference of Gaussians `G_σc − ρ·G_σs` ([`RHO`]).
pub(crate) fn dog_kernel(sigma_c: f32) -> Vec<f32> {
    difference_of_gaussians(sigma_c, RHO)
}

/// The difference of Gaussians `G_σc − rho·G_σs` sampled at whole steps over ±3σ_s, each
/// Gaussian normalised to sum 1.
pub(crate) fn difference_of_gaussians(sigma_c: f32, rho: f32) -> Vec<f32> {
    let sigma_s = SURROUND * sigma_c;
    let reach = (3.0 * sigma_s).ceil() as i32;
    let gauss = |sigma: f32| -> Vec<f32> {
        let g: Vec<f32> = (-reach..=reach)
            .map(|t| (-(t * t) as f32 / (2.0 * sigma * sigma)).exp())
            .collect();
        let total: f32 = g.iter().sum();
        g.into_iter().map(|v| v / total).collect()
    };
    let (c, s) = (gauss(sigma_c), gauss(sigma_s));
    c.iter().zip(&s).map(|(c, s)| c - rho * s).collect()
}

/// `values` (the lightness, or a chroma channel) filtered by the kernel
/// `across` (a difference of Gaussians, [`difference_of_gaussians`]) across the edge at every
/// node, along `normals`.
pub(crate) fn across_edges(
    values: &[f32],
    normals: &[[f32; 2]],
    (cols, rows): (usize, usize),
    across: &[f32],
) -> Vec<f32> {
    let reach = (across.len() / 2) as f32;
    per_node(cols, rows, |c, r| {
        let (x, y) = (c as f32, r as f32);
        let [nx, ny] = normals[r * cols + c];
        let tap = |i: usize| {
            let t = i as f32 - reach;
            (x + t * nx, y + t * ny)
        };
        // Rounded products and sums are monotone in t, so when both ends of the
        // segment lie on the grid every tap does, and the clamps can be skipped.
        let inside = |(x, y): (f32, f32)| {
            (0.0..=(cols - 1) as f32).contains(&x) && (0.0..=(rows - 1) as f32).contains(&y)
        };
        if inside(tap(0)) && inside(tap(across.len() - 1)) {
            weighted_taps(across, tap, |x, y| {
                bilinear_inside(values, cols, rows, x, y)
            })
        } else {
            weighted_taps(across, tap, |x, y| bilinear(values, cols, rows, x, y))
        }
    })
}

/// `Σ w_i · read(tap(i))` over the kernel `weights`: one loop for both ways of reading the
/// grid (generic, so each is inlined).
#[inline(always)]
fn weighted_taps(
    weights: &[f32],
    tap: impl Fn(usize) -> (f32, f32),
    read: impl Fn(f32, f32) -> f32,
) -> f32 {
    weights
        .iter()
        .enumerate()
        .map(|(i, w)| {
            let (x, y) = tap(i);
            w * read(x, y)
        })
        .sum()
}
