//! `anisopaint render` through the real binary: every look writes a picture of the asked size,
//! the label map is a valid int32 .npy indexing samples.csv, samples can be reused, and bad
//! options and bad sample files fail with exit code 2 and no output.

mod common;

use assert_cmd::Command;
use std::path::Path;

fn bin() -> Command {
    Command::cargo_bin("anisopaint").unwrap()
}

fn size_of(path: &Path) -> (u32, u32) {
    image::image_dimensions(path).unwrap()
}

#[test]
fn every_look_renders_at_the_asked_size() {
    let dir = tempfile::tempdir().unwrap();
    for look in anisopaint::render::Look::NAMES {
        let out = dir.path().join(format!("{look}.png"));
        bin()
            .args([
                "render",
                "analytic:circular",
                "--width",
                "90",
                "--height",
                "60",
            ])
            .args(["--look", look, "--scale", "1.5", "-o"])
            .arg(&out)
            .assert()
            .success();
        assert_eq!(size_of(&out), (135, 90), "{look}");
        // Something was drawn: the circular field's cells differ in colour and shape.
        let colours = common::distinct_colours(&out);
        assert!(colours > 20, "{look}: {colours} colours");
    }
    let out = dir.path().join("w.png");
    bin()
        .args(["render", "samples/chelsea.png", "--out-width", "200", "-o"])
        .arg(&out)
        .assert()
        .success();
    let (w, h) = size_of(&out);
    assert_eq!(w, 200);
    assert!((h as i32 - 133).abs() <= 1, "{h}");
    assert!(common::distinct_colours(&out) > 100);
}

#[test]
fn labels_index_the_samples_and_samples_are_reused() {
    let dir = tempfile::tempdir().unwrap();
    let (samples, labels, a, b) = (
        dir.path().join("s.csv"),
        dir.path().join("l.npy"),
        dir.path().join("a.png"),
        dir.path().join("b.png"),
    );
    bin()
        .args(["sample", "samples/coffee.png", "--seed", "4", "--out"])
        .arg(&samples)
        .assert()
        .success();
    let rows = std::fs::read_to_string(&samples).unwrap().lines().count() - 1;
    bin()
        .args([
            "render",
            "samples/coffee.png",
            "--look",
            "mosaic",
            "--samples",
        ])
        .arg(&samples)
        .arg("--labels")
        .arg(&labels)
        .arg("-o")
        .arg(&a)
        .assert()
        .success();
    let bytes = std::fs::read(&labels).unwrap();
    let npy = npyz::NpyFile::new(&bytes[..]).unwrap();
    assert_eq!(npy.shape(), &[400, 600]);
    let values: Vec<i32> = npy.into_vec().unwrap();
    assert!(values.iter().all(|&v| v >= 0 && (v as usize) < rows));
    // Most samples own some pixel.
    let mut owned = vec![false; rows];
    for &v in &values {
        owned[v as usize] = true;
    }
    assert!(owned.iter().filter(|&&o| o).count() as f64 > 0.95 * rows as f64);
    // Sampling again with the same seed gives the same picture as reusing the samples.
    bin()
        .args([
            "render",
            "samples/coffee.png",
            "--look",
            "mosaic",
            "--seed",
            "4",
            "-o",
        ])
        .arg(&b)
        .assert()
        .success();
    let (ia, ib) = (image::open(&a).unwrap(), image::open(&b).unwrap());
    let differing = ia
        .to_rgb8()
        .pixels()
        .zip(ib.to_rgb8().pixels())
        .filter(|(p, q)| p != q)
        .count();
    // The CSV rounds nothing away (full f64 text), but the metrics there are the full-field
    // ones, as the renderer gets them from the sampler: the same picture.
    assert_eq!(differing, 0);
}

#[test]
fn bad_options_and_bad_samples_exit_2_without_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.png");
    let bad_csv = dir.path().join("bad.csv");
    std::fs::write(&bad_csv, "x,y,m11,m12,m22\n1,2,3,0,3\n4,5,nan,0,1\n").unwrap();
    let outside = dir.path().join("outside.csv");
    std::fs::write(
        &outside,
        "x,y,m11,m12,m22\n1,2,3,0,3\n4,5,3,0,3\n9000,5,3,0,3\n",
    )
    .unwrap();
    let cases: Vec<Vec<String>> = vec![
        vec!["--look".into(), "watercolour".into()],
        vec!["--scale".into(), "0".into()],
        vec!["--scale".into(), "1000".into()],
        vec!["--supersample".into(), "9".into()],
        vec!["--samples".into(), bad_csv.display().to_string()],
        vec!["--samples".into(), outside.display().to_string()],
        vec!["--samples".into(), "missing.csv".into()],
    ];
    for extra in cases {
        let assert = bin()
            .args(["render", "samples/chelsea.png", "-o"])
            .arg(&out)
            .args(&extra)
            .assert()
            .code(2);
        let stderr = String::from_utf8_lossy(&assert.get_output().stderr).to_string();
        // Our own errors are one line; clap's usage errors (an unknown look) explain more.
        if extra[0] != "--look" {
            assert_eq!(stderr.trim().lines().count(), 1, "{extra:?}: {stderr}");
        }
        assert!(!out.exists(), "{extra:?} left an output");
    }
    let assert = bin()
        .args(["render", "samples/chelsea.png", "-o"])
        .arg(&out)
        .arg("--samples")
        .arg(&bad_csv)
        .assert()
        .code(2);
    let stderr = String::from_utf8_lossy(&assert.get_output().stderr).to_string();
    assert!(stderr.contains("bad.csv:3"), "{stderr}");
}

#[test]
fn texture_tiles_and_glyph_placements() {
    let dir = tempfile::tempdir().unwrap();
    let tile = dir.path().join("tile.png");
    // A vertical ramp: ink coverage from 0 to 1 across the tile.
    image::GrayImage::from_fn(16, 16, |_, y| image::Luma([(y * 16) as u8]))
        .save(&tile)
        .unwrap();
    let out = dir.path().join("t.png");
    bin()
        .args([
            "render",
            "samples/chelsea.png",
            "--look",
            "hatch",
            "--texture",
        ])
        .arg(&tile)
        .arg("-o")
        .arg(&out)
        .assert()
        .success();
    assert_eq!(size_of(&out), (451, 300));
    let refused = dir.path().join("m.png");
    bin()
        .args([
            "render",
            "samples/chelsea.png",
            "--look",
            "mosaic",
            "--texture",
        ])
        .arg(&tile)
        .arg("-o")
        .arg(&refused)
        .assert()
        .code(2);
    assert!(!refused.exists());
    for placement in ["relaxed", "grid", "random"] {
        let out = dir.path().join(format!("{placement}.png"));
        bin()
            .args([
                "render",
                "analytic:circular",
                "--look",
                "glyphs",
                "--placement",
                placement,
            ])
            .arg("-o")
            .arg(&out)
            .assert()
            .success();
        assert_eq!(size_of(&out), (512, 512));
    }
}

/// The pixels of a picture file (paint's PNGs carry text chunks that render's do not).
fn pixels(path: &Path) -> image::RgbImage {
    image::open(path).unwrap().to_rgb8()
}

#[test]
fn explore_commands_take_presets_and_go_through_paints_pipeline() {
    let dir = tempfile::tempdir().unwrap();
    let d = |name: &str| dir.path().join(name);
    for style in ["strokes", "pen-hatch"] {
        let (painted, rendered, labels) = (d("p.png"), d("r.png"), d("l.npy"));
        let seed = ["--seed", "5", "--set", "outlines.scale=1.5"];
        bin()
            .args(["paint", "samples/chelsea.png", "-s", style])
            .args(seed)
            .arg("-o")
            .arg(&painted)
            .assert()
            .success();
        bin()
            .args(["render", "samples/chelsea.png", "-s", style])
            .args(seed)
            .arg("-o")
            .arg(&rendered)
            .arg("--labels")
            .arg(&labels)
            .assert()
            .success();
        // The same preset, seed and override: the same picture, pixel for pixel.
        assert!(pixels(&painted) == pixels(&rendered), "{style}");
        let bytes = std::fs::read(&labels).unwrap();
        assert!(bytes.len() > 451 * 300 * 4, "{style}: label map");
    }
    // `sample` with a preset uses the preset's metric: strokes has larger, longer ellipses than
    // the defaults, so fewer samples; `--set` changes it again.
    // What `command samples/chelsea.png --out FILE extra…` writes.
    let written = |command: &str, file: &str, extra: &[&str]| {
        let out = d(file);
        bin()
            .args([command, "samples/chelsea.png", "--out"])
            .arg(&out)
            .args(extra)
            .assert()
            .success();
        std::fs::read(&out).unwrap()
    };
    let count = |extra: &[&str]| {
        let csv = written("sample", "s.csv", extra);
        csv.iter().filter(|&&b| b == b'\n').count() - 1
    };
    let (plain, strokes) = (count(&[]), count(&["-s", "strokes"]));
    let finer = count(&["-s", "strokes", "--set", "metric.max_size=0.01"]);
    assert!(strokes < plain, "strokes {strokes} vs defaults {plain}");
    assert!(
        finer > strokes,
        "max_size=0.01 {finer} vs strokes {strokes}"
    );
    // `field` with a preset writes the preset's metric.
    let metric = |extra: &[&str]| written("field", "m.npy", extra);
    assert_ne!(metric(&[]), metric(&["-s", "strokes"]));
    assert_eq!(
        metric(&[]),
        metric(&["-s", "crosshatch"]),
        "crosshatch keeps the default metric"
    );
    // A bad preset or key is refused with one line and exit 2.
    for bad in [&["-s", "nope"][..], &["--set", "look.nope=1"]] {
        bin()
            .args(["sample", "samples/chelsea.png"])
            .args(bad)
            .assert()
            .code(2);
    }
}
