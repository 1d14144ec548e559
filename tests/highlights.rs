//! Highlights on pictures whose answer is known: a thin light line on a dark ground is found
//! and laid in paper by the one-ink looks (without highlights their lines cover it), while the
//! light side of a step edge and a flat picture get none, and the ground keeps its tone.

use anisopaint::input::photo_field;
use anisopaint::render::lines::highlights::highlight_map;
use anisopaint::render::lines::outline::OutlineParams;
use image::{DynamicImage, RgbImage};

mod common;

const W: u32 = 240;
const H: u32 = 160;
/// Grey of the ground and of the line.
const GROUND: f64 = 70.0;
const LINE: f64 = 215.0;
const HALF: f64 = 0.5;

/// Distance of pixel centre `(x, y)` from the line through the picture's centre at 30°.
fn from_line(x: f64, y: f64) -> f64 {
    let (s, c) = 30f64.to_radians().sin_cos();
    ((x - f64::from(W) / 2.0) * s - (y - f64::from(H) / 2.0) * c).abs()
}

/// A light line 1 px wide on a dark ground, anti-aliased over 4×4 points per pixel.
fn light_line() -> DynamicImage {
    DynamicImage::ImageRgb8(RgbImage::from_fn(W, H, |x, y| {
        let on = common::covered(x, y, |px, py| from_line(px, py) < HALF);
        let v = (GROUND + (LINE - GROUND) * on).round() as u8;
        image::Rgb([v, v, v])
    }))
}

/// The dark ground on the left half, the light grey on the right: a step edge.
fn step() -> DynamicImage {
    DynamicImage::ImageRgb8(RgbImage::from_fn(W, H, |x, _| {
        let v = if x < W / 2 { GROUND } else { LINE } as u8;
        image::Rgb([v, v, v])
    }))
}

fn map_of(photo: &DynamicImage) -> (Vec<f32>, usize) {
    let loaded = photo_field(photo.clone(), &Default::default());
    assert_eq!(loaded.raw.spacing(), 1.0, "analysed at full size");
    (
        highlight_map(photo, &loaded.raw, &OutlineParams::default()),
        loaded.raw.cols(),
    )
}

#[test]
fn a_thin_light_line_is_found_and_a_step_edge_is_not() {
    let (map, cols) = map_of(&light_line());
    // Along the line, away from the picture's border: nearly full paper on its centre.
    let mut centre = Vec::new();
    let mut far = 0.0f32;
    for (k, &v) in map.iter().enumerate() {
        let (x, y) = ((k % cols) as f64 + 0.5, (k / cols) as f64 + 0.5);
        let inside = x > 20.0 && x < f64::from(W) - 20.0 && y > 20.0 && y < f64::from(H) - 20.0;
        let d = from_line(x, y);
        if inside && d < 0.5 {
            centre.push(v);
        }
        if d > 6.0 {
            far = far.max(v);
        }
    }
    // Paper no lighter than the photo: at most the node's lightness (the line's centre nodes
    // read 0.71, the line 0.84 over pixels it crosses in part).
    let mean = centre.iter().sum::<f32>() / centre.len() as f32;
    assert!(mean > 0.6, "the line's centre reads {mean}");
    assert_eq!(far, 0.0, "paper away from the line");
    // The light side of a step edge is no light line; a flat picture has none.
    let (map, _) = map_of(&step());
    assert!(
        map.iter().all(|&v| v == 0.0),
        "step: {:?}",
        map.iter().copied().fold(0.0f32, f32::max)
    );
    let flat = DynamicImage::ImageRgb8(RgbImage::from_pixel(W, H, image::Rgb([120; 3])));
    assert!(map_of(&flat).0.iter().all(|&v| v == 0.0));
}

/// `look` painted over the light line with `highlights.strength` at `strength`.
fn paint(look: &str, strength: &str) -> RgbImage {
    common::painted_with(
        &light_line(),
        look,
        &[format!("highlights.strength={strength}")],
        1,
    )
}

/// Mean grey of the pixels whose centres lie within `(d0, d1)` of the line, away from the border.
fn band_mean(img: &RgbImage, d0: f64, d1: f64) -> f64 {
    common::mean_where(img, 1, |x, y| {
        let inside = x > 20.0 && x < f64::from(W) - 20.0 && y > 20.0 && y < f64::from(H) - 20.0;
        inside && (d0..d1).contains(&from_line(x, y))
    })
}

#[test]
fn the_ink_looks_lay_paper_along_thin_light_lines() {
    for look in ["pen-hatch", "crosshatch", "engraving"] {
        let (with, without) = (paint(look, "1"), paint(look, "0"));
        let (on_with, on_without) = (band_mean(&with, 0.0, 0.7), band_mean(&without, 0.0, 0.7));
        // The look's lines, spaced wider than the line, half hide it without highlights
        // (measured 151-169 over its centre); with them it reads 193-203, the paper laid no
        // stronger than the line's lightness, so never as light as the line itself (215).
        assert!(
            on_with > on_without + 25.0 && on_with < LINE,
            "{look}: the line reads {on_with} with highlights, {on_without} without"
        );
        // The ground keeps its tone (70) within a few levels either way.
        let ground = band_mean(&with, 12.0, 60.0);
        assert!(
            (ground - band_mean(&without, 12.0, 60.0)).abs() < 3.0,
            "{look}: ground {ground}"
        );
    }
}
