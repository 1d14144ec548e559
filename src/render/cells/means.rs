//! The cells' mean photo colours (paper section 6: a cell filled with the colour of the photo
//! under it), summed per cell at the photo's own resolution, and the cells' widths across
//! their narrowest direction.

use super::sums::pixel_sums;
use super::voronoi::VoronoiCells;
use crate::render::support::colour::{linear_of, rgb8, to_linear, Linear};
use image::DynamicImage;

/// Mean colour of the photo over every cell, in linear light. The photo is read at its own
/// resolution (the domain of the sites is the photo's pixel grid), summed by
/// [`pixel_sums`]. A cell that receives no pixel takes the photo's colour at its site.
#[must_use]
pub fn cell_means(cells: &VoronoiCells, photo: &DynamicImage) -> Vec<Linear> {
    let rgb = rgb8(photo);
    let sums = pixel_sums(
        cells,
        rgb.width() as usize,
        rgb.height() as usize,
        2,
        |x, y| {
            let [r, g, b] = rgb.get_pixel(x as u32, y as u32).0.map(to_linear);
            [f64::from(r), f64::from(g), f64::from(b), 1.0]
        },
    );
    means_of(&sums, cells, &rgb)
}

/// Mean colours from per-cell sums whose first four entries are the linear colour sums and
/// the pixel count; a cell without pixels takes the photo's colour at its site.
fn means_of<const N: usize>(
    sums: &[[f64; N]],
    cells: &VoronoiCells,
    rgb: &image::RgbImage,
) -> Vec<Linear> {
    let (pw, ph) = (rgb.width() as usize, rgb.height() as usize);
    sums.iter()
        .zip(cells.positions())
        .map(|(s, p)| {
            if s[3] > 0.0 {
                [s[0] / s[3], s[1] / s[3], s[2] / s[3]].map(|v| v as f32)
            } else {
                let x = (p.x as usize).min(pw - 1) as u32;
                let y = (p.y as usize).min(ph - 1) as u32;
                linear_of(rgb.get_pixel(x, y).0)
            }
        })
        .collect()
}

/// [`cell_means`], and every cell's width across its narrowest direction in domain units,
/// `√(12 λ_min)` of its pixels' position covariance (exact for a strip; a cell without pixels
/// gets 0).
#[must_use]
pub fn cell_means_and_widths(
    cells: &VoronoiCells,
    photo: &DynamicImage,
) -> (Vec<Linear>, Vec<f64>) {
    let rgb = rgb8(photo);
    let (pw, ph) = (rgb.width() as usize, rgb.height() as usize);
    let sums = pixel_sums(cells, pw, ph, 2, |x, y| {
        let [r, g, b] = rgb.get_pixel(x as u32, y as u32).0.map(to_linear);
        let (u, v) = (x as f64 + 0.5, y as f64 + 0.5);
        [
            f64::from(r),
            f64::from(g),
            f64::from(b),
            1.0,
            u,
            v,
            u * u,
            u * v,
            v * v,
        ]
    });
    let widths = sums
        .iter()
        .map(|s| {
            if s[3] <= 0.0 {
                return 0.0;
            }
            let n = s[3];
            let (mu, mv) = (s[4] / n, s[5] / n);
            let (cuu, cuv, cvv) = (s[6] / n - mu * mu, s[7] / n - mu * mv, s[8] / n - mv * mv);
            let half_trace = 0.5 * (cuu + cvv);
            let least = half_trace - (0.25 * (cuu - cvv).powi(2) + cuv * cuv).sqrt();
            (12.0 * least.max(0.0)).sqrt()
        })
        .collect();
    (means_of(&sums, cells, &rgb), widths)
}
