//! SVG output against independent truths: the traced and simplified cells, filled by
//! tiny-skia with one colour per label and no anti-aliasing, reproduce the label map; and the
//! SVG files `paint --svg` writes, rasterised by resvg (a renderer that shares no code with
//! ours), look like the PNG painted in the same run. Fabric has no vector form: refused
//! before any work, nothing written.

mod common;
use common::Blend;

use anisopaint::input::{self, FieldOptions, Input};
use anisopaint::render::vector::trace::{rings, simplify, Borders};
use anisopaint::render::{label_map, Raster, VoronoiCells};
use anisopaint::sampling::{self, SamplerParams};
use assert_cmd::Command;
use image::RgbImage;
use std::path::Path;

fn bin() -> Command {
    Command::cargo_bin("anisopaint").unwrap()
}

#[test]
fn traced_cells_reproduce_the_label_map() {
    let input = Input::parse("samples/chelsea.png").unwrap();
    let loaded = input::load_field(&input, &FieldOptions::default()).unwrap();
    let field = &loaded.metric;
    let s = sampling::sample(field, &SamplerParams::default()).unwrap();
    let cells = VoronoiCells::new(&s.positions, &s.metrics, &s.mesh);
    let d = field.domain();
    for scale in [1.0, 2.0] {
        let raster = Raster {
            width: (d.x * scale).round() as usize,
            height: (d.y * scale).round() as usize,
            supersample: 1,
            domain: d,
        };
        let labels = label_map(&cells, &raster);
        let borders = Borders::trace(&labels, raster.width, raster.height);
        let simplified: Vec<_> = borders
            .chains
            .iter()
            .map(|c| simplify(&c.points, 0.7))
            .collect();
        let rings = rings(&borders, &simplified, s.positions.len());
        let (w, h) = (raster.width as u32, raster.height as u32);
        let mut pixmap = tiny_skia::Pixmap::new(w, h).unwrap();
        for (label, cell_rings) in rings.iter().enumerate() {
            let mut pb = tiny_skia::PathBuilder::new();
            for ring in cell_rings {
                pb.move_to(ring[0][0], ring[0][1]);
                for p in &ring[1..] {
                    pb.line_to(p[0], p[1]);
                }
                pb.close();
            }
            let Some(path) = pb.finish() else { continue };
            let id = label as u32 + 1;
            let mut paint = tiny_skia::Paint {
                anti_alias: false,
                ..tiny_skia::Paint::default()
            };
            paint.set_color_rgba8((id >> 16) as u8, (id >> 8) as u8, id as u8, 255);
            pixmap.fill_path(
                &path,
                &paint,
                tiny_skia::FillRule::Winding,
                tiny_skia::Transform::identity(),
                None,
            );
        }
        let agree = pixmap
            .pixels()
            .iter()
            .zip(&labels)
            .filter(|(px, &l)| {
                let id = (u32::from(px.red()) << 16)
                    | (u32::from(px.green()) << 8)
                    | u32::from(px.blue());
                id == (l + 1) as u32
            })
            .count();
        let fraction = agree as f64 / labels.len() as f64;
        // Simplification moves borders by at most 0.7 px: only pixels along them may change
        // (measured: 99.0 % keep their cell at scale 1, 99.5 % at scale 2).
        assert!(
            fraction > 0.98,
            "scale {scale}: {:.4} of pixels keep their cell",
            fraction
        );
        // Every cell with pixels got an outline.
        let mut has_pixels = vec![false; s.positions.len()];
        for &l in &labels {
            has_pixels[l as usize] = true;
        }
        for (k, yes) in has_pixels.iter().enumerate() {
            assert!(!yes || !rings[k].is_empty(), "cell {k} has no outline");
        }
    }
}

/// Rasterises an SVG file with resvg at its own size, `k × k` points per pixel averaged in
/// linear light (resvg, like browsers, blends edges in sRGB: at k = 1 a hairline's partial
/// pixels come out darker than its ink coverage).
fn rasterise(svg: &Path, k: u32) -> RgbImage {
    common::rasterise_blended(svg, k, Blend::Linear)
}

/// Fraction of pixels whose channels all lie within `tolerance` levels.
fn close_fraction(a: &RgbImage, b: &RgbImage, tolerance: u8) -> f64 {
    assert_eq!(a.dimensions(), b.dimensions());
    let close = a
        .pixels()
        .zip(b.pixels())
        .filter(|(p, q)| (0..3).all(|c| p.0[c].abs_diff(q.0[c]) <= tolerance))
        .count();
    close as f64 / f64::from(a.width() * a.height())
}

/// Mean absolute difference, in linear light (0 to 1), of the means of 8×8 blocks: the tone
/// a viewer sees, whichever way each edge pixel was anti-aliased.
fn tone_difference(a: &RgbImage, b: &RgbImage) -> f64 {
    tone_difference_blended(a, b, Blend::Linear)
}

fn tone_difference_blended(a: &RgbImage, b: &RgbImage, blend: Blend) -> f64 {
    assert_eq!(a.dimensions(), b.dimensions());
    let (bw, bh) = (a.width() / 8, a.height() / 8);
    let mut total = 0.0;
    for by in 0..bh {
        for bx in 0..bw {
            for c in 0..3 {
                let mean = |img: &RgbImage| {
                    let mut sum = 0.0;
                    for y in by * 8..by * 8 + 8 {
                        for x in bx * 8..bx * 8 + 8 {
                            let v = img.get_pixel(x, y).0[c];
                            sum += match blend {
                                Blend::Linear => common::linear(v),
                                Blend::Encoded => f64::from(v) / 255.0,
                            };
                        }
                    }
                    sum / 64.0
                };
                total += (mean(a) - mean(b)).abs();
            }
        }
    }
    total / f64::from(bw * bh * 3)
}

/// Paints chelsea with `style` (and `extra` arguments) to PNG and SVG; returns both pictures
/// (the SVG rasterised with `k × k` points per pixel) and the SVG text.
fn paint_both(dir: &Path, style: &str, extra: &[&str], k: u32) -> (RgbImage, RgbImage, String) {
    paint_photo_both(dir, Path::new("samples/chelsea.png"), style, extra, k)
}

/// [`paint_both`] of `photo`.
fn paint_photo_both(
    dir: &Path,
    photo: &Path,
    style: &str,
    extra: &[&str],
    k: u32,
) -> (RgbImage, RgbImage, String) {
    let (png, svg) = (
        dir.join(format!("{style}.png")),
        dir.join(format!("{style}.svg")),
    );
    bin()
        .arg("paint")
        .arg(photo)
        .args(["-s", style])
        .args(extra)
        .arg("-o")
        .arg(&png)
        .arg("--svg")
        .arg(&svg)
        .assert()
        .success();
    let text = std::fs::read_to_string(&svg).unwrap();
    (
        image::open(&png).unwrap().to_rgb8(),
        rasterise(&svg, k),
        text,
    )
}

#[test]
fn glyph_svg_draws_the_same_ellipses() {
    let dir = tempfile::tempdir().unwrap();
    let (png, svg, text) = paint_both(dir.path(), "glyphs", &[], 1);
    assert!(
        text.matches("<ellipse").count() > 500,
        "one ellipse per sample"
    );
    // Only the anti-aliased rims of the ellipses may differ (measured: 0.3 % beyond 30).
    let close = close_fraction(&png, &svg, 30);
    assert!(close > 0.99, "{close:.4} of pixels match the PNG");
    let tone = tone_difference(&png, &svg);
    assert!(tone < 0.01, "tone differs by {tone:.4}");
}

#[test]
fn brush_stroke_svg_looks_like_the_png() {
    let dir = tempfile::tempdir().unwrap();
    let (png, svg, text) = paint_both(dir.path(), "strokes", &[], 1);
    assert!(text.matches("<path").count() > 500);
    // Flat strokes stand for the bristled ones over the same traced underpainting, and the
    // SVG lays the strokes the PNG laid: the ones its coarse-to-fine canvas chose, then the
    // detail strokes; the rigger's lines (outlines in the photo's own colour) clip a copy of
    // the photo, so they have the PNG's colours pixel by pixel. Measured: 98.0 % of pixels
    // within 12 levels (95.6 % when the SVG filled each piece of line in a 4 px tile at its
    // mean colour; 94.8 % with the lines left out, as a renderer without raster images
    // draws it); with every stroke drawn once and no detail strokes (the SVG before), 83.3 %.
    assert!(text.contains("clip-path=\"url(#rigger)\" xlink:href=\"data:image/png;base64,"));
    let tone = tone_difference(&png, &svg);
    assert!(tone < 0.008, "tone differs by {tone:.4}");
    let close = close_fraction(&png, &svg, 12);
    assert!(
        close > 0.96,
        "{close:.4} of pixels within 12 levels of the PNG"
    );
}

#[test]
fn mosaic_svg_looks_like_the_png() {
    let dir = tempfile::tempdir().unwrap();
    // Without relief (see `mosaic_svg_keeps_the_relief` for its gradients). Cell
    // interiors match exactly; the leading moves by up to the trace tolerance, and SVG viewers
    // blend its edges in sRGB, not in linear light. Edge-following cells have longer, more
    // winding borders, so more leading pixels move (measured: tone 0.026 and 58 % of pixels
    // within 12 levels, against 0.017 and 66 % for the paper's cells).
    for (cells, least_close) in [("voronoi", 0.6), ("edges", 0.52)] {
        let set = format!("cells.kind={cells}");
        let sets = ["--set", "look.relief=0", "--set", set.as_str()];
        let (png, svg, text) = paint_both(dir.path(), "mosaic", &sets, 1);
        assert!(
            text.matches("<path").count() > 500,
            "{cells}: one path per cell"
        );
        let tone = tone_difference(&png, &svg);
        assert!(tone < 0.03, "{cells}: tone differs by {tone:.4}");
        let close = close_fraction(&png, &svg, 12);
        assert!(
            close > least_close,
            "{cells}: {close:.4} of pixels match the PNG"
        );
    }
}

#[test]
fn mosaic_svg_keeps_the_relief() {
    // The relief's shading is linear in the position within a cell (but for its clamps), and
    // the SVG gives each cell a gradient along it with stops at the site and either side.
    // Without leading, the SVG's glass against the PNG's: measured 77.0 % of pixels within 4
    // levels (92.9 % within 12) with the gradients, 47.0 % (91.5 %) with each cell filled
    // flat at its glass colour.
    let dir = tempfile::tempdir().unwrap();
    let sets = ["--set", "look.border_width=0"];
    let (png, svg, text) = paint_both(dir.path(), "mosaic", &sets, 1);
    assert!(
        text.matches("<linearGradient").count() > 500,
        "a gradient per cell"
    );
    let close = close_fraction(&png, &svg, 4);
    assert!(
        close > 0.7,
        "{close:.4} of pixels within 4 levels of the PNG"
    );
}

#[test]
fn hatch_svg_keeps_the_tones() {
    let dir = tempfile::tempdir().unwrap();
    for style in ["pen-hatch", "crosshatch"] {
        // The hatching alone (the outlines are compared in the test below).
        let sets = ["--set", "outlines.strength=0"];
        let (png, _, text) = paint_both(dir.path(), style, &sets, 1);
        assert!(
            text.matches("<clipPath").count() > 500,
            "vector lines per cell"
        );
        // The same ink coverage: the PNG maps tone to the share of ink in the sRGB encoding,
        // so the SVG, rasterised finely enough that edges hardly count, is averaged the same
        // way (measured: 0.022 and 0.020).
        let svg =
            common::rasterise_blended(&dir.path().join(format!("{style}.svg")), 8, Blend::Encoded);
        let tone = tone_difference_blended(&png, &svg, Blend::Encoded);
        assert!(tone < 0.025, "{style}: tone differs by {tone:.4}");
    }
}

#[test]
fn engraving_stipple_and_outline_svgs_keep_the_tones() {
    let dir = tempfile::tempdir().unwrap();
    // Engraving lines as variable-width outlines, pointillist dots as circles, and pen-hatch
    // with its outlines traced over it: each, rasterised finely and averaged in the encoding
    // as the PNG mixes ink and paper, has the PNG's tones.
    for (style, shape, limit) in [
        // Measured: 0.0048, 0.0110 (the PNG's dots take the photo's colour under each point,
        // the SVG's at their centres; both with the same per-dot jitter), 0.0121 (0.0064 and
        // 0.0141 for the engraving and pen-hatch while the highlights were traced like the
        // outlines, at half their map and full strength).
        ("engraving", "<path fill=", 0.015),
        ("pointillist", "<circle", 0.015),
        ("pen-hatch", "fill-rule=\"evenodd\"", 0.025),
    ] {
        let (png, _, text) = paint_both(dir.path(), style, &[], 1);
        assert!(text.matches(shape).count() > 0, "{style}: no {shape}");
        let svg =
            common::rasterise_blended(&dir.path().join(format!("{style}.svg")), 4, Blend::Encoded);
        let tone = tone_difference_blended(&png, &svg, Blend::Encoded);
        eprintln!("{style}: the SVG's tone differs from the PNG's by {tone:.4}");
        assert!(tone < limit, "{style}: tone differs by {tone:.4}");
    }
}

#[test]
fn dim_highlights_are_in_the_svg_as_in_the_png() {
    // Light lines 1 px wide of grey 120 on a ground of 25, 12 px apart at 30°: their paper is
    // no lighter than the photo there, under half the map, which the outlines' trace at half
    // left out of the SVG. Along the lines, the SVG rasterised has the PNG's tone.
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (240u32, 160u32);
    let across = |x: f64, y: f64| {
        let (s, c) = 30f64.to_radians().sin_cos();
        let d = (x * s - y * c).rem_euclid(12.0);
        d.min(12.0 - d)
    };
    let photo = RgbImage::from_fn(w, h, |x, y| {
        let on = common::covered(x, y, |px, py| across(px, py) < 0.5);
        let v = (25.0 + 95.0 * on).round() as u8;
        image::Rgb([v, v, v])
    });
    let path = dir.path().join("lines.png");
    photo.save(&path).unwrap();
    let (png, _, text) = paint_photo_both(dir.path(), &path, "pen-hatch", &[], 1);
    assert!(text.contains("fill=\"#f7f3e8\" fill-opacity=\"0."));
    let svg = common::rasterise_blended(&dir.path().join("pen-hatch.svg"), 4, Blend::Encoded);
    // The mean over the pixels on the lines, away from the picture's rim.
    let band = |img: &RgbImage| {
        let (w, h) = (f64::from(w), f64::from(h));
        common::mean_where(img, 1, |x, y| {
            x > 10.0 && x < w - 10.0 && y > 10.0 && y < h - 10.0 && across(x, y) < 1.0
        })
    };
    let (on_png, on_svg) = (band(&png), band(&svg));
    eprintln!("along the lines: PNG {on_png:.1}, SVG {on_svg:.1}");
    assert!(
        (on_png - on_svg).abs() < 6.0,
        "along the lines: PNG {on_png:.1}, SVG {on_svg:.1}"
    );
}

#[test]
fn the_engraving_svg_is_as_dark_as_the_png_under_its_ink() {
    // Greys darker than the engraving's ink (#231c14, 29): the raster lays the ink again,
    // darkened to the tone, and so does the SVG, in steps of tone; before, its one ink read 29.
    assert_engraved_greys_alike([6, 16], 4, 4.0);
}

#[test]
fn the_engraving_svg_keeps_the_dark_tones_at_its_own_size() {
    // Greys 30 and 40: the lines leave slits of paper finer than a pixel between them. Drawn
    // at the picture's own size, as a viewer shows it, two lines a hair apart must ink the
    // pixel between them as the raster does; as separate shapes each was blended over the
    // other and grey 30 read 42 (resvg; measured now: 29.7 for the PNG's 29.4, 40.2 for 39.4).
    assert_engraved_greys_alike([30, 40], 1, 3.0);
}

/// A picture of two greys side by side engraved as PNG and SVG; the SVG, drawn by resvg at
/// `k` times the size and averaged back in the encoding, reads within `tolerance` levels of
/// the PNG on each half.
fn assert_engraved_greys_alike(greys: [u8; 2], k: u32, tolerance: f64) {
    let dir = tempfile::tempdir().unwrap();
    let photo = RgbImage::from_fn(240, 160, |x, _| {
        image::Rgb([greys[usize::from(x >= 120)]; 3])
    });
    let path = dir.path().join("dark.png");
    photo.save(&path).unwrap();
    let (png, _, _) = paint_photo_both(dir.path(), &path, "engraving", &[], 1);
    let svg = common::rasterise_blended(&dir.path().join("engraving.svg"), k, Blend::Encoded);
    for (x0, x1) in [(20.0, 100.0), (140.0, 220.0)] {
        let mean = |img: &RgbImage| {
            common::mean_where(img, 1, |x, y| x > x0 && x < x1 && y > 20.0 && y < 140.0)
        };
        let (a, b) = (mean(&png), mean(&svg));
        assert!(
            (a - b).abs() < tolerance,
            "greys {greys:?}, x {x0}..{x1}: PNG {a:.1}, SVG {b:.1}"
        );
    }
}

#[test]
fn outline_svg_is_no_lighter_than_the_black_it_lies_on() {
    // A black disc on white in pen-hatch: the outlines lie inside its rim, on black, where the
    // PNG darkens their ink to black; the SVG's pieces of line take their ink darkened to the
    // mean photo colour under them. Measured: PNG 0.0, SVG 6.9 (a piece's mean takes in the
    // rim's grey pixels); in the one ink 23.5.
    let dir = tempfile::tempdir().unwrap();
    let (c, radius) = (100.0, 60.0);
    let photo = RgbImage::from_fn(200, 200, |x, y| {
        let on = common::covered(x, y, |px, py| (px - c).hypot(py - c) < radius);
        let v = (255.0 * (1.0 - on)).round() as u8;
        image::Rgb([v, v, v])
    });
    let path = dir.path().join("disc.png");
    photo.save(&path).unwrap();
    let (png, _, _) = paint_photo_both(dir.path(), &path, "pen-hatch", &[], 1);
    let svg = common::rasterise_blended(&dir.path().join("pen-hatch.svg"), 4, Blend::Encoded);
    let rim = |img: &RgbImage| {
        common::mean_where(img, 0, |x, y| {
            ((radius - 3.0)..(radius - 1.0)).contains(&(x - c).hypot(y - c))
        })
    };
    let (a, b) = (rim(&png), rim(&svg));
    eprintln!("rim: PNG {a:.1}, SVG {b:.1}");
    assert!(b < a + 10.0, "rim: PNG {a:.1}, SVG {b:.1}");
}

#[test]
fn hatch_svg_lines_follow_the_field() {
    // A constant field at 30°: every vector line of the SVG runs at 30° (y down on screen).
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("c.svg");
    bin()
        .args([
            "render",
            "analytic:constant:angle=30,anisotropy=4,size=0.02",
            "--width",
            "300",
            "--height",
            "200",
            "--look",
            "hatch",
            "-o",
        ])
        .arg(dir.path().join("c.png"))
        .arg("--svg")
        .arg(&svg)
        .assert()
        .success();
    let text = std::fs::read_to_string(&svg).unwrap();
    let mut angles = Vec::new();
    for part in text.split(r#"fill="none" stroke=""#).skip(1) {
        let d = part
            .split(r#" d=""#)
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap();
        for segment in d.split('M').filter(|s| !s.is_empty()) {
            let v: Vec<f64> = segment
                .split_whitespace()
                .map(|x| x.parse().unwrap())
                .collect();
            angles.push(
                (v[3] - v[1])
                    .atan2(v[2] - v[0])
                    .to_degrees()
                    .rem_euclid(180.0),
            );
        }
    }
    assert!(angles.len() > 100, "{} lines", angles.len());
    // Coordinates carry one decimal: long segments keep the angle within a few tenths.
    assert!(
        angles.iter().all(|a| (a - 30.0).abs() < 0.5),
        "{:?}",
        &angles[..10]
    );
}

#[test]
fn fabric_has_no_vector_form() {
    let dir = tempfile::tempdir().unwrap();
    let run = bin()
        .args(["paint", "samples/chelsea.png", "-s", "fabric", "-o"])
        .arg(dir.path().join("f.png"))
        .arg("--svg")
        .arg(dir.path().join("f.svg"))
        .assert()
        .code(2);
    let stderr = common::stderr_of(&run);
    assert!(stderr.contains("no vector form"), "{stderr}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn an_svg_output_name_writes_the_vector_form_only() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("only.svg");
    bin()
        .args(["paint", "samples/chelsea.png", "-s", "glyphs", "-o"])
        .arg(&out)
        .assert()
        .success();
    assert_eq!(rasterise(&out, 1).dimensions(), (451, 300));
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    // A format we do not write is refused before any work.
    let run = bin()
        .args(["paint", "samples/chelsea.png", "-o"])
        .arg(dir.path().join("x.bmp"))
        .assert()
        .code(2);
    let stderr = common::stderr_of(&run);
    assert!(stderr.contains(".bmp"), "{stderr}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}
