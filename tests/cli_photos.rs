//! Photos as users have them, through `anisopaint paint`: EXIF orientation applied, 16-bit
//! and greyscale photos painted like their 8-bit colour versions, transparency composited
//! over white paper, and an output folder that cannot be written failing cleanly (exit 2, one
//! line, nothing left behind).

mod common;

use assert_cmd::Command;
use image::{DynamicImage, Rgb, RgbImage};
use std::path::Path;

fn bin() -> Command {
    Command::cargo_bin("anisopaint").unwrap()
}

/// Paints `input` with `style`, seed 1 and `extra` arguments into `out`, expecting success;
/// returns the picture.
fn paint(input: &Path, style: &str, out: &Path, extra: &[&str]) -> RgbImage {
    bin()
        .arg("paint")
        .arg(input)
        .args(["-s", style, "--seed", "1"])
        .args(extra)
        .arg("-o")
        .arg(out)
        .assert()
        .success();
    image::open(out).unwrap().to_rgb8()
}

/// Median of one channel over a rectangle.
fn median(img: &RgbImage, x0: u32, y0: u32, x1: u32, y1: u32, channel: usize) -> u8 {
    let mut v: Vec<u8> = (y0..y1)
        .flat_map(|y| (x0..x1).map(move |x| (x, y)))
        .map(|(x, y)| img.get_pixel(x, y).0[channel])
        .collect();
    v.sort_unstable();
    v[v.len() / 2]
}

/// Mean absolute difference of two pictures after averaging 16×16 blocks: what a viewer
/// sees, not where individual cells fall.
fn block_difference(a: &RgbImage, b: &RgbImage) -> f64 {
    assert_eq!(a.dimensions(), b.dimensions());
    let small = |img: &RgbImage| {
        image::imageops::resize(
            img,
            img.width() / 16,
            img.height() / 16,
            image::imageops::FilterType::Triangle,
        )
    };
    let (a, b) = (small(a), small(b));
    let total: f64 = a
        .as_raw()
        .iter()
        .zip(b.as_raw())
        .map(|(&x, &y)| (f64::from(x) - f64::from(y)).abs())
        .sum();
    total / a.as_raw().len() as f64
}

#[test]
fn exif_orientation_is_applied() {
    let dir = tempfile::tempdir().unwrap();
    // Stored 120×80: red on the left, blue on the right.
    let stored = RgbImage::from_fn(120, 80, |x, _| {
        if x < 60 {
            Rgb([200, 30, 30])
        } else {
            Rgb([30, 30, 200])
        }
    });
    let mut jpeg = Vec::new();
    DynamicImage::ImageRgb8(stored)
        .write_to(
            &mut std::io::Cursor::new(&mut jpeg),
            image::ImageFormat::Jpeg,
        )
        .unwrap();
    // Orientation 6: the camera was turned, show the picture rotated 90° clockwise, so
    // the stored left (red) is shown on top.
    let photo = dir.path().join("turned.jpg");
    std::fs::write(&photo, common::with_exif_orientation(&jpeg, 6)).unwrap();
    let out = paint(&photo, "mosaic", &dir.path().join("turned.png"), &[]);
    assert_eq!(out.dimensions(), (80, 120));
    assert!(median(&out, 0, 0, 80, 50, 0) > 150, "top is red");
    assert!(median(&out, 0, 0, 80, 50, 2) < 80, "top is red");
    assert!(median(&out, 0, 70, 80, 120, 2) > 150, "bottom is blue");
    assert!(median(&out, 0, 70, 80, 120, 0) < 80, "bottom is blue");
}

#[test]
fn sixteen_bit_and_greyscale_paint_like_eight_bit_colour() {
    let dir = tempfile::tempdir().unwrap();
    let eight = image::open("samples/chelsea.png").unwrap();
    let reference = paint(
        Path::new("samples/chelsea.png"),
        "mosaic",
        &dir.path().join("8.png"),
        &[],
    );

    let sixteen = dir.path().join("16.png");
    DynamicImage::ImageRgb16(eight.to_rgb16())
        .save(&sixteen)
        .unwrap();
    let painted = paint(&sixteen, "mosaic", &dir.path().join("16-out.png"), &[]);
    let diff = block_difference(&reference, &painted);
    assert!(diff < 1.0, "16-bit differs from 8-bit by {diff:.2} levels");

    // The mosaic's leading is warm brown by default: grey here.
    let grey_leading = ["--set", "look.border_colour=#303030"];
    let grey_reference = DynamicImage::ImageRgb8(paint(
        Path::new("samples/chelsea.png"),
        "mosaic",
        &dir.path().join("8-grey-leading.png"),
        &grey_leading,
    ))
    .to_luma8();
    let grey_reference = DynamicImage::ImageLuma8(grey_reference).to_rgb8();
    for (name, grey) in [
        ("grey8.png", DynamicImage::ImageLuma8(eight.to_luma8())),
        ("grey16.png", DynamicImage::ImageLuma16(eight.to_luma16())),
    ] {
        let path = dir.path().join(name);
        grey.save(&path).unwrap();
        let painted = paint(
            &path,
            "mosaic",
            &dir.path().join(format!("out-{name}")),
            &grey_leading,
        );
        assert!(
            painted.pixels().all(|p| {
                let [r, g, b] = p.0;
                r.abs_diff(g) <= 1 && g.abs_diff(b) <= 1
            }),
            "{name}: a grey photo gives a grey painting"
        );
        let diff = block_difference(&grey_reference, &painted);
        assert!(diff < 3.0, "{name}: far from the photo ({diff:.2})");
    }
}

#[test]
fn transparency_is_composited_over_white_paper() {
    let dir = tempfile::tempdir().unwrap();
    let photo = image::open("samples/chelsea.png").unwrap().to_rgba8();
    let (w, h) = photo.dimensions();
    // The right half fully transparent, black under the alpha (as many editors leave it).
    let cut = image::RgbaImage::from_fn(w, h, |x, y| {
        if x < w / 2 {
            *photo.get_pixel(x, y)
        } else {
            image::Rgba([0, 0, 0, 0])
        }
    });
    let path = dir.path().join("cut.png");
    cut.save(&path).unwrap();
    for style in ["mosaic", "pointillist"] {
        let out = paint(
            &path,
            style,
            &dir.path().join(format!("cut.{style}.png")),
            &[],
        );
        for c in 0..3 {
            let m = median(&out, w * 5 / 8, 0, w, h, c);
            assert!(
                m >= 240,
                "{style}: transparent half is paper, channel {c} = {m}"
            );
        }
        // The opaque half keeps the photo.
        let left = median(&out, 0, 0, w * 3 / 8, h, 1);
        assert!(left < 200, "{style}: opaque half keeps the photo ({left})");
    }
}

#[test]
fn unwritable_output_folder_fails_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    // A regular file where a folder should be: cannot be written even as root.
    let blocker = dir.path().join("not-a-folder");
    std::fs::write(&blocker, b"x").unwrap();
    let out = blocker.join("cat.png");
    let run = bin()
        .arg("paint")
        .arg("samples/chelsea.png")
        .arg("-o")
        .arg(&out)
        .assert()
        .code(2);
    let stderr = common::stderr_of(&run);
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(stderr.contains("not-a-folder"), "{stderr}");

    // A read-only folder, where permissions are enforced (not as root).
    let locked = dir.path().join("locked");
    std::fs::create_dir(&locked).unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o555)).unwrap();
        let probe = locked.join("probe");
        if std::fs::File::create(&probe).is_err() {
            let run = bin()
                .arg("paint")
                .arg("samples/chelsea.png")
                .arg("-o")
                .arg(locked.join("cat.png"))
                .assert()
                .code(2);
            let stderr = common::stderr_of(&run);
            assert!(stderr.contains("locked"), "{stderr}");
        } else {
            std::fs::remove_file(&probe).unwrap();
            eprintln!("running as root: read-only folder case skipped");
        }
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    assert_eq!(common::files_under(dir.path()), vec![blocker]);
}
