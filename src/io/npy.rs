//! `.npy` files: tensor fields `(H, W, 3)` of `(t11, t12, t22)` read (float32 or float64, C or
//! Fortran order, either byte order; C order streamed in blocks of rows) and written (float32),
//! and label maps written (int32). Every value read must be finite, and a file cut short is
//! refused.

use super::{check_size, write_atomic};
use crate::error::{Error, Result};
use crate::field::TensorField;
use npyz::WriterBuilder;
use std::fs::File;
use std::io::{BufReader, Read};
use std::path::Path;

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
                if bytes_per == 4 && !big {
                    return little_f32_row(row, bytes).map(|x| (x, y));
                }
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

/// One row of little-endian `f32` tensors (the usual `.npy` of a float32 array) into `row`,
/// without a branch per value: [`stored_value`]'s values, and the column of the first pixel
/// holding one that is not finite.
fn little_f32_row(row: &mut [[f32; 3]], bytes: &[u8]) -> Option<usize> {
    let mut finite = true;
    for (t, px) in row.iter_mut().zip(bytes.chunks_exact(12)) {
        *t = std::array::from_fn(|k| {
            f32::from_le_bytes([px[4 * k], px[4 * k + 1], px[4 * k + 2], px[4 * k + 3]])
        });
        finite &= t.iter().all(|v| v.is_finite());
    }
    if finite {
        return None;
    }
    row.iter().position(|t| !t.iter().all(|v| v.is_finite()))
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
