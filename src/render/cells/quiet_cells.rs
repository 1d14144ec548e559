//! Cells with no structure of their own, for the hatchings' flat angle (paper section 6: the
//! texture follows the metric's long axis, and where the metric has no direction, Figure 6
//! fades it; with a flat angle such cells are hatched at that angle instead, `frames.rs`) and
//! the brush strokes of flat areas (`flat_strokes.rs`, by colour).
//!
//! The metric is integrated over about an ellipse (paper section 3), so a cell beside a thin
//! mast, a wire or a face's contour in a plain sky or wall takes that structure's direction
//! though nothing inside it has any: hatched along it, every such cell was a patch of lines at
//! the structure's angle in the plain's even hatching, a halo a cell wide round the mast. A
//! cell whose own pixels hardly vary ([`QUIET_STD`]) about a gentle ramp ([`RAMP_STD`]: a
//! sky's gradient is no structure either) is counted as having no direction.
//! The spread is read from the photo the edge-following cells were made from (the blurred
//! photo, one pixel per domain unit), over each cell's pixels in their cell map; Rec. 601 luma
//! of the sRGB bytes (or each channel), about the least-squares plane over the cell's pixels,
//! sums in `f64`.

use super::sums::pixel_sums;
use super::voronoi::VoronoiCells;

/// A cell whose pixels' luma has a standard deviation under this (levels of 255) has no
/// structure of its own: at 3 levels the halos of lines round masts, wires and contours in a
/// plain go, while a face's smooth cheeks keep the lines that follow their form (at 5 they
/// lose them).
pub const QUIET_STD: f64 = 3.0;

/// The largest standard deviation, over a cell, of the plane that best fits its luma (or a
/// channel) for the cell still to count as quiet about a gentle ramp (levels of 255). A sky's
/// gradient over a large cell is a plane of 1.5–4 levels (a dusk sky 960 px wide, cells of
/// 25–30 px); a colour wheel's hues turn by 7 or more over its cells. Without a bound a
/// colour wheel's hues would be laid flat; at 5 levels a sky's gradient is quiet (hatched at
/// the flat angle, not in a patch of level lines along its glow) and the wheel keeps its
/// hues.
pub const RAMP_STD: f64 = 5.0;

/// Per cell of `cells`, whether it has no structure of its own: its pixels' luma departs from
/// the luma's best-fitting plane over the cell by under [`QUIET_STD`] (a standard deviation),
/// the plane itself no steeper than [`RAMP_STD`]. `None` without the colour term's cell map
/// (the paper's cells, or a picture the map was not made for).
#[must_use]
pub(crate) fn quiet_cells(cells: &VoronoiCells) -> Option<Vec<bool>> {
    let sums = cell_sums(cells, |x, y, [r, g, b]| {
        let l = 0.299 * r + 0.587 * g + 0.114 * b;
        [1.0, x, y, x * x, x * y, y * y, l, l * l, x * l, y * l]
    })?;
    Some(
        sums.iter()
            .map(|s| quiet_about_ramp(&s[..6], &[&s[6..]]))
            .collect(),
    )
}

/// [`quiet_cells`] by colour: no channel departs from its plane by [`QUIET_STD`] or more, nor
/// is any plane steeper than [`RAMP_STD`]. A texture only the hue shows (two colours of one
/// lightness) is structure the luma does not see.
#[must_use]
pub(crate) fn quiet_colour_cells(cells: &VoronoiCells) -> Option<Vec<bool>> {
    let sums = cell_sums(cells, |x, y, [r, g, b]| {
        [
            1.0,
            x,
            y,
            x * x,
            x * y,
            y * y,
            r,
            r * r,
            x * r,
            y * r,
            g,
            g * g,
            x * g,
            y * g,
            b,
            b * b,
            x * b,
            y * b,
        ]
    })?;
    Some(
        sums.iter()
            .map(|s| quiet_about_ramp(&s[..6], &[&s[6..10], &s[10..14], &s[14..]]))
            .collect(),
    )
}

/// Whether a cell is quiet about a gentle ramp in every channel: `positions` are its sums of
/// `1`, `x`, `y`, `x²`, `xy`, `y²` over its pixels, each of `channels` the sums of `v`, `v²`,
/// `xv`, `yv` of one channel.
fn quiet_about_ramp(positions: &[f64], channels: &[&[f64]]) -> bool {
    measurable(positions[0])
        && channels.iter().all(|v| {
            let (plane, residual) = ramp_spreads(positions, v);
            plane < RAMP_STD && residual < QUIET_STD
        })
}

/// The standard deviations of a channel over a cell explained by its least-squares plane and
/// left about it, from the sums of [`quiet_about_ramp`]. A cell too thin for a plane (its
/// pixels on a line) takes none.
fn ramp_spreads(positions: &[f64], v: &[f64]) -> (f64, f64) {
    let n = positions[0];
    let (mx, my) = (positions[1] / n, positions[2] / n);
    let cxx = positions[3] / n - mx * mx;
    let cxy = positions[4] / n - mx * my;
    let cyy = positions[5] / n - my * my;
    let mv = v[0] / n;
    let cvv = v[1] / n - mv * mv;
    let (cxv, cyv) = (v[2] / n - mx * mv, v[3] / n - my * mv);
    let det = cxx * cyy - cxy * cxy;
    let explained = if det > 1e-9 * (cxx + cyy).powi(2) {
        // [cxv cyv] C⁻¹ [cxv cyv]ᵀ, C the positions' covariance.
        (cyy * cxv * cxv - 2.0 * cxy * cxv * cyv + cxx * cyv * cyv) / det
    } else {
        0.0
    };
    let explained = explained.clamp(0.0, cvv.max(0.0));
    (explained.sqrt(), (cvv - explained).max(0.0).sqrt())
}

/// Whether a cell of `n` pixels has enough of them to measure a spread.
fn measurable(n: f64) -> bool {
    n >= 2.0
}

/// Per cell, the sums of `value` of every pixel of the blurred photo the colour term's cell map
/// assigns it: of its position (from the picture's centre, which keeps the sums of squares
/// small) and its sRGB levels; `None` without that map at the photo's size.
fn cell_sums<const N: usize>(
    cells: &VoronoiCells,
    value: impl Fn(f64, f64, [f64; 3]) -> [f64; N] + Sync,
) -> Option<Vec<[f64; N]>> {
    let term = cells.colour()?;
    let map = term.map.as_ref()?;
    let photo = term.photo();
    let (width, height) = map.size();
    if (photo.width() as usize, photo.height() as usize) != (width, height) {
        return None;
    }
    let raw = photo.as_raw();
    let (cx, cy) = (0.5 * width as f64, 0.5 * height as f64);
    Some(pixel_sums(cells, width, height, 1, |x, y| {
        let i = 3 * (y * width + x);
        let levels = [raw[i], raw[i + 1], raw[i + 2]].map(f64::from);
        value(x as f64 - cx, y as f64 - cy, levels)
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sums of [`quiet_about_ramp`] over the pixels of a disc of radius `r` about the
    /// origin, the channel `v(x, y)`.
    fn disc_sums(r: f64, v: impl Fn(f64, f64) -> f64) -> ([f64; 6], [f64; 4]) {
        let (mut p, mut c) = ([0.0; 6], [0.0; 4]);
        let n = r.ceil() as i32;
        for j in -n..=n {
            for i in -n..=n {
                let (x, y) = (f64::from(i), f64::from(j));
                if x * x + y * y > r * r {
                    continue;
                }
                let value = v(x, y);
                for (s, t) in p.iter_mut().zip([1.0, x, y, x * x, x * y, y * y]) {
                    *s += t;
                }
                for (s, t) in c
                    .iter_mut()
                    .zip([value, value * value, x * value, y * value])
                {
                    *s += t;
                }
            }
        }
        (p, c)
    }

    #[test]
    fn a_ramp_is_a_plane_and_grain_is_left_about_it() {
        // A sky's gradient, 1.5 levels a pixel across a cell 12 px in radius: the plane's
        // spread is 1.5·r/2 over a disc, nothing is left about it.
        let (p, c) = disc_sums(12.0, |_, y| 100.0 + 1.5 * y);
        let (plane, residual) = ramp_spreads(&p, &c);
        assert!((plane - 9.0).abs() < 0.2, "{plane}");
        assert!(residual < 1e-6, "{residual}");
        // Grain of ±4 levels in a checker of pixels on a gentle ramp: the grain is left.
        let grain = |x: f64, y: f64| {
            if (x + y).rem_euclid(2.0) == 0.0 {
                4.0
            } else {
                -4.0
            }
        };
        let (p, c) = disc_sums(12.0, |x, y| 100.0 + 0.3 * x + grain(x, y));
        let (plane, residual) = ramp_spreads(&p, &c);
        assert!((plane - 1.8).abs() < 0.1, "{plane}");
        assert!((residual - 4.0).abs() < 0.05, "{residual}");
        // Pixels on a line have no plane: their whole spread is left.
        let mut p = [0.0; 6];
        let mut c = [0.0; 4];
        for i in 0..20 {
            let (x, v) = (f64::from(i), 50.0 + 2.0 * f64::from(i));
            for (s, t) in p.iter_mut().zip([1.0, x, 0.0, x * x, 0.0, 0.0]) {
                *s += t;
            }
            for (s, t) in c.iter_mut().zip([v, v * v, x * v, 0.0]) {
                *s += t;
            }
        }
        let (plane, residual) = ramp_spreads(&p, &c);
        assert_eq!(plane, 0.0);
        assert!(
            (residual - 2.0 * (399.0f64 / 12.0).sqrt()).abs() < 1e-6,
            "{residual}"
        );
    }

    #[test]
    fn quiet_about_a_ramp_needs_a_gentle_plane_and_little_left() {
        let gentle = disc_sums(10.0, |x, y| 80.0 + 0.5 * x - 0.4 * y);
        let steep = disc_sums(10.0, |x, _| 80.0 + 1.5 * x);
        let grainy = disc_sums(10.0, |x, y| 80.0 + 8.0 * ((x * 7.0 + y * 13.0).sin()));
        assert!(quiet_about_ramp(&gentle.0, &[&gentle.1]));
        assert!(
            !quiet_about_ramp(&steep.0, &[&steep.1]),
            "a colour wheel's hues"
        );
        assert!(!quiet_about_ramp(&grainy.0, &[&grainy.1]), "grain");
        // Every channel must be quiet.
        assert!(!quiet_about_ramp(&gentle.0, &[&gentle.1, &steep.1]));
    }
}
