//! Cells with no structure of their own, for the hatchings' flat angle (paper section 6: the
//! texture follows the metric's long axis, and where the metric has no direction, Figure 6
//! fades it; with a flat angle such cells are hatched at that angle instead, `frames.rs`) and
//! the brush strokes of flat areas (`flat_strokes.rs`, by colour).
//!
//! The metric is integrated over about an ellipse (paper section 3), so a cell beside a thin
//! mast, a wire or a face's contour in a plain sky or wall takes that structure's direction
//! though nothing inside it has any: hatched along it, every such cell was a patch of lines at
//! the structure's angle in the plain's even hatching, a halo a cell wide round the mast. A
//! cell whose own pixels hardly vary ([`QUIET_STD`]) is counted as having no direction.
//! The spread is read from the photo the edge-following cells were made from (the blurred
//! photo, one pixel per domain unit), over each cell's pixels in their cell map; Rec. 601 luma
//! of the sRGB bytes, sums in `f64`.

use super::sums::pixel_sums;
use super::voronoi::VoronoiCells;

/// A cell whose pixels' luma has a standard deviation under this (levels of 255) has no
/// structure of its own. Measured with `tone.py` on 22 held-out pictures (seed 7), pen-hatch
/// without / with it at 2, 3 and 5 levels (such cells then taken as round cells of their
/// area): PSNR 35.13 / 35.79 / 36.41 / 37.15 dB, edge recall 0.883 / 0.899 / 0.919 / 0.935. At
/// 5 a face's smooth cheeks lose the lines that follow their form (looked at); at 3 they keep
/// them, and the halos round masts, wires and contours are gone. At 3, with their own axes
/// kept: pen-hatch 36.39 dB, SSIM 0.9574 → 0.9697, recall 0.921; crosshatch 36.10 → 36.73 dB,
/// SSIM 0.9633 → 0.9690, recall 0.909 → 0.927; no picture loses 0.2 dB or 0.005 of SSIM.
pub const QUIET_STD: f64 = 3.0;

/// Per cell of `cells`, whether it has no structure of its own ([`QUIET_STD`]); `None`
/// without the colour term's cell map (the paper's cells, or a picture the map was not made
/// for).
#[must_use]
pub(super) fn quiet_cells(cells: &VoronoiCells) -> Option<Vec<bool>> {
    let sums = cell_sums(cells, |[r, g, b]| {
        let luma = 0.299 * r + 0.587 * g + 0.114 * b;
        [1.0, luma, luma * luma]
    })?;
    Some(
        sums.iter()
            .map(|&[n, sum, squares]| measurable(n) && spread(n, sum, squares) < QUIET_STD)
            .collect(),
    )
}

/// [`quiet_cells`] by colour: whether no channel of the cell's pixels has a standard
/// deviation of [`QUIET_STD`] or more. A texture only the hue shows (two colours of one
/// lightness) is structure the luma does not see.
#[must_use]
pub(super) fn quiet_colour_cells(cells: &VoronoiCells) -> Option<Vec<bool>> {
    let sums = cell_sums(cells, |[r, g, b]| [1.0, r, g, b, r * r, g * g, b * b])?;
    Some(
        sums.iter()
            .map(|s| measurable(s[0]) && (1..4).all(|k| spread(s[0], s[k], s[k + 3]) < QUIET_STD))
            .collect(),
    )
}

/// Whether a cell of `n` pixels has enough of them to measure a spread.
fn measurable(n: f64) -> bool {
    n >= 2.0
}

/// The standard deviation of `n` values from their sum and their squares' sum (0 where
/// rounding makes the variance negative).
fn spread(n: f64, sum: f64, squares: f64) -> f64 {
    let mean = sum / n;
    (squares / n - mean * mean).max(0.0).sqrt()
}

/// Per cell, the sums of `value` of the sRGB levels of every pixel of the blurred photo the
/// colour term's cell map assigns it; `None` without that map at the photo's size.
fn cell_sums<const N: usize>(
    cells: &VoronoiCells,
    value: impl Fn([f64; 3]) -> [f64; N] + Sync,
) -> Option<Vec<[f64; N]>> {
    let term = cells.colour()?;
    let map = term.map.as_ref()?;
    let photo = term.photo();
    let (width, height) = map.size();
    if (photo.width() as usize, photo.height() as usize) != (width, height) {
        return None;
    }
    let raw = photo.as_raw();
    Some(pixel_sums(cells, width, height, 1, |x, y| {
        let i = 3 * (y * width + x);
        value([raw[i], raw[i + 1], raw[i + 2]].map(f64::from))
    }))
}
