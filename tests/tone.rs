//! Tone reproduction of the ink, stipple, stroke and mosaic looks, on pictures whose answer is
//! known. A ramp of lightness from black to white, hatched and seen from afar (blurred at
//! σ = 4 px, averaged down each column band), is a monotone ramp within 0.1 of the photo's own
//! (on a 0–1 scale) after the tone curve its preset asks for (`look.gamma`: lightness
//! `1 − (1 − L)^γ`), light areas paper, dark ones dense. Fine textures and pixel grain keep
//! their mean under hatching. Flat greys keep their grey in every ink look and in the mosaic,
//! and stipple without paper showing through; soft spots keep their depth in hatching; strokes
//! keep what is smaller than their cells; glyphs keep a black area black.

use anisopaint::input::photo_field;
use anisopaint::paint::{paint_loaded, Extras, Recipe};
use anisopaint::progress::Silent;
use image::{DynamicImage, GrayImage, RgbImage};

const W: u32 = 320;
const H: u32 = 120;

/// Lightness `x / W` (the sRGB value) across, the same down every column.
fn ramp() -> RgbImage {
    RgbImage::from_fn(W, H, |x, _| {
        let v = (255.0 * (f64::from(x) + 0.5) / f64::from(W)).round() as u8;
        image::Rgb([v, v, v])
    })
}

/// `photo` painted in the built-in `style` with `sets` applied, the sampler seeded with `seed`.
fn painted(photo: &RgbImage, style: &str, sets: &[String], seed: u64) -> RgbImage {
    let mut preset = anisopaint::style::load(style).unwrap();
    anisopaint::style::apply_sets(&mut preset, sets).unwrap();
    let recipe = Recipe::from_preset(&preset, Default::default(), Some(seed)).unwrap();
    let loaded = photo_field(DynamicImage::ImageRgb8(photo.clone()), &recipe.field.metric);
    paint_loaded(&loaded, &recipe, Extras::default(), &Silent)
        .unwrap()
        .image
}

/// Luma (0–255) of an sRGB pixel.
fn luma(p: [u8; 3]) -> f64 {
    0.299 * f64::from(p[0]) + 0.587 * f64::from(p[1]) + 0.114 * f64::from(p[2])
}

/// `img`'s luma, rounded to bytes.
fn luma_image(img: &RgbImage) -> GrayImage {
    GrayImage::from_fn(img.width(), img.height(), |x, y| {
        image::Luma([luma(img.get_pixel(x, y).0).round() as u8])
    })
}

/// Mean sRGB luma (0–1) of `img` blurred at σ = 4 px, in `bands` column bands, away from
/// the picture's edges.
fn profile(img: &RgbImage, bands: u32) -> Vec<f64> {
    let blurred = image::imageops::blur(&luma_image(img), 4.0);
    let band = W / bands;
    (0..bands)
        .map(|b| {
            let mut sum = 0.0;
            let mut n = 0.0;
            for y in 16..H - 16 {
                for x in b * band..(b + 1) * band {
                    sum += f64::from(blurred.get_pixel(x, y).0[0]) / 255.0;
                    n += 1.0;
                }
            }
            sum / n
        })
        .collect()
}

#[test]
fn a_hatched_ramp_keeps_its_tones() {
    let photo = ramp();
    let expected = profile(&photo, 10);
    for style in ["pen-hatch", "crosshatch", "pointillist", "engraving"] {
        let preset = anisopaint::style::load(style).unwrap();
        let gamma = f64::from(preset.file.look.gamma.unwrap_or(1.0));
        let got = profile(&painted(&photo, style, &[], 2), 10);
        for (k, (g, e)) in got.iter().zip(&expected).enumerate() {
            let e = 1.0 - (1.0 - e).powf(gamma);
            assert!(
                (g - e).abs() <= 0.1,
                "{style}: band {k} reads {g:.3}, the photo {e:.3}\n{got:.3?}"
            );
        }
        for w in got.windows(2) {
            assert!(w[1] > w[0], "{style}: not monotone: {got:.3?}");
        }
    }
}

#[test]
fn pointillist_dots_leave_no_crackle_of_paper() {
    // A flat photo in five tones, black, near-black, dark, mid and light. Painted
    // pointillist, the dots cover each tone densely: no pixel (measured: none) shows the paper
    // between them, 40 sRGB levels or more lighter than the tone. When the dots were twice as
    // dark as the tone they left about 4-5 % of every tone bare, a white crackle over the
    // picture; when a tone of solid ink still read its coverage back through the 8-bit
    // encoding (just short of 1) and left the gaps of the dots' lattice, 0.8 % and 0.6 % of
    // the two dark tones were single white pixels, stars in a black coat; and a black of
    // (2, 0, 1), the background of a fundus photo, whose ink read a level darker than its
    // target, was covered 0.997 and showed the stars again (4.8 % of it).
    let tones = [
        [2, 0, 1],
        [12, 10, 8],
        [70, 50, 35],
        [150, 100, 60],
        [210, 190, 150],
    ];
    let band = W / 5;
    let photo = RgbImage::from_fn(W, H, |x, _| image::Rgb(tones[(x / band).min(4) as usize]));
    let img = painted(&photo, "pointillist", &[], 3);
    for (k, &tone) in tones.iter().enumerate() {
        let k = k as u32;
        let pixels = band_lumas(&img, k * band..(k + 1) * band, 16);
        let bare = pixels.iter().filter(|&&l| l >= luma(tone) + 40.0).count();
        let share = bare as f64 / pixels.len() as f64;
        assert!(
            share < 0.001,
            "tone {tone:?}: paper on {:.2} %",
            100.0 * share
        );
    }
}

/// The lumas of the column band `columns` of `img`, `margin` pixels clear of its sides and
/// 16 clear of the picture's top and bottom.
fn band_lumas(img: &RgbImage, columns: std::ops::Range<u32>, margin: u32) -> Vec<f64> {
    (16..H - 16)
        .flat_map(|y| (columns.start + margin..columns.end - margin).map(move |x| (x, y)))
        .map(|(x, y)| luma(img.get_pixel(x, y).0))
        .collect()
}

/// The grey a painting of a flat photo reads as from afar: its mean luma, 16 pixels clear of
/// the picture's borders.
fn flat_grey_read(img: &RgbImage) -> f64 {
    let (mut sum, mut n) = (0.0, 0.0);
    for y in 16..img.height() - 16 {
        for x in 16..img.width() - 16 {
            sum += luma(img.get_pixel(x, y).0);
            n += 1.0;
        }
    }
    sum / n
}

#[test]
fn ink_looks_keep_flat_greys() {
    // A flat grey, hatched, cross-hatched or engraved in black ink on cream paper, reads from
    // afar (the mean luma away from the borders) as the same grey within 3 levels (measured:
    // within 1.7; under a tone curve of γ = 0.9, 200 would read 191 and 120 read 113).
    for style in ["pen-hatch", "crosshatch", "engraving"] {
        flat_greys_come_back(style, &[50, 90, 140, 200], 3.0);
    }
}

/// Each of `greys`, a flat photo painted in `style` (seed 4), reads from afar
/// ([`flat_grey_read`]) within `levels` of itself.
fn flat_greys_come_back(style: &str, greys: &[u8], levels: f64) {
    for &grey in greys {
        let photo = RgbImage::from_pixel(W, H, image::Rgb([grey; 3]));
        let mean = flat_grey_read(&painted(&photo, style, &[], 4));
        assert!(
            (mean - f64::from(grey)).abs() <= levels,
            "{style}: grey {grey} reads {mean:.1}"
        );
    }
}

#[test]
fn the_mosaic_keeps_flat_greys_under_its_leading() {
    // A flat grey in stained glass reads from afar (the mean luma away from the borders) as the
    // same grey within 5 levels (measured: within 4): the glass is lifted by the share of the
    // cell its dark leading covers. Unlifted, 200 read 182 and 120 read 110.
    flat_greys_come_back("mosaic", &[60, 120, 200], 5.0);
}

#[test]
fn the_mosaic_lifts_light_glass_without_whitening_it() {
    // Light skin in stained glass: the glass is lifted for its leading, every channel by the
    // same share of its lift, so the lightest glass keeps the skin's hue. Each channel lifted
    // alone until it clamped gave 255, 255, 240 (its red less its blue 15, the photo's 50).
    let photo = RgbImage::from_pixel(W, H, image::Rgb([240, 210, 190]));
    let img = painted(&photo, "mosaic", &["look.relief=0".into()], 4);
    let lightest = img
        .pixels()
        .map(|p| p.0)
        .fold([0u8; 3], |a, p| if luma(p) > luma(a) { p } else { a });
    let chroma = i32::from(lightest[0]) - i32::from(lightest[2]);
    assert!(
        luma(lightest) > luma([240, 210, 190]) + 3.0 && chroma >= 40,
        "lightest glass {lightest:?}"
    );
}

#[test]
fn glyphs_keep_flat_greys() {
    // A flat grey in glyphs over their wash reads from afar as the same grey within 1.5 levels
    // (measured: within 1.1): the glyphs' colours are solved for the share of the picture they
    // cover. Counted as the sum of their areas (overlaps twice), 35 read 38.9 and 120 read 121.8.
    flat_greys_come_back("glyphs", &[35, 60, 120, 200, 230], 1.5);
}

#[test]
fn pointillist_keeps_flat_tones() {
    // Flat greys from dark to light, painted pointillist, read from afar (the mean luma of the
    // band's middle) as the photo's own grey within 3 levels: the dots take the photo's colour,
    // each a little off it, and cover the paper. Dots darkened by a quarter under a tone curve
    // of γ = 0.7 read 90 as 78, 200 as 175. White, lighter than the paper, is bare paper: no
    // dot of jittered near-white on it.
    let greys = [40u8, 90, 140, 200, 235, 255];
    let band = W / 6;
    let photo = RgbImage::from_fn(W, H, |x, _| {
        let v = greys[(x / band).min(5) as usize];
        image::Rgb([v, v, v])
    });
    let img = painted(&photo, "pointillist", &[], 5);
    let paper = luma([0xfb, 0xfa, 0xf6]);
    for (k, &grey) in greys.iter().enumerate() {
        let k = k as u32;
        let lumas = band_lumas(&img, k * band..(k + 1) * band, 10);
        let mean = lumas.iter().sum::<f64>() / lumas.len() as f64;
        if grey == 255 {
            let darkest = lumas.iter().copied().fold(f64::INFINITY, f64::min);
            let dotted = lumas.iter().filter(|&&l| l < paper - 1.0).count();
            assert!(
                dotted == 0,
                "{dotted} dotted pixels on white, darkest luma {darkest:.1}"
            );
        } else {
            assert!(
                (mean - f64::from(grey)).abs() <= 3.0,
                "grey {grey} reads {mean:.1}"
            );
        }
    }
}

#[test]
fn strokes_keep_details_smaller_than_their_cells() {
    // Strokes as large as the samples paint over what is smaller than a cell (an eye, a
    // whisker) with the colour of the cell around it; the detail strokes of half and a quarter
    // their size, laid where the canvas still differs from the photo, bring it back. Measured
    // on the bundled photo as the shared evaluator `tone.py` does (sRGB luma blurred at
    // σ = 2 px, PSNR against the photo's): without detail strokes 33.7 dB, with
    // half-size ones only 35.2, with both levels 37.1.
    let photo = image::open(concat!(env!("CARGO_MANIFEST_DIR"), "/samples/chelsea.png"))
        .unwrap()
        .to_rgb8();
    let img = painted(&photo, "strokes", &[], 7);
    let blurred_luma = |img: &RgbImage| image::imageops::blur(&luma_image(img), 2.0);
    let (a, b) = (blurred_luma(&photo), blurred_luma(&img));
    let mse = a
        .pixels()
        .zip(b.pixels())
        .map(|(p, q)| (f64::from(p.0[0]) - f64::from(q.0[0])).powi(2))
        .sum::<f64>()
        / f64::from(a.width() * a.height());
    let psnr = 10.0 * (255.0f64 * 255.0 / mse).log10();
    assert!(psnr > 35.5, "blurred luma PSNR {psnr:.2} dB");
}

#[test]
fn hatching_follows_the_photos_tone_inside_its_cells() {
    // Soft dark spots on a light ground. Their cells follow them only roughly: with one tone
    // per cell (the paper's, `look.cell_tone`), a cell holding a spot's core and some of its
    // lighter rim hatches their mean; with the photo's tone point by point, the lines swell
    // towards the core. Seen from afar (blurred at σ = 1.5 px), ground minus core luma,
    // measured: photo 117.6; one tone per cell 112.9 (pen-hatch) and 113.4 (crosshatch);
    // point by point 117.5 and 117.9 (before the pixels at the cells' borders were averaged
    // in the encoding, 110.2, 110.3, 115.6 and 115.8). The spots: Gaussian, σ = 5 px, sRGB
    // 200 down to 60, every 32 px.
    let spot = |x: u32, y: u32| {
        let (dx, dy) = (f64::from(x % 32) - 15.5, f64::from(y % 32) - 15.5);
        (-(dx * dx + dy * dy) / 50.0).exp()
    };
    let photo = RgbImage::from_fn(W, H, |x, y| {
        let v = (200.0 - 140.0 * spot(x, y)).round() as u8;
        image::Rgb([v, v, v])
    });
    let contrast = |img: &RgbImage| {
        let blurred = image::imageops::blur(&luma_image(img), 1.5);
        let (mut dark, mut light) = ((0.0, 0.0), (0.0, 0.0));
        for y in 0..H {
            for x in 0..W {
                let v = f64::from(blurred.get_pixel(x, y).0[0]);
                let s = spot(x, y);
                if s > 0.8 {
                    dark = (dark.0 + v, dark.1 + 1.0);
                } else if s < 0.01 {
                    light = (light.0 + v, light.1 + 1.0);
                }
            }
        }
        light.0 / light.1 - dark.0 / dark.1
    };
    let own = contrast(&photo);
    for style in ["pen-hatch", "crosshatch"] {
        let mut found = Vec::new();
        for cell_tone in ["true", "false"] {
            let sets = [format!("look.cell_tone={cell_tone}")];
            found.push(contrast(&painted(&photo, style, &sets, 2)));
        }
        // Point by point within 2 levels of the photo's contrast; one tone per cell (the
        // control, which shows the test can tell) more than 3.5 short.
        assert!(
            (own - found[1]).abs() < 2.0,
            "{style}: {found:.1?} against {own:.1}"
        );
        assert!(
            own - found[0] > 3.5,
            "{style}: {found:.1?} against {own:.1}"
        );
    }
}

#[test]
fn strokes_keep_thin_lines_in_their_colour() {
    // A lattice of thin dark struts (1.5 px wide, upright and diagonal every 24 px, a mast
    // against an evening sky) on a blue ground. The strokes, a sample's size and more, paint
    // over the struts with the ground's colour; the outlines in the photo's own colour
    // (`outlines.ink = "pixel"`, on in `strokes`) draw them back. Measured on the struts'
    // cores (coverage ≥ 0.9), mean distance to the photo's colour (sRGB, 0–255, Euclidean):
    // without the outlines 86.9, with them 0.0 (the photo's own pixels); on the ground 3 px or
    // more from a strut 3.3 and 3.2 (the outlines stay on the struts).
    struts_come_back("strokes", [90.0, 120.0, 170.0], [50.0, 35.0, 25.0], 30.0);
}

#[test]
fn glyphs_keep_thin_lines_in_their_colour() {
    // The lattice of dark struts on a blue ground, in glyphs: an ellipse per cell cannot draw
    // a line thinner than itself, the outlines in the photo's colour at half ink draw it
    // halfway back. Measured: 42.7 from the struts' colour, 84.6 without the outlines; the
    // ground 12.0 both ways.
    struts_come_back("glyphs", [90.0, 120.0, 170.0], [50.0, 35.0, 25.0], 65.0);
}

#[test]
fn strokes_keep_thin_light_lines_in_their_colour() {
    // The same lattice of struts, light on a dark ground (whiskers, wires against a dark
    // wall): the outlines in the photo's colour are drawn on the light side of edges too, so
    // the struts come back. Measured: 0.0 from their colour with the outlines (the photo's
    // own pixels), 70.2 without them and with outlines on the dark side only; the ground 4.7
    // both ways.
    struts_come_back("strokes", [70.0, 55.0, 45.0], [230.0, 220.0, 190.0], 30.0);
}

/// Struts of colour `strut` on a `ground` ([`strut_distances`]) come back in `style`: their
/// cores within `limit` of their colour with the outlines, over 45 without them (the
/// control), and the ground away from them no further from its colour than without outlines.
fn struts_come_back(style: &str, ground: [f64; 3], strut: [f64; 3], limit: f64) {
    let [struts, ground_off, painted_over, plain_ground] = strut_distances(style, ground, strut);
    assert!(
        struts < limit,
        "the struts are {struts:.1} from their colour"
    );
    assert!(
        painted_over > 45.0,
        "control: without outlines the struts are only {painted_over:.1} from their colour"
    );
    assert!(
        ground_off < plain_ground + 1.0,
        "the ground: {ground_off:.1} against {plain_ground:.1} without outlines"
    );
}

/// A lattice of thin struts (1.5 px wide, upright and diagonal every 24 px) of colour `strut`
/// on a `ground`, painted in `style`: the mean distance (sRGB, 0–255, Euclidean) to the
/// photo's colour on the struts' cores (coverage ≥ 0.9) and on the ground 3 px or more from a
/// strut, with the outlines and then without them.
fn strut_distances(style: &str, ground: [f64; 3], strut: [f64; 3]) -> [f64; 4] {
    let coverage = |x: u32, y: u32| {
        let mut inside = 0.0;
        for j in 0..4 {
            for i in 0..4 {
                let px = f64::from(x) + (f64::from(i) + 0.5) / 4.0;
                let py = f64::from(y) + (f64::from(j) + 0.5) / 4.0;
                let upright = (px.rem_euclid(24.0) - 12.0).abs();
                let diagonal = ((px + py).rem_euclid(24.0) - 12.0).abs() / 2f64.sqrt();
                if upright < 0.75 || diagonal < 0.75 {
                    inside += 1.0 / 16.0;
                }
            }
        }
        inside
    };
    let cover: Vec<f64> = (0..W * H).map(|i| coverage(i % W, i / W)).collect();
    // With a camera's grain: a picture without any is a drawing, whose cells are not blurred
    // against grain and follow the struts.
    let photo = RgbImage::from_fn(W, H, |x, y| {
        let c = cover[(y * W + x) as usize];
        image::Rgb([0u32, 1, 2].map(|k| {
            let v = ground[k as usize] + (strut[k as usize] - ground[k as usize]) * c;
            (v + grain(x, y, k)).round().clamp(0.0, 255.0) as u8
        }))
    });
    // Within 3 px of a strut: the ground near it is not judged.
    let near = |x: u32, y: u32| {
        let (x0, y0) = (x.saturating_sub(3), y.saturating_sub(3));
        (y0..(y + 4).min(H))
            .any(|v| (x0..(x + 4).min(W)).any(|u| cover[(v * W + u) as usize] > 0.0))
    };
    let distances = |sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let img = painted(&photo, style, &sets, 7);
        let (mut on, mut off) = ((0.0, 0.0), (0.0, 0.0));
        for (i, (p, q)) in photo.pixels().zip(img.pixels()).enumerate() {
            let (x, y) = (i as u32 % W, i as u32 / W);
            let d = (0..3)
                .map(|k| (f64::from(p.0[k]) - f64::from(q.0[k])).powi(2))
                .sum::<f64>()
                .sqrt();
            if cover[i] >= 0.9 {
                on = (on.0 + d, on.1 + 1.0);
            } else if !near(x, y) {
                off = (off.0 + d, off.1 + 1.0);
            }
        }
        (on.0 / on.1, off.0 / off.1)
    };
    let (struts, ground_off) = distances(&[]);
    let (painted_over, plain_ground) = distances(&["outlines.strength=0"]);
    [struts, ground_off, painted_over, plain_ground]
}

#[test]
fn glyphs_keep_a_black_area_black() {
    // Glyphs stand on a wash of their cell's colour 15 % towards the paper, their colour
    // solved so that glyph and wash average to the cell's. A black cell's glyph cannot be
    // darker than black: its wash went grey (37 sRGB levels, a grey mesh between black discs
    // over the helmet and table of astronaut, mean 6.6 over the black surround of a fundus
    // photo). The wash takes what the glyph cannot: black under black. The grey half keeps
    // its tone from afar.
    let photo = RgbImage::from_fn(W, H, |x, _| {
        image::Rgb(if x < W / 2 {
            [0, 0, 0]
        } else {
            [128, 128, 128]
        })
    });
    let img = painted(&photo, "glyphs", &[], 3);
    let luma_at = |x: u32, y: u32| luma(img.get_pixel(x, y).0);
    let black = (16..H - 16).flat_map(|y| (16..W / 2 - 16).map(move |x| (x, y)));
    let brightest = black.map(|(x, y)| luma_at(x, y)).fold(0.0, f64::max);
    assert!(brightest <= 4.0, "the black half reaches {brightest:.1}");
    let grey: Vec<f64> = (16..H - 16)
        .flat_map(|y| (W / 2 + 16..W - 16).map(move |x| (x, y)))
        .map(|(x, y)| luma_at(x, y))
        .collect();
    let mean = grey.iter().sum::<f64>() / grey.len() as f64;
    assert!((mean - 128.0).abs() < 10.0, "the grey half reads {mean:.1}");
}

/// `values` (`w × h`, row-major) blurred by a Gaussian of `sigma` px.
fn blurred(values: &[f32], w: u32, h: u32, sigma: f32) -> Vec<f32> {
    let img = image::ImageBuffer::<image::Luma<f32>, Vec<f32>>::from_raw(w, h, values.to_vec());
    imageproc::filter::gaussian_blur_f32(&img.unwrap(), sigma).into_raw()
}

/// Central-difference gradients of `values` (`w × h`, row-major), edges clamped.
fn gradients(values: &[f32], w: u32, h: u32) -> Vec<(f32, f32)> {
    let at = |x: u32, y: u32| values[(y * w + x) as usize];
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let gx = (at((x + 1).min(w - 1), y) - at(x.saturating_sub(1), y)) / 2.0;
            let gy = (at(x, (y + 1).min(h - 1)) - at(x, y.saturating_sub(1))) / 2.0;
            (gx, gy)
        })
        .collect()
}

/// The evaluator `tone.py`'s edge recall: of the photo's strongest tenth of gradients (luma
/// blurred at σ = 1 px), the share where the painting's gradient at σ = 2 px is within 30° of
/// the same line with at least a quarter of the photo's strength (itself blurred at 1 px).
fn edge_recall(photo: &RgbImage, painting: &RgbImage) -> f64 {
    let (w, h) = photo.dimensions();
    let lumas = |img: &RgbImage| -> Vec<f32> { img.pixels().map(|p| luma(p.0) as f32).collect() };
    let a = gradients(&blurred(&lumas(photo), w, h, 1.0), w, h);
    let b = gradients(&blurred(&lumas(painting), w, h, 2.0), w, h);
    let strength: Vec<f32> = a.iter().map(|g| g.0.hypot(g.1)).collect();
    let around = blurred(&strength, w, h, 1.0);
    let mut sorted = strength.clone();
    sorted.sort_by(f32::total_cmp);
    let threshold = sorted[sorted.len() * 9 / 10];
    let (mut strong, mut kept) = (0usize, 0usize);
    for k in 0..a.len() {
        let (na, nb) = (strength[k], b[k].0.hypot(b[k].1));
        if na < threshold || na == 0.0 {
            continue;
        }
        strong += 1;
        let cos = (a[k].0 * b[k].0 + a[k].1 * b[k].1).abs() / (na * nb + 1e-9);
        kept += usize::from(cos > 30f32.to_radians().cos() && nb > 0.25 * around[k]);
    }
    kept as f64 / strong.max(1) as f64
}

#[test]
fn glyphs_keep_the_photos_edges() {
    // Glyphs of cells along an edge reached across it into the cells of the other side (a
    // rim of bumps round an object); a pixel of a cell whose colour is neither its wash's nor
    // its glyph's now takes the cell's colour, so objects end where their cells do. Edge
    // recall (as tone.py measures it) on the bundled astronaut: 0.860, 0.768 before.
    let photo =
        image::open(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("samples/astronaut.jpg"))
            .unwrap()
            .to_rgb8();
    let img = painted(&photo, "glyphs", &[], 7);
    let recall = edge_recall(&photo, &img);
    assert!(recall > 0.83, "edge recall {recall:.3}");
}

#[test]
fn a_hatched_texture_keeps_its_mean_tone() {
    // A fine grey texture (noise of ±40 levels around 120, a pixel or two across) gives a
    // field of small cells, so many pixels lie on a cell's border and are shaded at several
    // points. The hatchings mix ink and paper in the sRGB encoding and average those points
    // the same way: the picture's mean luma away from the borders is the photo's within 2
    // levels (measured +0.26 and +0.25). Averaged in linear light, the border pixels came out
    // lighter than their ink, and the texture 6.0 (pen-hatch) and 4.4 levels light.
    let mut state = 0x2545_f491_u32;
    let noise: Vec<f64> = (0..W * H).map(|_| uniform(&mut state) - 0.5).collect();
    let at = |x: i64, y: i64| {
        noise[(y.clamp(0, H as i64 - 1) * W as i64 + x.clamp(0, W as i64 - 1)) as usize]
    };
    let photo = RgbImage::from_fn(W, H, |x, y| {
        let (x, y) = (i64::from(x), i64::from(y));
        let mut sum = 0.0;
        for j in -1..=1 {
            for i in -1..=1 {
                sum += at(x + i, y + j);
            }
        }
        let v = (120.0 + 240.0 * sum / 9.0).round().clamp(0.0, 255.0) as u8;
        image::Rgb([v, v, v])
    });
    // The mean luma away from the borders, as a flat grey is read.
    let want = flat_grey_read(&photo);
    for style in ["pen-hatch", "crosshatch"] {
        let got = flat_grey_read(&painted(&photo, style, &["outlines.strength=0".into()], 2));
        assert!(
            (got - want).abs() < 2.0,
            "{style}: reads {got:.1}, the photo {want:.1}"
        );
    }
}

#[test]
fn a_hatched_pixel_grain_keeps_its_mean_tone() {
    // Grain of ±100 levels around 128 from pixel to pixel, on a photo large enough (600 × 400)
    // that the tone under the ink is blurred by half a pixel. Blurred as ink coverage, the
    // hatching reads the grain's mean within 2 levels (measured +0.12); blurred as light in
    // linear light and then read as ink, the grain came out 10.2 levels light.
    let (w, h) = (600u32, 400u32);
    let mut state = 0x9e37_79b9_u32;
    let photo = RgbImage::from_fn(w, h, |_, _| {
        let v = (28.0 + 200.0 * uniform(&mut state)).round() as u8;
        image::Rgb([v, v, v])
    });
    let want = flat_grey_read(&photo);
    let got = flat_grey_read(&painted(
        &photo,
        "pen-hatch",
        &["outlines.strength=0".into()],
        2,
    ));
    assert!(
        (got - want).abs() < 2.0,
        "reads {got:.1}, the photo {want:.1}"
    );
}

/// A camera's grain at pixel `(x, y)`, channel `k`: −2 to 2 levels, hashed.
fn grain(x: u32, y: u32, k: u32) -> f64 {
    let h =
        (u64::from(x) << 32 | u64::from(y) << 2 | u64::from(k)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    ((h >> 40) % 5) as f64 - 2.0
}

/// The next number of a xorshift32 stream at `state`, uniform in [0, 1].
fn uniform(state: &mut u32) -> f64 {
    *state ^= *state << 13;
    *state ^= *state >> 17;
    *state ^= *state << 5;
    f64::from(*state) / f64::from(u32::MAX)
}

#[test]
fn pointillist_keeps_fine_detail_of_a_large_photo() {
    // The dots take their colours from the photo under them. Read from the photo at half its
    // size (a diagonal of at most 1 024 px): 116.4 against 165.4; from the photo itself
    // 96.0 against 176.0.
    bands_keep_contrast("pointillist", 65.0);
}

#[test]
fn hatching_keeps_fine_detail_of_a_large_photo() {
    // Pen-hatch without its outlines: the lines swell and thin with the tone read from the
    // photo. Read at half its size: 59.0 against 209.6; from the photo itself 43.7
    // against 211.1.
    bands_keep_contrast("pen-hatch", 160.0);
}

/// Bands 3 px wide, dark and light in turn (60 and 190, with a camera's grain), across a
/// picture 1 400 × 600 (a diagonal over 1 024 px), painted in `style` without outlines (seed
/// 3): the mean luma of the light bands' middle rows exceeds the dark bands' by `least`.
fn bands_keep_contrast(style: &str, least: f64) {
    let (w, h, width) = (1400u32, 600u32, 3u32);
    let photo = RgbImage::from_fn(w, h, |x, y| {
        let v = if y % (2 * width) < width { 60.0 } else { 190.0 };
        image::Rgb([(v + grain(x, y, 0)) as u8; 3])
    });
    let img = painted(&photo, style, &["outlines.strength=0".to_string()], 3);
    let (mut dark, mut light) = ((0.0, 0.0), (0.0, 0.0));
    for y in (20..h - 20).filter(|&y| y % width == 1) {
        for x in 20..w - 20 {
            let l = luma(img.get_pixel(x, y).0);
            if y % (2 * width) < width {
                dark = (dark.0 + l, dark.1 + 1.0);
            } else {
                light = (light.0 + l, light.1 + 1.0);
            }
        }
    }
    let (dark, light) = (dark.0 / dark.1, light.0 / light.1);
    assert!(
        light - dark > least,
        "{style}: dark bands {dark:.1} against light {light:.1}"
    );
}
