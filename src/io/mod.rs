//! Reading inputs and writing outputs safely: photos (with a pixel limit against decompression
//! bombs, EXIF orientation applied, truncated files refused), `.npy` tensor fields and label
//! maps (`npy.rs`), CSV, PNGs with text chunks and JPEGs. Every output goes through
//! [`write_atomic`] (`output.rs`): standard output for `-`, devices and pipes in place, regular
//! files through a temporary file and a rename, so no half-written output is ever left behind.

use crate::error::{Error, Result};
use crate::field::Tensor;
use image::{DynamicImage, ImageDecoder, ImageReader, Limits};
use std::fs::File;
use std::io::{BufReader, Read};
use std::path::Path;

mod npy;
mod output;
mod whole;
pub use npy::{decode_npy, read_npy, write_labels_npy, write_npy};
pub use output::{is_stdout, remove_stale_partials, write_atomic, STDOUT};
pub use whole::{gif_is_whole, jpeg_is_whole, png_is_whole};

/// Largest photo or field we accept, in pixels (width × height): 150 megapixels. A larger
/// image is refused before it is decoded.
pub const MAX_PIXELS: u64 = 150_000_000;

/// Largest side of a photo we accept, in pixels.
pub const MAX_SIDE: u32 = 1 << 16;

/// Decodes a photo, refusing images over [`MAX_PIXELS`] before any pixel is decoded, and
/// applies its EXIF orientation. The format is read from the file's content, not its name;
/// `-` reads standard input. A file cut short is refused, whatever the decoder would make of it.
pub fn read_photo(path: &Path) -> Result<DynamicImage> {
    if !is_stdout(path) {
        let bytes = std::fs::read(path).map_err(|e| Error::input_io(path, e))?;
        return decode_photo(path, &bytes);
    }
    let mut bytes = Vec::new();
    std::io::stdin()
        .lock()
        .read_to_end(&mut bytes)
        .map_err(|e| Error::io(STDIN_NAME, e))?;
    decode_photo(Path::new(STDIN_NAME), &bytes)
}

/// How messages name standard input.
const STDIN_NAME: &str = "standard input";

/// [`read_photo`] of bytes already read from `path` (named in errors).
pub fn decode_photo(path: &Path, bytes: &[u8]) -> Result<DynamicImage> {
    if bytes.is_empty() {
        return Err(Error::Decode {
            path: path.into(),
            reason: "empty file (0 bytes)".into(),
        });
    }
    let decode_err = |e: image::ImageError| match e {
        image::ImageError::IoError(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            Error::Decode {
                path: path.into(),
                reason: "truncated (unexpected end of file)".into(),
            }
        }
        image::ImageError::IoError(io) => Error::io(path, io),
        image::ImageError::Limits(l) => Error::Decode {
            path: path.into(),
            reason: format!("over the memory limit ({l})"),
        },
        other => Error::Decode {
            path: path.into(),
            reason: other.to_string(),
        },
    };
    let mut reader = ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| Error::io(path, e))?;
    if reader.format().is_none() {
        return Err(Error::Decode {
            path: path.into(),
            reason: "not a PNG, JPEG, TIFF, WebP, GIF, BMP or PNM image".into(),
        });
    }
    // Decoders stop once they have the pixels (PNG, without its end chunk) or fill a missing
    // tail with grey and report success (JPEG): check that the file is whole first.
    let whole = match reader.format() {
        Some(image::ImageFormat::Jpeg) => jpeg_is_whole(bytes),
        Some(image::ImageFormat::Png) => png_is_whole(bytes),
        Some(image::ImageFormat::Gif) => gif_is_whole(bytes),
        _ => Ok(()),
    };
    whole.map_err(|reason| Error::Decode {
        path: path.into(),
        reason,
    })?;
    let mut limits = Limits::default();
    limits.max_image_width = Some(MAX_SIDE);
    limits.max_image_height = Some(MAX_SIDE);
    limits.max_alloc = Some(MAX_PIXELS * 8);
    reader.limits(limits);
    let mut decoder = reader.into_decoder().map_err(decode_err)?;
    let (w, h) = decoder.dimensions();
    check_size(path, u64::from(w), u64::from(h))?;
    let orientation = decoder.orientation().map_err(decode_err)?;
    let mut img = DynamicImage::from_decoder(decoder).map_err(decode_err)?;
    img.apply_orientation(orientation);
    Ok(img)
}

fn check_size(path: &Path, width: u64, height: u64) -> Result<()> {
    if width == 0 || height == 0 {
        return Err(Error::EmptyImage {
            path: path.into(),
            width,
            height,
        });
    }
    if width.saturating_mul(height) > MAX_PIXELS {
        return Err(Error::TooLarge {
            path: path.into(),
            width,
            height,
            limit: MAX_PIXELS,
        });
    }
    Ok(())
}

/// Writes samples as CSV `x,y,m11,m12,m22` (pixels), one row per sample, atomically. Rows are
/// formatted in parallel, `CSV_ROWS` at a time, and written in order.
pub fn write_samples_csv(path: &Path, positions: &[glam::DVec2], metrics: &[Tensor]) -> Result<()> {
    use std::fmt::Write as _;
    write_atomic(path, |w| {
        writeln!(w, "x,y,m11,m12,m22")?;
        write_rows(w, positions.len().min(metrics.len()), |i, row| {
            let (p, m) = (positions[i], metrics[i]);
            writeln!(row, "{},{},{},{},{}", p.x, p.y, m.xx, m.xy, m.yy)
        })
    })
}

/// Writes triangles as CSV `a,b,c` (row indices of the samples file), atomically. Each is
/// counter-clockwise in the mathematical sense: `(b − a) × (c − a) > 0` in pixel coordinates
/// (so clockwise as seen on screen, where y points down).
pub fn write_triangles_csv(path: &Path, triangles: &[[u32; 3]]) -> Result<()> {
    use std::fmt::Write as _;
    write_atomic(path, |w| {
        writeln!(w, "a,b,c")?;
        write_rows(w, triangles.len(), |i, row| {
            let [a, b, c] = triangles[i];
            writeln!(row, "{a},{b},{c}")
        })
    })
}

/// Writes rows `0..n` to `w`, each formatted by `row(i, text)`: blocks of [`CSV_BLOCK`] rows
/// are formatted in parallel, [`CSV_ROWS`] rows at a time, then written in order (formatting
/// floating-point numbers is most of a large CSV's cost).
fn write_rows(
    w: &mut dyn std::io::Write,
    n: usize,
    row: impl Fn(usize, &mut String) -> std::fmt::Result + Sync,
) -> std::io::Result<()> {
    use rayon::prelude::*;
    for start in (0..n).step_by(CSV_ROWS) {
        let end = (start + CSV_ROWS).min(n);
        let blocks: Vec<String> = (start..end)
            .step_by(CSV_BLOCK)
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|first| {
                let mut text = String::new();
                for i in first..(first + CSV_BLOCK).min(end) {
                    // Writing into a String cannot fail.
                    let _ = row(i, &mut text);
                }
                text
            })
            .collect();
        for text in blocks {
            w.write_all(text.as_bytes())?;
        }
    }
    Ok(())
}

/// Rows of a CSV formatted by one task.
const CSV_BLOCK: usize = 2048;

/// Rows of a CSV formatted before they are written (about 20 MB of samples).
const CSV_ROWS: usize = 1 << 18;

/// Reads samples written by [`write_samples_csv`]: header `x,y,m11,m12,m22`, then one sample
/// per line. Every value must be finite and every metric positive definite; errors name the
/// line.
pub fn read_samples_csv(path: &Path) -> Result<(Vec<glam::DVec2>, Vec<Tensor>)> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let bad = |line: usize, reason: String| Error::Csv {
        path: path.into(),
        line,
        reason,
    };
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, h)) if h.trim() == "x,y,m11,m12,m22" => {}
        _ => return Err(bad(1, "expected the header x,y,m11,m12,m22".into())),
    }
    let mut positions = Vec::new();
    let mut metrics = Vec::new();
    for (i, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let values: Vec<f64> = line
            .split(',')
            .map(|v| v.trim().parse::<f64>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|e| bad(i + 1, format!("not a number: {e}")))?;
        let [x, y, a, b, c] = values[..] else {
            return Err(bad(
                i + 1,
                format!("expected 5 values, found {}", values.len()),
            ));
        };
        if !values.iter().all(|v| v.is_finite()) {
            return Err(bad(i + 1, "non-finite value".into()));
        }
        let m = Tensor::new(a, b, c);
        if !m.is_positive_definite() {
            return Err(bad(i + 1, "metric is not positive definite".into()));
        }
        positions.push(glam::DVec2::new(x, y));
        metrics.push(m);
    }
    if positions.len() < 3 {
        return Err(bad(
            1,
            format!("{} samples; at least 3 are needed", positions.len()),
        ));
    }
    Ok((positions, metrics))
}

/// Encodes `img` as PNG at `path` atomically, with `texts` as iTXt chunks (keyword, UTF-8
/// text): what a result needs to be reproduced.
pub fn save_png_with_text(
    path: &Path,
    img: &image::RgbImage,
    texts: &[(String, String)],
) -> Result<()> {
    let encode = |reason: String| Error::Encode {
        path: path.into(),
        reason,
    };
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, img.width(), img.height());
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        // Deflate runs on one core: at the default level it took a fifth of a 12 MP painting.
        encoder.set_compression(png::Compression::Fast);
        for (key, text) in texts {
            encoder
                .add_itxt_chunk(key.clone(), text.clone())
                .map_err(|e| encode(e.to_string()))?;
        }
        let mut writer = encoder.write_header().map_err(|e| encode(e.to_string()))?;
        writer
            .write_image_data(img.as_raw())
            .map_err(|e| encode(e.to_string()))?;
    }
    write_atomic(path, |w| w.write_all(&bytes))
}

/// The text chunks (tEXt, zTXt, iTXt) of the PNG at `path`, as (keyword, text), in file
/// order within each kind.
pub fn read_png_text(path: &Path) -> Result<Vec<(String, String)>> {
    let file = File::open(path).map_err(|e| Error::io(path, e))?;
    let decode = |reason: String| Error::Decode {
        path: path.into(),
        reason,
    };
    let mut reader = png::Decoder::new(BufReader::new(file))
        .read_info()
        .map_err(|e| decode(e.to_string()))?;
    // Text after the image data is read with the rest of the file.
    let mut buf = vec![0; reader.output_buffer_size().unwrap_or(0)];
    let _ = reader.next_frame(&mut buf);
    let info = reader.info();
    let mut out: Vec<(String, String)> = info
        .uncompressed_latin1_text
        .iter()
        .map(|t| (t.keyword.clone(), t.text.clone()))
        .collect();
    for t in &info.compressed_latin1_text {
        out.push((t.keyword.clone(), t.get_text().unwrap_or_default()));
    }
    for t in &info.utf8_text {
        out.push((t.keyword.clone(), t.get_text().unwrap_or_default()));
    }
    Ok(out)
}

/// Writes `text` to `path` atomically.
pub fn write_text(path: &Path, text: &str) -> Result<()> {
    write_atomic(path, |w| w.write_all(text.as_bytes()))
}

/// Encodes `img` to `path` ([`write_atomic`]); the format follows the extension (PNG when
/// unknown, and for standard output). JPEG is written as [`save_rgb`] writes it.
pub fn save_image(path: &Path, img: &DynamicImage) -> Result<()> {
    match img {
        DynamicImage::ImageRgb8(rgb) => save_rgb(path, rgb),
        _ if output_format(path) == image::ImageFormat::Jpeg => {
            // JPEG holds 8-bit RGB only.
            save_rgb(path, &img.to_rgb8())
        }
        _ => encode_with_image(path, |bytes, format| img.write_to(bytes, format)),
    }
}

/// Encodes the RGB picture `img` to `path` ([`write_atomic`]) in the format its extension
/// names (PNG when unknown, and for standard output). JPEG is written at [`JPEG_QUALITY`]
/// with full-resolution colour (4:4:4: the looks' fine coloured lines and dots keep their
/// colour) by `jpeg-encoder`, in a third to a half of the time of `image`'s encoder.
pub fn save_rgb(path: &Path, img: &image::RgbImage) -> Result<()> {
    if output_format(path) != image::ImageFormat::Jpeg {
        return encode_with_image(path, |bytes, format| img.write_to(bytes, format));
    }
    let failed = |reason: String| Error::Encode {
        path: path.into(),
        reason,
    };
    let (Ok(w), Ok(h)) = (u16::try_from(img.width()), u16::try_from(img.height())) else {
        return Err(failed(format!(
            "{} × {} pixels is over JPEG's limit of 65535 a side",
            img.width(),
            img.height()
        )));
    };
    let mut bytes = Vec::new();
    let mut encoder = jpeg_encoder::Encoder::new(&mut bytes, JPEG_QUALITY);
    encoder.set_sampling_factor(jpeg_encoder::SamplingFactor::R_4_4_4);
    encoder
        .encode(img.as_raw(), w, h, jpeg_encoder::ColorType::Rgb)
        .map_err(|e| failed(e.to_string()))?;
    write_atomic(path, |w| w.write_all(&bytes))
}

/// Quality (1 to 100) of JPEG outputs: GIMP's default; at 75 the hatching's fine lines ring.
pub const JPEG_QUALITY: u8 = 90;

/// The format an output at `path` is written in: the extension's, PNG when unknown.
fn output_format(path: &Path) -> image::ImageFormat {
    image::ImageFormat::from_path(path).unwrap_or(image::ImageFormat::Png)
}

/// Encodes through `image` (`write(bytes, format)`), in memory first (some encoders seek, and
/// pipes and standard output cannot), then to `path`.
fn encode_with_image(
    path: &Path,
    write: impl FnOnce(&mut std::io::Cursor<Vec<u8>>, image::ImageFormat) -> image::ImageResult<()>,
) -> Result<()> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    write(&mut bytes, output_format(path)).map_err(|e| Error::Encode {
        path: path.into(),
        reason: e.to_string(),
    })?;
    write_atomic(path, |w| w.write_all(bytes.get_ref()))
}
