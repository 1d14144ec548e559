//! Highlights: paper laid along the photo's thin light lines (a whisker, a mast against the sky,
//! a star) by the looks that lay one ink over paper, which cannot draw a light line finer than
//! their spacing. They are found by the outlines' difference of Gaussians
//! ([`super::outline`], after Kang, Lee and Chui's *Coherent Line Drawing*) on the light side,
//! without the walk along the flow (which drew a star as a dash), and kept only where a node is
//! lighter than both sides across: a ridge, not the light side of a step edge. Drawn like the
//! outlines, in the look's paper; the look leaves their paper out of its tone
//! ([`super::outline_share`]). `f32`, on the structure tensor's grid.

use super::edge_dog::{dog_kernel, RHO};
use super::node_grid::{bilinear, per_node};
use super::outline::{EdgeResponses, OutlineParams, FLOOR, SHARPNESS};
use crate::field::TensorField;
use image::DynamicImage;

/// Where paper is laid along the photo's thin light lines: 0 to 1 per node of `tensor`'s grid
/// (see the module's doc). The light side's response `(1 − ρ)·L − DoG` (as for outlines in the
/// photo's colour) is scaled by how much lighter the node is than both sides across, at
/// `RIDGE_REACH`·σ_c: `min / max` of the two differences, 0 on the light side of a step
/// edge, whose far side is as light. Then the outlines' soft threshold, node by node, above the
/// photo's grain: a light speck of grain is a ridge too, and a grainy photo would be sown with
/// paper (`grain_floor`). At most the node's lightness: paper laid at `a` over the ink reads
/// about `a`, so a highlight is no lighter than the photo under it (uncapped, a dim galaxy on a
/// black sky would come out a white speck).
#[must_use]
pub fn highlight_map(
    photo: &DynamicImage,
    tensor: &TensorField,
    params: &OutlineParams,
) -> Vec<f32> {
    highlights_of(&EdgeResponses::new(photo, tensor, params))
}

/// [`highlight_map`] from responses already found.
#[must_use]
pub fn highlights_of(responses: &EdgeResponses) -> Vec<f32> {
    let (light, normals, dog) = (&responses.light, &responses.normals, &responses.dog);
    let (cols, rows, sigma_c) = (responses.cols, responses.rows, responses.sigma_c);
    let w = RIDGE_REACH * sigma_c;
    let floor = FLOOR + grain_floor(light, cols, rows, sigma_c);
    per_node(cols, rows, |c, r| {
        let k = r * cols + c;
        let h = (1.0 - RHO) * light[k] - dog[k];
        if h >= -floor {
            return 0.0;
        }
        let [nx, ny] = normals[k];
        let (x, y) = (c as f32, r as f32);
        let a = light[k] - bilinear(light, cols, rows, x + w * nx, y + w * ny);
        let b = light[k] - bilinear(light, cols, rows, x - w * nx, y - w * ny);
        let ridge = if a.max(b) > 0.0 {
            (a.min(b) / a.max(b)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let h = ridge * h;
        if h < -floor {
            (-(SHARPNESS * (h + floor)).tanh()).min(light[k])
        } else {
            0.0
        }
    })
}

/// The response the photo's grain reaches: [`GRAIN_SIGMAS`] standard deviations of the
/// difference of Gaussians of white noise as strong as the grain of `light` (its `cols × rows`
/// lightness grid). The grain is Immerkær's estimate (*Fast Noise Variance Estimation*, 1996)
/// with the median absolute response, as [`crate::field::noise`] takes it for the metric: the
/// mask `[1 −2 1; −2 4 −2; 1 −2 1]` (its squares sum to 36) cancels smooth tones and leaves
/// noise of 6 σ, whose median absolute value is 0.6745 of that; edges covering under half the
/// picture do not move a median.
fn grain_floor(light: &[f32], cols: usize, rows: usize, sigma_c: f32) -> f32 {
    if cols < 3 || rows < 3 {
        return 0.0;
    }
    let mut responses: Vec<f32> = (1..rows - 1)
        .step_by(2)
        .flat_map(|r| (1..cols - 1).step_by(2).map(move |c| (r, c)))
        .map(|(r, c)| {
            let at = |dr: usize, dc: usize| light[(r + dr - 1) * cols + c + dc - 1];
            let corners = at(0, 0) + at(0, 2) + at(2, 0) + at(2, 2);
            let sides = at(0, 1) + at(1, 0) + at(1, 2) + at(2, 1);
            (corners - 2.0 * sides + 4.0 * at(1, 1)).abs()
        })
        .collect();
    let mid = responses.len() / 2;
    let (_, median, _) = responses.select_nth_unstable_by(mid, f32::total_cmp);
    let sigma = *median / (6.0 * 0.6745);
    // White noise of σ through the kernel's taps: σ·‖k‖₂.
    let gain = dog_kernel(sigma_c)
        .iter()
        .map(|k| k * k)
        .sum::<f32>()
        .sqrt();
    GRAIN_SIGMAS * sigma * gain
}

/// How many standard deviations of the grain's response a light line must stand above.
const GRAIN_SIGMAS: f32 = 3.0;

/// How far across a light line [`highlight_map`] looks for its darker sides, in σ_c.
const RIDGE_REACH: f32 = 2.5;
