//! Helpers shared by the integration tests: hand-made broken and unusual image files,
//! anti-aliased synthetic pictures, and a painting through the library with a preset's keys
//! set.
#![allow(dead_code)]

/// How many distinct colours a picture file holds: 1 means nothing was drawn on it.
pub fn distinct_colours(path: &std::path::Path) -> usize {
    let img = image::open(path).unwrap().to_rgb8();
    let mut seen: Vec<[u8; 3]> = img.pixels().map(|p| p.0).collect();
    seen.sort_unstable();
    seen.dedup();
    seen.len()
}

/// Standard CRC-32 (PNG chunks).
pub fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = 0xffff_ffffu32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xedb8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// A PNG whose header claims `w × h` pixels, followed by a few bytes of image data.
pub fn png_header_only(w: u32, h: u32) -> Vec<u8> {
    let mut out = vec![0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
    let mut chunk = b"IHDR".to_vec();
    chunk.extend_from_slice(&w.to_be_bytes());
    chunk.extend_from_slice(&h.to_be_bytes());
    chunk.extend_from_slice(&[8, 2, 0, 0, 0]);
    out.extend_from_slice(&13u32.to_be_bytes());
    out.extend_from_slice(&chunk);
    out.extend_from_slice(&crc32(&chunk).to_be_bytes());
    let idat = [
        b"IDAT".as_slice(),
        &[0x78, 0x9c, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01],
    ]
    .concat();
    out.extend_from_slice(&8u32.to_be_bytes());
    out.extend_from_slice(&idat);
    out.extend_from_slice(&crc32(&idat).to_be_bytes());
    out.extend_from_slice(&0u32.to_be_bytes());
    out.extend_from_slice(b"IEND");
    out.extend_from_slice(&crc32(b"IEND").to_be_bytes());
    out
}

/// `jpeg` (a baseline JPEG as the encoder wrote it) with an EXIF APP1 segment right after
/// its start marker holding only the Orientation tag (0x0112) set to `orientation` (1–8).
pub fn with_exif_orientation(jpeg: &[u8], orientation: u16) -> Vec<u8> {
    assert_eq!(&jpeg[..2], &[0xff, 0xd8], "a JPEG starts with SOI");
    let mut tiff = b"II*\0".to_vec();
    tiff.extend_from_slice(&8u32.to_le_bytes()); // first IFD right after the header
    tiff.extend_from_slice(&1u16.to_le_bytes()); // one entry
    tiff.extend_from_slice(&0x0112u16.to_le_bytes()); // Orientation
    tiff.extend_from_slice(&3u16.to_le_bytes()); // SHORT
    tiff.extend_from_slice(&1u32.to_le_bytes()); // one value
    tiff.extend_from_slice(&orientation.to_le_bytes());
    tiff.extend_from_slice(&[0, 0]); // value padded to 4 bytes
    tiff.extend_from_slice(&0u32.to_le_bytes()); // no next IFD
    let payload = [b"Exif\0\0".as_slice(), &tiff].concat();
    let mut out = vec![0xff, 0xd8, 0xff, 0xe1];
    out.extend_from_slice(&u16::try_from(payload.len() + 2).unwrap().to_be_bytes());
    out.extend_from_slice(&payload);
    out.extend_from_slice(&jpeg[2..]);
    out
}

/// Every regular file under `dir`, recursively, sorted.
pub fn files_under(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let p = entry.unwrap().path();
        if p.is_dir() {
            out.extend(files_under(&p));
        } else {
            out.push(p);
        }
    }
    out.sort();
    out
}

/// Makes `path` unreadable and reports whether that worked: as root (CI containers) the
/// permission bits are not enforced, and the caller skips that case.
pub fn make_unreadable(path: &std::path::Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o000)).unwrap();
        std::fs::File::open(path).is_err()
    }
    #[cfg(not(unix))]
    {
        let _ = path;
        false
    }
}

/// What a finished command printed on standard error.
pub fn stderr_of(run: &assert_cmd::assert::Assert) -> String {
    String::from_utf8_lossy(&run.get_output().stderr).to_string()
}

/// `n` batch items in `dir`, `{stem}{k}.png` holding only a PNG header that claims `w × h`
/// pixels (what the batch's memory estimate reads), painted to `out{k}.png`.
pub fn header_only_items(
    dir: &std::path::Path,
    stem: &str,
    n: usize,
    (w, h): (u32, u32),
) -> Vec<anisopaint::batch::Item> {
    (0..n)
        .map(|k| {
            let input = dir.join(format!("{stem}{k}.png"));
            std::fs::write(&input, png_header_only(w, h)).unwrap();
            anisopaint::batch::Item {
                input,
                output: dir.join(format!("out{k}.png")),
            }
        })
        .collect()
}

/// `photo` painted in the built-in preset `style` with the keys `sets` (`key=value`) at `seed`.
pub fn painted_with(
    photo: &image::DynamicImage,
    style: &str,
    sets: &[String],
    seed: u64,
) -> image::RgbImage {
    let mut preset = anisopaint::style::load(style).unwrap();
    anisopaint::style::apply_sets(&mut preset, sets).unwrap();
    let recipe =
        anisopaint::paint::Recipe::from_preset(&preset, Default::default(), Some(seed)).unwrap();
    let loaded = anisopaint::input::photo_field(photo.clone(), &recipe.field.metric);
    anisopaint::paint::paint_loaded(
        &loaded,
        &recipe,
        Default::default(),
        &anisopaint::progress::Silent,
    )
    .unwrap()
    .image
}

/// The share of pixel (`x`, `y`)'s square that `inside` holds, over 4×4 points: the
/// anti-aliasing of the synthetic pictures whose answers the tests know.
pub fn covered(x: u32, y: u32, inside: impl Fn(f64, f64) -> bool) -> f64 {
    let mut share = 0.0;
    for j in 0..4 {
        for i in 0..4 {
            let (px, py) = (
                f64::from(x) + (f64::from(i) + 0.5) / 4.0,
                f64::from(y) + (f64::from(j) + 0.5) / 4.0,
            );
            if inside(px, py) {
                share += 1.0 / 16.0;
            }
        }
    }
    share
}

/// The mean of channel `k` of `img` over the pixels whose centres `keep` holds.
pub fn mean_where(img: &image::RgbImage, k: usize, keep: impl Fn(f64, f64) -> bool) -> f64 {
    let (mut sum, mut n) = (0.0, 0.0);
    for (x, y, p) in img.enumerate_pixels() {
        if keep(f64::from(x) + 0.5, f64::from(y) + 0.5) {
            sum += f64::from(p.0[k]);
            n += 1.0;
        }
    }
    sum / n
}

/// Compares `img` with the committed reference picture at `path`: every channel within
/// `tolerance` levels for at least 99 % of pixels, none off by more than 64. Writes a diff
/// picture (four times the difference) beside the reference on a mismatch; `REGENERATE=1`
/// rewrites the reference instead.
pub fn check_reference(img: &image::RgbImage, path: &std::path::Path, tolerance: u8) {
    if std::env::var_os("REGENERATE").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        img.save(path).unwrap();
        return;
    }
    let name = path.display();
    let reference = image::open(path)
        .unwrap_or_else(|e| panic!("{name}: {e} (REGENERATE=1 writes it)"))
        .to_rgb8();
    assert_eq!(reference.dimensions(), img.dimensions(), "{name}: size");
    let mut diff = image::RgbImage::new(img.width(), img.height());
    let (mut off, mut worst) = (0usize, 0u8);
    for ((a, b), d) in img.pixels().zip(reference.pixels()).zip(diff.pixels_mut()) {
        let delta = [0, 1, 2].map(|k| a.0[k].abs_diff(b.0[k]));
        let m = *delta.iter().max().unwrap();
        worst = worst.max(m);
        off += usize::from(m > tolerance);
        d.0 = delta.map(|v| v.saturating_mul(4));
    }
    let share = off as f64 / f64::from(img.width() * img.height());
    if share > 0.01 || worst > 64 {
        let out = path.with_extension("diff.png");
        diff.save(&out).unwrap();
        panic!(
            "{name}: {:.2} % of pixels off by more than {tolerance}, worst {worst}; diff in {}",
            100.0 * share,
            out.display()
        );
    }
}

/// sRGB byte → linear light.
pub fn linear(v: u8) -> f64 {
    let v = f64::from(v) / 255.0;
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// How `k × k` points, or the pixels of a block, are averaged: in linear light (what the
/// cells' supersampling does) or in the sRGB encoding (what ink coverage is mapped for).
#[derive(Clone, Copy, PartialEq)]
pub enum Blend {
    Linear,
    Encoded,
}

pub fn rasterise_blended(svg: &std::path::Path, k: u32, blend: Blend) -> image::RgbImage {
    let data = std::fs::read(svg).unwrap();
    let tree = resvg::usvg::Tree::from_data(&data, &resvg::usvg::Options::default()).unwrap();
    let size = tree.size().to_int_size();
    let (w, h) = (size.width(), size.height());
    let mut pixmap = tiny_skia::Pixmap::new(w * k, h * k).unwrap();
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        tiny_skia::Transform::from_scale(k as f32, k as f32),
        &mut pixmap.as_mut(),
    );
    let big = pixmap.data();
    image::RgbImage::from_fn(w, h, |x, y| {
        let mut sum = [0.0f64; 3];
        for dy in 0..k {
            for dx in 0..k {
                let i = (((y * k + dy) * w * k + x * k + dx) * 4) as usize;
                for c in 0..3 {
                    sum[c] += match blend {
                        Blend::Linear => linear(big[i + c]),
                        Blend::Encoded => f64::from(big[i + c]) / 255.0,
                    };
                }
            }
        }
        image::Rgb(sum.map(|v| {
            let v = v / f64::from(k * k);
            if blend == Blend::Encoded {
                return (v * 255.0).round() as u8;
            }
            let s = if v <= 0.003_130_8 {
                v * 12.92
            } else {
                1.055 * v.powf(1.0 / 2.4) - 0.055
            };
            (s * 255.0).round().clamp(0.0, 255.0) as u8
        }))
    })
}
