//! Cells with no structure of their own, for the hatchings' flat angle (paper section 6: the
//! texture follows the metric's long axis, and where the metric has no direction, Figure 6
//! fades it; with a flat angle such cells are hatched at that angle instead, `frames.rs`).
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
    let term = cells.colour()?;
    let map = term.map.as_ref()?;
    let photo = term.photo();
    let (width, height) = map.size();
    if (photo.width() as usize, photo.height() as usize) != (width, height) {
        return None;
    }
    let raw = photo.as_raw();
    let sums = pixel_sums(cells, width, height, 1, |x, y| {
        let i = 3 * (y * width + x);
        let luma = 0.299 * f64::from(raw[i])
            + 0.587 * f64::from(raw[i + 1])
            + 0.114 * f64::from(raw[i + 2]);
        [1.0, luma, luma * luma]
    });
    Some(
        sums.iter()
            .map(|&[n, sum, squares]| {
                if n < 2.0 {
                    return false;
                }
                let mean = sum / n;
                squares / n - mean * mean < QUIET_STD * QUIET_STD
            })
            .collect(),
    )
}
