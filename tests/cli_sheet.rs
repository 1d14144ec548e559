//! `anisopaint contact-sheet` through the real binary: a labelled grid with one tile per
//! preset (every built-in one by default), each tile a reduced copy of what `paint` makes
//! with that preset; `--vary` sweeps one key; bad sweeps fail before any painting.

mod common;

use assert_cmd::Command;
use image::RgbImage;

fn bin() -> Command {
    Command::cargo_bin("anisopaint").unwrap()
}

const TILE: u32 = 160;

/// Tile `k` of a sheet of `columns` columns whose tiles are `TILE × tile_h` (layout of
/// `render::sheet` at this tile width: margin 8, label band 7 + 8).
fn tile(sheet: &RgbImage, k: u32, columns: u32, tile_h: u32) -> RgbImage {
    let (m, label) = (8, 7 + 8);
    let (col, row) = (k % columns, k / columns);
    let x = m + col * (TILE + m);
    let y = m + row * (tile_h + label + m);
    image::imageops::crop_imm(sheet, x, y, TILE, tile_h).to_image()
}

/// Mean absolute difference per channel after a blur of σ = 2 px, in levels: the tones a
/// viewer compares, not where each hatch line falls.
fn mean_difference(a: &RgbImage, b: &RgbImage) -> f64 {
    let (a, b) = (image::imageops::blur(a, 2.0), image::imageops::blur(b, 2.0));
    let sum: f64 = a
        .as_raw()
        .iter()
        .zip(b.as_raw())
        .map(|(&x, &y)| f64::from(x.abs_diff(y)))
        .sum();
    sum / a.as_raw().len() as f64
}

#[test]
fn every_preset_gets_a_tile_like_its_painting() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sheet.png");
    let sheet_args = ["--tile-width", "160", "--seed", "4", "--columns", "4"];
    bin()
        .args(["contact-sheet", "samples/chelsea.png", "-o"])
        .arg(&out)
        .args(sheet_args)
        .assert()
        .success();
    let sheet = image::open(&out).unwrap().to_rgb8();
    // Nine presets in 4 columns: 3 rows of tiles of the photo's aspect (±1 px of rounding).
    assert_eq!(sheet.width(), 8 + 4 * (TILE + 8));
    let tile_h = (sheet.height() - 8) / 3 - 15 - 8;
    assert_eq!((sheet.height() - 8) % 3, 0);
    assert!(tile_h.abs_diff(106) <= 1, "tile height {tile_h}");
    for (k, style) in ["mosaic", "pen-hatch", "glyphs", "lic"]
        .iter()
        .zip([0, 1, 5, 7])
        .map(|(s, k)| (k, s))
    {
        let painted = dir.path().join(format!("{style}.png"));
        bin()
            .args([
                "paint",
                "samples/chelsea.png",
                "-s",
                style,
                "--seed",
                "4",
                "-o",
            ])
            .arg(&painted)
            .assert()
            .success();
        let reduced = image::imageops::resize(
            &image::open(&painted).unwrap().to_rgb8(),
            TILE,
            tile_h,
            image::imageops::FilterType::Triangle,
        );
        let own = mean_difference(&tile(&sheet, k, 4, tile_h), &reduced);
        // Against another look's tile, the difference is far larger. (Not the next tile: after
        // pen-hatch comes crosshatch, the same ink on the same tones, alike once reduced.)
        let other = mean_difference(&tile(&sheet, (k + 2) % 9, 4, tile_h), &reduced);
        // Measured: 3.4 (lic) to 5.9 (mosaic) against 19 to 33 for the other look's tile.
        assert!(own < 10.0, "{style}: tile differs by {own:.1} levels");
        assert!(
            own * 1.5 < other,
            "{style}: {own:.1} vs another preset {other:.1}"
        );
    }
    // The last three places are empty.
    for k in 9..12 {
        let empty = tile(&sheet, k, 4, tile_h);
        assert!(empty.pixels().all(|p| p.0 == [244, 242, 238]));
    }
}

#[test]
fn vary_sweeps_one_key_and_is_reproducible() {
    let dir = tempfile::tempdir().unwrap();
    let run = |name: &str| {
        let out = dir.path().join(name);
        bin()
            .args([
                "contact-sheet",
                "samples/chelsea.png",
                "-s",
                "mosaic",
                "--vary",
                "look.border_width=0,4",
                "--tile-width",
                "160",
                "-o",
            ])
            .arg(&out)
            .assert()
            .success();
        std::fs::read(&out).unwrap()
    };
    let (a, b) = (run("a.png"), run("b.png"));
    assert_eq!(a, b, "same seed, same sheet");
    let sheet = image::load_from_memory(&a).unwrap().to_rgb8();
    let tile_h = sheet.height() - 8 - 15 - 8;
    let dark = |t: &RgbImage| t.pixels().filter(|p| p.0.iter().all(|&c| c < 60)).count();
    let (no_border, thick) = (
        dark(&tile(&sheet, 0, 2, tile_h)),
        dark(&tile(&sheet, 1, 2, tile_h)),
    );
    assert!(
        thick > 3 * no_border.max(1),
        "{no_border} vs {thick} dark pixels"
    );
}

#[test]
fn bad_sweeps_fail_before_painting() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.png");
    for (args, needle) in [
        (
            &["-s", "mosaic", "--vary", "look.border_widht=1,2"][..],
            "border_width",
        ),
        (
            &["-s", "mosaic,glyphs", "--vary", "look.relief=0,1"],
            "single",
        ),
        (&["-s", "mosaic", "--vary", "look.relief"], "expected"),
        (&["-s", "no-such-style"], "no-such-style"),
    ] {
        let run = bin()
            .args(["contact-sheet", "samples/chelsea.png", "-o"])
            .arg(&out)
            .args(args)
            .assert()
            .code(2);
        let stderr = common::stderr_of(&run);
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        assert!(!out.exists());
    }
}
