//! Mutation fuzzing of everything that reads user files: every image decoder path (PNG 8- and
//! 16-bit, baseline and progressive JPEG, WebP, TIFF, GIF, BMP, PNM), the `.npy` reader and the
//! preset parser with its conversion into parameters. Each case takes a real file of that
//! kind and damages it with one to four mutations (bit flips, bytes set to boundary values,
//! 16/32-bit fields overwritten, ranges deleted, duplicated or inserted, cuts); the reader
//! must return an error or a whole result, never panic, never take over 2 s; a file that was
//! only cut short must always be refused (no output for a damaged file). Decoded pictures
//! are also painted now and then, so what a decoder lets through reaches the whole pipeline.
//!
//! `cargo test` runs a small sample (`FUZZ_CASES`, default 300 per target, seeds fixed);
//! `tests/fuzz.sh` runs the long campaign (100 000 cases per target, new seeds each run).

use anisopaint::paint::{paint_loaded, Extras, Recipe};
use anisopaint::progress::Silent;
use std::io::Cursor;
use std::path::Path;
use std::time::{Duration, Instant};

/// A small deterministic generator (xorshift64*), so a failing case can be replayed from its
/// seed.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Byte values at the edges of fields' ranges.
const BOUNDARY: [u8; 8] = [0x00, 0x01, 0x7f, 0x80, 0xfe, 0xff, 0x20, 0x0a];
/// 32-bit values that break lengths, offsets and sizes.
const BOUNDARY_32: [u32; 7] = [
    0,
    1,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_ffff,
    0x0001_0000,
    65_535,
];

/// What one case did to its seed.
#[derive(Debug)]
enum Damage {
    /// Only cut short: always a damaged file.
    Cut(usize),
    /// Anything else (the result may still be a valid file).
    Mutated,
}

fn mutate(seed: &[u8], rng: &mut Rng) -> (Vec<u8>, Damage) {
    let mut b = seed.to_vec();
    if rng.below(4) == 0 {
        let at = 1 + rng.below(b.len() - 1);
        b.truncate(at);
        return (b, Damage::Cut(at));
    }
    for _ in 0..1 + rng.below(4) {
        if b.is_empty() {
            b.push(0);
        }
        let at = rng.below(b.len());
        match rng.below(8) {
            0 => b[at] ^= 1 << rng.below(8),
            1 => b[at] = BOUNDARY[rng.below(BOUNDARY.len())],
            2 => b[at] = rng.next() as u8,
            3 if at + 4 <= b.len() => {
                let v = BOUNDARY_32[rng.below(BOUNDARY_32.len())];
                let bytes = if rng.below(2) == 0 {
                    v.to_be_bytes()
                } else {
                    v.to_le_bytes()
                };
                b[at..at + 4].copy_from_slice(&bytes);
            }
            4 => {
                let len = 1 + rng.below(16.min(b.len() - at));
                b.drain(at..at + len);
            }
            5 => {
                let len = 1 + rng.below(64.min(b.len() - at));
                let copy: Vec<u8> = b[at..at + len].to_vec();
                let to = rng.below(b.len());
                b.splice(to..to, copy);
            }
            6 => {
                let extra: Vec<u8> = (0..1 + rng.below(8)).map(|_| rng.next() as u8).collect();
                b.splice(at..at, extra);
            }
            _ => {
                let cut = 1 + rng.below(b.len());
                b.truncate(cut);
            }
        }
    }
    (b, Damage::Mutated)
}

/// A small picture with an edge, a ramp and a line, so encoders have structure to code.
fn picture(w: u32, h: u32) -> image::RgbImage {
    image::RgbImage::from_fn(w, h, |x, y| {
        let v = (x * 255 / w.max(1)) as u8;
        if y == h / 2 {
            image::Rgb([10, 10, 10])
        } else if x > y {
            image::Rgb([v, 255 - v, 90])
        } else {
            image::Rgb([230, v / 2, v])
        }
    })
}

fn encoded(img: &image::DynamicImage, format: image::ImageFormat) -> Vec<u8> {
    let mut out = Cursor::new(Vec::new());
    img.write_to(&mut out, format).expect("the seed encodes");
    out.into_inner()
}

/// Real files of every format the tool reads.
fn image_seeds() -> Vec<(&'static str, Vec<u8>)> {
    use image::{DynamicImage, ImageFormat};
    let rgb = DynamicImage::ImageRgb8(picture(24, 16));
    let grey16 = DynamicImage::ImageLuma16(image::ImageBuffer::from_fn(20, 12, |x, y| {
        image::Luma([(x * 3000 + y * 700) as u16])
    }));
    let rgba = DynamicImage::ImageRgba8(image::RgbaImage::from_fn(16, 16, |x, y| {
        image::Rgba([x as u8 * 16, y as u8 * 16, 128, (x * y) as u8])
    }));
    let mut jpeg = Cursor::new(Vec::new());
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut jpeg, 80)
        .encode_image(&DynamicImage::ImageRgb8(picture(40, 24)))
        .unwrap();
    vec![
        ("png", encoded(&rgb, ImageFormat::Png)),
        ("png16", encoded(&grey16, ImageFormat::Png)),
        ("png-alpha", encoded(&rgba, ImageFormat::Png)),
        ("jpeg", jpeg.into_inner()),
        (
            "jpeg-progressive",
            std::fs::read("tests/photos/chelsea-progressive.jpg").unwrap(),
        ),
        ("webp", encoded(&rgb, ImageFormat::WebP)),
        ("tiff", encoded(&rgb, ImageFormat::Tiff)),
        ("gif", encoded(&rgb, ImageFormat::Gif)),
        ("bmp", encoded(&rgb, ImageFormat::Bmp)),
        ("pnm", encoded(&rgb, ImageFormat::Pnm)),
    ]
}

/// Cases per target: `FUZZ_CASES`, else a sample for `cargo test`.
fn cases() -> usize {
    std::env::var("FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(300)
}

/// First seed of the generator: `FUZZ_SEED`, else fixed.
fn first_seed() -> u64 {
    std::env::var("FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0x5eed_f00d)
}

/// Limit for one case.
const HANG: Duration = Duration::from_secs(2);

/// Runs `check` on `cases()` mutations spread over `seeds`; every panic or slow case fails the
/// test with the seed that replays it. Returns (refused, accepted) counts.
fn campaign(
    target: &str,
    seeds: &[(&str, Vec<u8>)],
    check: impl Fn(&str, &[u8], &Damage) -> bool + std::panic::RefUnwindSafe,
) -> (usize, usize) {
    let (mut refused, mut accepted) = (0, 0);
    let mut slowest = Duration::ZERO;
    let started = Instant::now();
    for case in 0..cases() {
        let case_seed = first_seed() ^ (case as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
        let mut rng = Rng(case_seed);
        let (name, seed) = &seeds[case % seeds.len()];
        let (bytes, damage) = mutate(seed, &mut rng);
        let t = Instant::now();
        let ok = std::panic::catch_unwind(|| check(name, &bytes, &damage)).unwrap_or_else(|_| {
            panic!("{target}/{name}: panic on case seed {case_seed} ({damage:?})")
        });
        let took = t.elapsed();
        slowest = slowest.max(took);
        assert!(
            took < HANG,
            "{target}/{name}: case seed {case_seed} took {took:?} ({damage:?})"
        );
        if ok {
            accepted += 1;
        } else {
            refused += 1;
        }
    }
    eprintln!(
        "fuzz {target}: {} cases in {:.1} s, {refused} refused, {accepted} accepted, slowest \
         {slowest:?}, 0 panics, 0 hangs",
        cases(),
        started.elapsed().as_secs_f64()
    );
    (refused, accepted)
}

#[test]
fn damaged_images_are_refused_or_decoded_whole() {
    let seeds = image_seeds();
    for (name, bytes) in &seeds {
        anisopaint::io::decode_photo(Path::new(name), bytes)
            .unwrap_or_else(|e| panic!("the {name} seed is a valid file: {e}"));
    }
    let painted = std::sync::atomic::AtomicUsize::new(0);
    let recipe = Recipe::from_preset(
        &anisopaint::style::load("mosaic").unwrap(),
        Default::default(),
        Some(1),
    )
    .unwrap();
    let (refused, _) = campaign("image", &seeds, |name, bytes, damage| {
        match anisopaint::io::decode_photo(Path::new(name), bytes) {
            Err(e) => {
                assert!(!e.to_string().contains('\n'), "{name}: {e}");
                false
            }
            Ok(img) => {
                if let Damage::Cut(at) = damage {
                    panic!("{name} cut at byte {at} of its whole length was decoded");
                }
                // Now and then the whole pipeline paints what got through.
                let n = painted.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                if n.is_multiple_of(16)
                    && u64::from(img.width()) * u64::from(img.height()) <= 1 << 16
                {
                    let loaded = anisopaint::input::photo_field(img, &recipe.field.metric);
                    let painting = paint_loaded(&loaded, &recipe, Extras::default(), &Silent)
                        .expect("a decoded picture paints");
                    assert!(painting.image.width() > 0);
                }
                true
            }
        }
    });
    assert!(refused > 0);
}

#[test]
fn damaged_npy_fields_are_refused_or_read_whole() {
    let dir = tempfile::tempdir().unwrap();
    let mut seeds = Vec::new();
    for (name, rows, cols) in [("npy-square", 8, 8), ("npy-wide", 3, 17)] {
        let field = anisopaint::field::TensorField::new(
            cols,
            rows,
            (0..rows * cols)
                .map(|k| anisopaint::field::Tensor::new(4.0 + k as f64 * 0.1, 0.5, 2.0).to_f32())
                .collect(),
        );
        let path = dir.path().join(format!("{name}.npy"));
        anisopaint::io::write_npy(&path, &field).unwrap();
        seeds.push((name, std::fs::read(&path).unwrap()));
    }
    let (refused, accepted) =
        campaign(
            "npy",
            &seeds,
            |name, bytes, damage| match anisopaint::io::decode_npy(Path::new(name), bytes) {
                Err(_) => false,
                Ok(field) => {
                    if let Damage::Cut(at) = damage {
                        panic!("{name} cut at byte {at} was read");
                    }
                    assert!(field.cols() > 0 && field.rows() > 0);
                    true
                }
            },
        );
    assert!(
        refused > 0 && accepted > 0,
        "{refused} refused, {accepted} read"
    );
}

#[test]
fn damaged_presets_are_refused_or_converted_whole() {
    let seeds: Vec<(&str, Vec<u8>)> = anisopaint::style::BUILT_IN
        .iter()
        .map(|(name, text)| (*name, text.as_bytes().to_vec()))
        .collect();
    let (refused, accepted) = campaign("preset", &seeds, |name, bytes, _| {
        let Ok(text) = std::str::from_utf8(bytes) else {
            return false;
        };
        let file = match anisopaint::style::parse(text, name) {
            Ok(f) => f,
            Err(e) => {
                assert!(!e.to_string().contains('\n'), "{name}: {e}");
                return false;
            }
        };
        let preset = anisopaint::style::Preset {
            name: name.to_string(),
            file,
            dir: None,
        };
        // The parsed file is converted as it is (`extends` is not followed here).
        Recipe::from_preset(&preset, Default::default(), None).is_ok()
            && anisopaint::style::full_toml(&preset).is_ok()
    });
    assert!(
        refused > 0 && accepted > 0,
        "{refused} refused, {accepted} accepted"
    );
}
