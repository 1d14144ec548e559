//! Reading inputs and writing outputs safely: photos (with a pixel limit against decompression
//! bombs, EXIF orientation applied, truncated files refused), `.npy` tensor fields `(H, W, 3)`
//! of float32/float64, CSV, label maps and PNGs with text chunks. Every output goes through
//! [`write_atomic`] (`output.rs`): standard output for `-`, devices and pipes in place, regular
//! files through a temporary file and a rename, so no half-written output is ever left behind.

use crate::error::{Error, Result};
use crate::field::{Tensor, TensorField};
use image::{DynamicImage, ImageDecoder, ImageReader, Limits};
use npyz::WriterBuilder;
use std::fs::File;
use std::io::{BufReader, Read};
use std::path::Path;

mod output;
mod whole;
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
        let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
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

/// Reads a tensor field `(H, W, 3)` of `(t11, t12, t22)`, float32 or float64, C or Fortran
/// order. Every value must be finite; the first bad pixel is named otherwise. C-ordered data
/// (the usual case) are read in blocks of rows straight into the field, so the file is never
/// held in memory whole.
pub fn read_npy(path: &Path) -> Result<TensorField> {
    let file = File::open(path).map_err(|e| Error::io(path, e))?;
    let len = file.metadata().map_err(|e| Error::io(path, e))?.len();
    decode_npy_from(path, BufReader::new(file), len)
}

/// [`read_npy`] of bytes already read from `path` (named in errors).
pub fn decode_npy(path: &Path, bytes: &[u8]) -> Result<TensorField> {
    decode_npy_from(path, bytes, bytes.len() as u64)
}

/// [`read_npy`] from `reader`, which holds `len` bytes in all.
fn decode_npy_from(path: &Path, mut reader: impl Read, len: u64) -> Result<TensorField> {
    let npy_err = |reason: String| Error::Npy {
        path: path.into(),
        reason,
    };
    let header = npyz::NpyHeader::from_reader(&mut reader)
        .map_err(|e| npy_err(format!("not a .npy file: {e}")))?;
    let shape = header.shape().to_vec();
    let (h, w) = match shape[..] {
        [h, w, 3] => (h, w),
        _ => {
            return Err(npy_err(format!(
                "shape {shape:?} is not (H, W, 3) of (t11, t12, t22)"
            )))
        }
    };
    check_size(path, w, h)?;
    let type_str = match header.dtype() {
        npyz::DType::Plain(t) => t,
        other => {
            return Err(npy_err(format!(
                "dtype {} is not float32 or float64",
                other.descr()
            )))
        }
    };
    let bytes_per = match (type_str.type_char(), type_str.size_field()) {
        (npyz::TypeChar::Float, 4) => 4,
        (npyz::TypeChar::Float, 8) => 8,
        _ => {
            return Err(npy_err(format!(
                "dtype {type_str} is not float32 or float64"
            )))
        }
    };
    let count = (h * w * 3) as usize;
    // The header is at least 10 bytes; a file shorter than header + data is truncated, and
    // checking first keeps a lying header from making us allocate for data that isn't there.
    if len < (count * bytes_per) as u64 + 10 {
        return Err(truncated(path, &shape, count * bytes_per));
    }
    let (h, w) = (h as usize, w as usize);
    let data_err = |e: std::io::Error| {
        if e.kind() == std::io::ErrorKind::UnexpectedEof {
            truncated(path, &shape, count * bytes_per)
        } else {
            npy_err(format!("cannot read data: {e}"))
        }
    };
    let data = if header.order() == npyz::Order::Fortran {
        let npy = npyz::NpyFile::with_header(header, reader);
        let values: Vec<f64> = if bytes_per == 4 {
            let v: Vec<f32> = npy.into_vec().map_err(data_err)?;
            v.into_iter().map(f64::from).collect()
        } else {
            npy.into_vec().map_err(data_err)?
        };
        if values.len() != count {
            return Err(npy_err(format!(
                "holds {} values, expected {count}",
                values.len()
            )));
        }
        tensors_fortran(&values, w, h)
    } else {
        let big = type_str.endianness() == npyz::Endianness::Big;
        match tensors_c(&mut reader, w, h, bytes_per, big) {
            Ok(data) => Ok(data),
            Err(Bad::Value(x, y)) => Err((x, y)),
            Err(Bad::Read(e)) => return Err(data_err(e)),
        }
    };
    match data {
        Ok(data) => Ok(TensorField::new(w, h, data)),
        Err((x, y)) => Err(Error::NonFinite {
            path: path.into(),
            x,
            y,
        }),
    }
}

/// Why C-ordered data could not be read: the reader failed, or pixel (x, y) holds a value that
/// is not finite.
enum Bad {
    Read(std::io::Error),
    Value(usize, usize),
}

/// One stored value as `f32`, or `None` when it is not finite or does not fit.
fn stored_value(b: &[u8], big: bool) -> Option<f32> {
    let v = match b.len() {
        4 => {
            let a = [b[0], b[1], b[2], b[3]];
            f64::from(if big {
                f32::from_be_bytes(a)
            } else {
                f32::from_le_bytes(a)
            })
        }
        _ => {
            let a = [b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]];
            if big {
                f64::from_be_bytes(a)
            } else {
                f64::from_le_bytes(a)
            }
        }
    };
    finite_f32(v)
}

/// `v` as `f32` when it is finite and fits.
fn finite_f32(v: f64) -> Option<f32> {
    (v.is_finite() && v.abs() <= f64::from(f32::MAX)).then_some(v as f32)
}

/// Tensors from C-ordered `(H, W, 3)` data of `bytes_per`-byte floats read from `reader`, in
/// blocks of about [`NPY_BLOCK`] bytes of whole rows, each converted row by row in parallel
/// straight into the field; or the first pixel in row order holding a value that is not
/// finite.
fn tensors_c(
    reader: &mut impl Read,
    w: usize,
    h: usize,
    bytes_per: usize,
    big: bool,
) -> std::result::Result<Vec<[f32; 3]>, Bad> {
    use rayon::prelude::*;
    let row_bytes = w * 3 * bytes_per;
    let rows_per_block = (NPY_BLOCK / row_bytes.max(1)).clamp(1, h.max(1));
    let mut block = vec![0u8; rows_per_block * row_bytes];
    let mut out = vec![[0.0f32; 3]; w * h];
    for (b, rows) in out.chunks_mut(rows_per_block * w.max(1)).enumerate() {
        let bytes = &mut block[..rows.len() / w.max(1) * row_bytes];
        reader.read_exact(bytes).map_err(Bad::Read)?;
        let first_bad = rows
            .par_chunks_mut(w.max(1))
            .zip(bytes.par_chunks(row_bytes.max(1)))
            .enumerate()
            .find_map_first(|(y, (row, bytes))| {
                let pixels = row.iter_mut().zip(bytes.chunks_exact(3 * bytes_per));
                for (x, (t, px)) in pixels.enumerate() {
                    for (k, v) in px.chunks_exact(bytes_per).enumerate() {
                        match stored_value(v, big) {
                            Some(v) => t[k] = v,
                            None => return Some((x, y)),
                        }
                    }
                }
                None
            });
        if let Some((x, y)) = first_bad {
            return Err(Bad::Value(x, b * rows_per_block + y));
        }
    }
    Ok(out)
}

/// Bytes of a `.npy` file [`tensors_c`] reads and converts at a time: large enough for the
/// conversion to be worth sharing among threads, small enough to stay in the cache.
const NPY_BLOCK: usize = 1 << 20;

/// Tensors from Fortran-ordered values, or the first pixel (x, y) in row order holding a
/// value that is not finite.
fn tensors_fortran(
    values: &[f64],
    w: usize,
    h: usize,
) -> std::result::Result<Vec<[f32; 3]>, (usize, usize)> {
    let mut data = Vec::with_capacity(w * h);
    for r in 0..h {
        for c in 0..w {
            let t = [0, 1, 2].map(|k| finite_f32(values[r + h * (c + w * k)]));
            match t {
                [Some(t11), Some(t12), Some(t22)] => data.push([t11, t12, t22]),
                _ => return Err((c, r)),
            }
        }
    }
    Ok(data)
}

fn truncated(path: &Path, shape: &[u64], data_bytes: usize) -> Error {
    Error::Npy {
        path: path.into(),
        reason: format!("truncated: shape {shape:?} needs {data_bytes} bytes of data"),
    }
}

/// Writes `field` as float32 `(rows, cols, 3)` `.npy`, atomically.
pub fn write_npy(path: &Path, field: &TensorField) -> Result<()> {
    write_atomic(path, |w| {
        let shape = [field.rows() as u64, field.cols() as u64, 3];
        let mut writer = npyz::WriteOptions::new()
            .default_dtype()
            .shape(&shape)
            .writer(w)
            .begin_nd()?;
        writer.extend(field.data().iter().flatten().copied())?;
        writer.finish()
    })
}

/// Writes samples as CSV `x,y,m11,m12,m22` (pixels), one row per sample, atomically. Rows are
/// formatted in parallel, [`CSV_ROWS`] at a time, and written in order.
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

/// Writes a label map as `.npy`, int32 of shape (height, width), atomically.
pub fn write_labels_npy(path: &Path, labels: &[i32], width: usize, height: usize) -> Result<()> {
    write_atomic(path, |w| {
        let shape = [height as u64, width as u64];
        let mut writer = npyz::WriteOptions::new()
            .default_dtype()
            .shape(&shape)
            .writer(w)
            .begin_nd()?;
        writer.extend(labels.iter().copied())?;
        writer.finish()
    })
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
/// unknown, and for standard output).
pub fn save_image(path: &Path, img: &DynamicImage) -> Result<()> {
    let format = image::ImageFormat::from_path(path).unwrap_or(image::ImageFormat::Png);
    let converted;
    let img = if format == image::ImageFormat::Jpeg && !matches!(img, DynamicImage::ImageRgb8(_)) {
        // JPEG holds 8-bit RGB only.
        converted = DynamicImage::ImageRgb8(img.to_rgb8());
        &converted
    } else {
        img
    };
    // Encoded in memory first: some encoders seek, and pipes and standard output cannot.
    let mut bytes = std::io::Cursor::new(Vec::new());
    img.write_to(&mut bytes, format)
        .map_err(|e| Error::Encode {
            path: path.into(),
            reason: e.to_string(),
        })?;
    write_atomic(path, |w| w.write_all(bytes.get_ref()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A field of several [`NPY_BLOCK`]s: read back value for value, and a NaN in a later
    /// block named at its own pixel.
    #[test]
    fn npy_fields_are_read_across_blocks() {
        let (w, h) = (600, 500);
        let data: Vec<[f32; 3]> = (0..w * h)
            .map(|i| [1.0 + i as f32, 0.25 * (i % 7) as f32, 2.0 + (i % 13) as f32])
            .collect();
        assert!(w * h * 12 > 3 * NPY_BLOCK, "spans several blocks");
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("field.npy");
        write_npy(&path, &TensorField::new(w, h, data.clone())).unwrap();
        let read = read_npy(&path).unwrap();
        assert_eq!((read.cols(), read.rows()), (w, h));
        assert_eq!(read.data(), &data[..]);
        // The same bytes through `decode_npy`.
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(decode_npy(&path, &bytes).unwrap().data(), &data[..]);

        let mut bad = data;
        bad[450 * w + 7][1] = f32::NAN;
        bad[460 * w + 2][0] = f32::INFINITY;
        write_npy(&path, &TensorField::new(w, h, bad)).unwrap();
        match read_npy(&path) {
            Err(Error::NonFinite { x, y, .. }) => assert_eq!((x, y), (7, 450)),
            other => panic!("{other:?}"),
        }
        // Cut short: refused before reading when far too short, and by the last block's read
        // when short by less than the header (whose length the first check cannot know).
        let bytes = std::fs::read(&path).unwrap();
        for cut in [2 * NPY_BLOCK + 1000, bytes.len() - 50] {
            match decode_npy(&path, &bytes[..cut]) {
                Err(Error::Npy { reason, .. }) => assert!(reason.contains("truncated"), "{reason}"),
                other => panic!("{other:?}"),
            }
        }
    }

    /// Fortran-ordered float32 and big-endian float64 fields read to the same tensors as the
    /// usual little-endian C order.
    #[test]
    fn npy_orders_and_byte_orders_read_alike() {
        use npyz::WriterBuilder;
        let (w, h) = (5usize, 3usize);
        let value = |x: usize, y: usize, k: usize| (1 + x + 10 * y) as f64 + 0.25 * k as f64;
        let expected: Vec<[f32; 3]> = (0..w * h)
            .map(|i| [0, 1, 2].map(|k| value(i % w, i / w, k) as f32))
            .collect();
        let dir = tempfile::tempdir().unwrap();
        let shape = [h as u64, w as u64, 3];
        // Fortran order: the first index runs fastest.
        let fortran = dir.path().join("fortran.npy");
        let mut bytes = Vec::new();
        let mut writer = npyz::WriteOptions::new()
            .default_dtype()
            .shape(&shape)
            .order(npyz::Order::Fortran)
            .writer(&mut bytes)
            .begin_nd()
            .unwrap();
        for k in 0..3 {
            for x in 0..w {
                for y in 0..h {
                    writer.push(&(value(x, y, k) as f32)).unwrap();
                }
            }
        }
        writer.finish().unwrap();
        std::fs::write(&fortran, &bytes).unwrap();
        assert_eq!(read_npy(&fortran).unwrap().data(), &expected[..]);
        // Big-endian float64, C order.
        let big = dir.path().join("big.npy");
        let mut bytes = Vec::new();
        let mut writer = npyz::WriteOptions::new()
            .dtype(npyz::DType::Plain(">f8".parse().unwrap()))
            .shape(&shape)
            .writer(&mut bytes)
            .begin_nd()
            .unwrap();
        for y in 0..h {
            for x in 0..w {
                for k in 0..3 {
                    writer.push(&value(x, y, k)).unwrap();
                }
            }
        }
        writer.finish().unwrap();
        std::fs::write(&big, &bytes).unwrap();
        assert_eq!(read_npy(&big).unwrap().data(), &expected[..]);
    }
}
