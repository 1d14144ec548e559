//! Flat areas are hatched evenly (issue 13, item 2): where the field has no direction (a flat
//! grey photo, a constant isotropic field) pen-hatch and cross-hatch lay lines at the preset's
//! `flat_angle` (−45°: rising to the right on screen) that run on from cell to cell, with the
//! tone the picture asks for, instead of fading every cell to one flat grey.

use anisopaint::input::{photo_field, Input};
use anisopaint::paint::{paint, paint_loaded, Extras, Recipe};
use anisopaint::progress::Silent;
use image::{DynamicImage, RgbImage};

/// Luma (0–255) of pixel `(x, y)`.
fn luma(img: &RgbImage, x: u32, y: u32) -> f64 {
    let p = img.get_pixel(x, y).0;
    0.299 * f64::from(p[0]) + 0.587 * f64::from(p[1]) + 0.114 * f64::from(p[2])
}

/// Mean absolute luma difference between each pixel and its neighbour one step along
/// `(dx, dy)`, away from the picture's border.
fn difference(img: &RgbImage, dx: i64, dy: i64) -> f64 {
    let (w, h) = (i64::from(img.width()), i64::from(img.height()));
    let (mut sum, mut n) = (0.0, 0.0);
    for y in 8..h - 8 {
        for x in 8..w - 8 {
            sum +=
                (luma(img, x as u32, y as u32) - luma(img, (x + dx) as u32, (y + dy) as u32)).abs();
            n += 1.0;
        }
    }
    sum / n
}

/// Lines at −45°: the picture barely changes one step up and to the right, and changes a lot
/// one step down and to the right (across the lines), and it is not one flat grey.
fn assert_hatched_at_minus_45(img: &RgbImage, what: &str) {
    let (along, across) = (difference(img, 1, -1), difference(img, 1, 1));
    assert!(across > 20.0, "{what}: hardly any lines ({across:.1})");
    assert!(
        along < 0.3 * across,
        "{what}: not lines at −45°: {along:.1} along, {across:.1} across"
    );
}

#[test]
fn a_flat_grey_photo_is_hatched_evenly_in_its_tone() {
    let grey = 170u8;
    let photo = RgbImage::from_pixel(200, 150, image::Rgb([grey; 3]));
    for style in ["pen-hatch", "crosshatch"] {
        let mut preset = anisopaint::style::load(style).unwrap();
        anisopaint::style::apply_sets(&mut preset, &["look.outlines=0".into()]).unwrap();
        let recipe = Recipe::from_preset(&preset, Default::default(), Some(5)).unwrap();
        let loaded = photo_field(DynamicImage::ImageRgb8(photo.clone()), &recipe.field.metric);
        let img = paint_loaded(&loaded, &recipe, Extras::default(), &Silent)
            .unwrap()
            .image;
        if style == "pen-hatch" {
            assert_hatched_at_minus_45(&img, style);
        }
        // The tone the preset asks for: lightness 1 − (1 − L)^gamma, ±0.05.
        let gamma = f64::from(preset.file.look.gamma.unwrap_or(1.0));
        let want = 1.0 - (1.0 - f64::from(grey) / 255.0).powf(gamma);
        let (w, h) = img.dimensions();
        let mean = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| luma(&img, x, y))
            .sum::<f64>()
            / f64::from(w * h)
            / 255.0;
        assert!(
            (mean - want).abs() < 0.05,
            "{style}: {mean:.3} for {want:.3}"
        );
    }
}

#[test]
fn a_constant_isotropic_field_is_hatched_not_grey() {
    let preset = anisopaint::style::load("pen-hatch").unwrap();
    let recipe = Recipe::from_preset(&preset, Default::default(), Some(5)).unwrap();
    let input = Input::parse("analytic:constant").unwrap();
    let img = paint(&input, &recipe).unwrap();
    assert_hatched_at_minus_45(&img, "analytic:constant");
}
