//! A damaged photo is never painted: real JPEG (baseline and progressive), PNG, TIFF and WebP
//! files cut at 24 places spread over their whole length must each fail with exit code 2, a
//! message naming the file, and no output; the whole files paint. (The JPEG decoder fills a
//! missing tail with grey and reports success, so JPEGs are checked for their end-of-image
//! marker before decoding.)

use assert_cmd::Command;
use std::io::Cursor;
use std::path::Path;

fn bin() -> Command {
    Command::cargo_bin("anisopaint").unwrap()
}

/// The test photos: name and bytes.
fn photos() -> Vec<(&'static str, Vec<u8>)> {
    let chelsea = image::open("samples/chelsea.png").unwrap().to_rgb8();
    let encode = |format| {
        let mut out = Cursor::new(Vec::new());
        chelsea.write_to(&mut out, format).unwrap();
        out.into_inner()
    };
    vec![
        (
            "baseline.jpg",
            std::fs::read("samples/astronaut.jpg").unwrap(),
        ),
        (
            "progressive.jpg",
            std::fs::read("tests/photos/chelsea-progressive.jpg").unwrap(),
        ),
        ("photo.png", encode(image::ImageFormat::Png)),
        ("photo.tif", encode(image::ImageFormat::Tiff)),
        ("photo.webp", encode(image::ImageFormat::WebP)),
        ("photo.gif", encode(image::ImageFormat::Gif)),
        ("photo.bmp", encode(image::ImageFormat::Bmp)),
        ("photo.ppm", encode(image::ImageFormat::Pnm)),
    ]
}

fn paint(input: &Path, out: &Path) -> assert_cmd::assert::Assert {
    bin()
        .arg("paint")
        .arg(input)
        .arg("-q")
        .arg("-o")
        .arg(out)
        .assert()
}

#[test]
fn cut_photos_fail_with_exit_2_and_no_output_and_whole_ones_paint() {
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes) in photos() {
        let whole = dir.path().join(name);
        std::fs::write(&whole, &bytes).unwrap();
        let out = dir.path().join(format!("{name}.whole.png"));
        paint(&whole, &out).success();
        assert!(out.exists(), "{name}: the whole file paints");
        for k in 0..24 {
            // From 5 % to 99 % of the length.
            let fraction = 0.05 + 0.94 * f64::from(k) / 23.0;
            let cut_at = ((bytes.len() as f64 * fraction) as usize).clamp(1, bytes.len() - 1);
            let cut = dir.path().join(format!("cut-{cut_at}-{name}"));
            std::fs::write(&cut, &bytes[..cut_at]).unwrap();
            let out = dir.path().join(format!("cut-{cut_at}-{name}.png"));
            let run = paint(&cut, &out).code(2);
            let stderr = String::from_utf8_lossy(&run.get_output().stderr).into_owned();
            assert!(
                stderr.contains(&cut.display().to_string()),
                "{name} cut at {cut_at}: the message names the file: {stderr}"
            );
            if name.ends_with(".jpg") {
                assert!(
                    stderr.contains("truncated"),
                    "{name} cut at {cut_at}: {stderr}"
                );
            }
            assert!(!out.exists(), "{name} cut at {cut_at}: no output");
        }
    }
}

#[test]
fn a_jpeg_with_data_after_its_end_and_an_embedded_thumbnail_still_paints() {
    // Bytes after the end-of-image marker are ignored; an APP1 segment holding a whole JPEG
    // (a thumbnail, with its own end marker) is skipped with its segment.
    let dir = tempfile::tempdir().unwrap();
    let photo = std::fs::read("tests/photos/chelsea-progressive.jpg").unwrap();
    let mut tailed = photo.clone();
    tailed.extend_from_slice(b"trailing bytes a camera left");
    assert!(anisopaint::io::jpeg_is_whole(&tailed).is_ok());
    let mut app1 = vec![0xFF, 0xE1];
    app1.extend_from_slice(&((photo.len() + 2) as u16).to_be_bytes());
    app1.extend_from_slice(&photo);
    let mut with_thumbnail = vec![0xFF, 0xD8];
    with_thumbnail.extend_from_slice(&app1);
    with_thumbnail.extend_from_slice(&photo[2..]);
    assert!(anisopaint::io::jpeg_is_whole(&with_thumbnail).is_ok());
    // Cut inside the real image's scan, after the thumbnail's own end marker: still refused.
    let cut = &with_thumbnail[..with_thumbnail.len() - photo.len() / 2];
    assert!(anisopaint::io::jpeg_is_whole(cut).is_err());
    let path = dir.path().join("tailed.jpg");
    std::fs::write(&path, &tailed).unwrap();
    paint(&path, &dir.path().join("out.png")).success();
}

#[test]
fn a_png_cut_between_its_pixels_and_its_end_chunk_is_refused() {
    // The decoder has every pixel once the image data ends, so it would return the picture;
    // without its IEND chunk the file is still cut short.
    let dir = tempfile::tempdir().unwrap();
    let png = std::fs::read("samples/chelsea.png").unwrap();
    assert_eq!(&png[png.len() - 8..png.len() - 4], b"IEND");
    for cut in [png.len() - 12, png.len() - 6, png.len() - 1] {
        assert!(
            anisopaint::io::png_is_whole(&png[..cut]).is_err(),
            "cut at {cut}"
        );
        let path = dir.path().join(format!("cut{cut}.png"));
        std::fs::write(&path, &png[..cut]).unwrap();
        let out = dir.path().join("out.png");
        paint(&path, &out)
            .code(2)
            .stderr(predicates::str::contains("truncated"));
        assert!(!out.exists());
    }
    let mut tailed = png.clone();
    tailed.extend_from_slice(b"bytes after IEND");
    assert!(anisopaint::io::png_is_whole(&tailed).is_ok());
}

#[test]
fn a_gif_cut_after_its_first_frame_is_refused() {
    // The decoder reads the first frame and stops, so a GIF missing its last bytes (or its
    // trailer) would decode; it is still cut short.
    let img = image::DynamicImage::ImageRgb8(image::RgbImage::from_fn(30, 20, |x, y| {
        image::Rgb([(x * 8) as u8, (y * 12) as u8, 90])
    }));
    let mut gif = std::io::Cursor::new(Vec::new());
    img.write_to(&mut gif, image::ImageFormat::Gif).unwrap();
    let gif = gif.into_inner();
    assert_eq!(gif.last(), Some(&b';'), "a GIF ends with its trailer");
    assert!(anisopaint::io::gif_is_whole(&gif).is_ok());
    for cut in [gif.len() - 1, gif.len() - 2, gif.len() - 5] {
        assert!(
            anisopaint::io::gif_is_whole(&gif[..cut]).is_err(),
            "cut at {cut}"
        );
        assert!(anisopaint::io::decode_photo(std::path::Path::new("x.gif"), &gif[..cut]).is_err());
    }
}
