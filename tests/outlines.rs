//! Outlines (flow-based difference of Gaussians) on pictures whose answer is known: a black
//! disc on white gets a closed line along its rim and nothing inside or far outside; a flat
//! picture gets no line at all; the ink looks draw their outlines over the hatching, taking
//! the outlines' ink out of their own tone; a red disc's outline is drawn in the ink asked
//! for, or in the photo's red.

use anisopaint::input::photo_field;
use anisopaint::render::lines::outline::{draw_outlines, line_map, OutlineParams};
use anisopaint::render::lines::outline_ink::OutlineInk;
use image::{DynamicImage, RgbImage};

mod common;

const SIDE: u32 = 200;
const RADIUS: f64 = 60.0;

/// A black disc on white, anti-aliased over 4×4 points per pixel.
fn disc() -> DynamicImage {
    disc_of(0)
}

/// A disc of grey `level` on white, anti-aliased over 4×4 points per pixel.
fn disc_of(level: u8) -> DynamicImage {
    disc_in([level; 3], [255; 3])
}

/// A disc of colour `inside` on `outside`, anti-aliased over 4×4 points per pixel (in sRGB
/// values, as a photo's edge is).
fn disc_in(inside: [u8; 3], outside: [u8; 3]) -> DynamicImage {
    let c = f64::from(SIDE) / 2.0;
    DynamicImage::ImageRgb8(RgbImage::from_fn(SIDE, SIDE, |x, y| {
        let share = common::covered(x, y, |px, py| (px - c).hypot(py - c) < RADIUS);
        image::Rgb(std::array::from_fn(|k| {
            let (a, b) = (f64::from(inside[k]), f64::from(outside[k]));
            (b + (a - b) * share).round() as u8
        }))
    }))
}

fn lines_of(photo: DynamicImage) -> (Vec<f32>, usize) {
    let loaded = photo_field(photo.clone(), &Default::default());
    let params = OutlineParams {
        strength: 1.0,
        ..OutlineParams::default()
    };
    assert_eq!(
        loaded.raw.spacing(),
        1.0,
        "a small photo is analysed at full size"
    );
    (line_map(&photo, &loaded.raw, &params), loaded.raw.cols())
}

#[test]
fn a_black_disc_gets_a_closed_outline_and_nothing_else() {
    closed_outline_and_nothing_else(disc(), RADIUS - 4.0);
}

#[test]
fn a_disc_as_light_as_its_ground_gets_its_outline_from_colour() {
    // Red on green of the same luma (101.8 and 101.7 of 255): the lightness has no edge, the
    // eye sees one at once. The chroma draws it, on one side of the rim all round: outside,
    // on the green, since red is the yellower (Decolorize's yellow reads lighter than blue).
    let (red, green) = ([200, 60, 60], [40, 145, 40]);
    let luma =
        |c: [u8; 3]| 0.299 * f64::from(c[0]) + 0.587 * f64::from(c[1]) + 0.114 * f64::from(c[2]);
    assert!((luma(red) - luma(green)).abs() < 0.5);
    closed_outline_and_nothing_else(disc_in(red, green), RADIUS);
    // A grey disc as far from its ground in lightness alone as 1 / 255 draws nothing.
    let (lines, _) = lines_of(disc_in([101; 3], [102; 3]));
    assert!(lines.iter().all(|&v| v < 0.05));
}

/// The line map of `photo`, a disc of [`RADIUS`] about the centre, holds a closed line within
/// 4 px outwards of radius `from` and no ink inside or far outside.
fn closed_outline_and_nothing_else(photo: DynamicImage, from: f64) {
    let (lines, cols) = lines_of(photo);
    let at = |r: f64, a: f64| {
        let c = f64::from(SIDE) / 2.0 - 0.5;
        let (x, y) = ((c + r * a.cos()).round(), (c + r * a.sin()).round());
        lines[y as usize * cols + x as usize]
    };
    let mut weakest = f32::INFINITY;
    for k in 0..360 {
        let a = f64::from(k).to_radians();
        // The line lies on the dark side of the rim, within a few pixels of it.
        let best = (0..8)
            .map(|i| at(from + f64::from(i) * 0.5, a))
            .fold(0.0f32, f32::max);
        weakest = weakest.min(best);
        for r in [0.0, 20.0, RADIUS - 15.0, RADIUS + 12.0, RADIUS + 30.0] {
            assert!(at(r, a) < 0.05, "ink {} at r = {r}, {k}°", at(r, a));
        }
    }
    assert!(
        weakest > 0.6,
        "the outline is open: ink {weakest} somewhere on the rim"
    );
}

#[test]
fn a_flat_picture_gets_no_line() {
    let flat = DynamicImage::ImageRgb8(RgbImage::from_pixel(120, 90, image::Rgb([90, 140, 60])));
    let (lines, _) = lines_of(flat);
    assert!(lines.iter().all(|&v| v == 0.0));
}

/// The mean red of `img`'s pixels whose centres lie between radii `r0` and `r1` of its centre.
fn ring_mean(img: &RgbImage, r0: f64, r1: f64) -> f64 {
    let c = f64::from(SIDE) / 2.0;
    common::mean_where(img, 0, |x, y| (r0..r1).contains(&(x - c).hypot(y - c)))
}

#[test]
fn outlines_are_no_lighter_than_the_black_they_lie_on() {
    // The outlines' ink (#181412) lies on the dark side of the rim of a black disc, inside it,
    // where the looks lay black: drawn as it is, it made a brown-black ring round the disc.
    for look in ["pen-hatch", "crosshatch", "engraving"] {
        let img = common::painted_with(&disc(), look, &[], 1);
        let (rim, inside) = (
            ring_mean(&img, RADIUS - 3.0, RADIUS - 1.0),
            ring_mean(&img, 0.0, RADIUS - 10.0),
        );
        assert!(
            rim < inside + 3.0,
            "{look}: rim {rim:.1}, inside {inside:.1}"
        );
    }
}

#[test]
fn ink_looks_draw_outlines_over_their_hatching() {
    // The rim of a mid-grey disc, just inside: with outlines the pen-hatch is darker there
    // than without (its hatching alone keeps the grey), and the paper far outside stays as
    // it was.
    let photo = disc_of(120);
    let paint = |outlines: &str| {
        common::painted_with(
            &photo,
            "pen-hatch",
            &[format!("outlines.strength={outlines}")],
            1,
        )
    };
    let (with, without) = (paint("1"), paint("0"));
    let (rim_with, rim_without) = (
        ring_mean(&with, RADIUS - 3.0, RADIUS),
        ring_mean(&without, RADIUS - 3.0, RADIUS),
    );
    assert!(
        rim_with < rim_without - 10.0,
        "rim {rim_with} with, {rim_without} without"
    );
    // The hatching under the outline draws less, for the outline's own ink (see the next
    // test), and the rim still reads well darker than the disc's grey.
    assert!(rim_with < 105.0, "the rim is not dark: {rim_with}");
    let far = |img: &RgbImage| ring_mean(img, RADIUS + 15.0, RADIUS + 30.0);
    assert!((far(&with) - far(&without)).abs() < 1.0);
}

#[test]
fn outlines_take_their_ink_or_the_photos_colour_under_them() {
    // A red disc on white, outlined on a white canvas: in a fixed ink the rim is that ink; in
    // `pixel` ink it is the photo's red (the line lies on the disc's side of the rim), and a
    // preset naming neither fails on the key.
    let red = [200u8, 40, 40];
    let c = f64::from(SIDE) / 2.0;
    let photo = DynamicImage::ImageRgb8(RgbImage::from_fn(SIDE, SIDE, |x, y| {
        let r = (f64::from(x) + 0.5 - c).hypot(f64::from(y) + 0.5 - c);
        image::Rgb(if r < RADIUS { red } else { [255, 255, 255] })
    }));
    let loaded = photo_field(photo.clone(), &Default::default());
    let outlined = |ink: &str| {
        let mut preset = anisopaint::style::load("mosaic").unwrap();
        let sets = [
            "outlines.strength=1".to_string(),
            format!("outlines.ink={ink}"),
        ];
        anisopaint::style::apply_sets(&mut preset, &sets).unwrap();
        let params = preset.outline().unwrap();
        let mut canvas = RgbImage::from_pixel(SIDE, SIDE, image::Rgb([255, 255, 255]));
        let lines = line_map(&photo, &loaded.raw, &params);
        draw_outlines(
            &mut canvas,
            &photo,
            (&loaded.raw, &lines),
            loaded.metric.domain(),
            &params,
        );
        canvas
    };
    // The most inked pixel of the rim's inner band, and its colour.
    let darkest_on_rim = |img: &RgbImage| {
        img.enumerate_pixels()
            .filter(|(x, y, _)| {
                let r = (f64::from(*x) + 0.5 - c).hypot(f64::from(*y) + 0.5 - c);
                r > RADIUS - 4.0 && r < RADIUS
            })
            .map(|(_, _, p)| p.0)
            .min_by_key(|p| p.iter().map(|&v| u32::from(v)).sum::<u32>())
            .unwrap()
    };
    let blue = darkest_on_rim(&outlined("#2040c0"));
    assert!(blue[2] > 150 && blue[0] < 60, "a blue ink drew {blue:?}");
    let own = darkest_on_rim(&outlined("pixel"));
    let off = (0..3)
        .map(|k| (i32::from(own[k]) - i32::from(red[k])).abs())
        .max()
        .unwrap();
    // The line's ink is just under full there, so a little of the white canvas shows
    // (measured: [203, 50, 50]).
    assert!(
        off <= 16,
        "the pixel ink drew {own:?}, the photo is {red:?}"
    );
    let mut preset = anisopaint::style::load("mosaic").unwrap();
    anisopaint::style::apply_sets(&mut preset, &["outlines.ink=photo".to_string()]).unwrap();
    let err = preset.outline().unwrap_err().to_string();
    assert!(
        err.contains("outlines.ink") && err.contains("pixel"),
        "{err}"
    );
}

#[test]
fn outlines_take_their_ink_out_of_the_ink_looks_tone() {
    // Around the rim of a mid-grey disc the outlines ink the dark side of the edge. The ink
    // looks draw that much less there themselves, so the band 8 px either side of the rim
    // keeps the tone of the look without outlines: measured 1.8 (pen-hatch), 2.3
    // (crosshatch) and 3.5 (engraving) levels of luma darker. Laid on top of the look's own
    // tone they darkened it by 10.5, 10.8 and 11.0.
    let photo = disc_of(120);
    let band = |img: &RgbImage| {
        let c = f64::from(SIDE) / 2.0;
        let (mut sum, mut n) = (0.0, 0.0);
        for (x, y, p) in img.enumerate_pixels() {
            let r = (f64::from(x) + 0.5 - c).hypot(f64::from(y) + 0.5 - c);
            if (RADIUS - 8.0..RADIUS + 8.0).contains(&r) {
                let luma = 0.299 * f64::from(p.0[0]) + 0.587 * f64::from(p.0[1]);
                sum += luma + 0.114 * f64::from(p.0[2]);
                n += 1.0;
            }
        }
        sum / n
    };
    for style in ["pen-hatch", "crosshatch", "engraving"] {
        let paint = |outlines: &str| {
            let mut preset = anisopaint::style::load(style).unwrap();
            let sets = [format!("outlines.strength={outlines}")];
            anisopaint::style::apply_sets(&mut preset, &sets).unwrap();
            let recipe =
                anisopaint::paint::Recipe::from_preset(&preset, Default::default(), Some(1))
                    .unwrap();
            let loaded = photo_field(photo.clone(), &recipe.field.metric);
            let silent = &anisopaint::progress::Silent;
            anisopaint::paint::paint_loaded(&loaded, &recipe, Default::default(), silent)
                .unwrap()
                .image
        };
        let (with, without) = (band(&paint("1")), band(&paint("0")));
        assert!(
            (with - without).abs() < 6.0,
            "{style}: {with:.1} with outlines, {without:.1} without"
        );
    }
}

#[test]
fn a_faint_lone_line_is_laid_whole_in_the_photos_colour_not_in_a_pens_ink() {
    // A vertical 1 px line a little darker than a flat blue ground (steel 45/55/90 on a sky of
    // 60/80/140). The pen's soft threshold inks such a faint line partly, as dark as its edge;
    // the rigger (pixel ink), whose colour carries the contrast itself, lays a lone line whole.
    let (w, h) = (200u32, 120u32);
    let photo = DynamicImage::ImageRgb8(RgbImage::from_fn(w, h, |x, _| {
        image::Rgb(if x == 100 {
            [45, 55, 90]
        } else {
            [60, 80, 140]
        })
    }));
    let loaded = photo_field(photo.clone(), &Default::default());
    let cols = loaded.raw.cols();
    let strongest = |ink: OutlineInk| {
        let params = OutlineParams {
            strength: 1.0,
            ink,
            ..OutlineParams::default()
        };
        let lines = line_map(&photo, &loaded.raw, &params);
        // The median over the middle rows of each row's strongest ink near the line.
        let mut per_row: Vec<f32> = (30..90)
            .map(|r| {
                let row = &lines[r * cols + 94..r * cols + 107];
                row.iter().fold(0.0f32, |m, &v| m.max(v))
            })
            .collect();
        per_row.sort_by(f32::total_cmp);
        per_row[per_row.len() / 2]
    };
    let pen = strongest(OutlineInk::Colour([24, 20, 18]));
    let rigger = strongest(OutlineInk::Pixel);
    // Measured: the pen 0.17, the rigger 0.77 (0.17 as well before the rigger's gain).
    assert!(pen > 0.1 && pen < 0.3, "the pen: {pen}");
    assert!(rigger > 0.7, "the lone line in pixel ink: {rigger}");
}

#[test]
fn the_rigger_does_not_lay_a_photos_noise_back() {
    // A flat blue under Gaussian noise of 16 levels per channel (a high-ISO night sky): the
    // flow walk finds faint lines on nearly every node. They are the grain, not sparse lines,
    // and the rigger keeps the pen's strength for them (laid whole, they came back as a
    // speckle over the painting).
    let mut rng = anisopaint::sampling::rng::Rng::new(3, 0);
    let mut gauss = move || {
        // Box–Muller.
        let (u, v) = (rng.uniform().max(1e-12), rng.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    };
    let photo = DynamicImage::ImageRgb8(RgbImage::from_fn(300, 200, |_, _| {
        image::Rgb(
            [80.0, 100.0, 160.0].map(|c: f64| (c + 16.0 * gauss()).round().clamp(0.0, 255.0) as u8),
        )
    }));
    let loaded = photo_field(photo.clone(), &Default::default());
    let params = OutlineParams {
        strength: 1.0,
        ink: OutlineInk::Pixel,
        ..OutlineParams::default()
    };
    let mut lines = line_map(&photo, &loaded.raw, &params);
    let inked = lines.iter().filter(|&&v| v > 0.0).count() as f64 / lines.len() as f64;
    lines.sort_by(f32::total_cmp);
    let p99 = lines[lines.len() * 99 / 100];
    // Measured: 0.95 of the nodes inked, the 99th percentile of ink 0.20 (0.80 when the
    // rigger's density was the lines' mean ink).
    assert!(inked > 0.5, "the noise inks {inked:.2} of the nodes");
    assert!(p99 < 0.35, "99th percentile of the noise's ink {p99}");
}
