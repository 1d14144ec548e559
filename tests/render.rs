//! The renderers against independent truths: the label map against a brute-force owner over
//! all sites, hatch and LIC direction against the field's angle (found in the picture by a
//! Radon-style search), flat photos against the colours they must give, odd sizes, and small
//! reference pictures compared with a per-channel tolerance (`REGENERATE=1` rewrites them; on
//! a mismatch a diff picture is written next to the reference).

mod common;

use anisopaint::field::{self, TensorField};
use anisopaint::input::LoadedField;
use anisopaint::input::{self, FieldOptions, Input};
use anisopaint::paint::{self, Extras, Recipe, Samples};
use anisopaint::progress::Silent;
use anisopaint::render::cells::{CellKind, CellParams};
use anisopaint::render::{label_map, Look, Raster, RenderSize, VoronoiCells};
use anisopaint::sampling::{self, SamplerParams, Sampling};
use image::{DynamicImage, RgbImage};
use std::path::Path;

fn analytic(spec: &str, w: usize, h: usize) -> TensorField {
    let input = Input::parse(&format!("analytic:{spec}")).unwrap();
    let options = FieldOptions {
        analytic_size: Some((w, h)),
        ..FieldOptions::default()
    };
    input::load_field(&input, &options)
        .unwrap()
        .metric
        .as_ref()
        .clone()
}

fn sampled(field: &TensorField) -> Sampling {
    sampling::sample(field, &SamplerParams::default()).unwrap()
}

/// `look` drawn from the sampling `s` of `field` at `width × height`, 2x2 supersampled.
fn draw(
    look: &Look,
    s: &Sampling,
    field: &TensorField,
    photo: Option<&DynamicImage>,
    (width, height): (usize, usize),
) -> RgbImage {
    let size = RenderSize {
        width,
        height,
        supersample: 2,
    };
    draw_at(look, s, field, photo, size)
}

/// `look` drawn through the paint pipeline over the paper's cells of the sampling `s` of
/// `field` (the metric, and the tensor the outlines would read: none are laid) at `size`.
fn draw_at(
    look: &Look,
    s: &Sampling,
    field: &TensorField,
    photo: Option<&DynamicImage>,
    size: RenderSize,
) -> RgbImage {
    let field = std::sync::Arc::new(field.clone());
    let loaded = LoadedField {
        metric: field.clone(),
        raw: field,
        photo: photo.cloned(),
    };
    let samples = Samples {
        positions: s.positions.clone(),
        metrics: s.metrics.clone(),
        mesh: s.mesh.clone(),
    };
    let recipe = Recipe {
        cells: CellParams {
            kind: CellKind::Voronoi,
            ..CellParams::default()
        },
        supersample: size.supersample,
        ..Recipe::new(look.clone())
    };
    paint::draw(&loaded, &samples, &recipe, size, Extras::default(), &Silent)
        .unwrap()
        .image
}

/// Fraction of pixel centres (every `stride`-th in each direction) whose label is the
/// brute-force owner.
fn agreement(field: &TensorField, s: &Sampling, stride: usize) -> f64 {
    let cells = VoronoiCells::new(&s.positions, &s.metrics, &s.mesh);
    let d = field.domain();
    let raster = Raster {
        width: d.x.round() as usize,
        height: d.y.round() as usize,
        supersample: 1,
        domain: d,
    };
    let labels = label_map(&cells, &raster);
    let (mut agree, mut total) = (0usize, 0usize);
    for y in (0..raster.height).step_by(stride) {
        for x in (0..raster.width).step_by(stride) {
            let truth = cells.owner_brute_force(raster.point(x, y));
            let label = labels[y * raster.width + x];
            // A tie (equal distances) may go either way.
            let tied = (cells.delta(label as u32, raster.point(x, y)) - f64::from(truth.delta))
                .abs()
                < 1e-9;
            agree += usize::from(label == truth.site as i32 || tied);
            total += 1;
        }
    }
    agree as f64 / total as f64
}

#[test]
fn label_map_agrees_with_brute_force_on_photos_and_fields() {
    let mut cases: Vec<(String, TensorField)> = ["constant:angle=30,anisotropy=4", "circular"]
        .iter()
        .chain(&["degenerate-point", "two-point-load"])
        .map(|s| (s.to_string(), analytic(s, 300, 220)))
        .collect();
    for photo in [
        "samples/chelsea.png",
        "samples/coffee.png",
        "samples/astronaut.jpg",
    ] {
        let loaded = input::load_field(&Input::parse(photo).unwrap(), &FieldOptions::default());
        cases.push((photo.into(), loaded.unwrap().metric.as_ref().clone()));
    }
    for (name, field) in cases {
        let s = sampled(&field);
        let rate = agreement(&field, &s, 2);
        assert!(rate >= 0.995, "{name}: {rate}");
    }
}

/// Direction (degrees in [0, 180)) of the lines in `img`, by a Radon-style search: the
/// luminance is averaged along lines of each candidate angle (bins of half a pixel across
/// them), and the angle whose averages vary most is the lines' (a wrong angle averages the
/// lines away). Coarse steps of 0.5°, then 0.02° around the best.
fn line_direction(img: &RgbImage) -> f64 {
    let (w, h) = (img.width() as usize, img.height() as usize);
    let lum: Vec<f64> = img
        .pixels()
        .map(|p| {
            f64::from(p.0[0]) * 0.2126 + f64::from(p.0[1]) * 0.7152 + f64::from(p.0[2]) * 0.0722
        })
        .collect();
    let score = |deg: f64| {
        let a = deg.to_radians();
        let n = (-a.sin(), a.cos());
        let diag = ((w * w + h * h) as f64).sqrt();
        let bins = (4.0 * diag) as usize + 2;
        let mut sum = vec![0.0; bins];
        let mut count = vec![0.0; bins];
        for y in 0..h {
            for x in 0..w {
                let t = n.0 * x as f64 + n.1 * y as f64 + diag;
                let b = (2.0 * t) as usize;
                sum[b] += lum[y * w + x];
                count[b] += 1.0;
            }
        }
        let means: Vec<f64> = sum
            .iter()
            .zip(&count)
            .filter(|(_, &c)| c >= 16.0)
            .map(|(s, c)| s / c)
            .collect();
        let m = means.iter().sum::<f64>() / means.len() as f64;
        means.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / means.len() as f64
    };
    let best = |from: f64, to: f64, step: f64| {
        let n = ((to - from) / step).round() as usize;
        (0..=n)
            .map(|i| from + i as f64 * step)
            .max_by(|a, b| score(*a).total_cmp(&score(*b)))
            .unwrap()
    };
    let coarse = best(0.0, 179.5, 0.5);
    best(coarse - 0.5, coarse + 0.5, 0.02).rem_euclid(180.0)
}

#[test]
fn hatch_lines_and_lic_streaks_follow_a_constant_field() {
    // Hatching draws lines along the long axis; LIC smears white noise along it.
    let cases = [
        ("hatch", &[0.0f64, 30.0, 75.0, 120.0][..], 512),
        ("lic", &[30.0, 120.0][..], 384),
    ];
    for (look, angles, size) in cases {
        for &angle in angles {
            let field = analytic(
                &format!("constant:angle={angle},anisotropy=3,size=0.03"),
                256,
                256,
            );
            let s = sampled(&field);
            let img = draw(&Look::named(look).unwrap(), &s, &field, None, (size, size));
            let found = line_direction(&img);
            let off = (found - angle).rem_euclid(180.0);
            let off = off.min(180.0 - off);
            assert!(
                off <= 2.0,
                "{look}, field at {angle}°: lines at {found:.2}°"
            );
        }
    }
}

fn flat_photo(value: u8, w: u32, h: u32) -> DynamicImage {
    DynamicImage::ImageRgb8(RgbImage::from_pixel(w, h, image::Rgb([value; 3])))
}

fn render_photo(photo: &DynamicImage, look: &str, w: usize, h: usize) -> RgbImage {
    let (_, metric) = field::photo_metric(photo, &field::MetricParams::default());
    let s = sampled(&metric);
    draw(
        &Look::named(look).unwrap(),
        &s,
        &metric,
        Some(photo),
        (w, h),
    )
}

#[test]
fn black_and_white_photos_give_the_expected_colours() {
    let white = flat_photo(255, 120, 80);
    let black = flat_photo(0, 120, 80);
    let paper = [247, 243, 232];
    for look in Look::NAMES {
        // The most frequent colour: cells, paper or glyph fill (borders and lines are thin).
        let (on_white, on_black) = match look {
            "mosaic" | "glyphs" | "stroke" => ([255; 3], [0; 3]),
            // Black is inked twice over (darker than one layer of ink can be).
            "hatch" | "crosshatch" | "stipple" | "engraving" => (paper, [0; 3]),
            // The line is the cell's own colour, darkened: black on black.
            "line" => (paper, [0; 3]),
            // Threads darken and lighten the colour: only black stays exactly black.
            _ => ([0; 3], [0; 3]),
        };
        let img = render_photo(&white, look, 120, 80);
        if on_white != [0; 3] {
            assert_eq!(mode(&img), on_white, "{look} on white");
        } else {
            let mean = mean_rgb(&img);
            assert!(mean.iter().all(|&v| v > 150.0), "{look} on white: {mean:?}");
        }
        let img = render_photo(&black, look, 120, 80);
        assert_eq!(mode(&img), on_black, "{look} on black");
    }
    // Hatch on white has no ink at all.
    let img = render_photo(&white, "hatch", 60, 40);
    assert!(img.pixels().all(|p| p.0 == paper));
}

#[test]
fn the_engraving_reads_as_dark_as_the_photo_under_its_ink() {
    // Its ink is [20, 18, 16]: lighter greys take ink and paper in proportion; from a little
    // above the ink down to black the lines leave slits of paper in proportion to the tone and
    // their ink darkens to keep it. Seen from afar (the mean of the encoding, as the look mixes
    // ink and paper), each reads as its grey. (Before, the lines merged into the ink itself
    // from about 30 down to it, and every grey there read as the ink.)
    for value in [0u8, 6, 12, 20, 26, 32, 48, 96] {
        let img = render_photo(&flat_photo(value, 120, 80), "engraving", 120, 80);
        let mean = mean_rgb(&img)[1];
        assert!(
            (mean - f64::from(value)).abs() < 4.0,
            "grey {value} reads {mean:.1}"
        );
    }
}

/// The most frequent pixel value.
fn mode(img: &RgbImage) -> [u8; 3] {
    let mut counts = std::collections::BTreeMap::new();
    for p in img.pixels() {
        *counts.entry(p.0).or_insert(0usize) += 1;
    }
    counts.into_iter().max_by_key(|&(_, n)| n).unwrap().0
}

fn mean_rgb(img: &RgbImage) -> [f64; 3] {
    let mut s = [0.0; 3];
    for p in img.pixels() {
        for (acc, v) in s.iter_mut().zip(p.0) {
            *acc += f64::from(v);
        }
    }
    let n = f64::from(img.width() * img.height());
    s.map(|v| v / n)
}

#[test]
fn odd_sizes_render() {
    for (w, h) in [(1, 40), (40, 1), (3, 3), (2, 2)] {
        let field = analytic("two-point-load", w, h);
        let s = sampled(&field);
        for look in Look::NAMES {
            for (ow, oh) in [(w, h), (w * 3, h * 3)] {
                let img = draw_at(
                    &Look::named(look).unwrap(),
                    &s,
                    &field,
                    None,
                    RenderSize {
                        width: ow,
                        height: oh,
                        supersample: 3,
                    },
                );
                assert_eq!(
                    (img.width(), img.height()),
                    (ow as u32, oh as u32),
                    "{look}"
                );
            }
        }
    }
}

#[test]
fn looks_match_their_reference_pictures() {
    let field = analytic("two-point-load", 120, 80);
    let s = sampled(&field);
    for look in Look::NAMES {
        let img = draw(&Look::named(look).unwrap(), &s, &field, None, (150, 100));
        common::check_reference(
            &img,
            &Path::new("tests/references").join(format!("{look}.png")),
            6,
        );
    }
}

#[test]
fn same_seed_same_picture_at_any_thread_count() {
    let field = analytic("degenerate-point", 160, 120);
    let s = sampled(&field);
    let draw = |look: &str| draw(&Look::named(look).unwrap(), &s, &field, None, (200, 150));
    for look in Look::NAMES {
        let many = draw(look);
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| draw(look));
        assert!(many == one, "{look} differs with one thread");
    }
}

#[test]
fn pixel_ink_follows_the_photo_within_cells() {
    use anisopaint::render::looks::texture::{Ink, TextureKind, TextureParams};
    // Left half red, right half blue, with a vertical stripe texture so the metric has a
    // direction: hatch ink should be red on the left and blue on the right.
    let photo = DynamicImage::ImageRgb8(RgbImage::from_fn(160, 100, |x, _| {
        let stripe = if (x / 3) % 2 == 0 { 40 } else { 0 };
        if x < 80 {
            image::Rgb([200 - stripe, 20, 20])
        } else {
            image::Rgb([20, 20, 200 - stripe])
        }
    }));
    let (_, metric) = field::photo_metric(&photo, &field::MetricParams::default());
    let s = sampled(&metric);
    let look = Look::Texture(TextureParams {
        ink: Ink::Pixel(0.2),
        ..TextureParams::for_kind(TextureKind::Hatch)
    });
    let img = draw(&look, &s, &metric, Some(&photo), (160, 100));
    // The darkest pixels of each side are its ink.
    let darkest = |x0: u32, x1: u32| {
        (x0..x1)
            .flat_map(|x| (0..100).map(move |y| (x, y)))
            .map(|(x, y)| img.get_pixel(x, y).0)
            .min_by_key(|p| u32::from(p[0]) + u32::from(p[1]) + u32::from(p[2]))
            .unwrap()
    };
    let (left, right) = (darkest(5, 60), darkest(100, 155));
    assert!(left[0] > left[2] + 40, "left ink {left:?}");
    assert!(right[2] > right[0] + 40, "right ink {right:?}");
}

#[test]
fn brush_strokes_over_an_underpainting_leave_no_paper() {
    use anisopaint::render::looks::glyphs::{GlyphParams, Shape};
    let photo = image::open("samples/chelsea.png").unwrap();
    let input = Input::Photo("samples/chelsea.png".into());
    let field = input::load_field(&input, &FieldOptions::default())
        .unwrap()
        .metric;
    let s = sampled(&field);
    let magenta = [255, 0, 255];
    for (underpaint, scale) in [(true, 0.8), (true, 1.4), (false, 0.8)] {
        let look = Look::Glyphs(GlyphParams {
            shape: Shape::Brush,
            underpaint,
            scale,
            background: magenta,
            ..GlyphParams::default()
        });
        let img = draw(&look, &s, &field, Some(&photo), (451, 300));
        let paper = img.pixels().filter(|p| p.0 == magenta).count();
        if underpaint {
            assert_eq!(
                paper, 0,
                "scale {scale}: the underpainting covers everything"
            );
            // The strokes keep the photo's colours.
            let (a, b) = (mean_rgb(&img), mean_rgb(&photo.to_rgb8()));
            for c in 0..3 {
                assert!(
                    (a[c] - b[c]).abs() < 12.0,
                    "channel {c}: {} vs {}",
                    a[c],
                    b[c]
                );
            }
        } else {
            assert!(paper > 1000, "small strokes alone leave paper showing");
        }
    }
}

/// `img` shrunk by a whole `factor` with a box filter.
fn box_shrunk(img: &RgbImage, factor: u32) -> RgbImage {
    RgbImage::from_fn(img.width() / factor, img.height() / factor, |x, y| {
        let mut sum = [0u32; 3];
        for j in 0..factor {
            for i in 0..factor {
                let p = img.get_pixel(x * factor + i, y * factor + j).0;
                for k in 0..3 {
                    sum[k] += u32::from(p[k]);
                }
            }
        }
        image::Rgb(sum.map(|s| (s / (factor * factor)) as u8))
    })
}

/// Mean absolute difference of two pictures of one size, per channel value.
fn mean_difference(a: &RgbImage, b: &RgbImage) -> f64 {
    let total: u64 = a
        .as_raw()
        .iter()
        .zip(b.as_raw())
        .map(|(&p, &q)| u64::from(p.abs_diff(q)))
        .sum();
    total as f64 / a.as_raw().len() as f64
}

#[test]
fn fabric_and_lic_keep_their_texture_at_large_sizes() {
    // One sampling of a photo of rings, painted at 1200 × 900 (the largest size whose LIC runs
    // on the output's own pixels: a 1500 px diagonal) and at twice that, shrunk back. The
    // large painting's threads and streaks must be the small one's, only finer: the same
    // picture seen whole. When the kernel and the threads were lengths in output pixels, the
    // large painting's threads were half as long and thick, relative to the picture (at 12 MP
    // a cross at every sample over the blurred photo), and the two differed by 3.2 (fabric)
    // and 7.5 (lic) levels on average; now 0.3 and 1.1.
    let photo = DynamicImage::ImageRgb8(RgbImage::from_fn(300, 225, |x, y| {
        let (dx, dy) = (f64::from(x) - 140.0, f64::from(y) - 100.0);
        let v = 128.0 + 90.0 * ((dx * dx + dy * dy).sqrt() / 9.0).sin();
        image::Rgb([v as u8, (0.8 * v) as u8, (0.6 * v + 40.0) as u8])
    }));
    let (_, metric) = field::photo_metric(&photo, &field::MetricParams::default());
    let s = sampled(&metric);
    for look in ["fabric", "lic"] {
        let look_of = Look::named(look).unwrap();
        let small = draw(&look_of, &s, &metric, Some(&photo), (1200, 900));
        let large = draw(&look_of, &s, &metric, Some(&photo), (2400, 1800));
        // Both seen at 600 × 450, where the bilinear reading of the grid no longer shows.
        let difference = mean_difference(&box_shrunk(&small, 2), &box_shrunk(&large, 4));
        assert!(
            difference < 1.5,
            "{look}: 2400 × 1800 differs from 1200 × 900 by {difference:.2} on average, seen whole"
        );
    }
}

/// How much of a painting is the mosaic's leading: the mean share of the way each pixel went
/// from `bare`, its glass without leading ([`glass_under`]), towards the leading's colour (linear in
/// the ink's coverage, as a count of dark pixels is not).
fn leading_share(img: &RgbImage, bare: &RgbImage) -> f64 {
    leading_share_towards(img, bare, [0x2a, 0x25, 0x21])
}

/// [`leading_share`] for leading of colour `lead`.
fn leading_share_towards(img: &RgbImage, bare: &RgbImage, lead: [u8; 3]) -> f64 {
    let luminance = |p: &image::Rgb<u8>| {
        let [r, g, b] = p.0.map(f64::from);
        0.2126 * r + 0.7152 * g + 0.0722 * b
    };
    let lead = luminance(&image::Rgb(lead));
    let total: f64 = img
        .pixels()
        .zip(bare.pixels())
        .map(|(p, q)| {
            let (l, l0) = (luminance(p), luminance(q));
            ((l0 - l) / (l0 - lead).max(1.0)).clamp(0.0, 1.0)
        })
        .sum();
    total / (f64::from(img.width()) * f64::from(img.height()))
}

#[test]
fn mosaic_leading_runs_along_every_border_of_the_cells() {
    // A real photo's mosaic at its own size: across every pair of neighbouring pixels that
    // the label map gives to different cells, the leading must show on one of the two (its
    // coverage measured in linear light against the cell's glass without leading,
    // `glass_under`, where the glass is light enough to tell), and, between cells that take
    // the full width, show clearly: 1.5 px of leading centred on the border covers at least
    // one of the two 0.75 or more (small cells' leading narrows to 0.6 px, which covers each
    // side about 0.3). The borders are the cell map's, placed by secants of `D_k − D_i`
    // between the pixel centres. Measured on chelsea: 9 of 47 378 pairs covered under 0.15, 2
    // of the 10 373 between large cells under 0.6. (Measured as a share of the encoded
    // lightness instead, 4 and 178, and with uniform 1.5 px leading and the runner-up's border
    // only, tangent distances, no border where the search kept no runner-up: 3.0 % of all
    // pairs under 0.3, 8.7 % faint; with the map's distance there but tangents elsewhere:
    // 0.13 % and 6.3 %.)
    let photo =
        image::open(Path::new(env!("CARGO_MANIFEST_DIR")).join("samples/chelsea.png")).unwrap();
    let paint = |sets: &[String], labels: bool| {
        let mut preset = anisopaint::style::load("mosaic").unwrap();
        anisopaint::style::apply_sets(&mut preset, sets).unwrap();
        let recipe =
            anisopaint::paint::Recipe::from_preset(&preset, Default::default(), Some(1)).unwrap();
        let loaded = input::photo_field(photo.clone(), &recipe.field.metric);
        let extras = anisopaint::paint::Extras { svg: false, labels };
        anisopaint::paint::paint_loaded(&loaded, &recipe, extras, &anisopaint::progress::Silent)
            .unwrap()
    };
    let painted = paint(&["look.relief=0".to_string()], true);
    let (img, labels) = (&painted.image, painted.labels.unwrap());
    let bare = glass_under(img, &labels);
    let w = img.width() as usize;
    let lead = [0x2a, 0x25, 0x21].map(f64::from);
    // Ink of pixel k: how far it moved from its glass's colour towards the leading's, in linear
    // light, where the leading is mixed (so the share is its coverage whatever the glass's
    // lightness), on the channel where the two differ most; `None` where they are too close
    // to tell (20 levels of the encoding).
    let linear = |v: f64| {
        let v = v / 255.0;
        if v <= 0.04045 {
            v / 12.92
        } else {
            ((v + 0.055) / 1.055).powf(2.4)
        }
    };
    let ink = |k: usize| {
        let (x, y) = ((k % w) as u32, (k / w) as u32);
        let (p, q) = (img.get_pixel(x, y).0, bare.get_pixel(x, y).0);
        let c = (0..3)
            .max_by(|&a, &b| {
                (f64::from(q[a]) - lead[a])
                    .abs()
                    .total_cmp(&(f64::from(q[b]) - lead[b]).abs())
            })
            .unwrap();
        let (p, q, l) = (f64::from(p[c]), f64::from(q[c]), lead[c]);
        ((q - l).abs() > 20.0).then(|| (linear(q) - linear(p)) / (linear(q) - linear(l)))
    };
    // Cells smaller than the picture's median take thinner leading (`leading_widths`): the
    // clear ink is asked of borders between cells of at least twice the median area.
    let mut area = vec![0usize; labels.iter().max().map_or(0, |&l| l as usize + 1)];
    for &l in &labels {
        area[l as usize] += 1;
    }
    let median_area = {
        let mut sorted: Vec<usize> = area.iter().copied().filter(|&a| a > 0).collect();
        sorted.sort_unstable();
        sorted[sorted.len() / 2]
    };
    let large = |l: i32| area[l as usize] >= 2 * median_area;
    let (mut pairs, mut uninked) = (0, 0);
    let (mut large_pairs, mut faint) = (0, 0);
    for k in 0..labels.len() {
        let x = k % w;
        for n in [
            (x + 1 < w).then(|| k + 1),
            (k + w < labels.len()).then(|| k + w),
        ] {
            let Some(n) = n.filter(|&n| labels[n] != labels[k]) else {
                continue;
            };
            if let (Some(a), Some(b)) = (ink(k), ink(n)) {
                pairs += 1;
                uninked += usize::from(a.max(b) < 0.15);
                if large(labels[k]) && large(labels[n]) {
                    large_pairs += 1;
                    faint += usize::from(a.max(b) < 0.6);
                }
            }
        }
    }
    assert!(pairs > 10_000, "{pairs} borders measured");
    assert!(
        uninked * 200 < pairs,
        "{uninked} of {pairs} borders without leading"
    );
    assert!(large_pairs > 2_000, "{large_pairs} borders of large cells");
    assert!(
        faint * 200 < large_pairs,
        "{faint} of {large_pairs} borders of large cells with faint leading"
    );
}

/// `photo` painted with the built-in mosaic and `sets`, seed 1, without relief (each cell one
/// flat glass colour), and its glass without the leading ([`glass_under`]).
fn mosaic_of(photo: DynamicImage, sets: &[String]) -> (RgbImage, RgbImage) {
    let mut sets = sets.to_vec();
    sets.push("look.relief=0".to_string());
    let (image, labels) = mosaic_labelled(photo, &sets);
    let glass = glass_under(&image, &labels);
    (image, glass)
}

/// `photo` painted with the built-in mosaic and `sets`, seed 1, and its label map.
fn mosaic_labelled(photo: DynamicImage, sets: &[String]) -> (RgbImage, Vec<i32>) {
    let mut preset = anisopaint::style::load("mosaic").unwrap();
    anisopaint::style::apply_sets(&mut preset, sets).unwrap();
    let recipe =
        anisopaint::paint::Recipe::from_preset(&preset, Default::default(), Some(1)).unwrap();
    let loaded = input::photo_field(photo, &recipe.field.metric);
    let extras = anisopaint::paint::Extras {
        svg: false,
        labels: true,
    };
    let painted =
        anisopaint::paint::paint_loaded(&loaded, &recipe, extras, &anisopaint::progress::Silent)
            .unwrap();
    (painted.image, painted.labels.unwrap())
}

/// The glass of a mosaic painted without relief, as it would be without its leading: every
/// pixel in its cell's lightest colour (the leading only darkens the cell's one colour), read
/// on the cell's pixels whose four neighbours are of the same cell where it has any (a pixel
/// on a border may show its neighbour's glass). A painting with `look.border_width=0` is no
/// such reference: the glass is lifted by the share of it the leading covers
/// (`lit_through_leading`), so without leading it is darker.
fn glass_under(img: &RgbImage, labels: &[i32]) -> RgbImage {
    let luminance =
        |p: [u8; 3]| 0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2]);
    let (w, h) = (img.width() as usize, img.height() as usize);
    let cells = labels.iter().max().map_or(0, |&l| l as usize + 1);
    // Per cell, the lightest colour of its inner pixels and of all its pixels.
    let mut inner: Vec<Option<[u8; 3]>> = vec![None; cells];
    let mut any = vec![[0u8; 3]; cells];
    for y in 0..h {
        for x in 0..w {
            let (k, l) = (y * w + x, labels[y * w + x]);
            let p = img.get_pixel(x as u32, y as u32).0;
            let cell = l as usize;
            if luminance(p) > luminance(any[cell]) {
                any[cell] = p;
            }
            let alone = x > 0
                && y > 0
                && x + 1 < w
                && y + 1 < h
                && [k - 1, k + 1, k - w, k + w].iter().all(|&n| labels[n] == l);
            if alone && inner[cell].is_none_or(|q| luminance(p) > luminance(q)) {
                inner[cell] = Some(p);
            }
        }
    }
    RgbImage::from_fn(img.width(), img.height(), |x, y| {
        let cell = labels[y as usize * w + x as usize] as usize;
        image::Rgb(inner[cell].unwrap_or(any[cell]))
    })
}

/// A light photo of coloured rings at `w × h`, the same picture at any size.
fn leading_photo(w: u32, h: u32) -> DynamicImage {
    let s = 1200.0 / f64::from(w);
    DynamicImage::ImageRgb8(RgbImage::from_fn(w, h, |x, y| {
        let (dx, dy) = (f64::from(x) * s - 560.0, f64::from(y) * s - 400.0);
        let t = ((dx * dx + dy * dy).sqrt() / 36.0).sin();
        let u = (f64::from(x) * s / 150.0).cos();
        image::Rgb([
            (180.0 + 60.0 * t) as u8,
            (170.0 + 50.0 * u) as u8,
            (150.0 - 40.0 * t) as u8,
        ])
    }))
}

#[test]
fn mosaic_leading_keeps_its_share_of_the_picture_at_large_sizes() {
    // The same photo painted at 1200 × 900 (a 1500 px diagonal, where the leading is its
    // preset's 1.5 px) and at twice that: the cells are the same share of the picture, so the
    // leading must be too. Measured: 0.107 against 0.090 (ratio 1.19; against the painting
    // without leading before the glass was lifted, 0.130 and 0.116). When its width was pixels
    // at any size, the ratio was about 0.5 (a 12 MP mosaic seen whole showed next to none).
    let share = |w, h| {
        let (led, glass) = mosaic_of(leading_photo(w, h), &[]);
        leading_share(&led, &glass)
    };
    let (small, large) = (share(1200, 900), share(2400, 1800));
    assert!(small > 0.02, "the leading shows at 1200 × 900: {small:.4}");
    let ratio = large / small;
    assert!(
        (0.85..1.25).contains(&ratio),
        "leading share {large:.4} at 2400 × 1800 against {small:.4} at 1200 × 900"
    );
}

/// A column of print beside a plain twice as wide: dark strokes two pixels wide every six on
/// the left third (small type, whose cells come out small), a light gradient on the rest
/// (large cells).
fn print_photo(w: u32, h: u32) -> DynamicImage {
    DynamicImage::ImageRgb8(RgbImage::from_fn(w, h, |x, y| {
        let v = if x < w / 3 {
            let stroke = (x % 6 < 2 && y % 14 < 10) || (y % 14 < 2 && x % 18 < 12);
            if stroke {
                40
            } else {
                225
            }
        } else {
            (200 + 30 * y / h) as u8
        };
        image::Rgb([v, v, v])
    }))
}

#[test]
fn small_cells_take_thin_leading() {
    // Where the cells are small (print), leading of the full width would cover most of them;
    // it narrows with the cell (down to 0.4 of the width), while the large cells of the plain
    // keep the full width. Black leading, whose colour no glass darkens further (the preset's
    // is kept no lighter than half the glass beside it, and along the print's dark strokes
    // that darkening would count as more leading): 0.135 of the print's tone is leading
    // (0.374 at the full width), 0.049 of the plain's.
    let sets = ["look.border_colour=#000000".to_string()];
    let (led, bare) = mosaic_of(print_photo(900, 300), &sets);
    let half = |img: &RgbImage, left: bool| {
        image::imageops::crop_imm(img, if left { 20 } else { 470 }, 20, 260, 260).to_image()
    };
    let share = |left| leading_share_towards(&half(&led, left), &half(&bare, left), [0; 3]);
    let (print, plain) = (share(true), share(false));
    assert!(plain > 0.03, "the plain's leading shows: {plain:.4}");
    assert!(
        print < 0.2,
        "leading over the print {print:.4} (plain {plain:.4})"
    );
}

#[test]
fn a_thumbnails_cells_are_not_all_leading() {
    // The cell count does not grow with the picture, so a thumbnail's cells are a few pixels
    // across, and leading of the preset's 1.5 px covered most of them: at 160 × 120 it took
    // 0.36 of the picture's tone (0.21 at 480 × 360, 0.09 at 1200 × 900). It is now no wider
    // than half the short semi-axis of the cells covering most of the picture, nor under a
    // pixel. Measured: 0.24.
    let (led, glass) = mosaic_of(leading_photo(160, 120), &[]);
    let share = leading_share(&led, &glass);
    assert!(share > 0.1, "the leading still shows: {share:.4}");
    assert!(share < 0.3, "leading share of a thumbnail {share:.4}");
}

/// A wood-like photo: bands of light and dark brown across the picture, under a grain of
/// ±24 levels that changes every pixel (a hash of its position).
fn grained_photo(w: u32, h: u32) -> DynamicImage {
    DynamicImage::ImageRgb8(RgbImage::from_fn(w, h, |x, y| {
        let band = ((f64::from(x) + 0.6 * f64::from(y)) / 9.0).sin();
        let hash = (x.wrapping_mul(73_856_093) ^ y.wrapping_mul(19_349_663)) % 49;
        let grain = f64::from(hash) - 24.0;
        let v = |base: f64, k: f64| (base + k * band + grain).clamp(0.0, 255.0) as u8;
        image::Rgb([v(170.0, 40.0), v(110.0, 30.0), v(60.0, 20.0)])
    }))
}

#[test]
fn relief_lights_each_cell_as_a_smooth_dome() {
    // The relief lights each cell as a dome over its ellipse: within a cell the shading is
    // linear in the position, whatever the photo's grain under it (the glass is the cell's
    // one colour), so no pixel inside a cell is lighter or darker than all four of its
    // neighbours. The slope was once scaled by the owner's distance with the colour term over
    // the geometric one, so a grained pixel unlike its cell's mean got a slope several times
    // the dome's and showed as a dark or light speck in the glass. Measured, pixels standing
    // out from all four neighbours by over 8 levels: 5 of 52 826 (95 with the scaled slope).
    let sets = ["look.relief=0.5", "look.border_width=0"].map(String::from);
    let (img, labels) = mosaic_labelled(grained_photo(320, 240), &sets);
    let (w, h) = (img.width() as usize, img.height() as usize);
    let luma = |k: usize| {
        let p = img.get_pixel((k % w) as u32, (k / w) as u32).0;
        0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2])
    };
    let (mut inner, mut specks) = (0usize, 0usize);
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let k = y * w + x;
            let around = [k - 1, k + 1, k - w, k + w];
            if around.iter().any(|&n| labels[n] != labels[k]) {
                continue;
            }
            inner += 1;
            // A dome's shading is linear in the position: no pixel inside the cell is
            // lighter or darker than all four of its neighbours.
            let (here, levels) = (luma(k), around.map(luma));
            let above = levels.iter().all(|&l| here > l + 8.0);
            let below = levels.iter().all(|&l| here < l - 8.0);
            specks += usize::from(above || below);
        }
    }
    let share = specks as f64 / inner as f64;
    assert!(inner > w * h / 2, "{inner} inner pixels");
    assert!(
        share < 0.0005,
        "{:.3} % of the glass is specks",
        100.0 * share
    );
    // Lit from the upper left: within a cell, lighter towards the upper left (the luma falls
    // as x + y grows). Measured: all 498 cells of over 30 pixels; the sign was once the other
    // way (none of them: lighter towards the lower right, the domes read as dishes).
    let cells = labels.iter().max().map_or(0, |&l| l as usize + 1);
    // Per cell: n, Σs, Σl, Σs·l over its pixels, s = x + y.
    let mut sums = vec![[0.0f64; 4]; cells];
    for (k, &l) in labels.iter().enumerate() {
        let (s, v) = (((k % w) + (k / w)) as f64, luma(k));
        let c = &mut sums[l as usize];
        *c = [c[0] + 1.0, c[1] + s, c[2] + v, c[3] + s * v];
    }
    let big: Vec<_> = sums.iter().filter(|c| c[0] > 30.0).collect();
    let lit = big
        .iter()
        .filter(|c| c[3] / c[0] - (c[1] / c[0]) * (c[2] / c[0]) < 0.0)
        .count();
    assert!(
        lit * 20 >= big.len() * 19,
        "{lit} of {} cells lighter towards the upper left",
        big.len()
    );
}
