//! `anisopaint field` through the real binary: outputs that round-trip, and every kind of bad
//! input giving exit code 2, one line naming the file and the problem, and no output left.

mod common;

use assert_cmd::Command;
use common::png_header_only;
use npyz::WriterBuilder;
use std::path::{Path, PathBuf};

const PHOTO: &str = "samples/chelsea.png";

fn bin() -> Command {
    Command::cargo_bin("anisopaint").unwrap()
}

fn write_npy_f64(path: &Path, shape: &[u64], values: &[f64]) {
    let mut out = Vec::new();
    let mut w = npyz::WriteOptions::new()
        .default_dtype()
        .shape(shape)
        .writer(&mut out)
        .begin_nd()
        .unwrap();
    w.extend(values.iter().copied()).unwrap();
    w.finish().unwrap();
    std::fs::write(path, out).unwrap();
}

fn read_npy_f32(path: &Path) -> (Vec<u64>, Vec<f32>) {
    let bytes = std::fs::read(path).unwrap();
    let npy = npyz::NpyFile::new(&bytes[..]).unwrap();
    let shape = npy.shape().to_vec();
    (shape, npy.into_vec::<f32>().unwrap())
}

/// Runs `field INPUT --out … --preview …` expecting failure with exit code 2, a one-line
/// message containing every needle, and nothing written in the output folder.
fn expect_bad_input(input: &str, extra: &[&str], needles: &[&str]) {
    let outdir = tempfile::tempdir().unwrap();
    let out = outdir.path().join("metric.npy");
    let preview = outdir.path().join("preview.png");
    let assert = bin()
        .arg("field")
        .arg(input)
        .args(extra)
        .arg("--out")
        .arg(&out)
        .arg("--preview")
        .arg(&preview)
        .assert()
        .code(2);
    let stderr = String::from_utf8_lossy(&assert.get_output().stderr).into_owned();
    assert_eq!(stderr.trim_end().lines().count(), 1, "one line: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    for n in needles {
        assert!(stderr.contains(n), "'{n}' not in: {stderr}");
    }
    let left: Vec<PathBuf> = std::fs::read_dir(outdir.path())
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert!(left.is_empty(), "files left behind: {left:?}");
}

#[test]
fn photo_gives_metric_npy_and_preview_at_its_size() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m.npy");
    let raw = dir.path().join("raw.npy");
    let preview = dir.path().join("p.png");
    bin()
        .args(["field", PHOTO, "--out"])
        .arg(&out)
        .arg("--preview")
        .arg(&preview)
        .assert()
        .success();
    bin()
        .args(["field", PHOTO, "--raw", "--out"])
        .arg(&raw)
        .assert()
        .success();
    let (shape, m) = read_npy_f32(&out);
    assert_eq!(shape, vec![300, 451, 3]);
    for t in m.chunks_exact(3) {
        // A metric: positive definite, semi-axes of a few pixels up to a few tens.
        let det = f64::from(t[0]) * f64::from(t[2]) - f64::from(t[1]).powi(2);
        assert!(t[0] > 0.0 && det > 0.0, "{t:?}");
        assert!(t[0] < 60.0 && t[2] < 60.0, "{t:?}");
    }
    let (shape, j) = read_npy_f32(&raw);
    assert_eq!(shape, vec![300, 451, 3]);
    assert!(j.chunks_exact(3).all(|t| t[0] >= 0.0 && t[2] >= 0.0));
    assert_ne!(m, j);
    let img = image::open(&preview).unwrap();
    assert_eq!((img.width(), img.height()), (451, 300));
    assert!(common::distinct_colours(&preview) > 100, "an empty preview");
}

#[test]
fn metric_npy_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    let first = dir.path().join("first.npy");
    let second = dir.path().join("second.npy");
    bin()
        .args(["field", PHOTO, "--out"])
        .arg(&first)
        .assert()
        .success();
    bin()
        .arg("field")
        .arg(&first)
        .args(["--tensor", "metric", "--out"])
        .arg(&second)
        .assert()
        .success();
    assert_eq!(
        std::fs::read(&first).unwrap(),
        std::fs::read(&second).unwrap()
    );
}

#[test]
fn float64_general_tensor_is_mapped() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("stress.npy");
    let out = dir.path().join("m.npy");
    // A 4x5 field with eigenvalues +1 and −1 everywhere: a general tensor (auto-detected).
    let values: Vec<f64> = (0..20).flat_map(|_| [1.0, 0.0, -1.0]).collect();
    write_npy_f64(&input, &[4, 5, 3], &values);
    bin()
        .arg("field")
        .arg(&input)
        .arg("--out")
        .arg(&out)
        .assert()
        .success();
    let (shape, m) = read_npy_f32(&out);
    assert_eq!(shape, vec![4, 5, 3]);
    // base size 0.02 of the diagonal √41, κ = 0.7, median magnitude 1: semi-axes
    // s·e^{±0.7·tanh 1}, long along x.
    let s = 0.02 * 41f64.sqrt();
    let k = 0.7 * 1f64.tanh();
    assert!((f64::from(m[0]) - s * k.exp()).abs() < 1e-5);
    assert!((f64::from(m[2]) - s * (-k).exp()).abs() < 1e-5);
}

#[test]
fn analytic_fields_render() {
    let dir = tempfile::tempdir().unwrap();
    for spec in [
        "analytic:constant:angle=30,anisotropy=4",
        "analytic:circular",
        "analytic:degenerate-point",
        "analytic:two-point-load",
    ] {
        let out = dir.path().join("a.npy");
        bin()
            .args(["field", spec, "--width", "40", "--height", "30", "--out"])
            .arg(&out)
            .assert()
            .success();
        let (shape, m) = read_npy_f32(&out);
        assert_eq!(shape, vec![30, 40, 3], "{spec}");
        assert!(m.iter().all(|v| v.is_finite()), "{spec}");
    }
}

#[test]
fn quiet_and_verbose_as_the_other_commands() {
    // `-q` and `-v` are accepted as by `paint`, `sample` and `render` (a script may pass them
    // to every command); `-v` prints the stages' times on standard error, `-q` nothing.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m.npy");
    let quiet = bin()
        .args(["field", PHOTO, "-q", "--out"])
        .arg(&out)
        .assert()
        .success();
    assert!(quiet.get_output().stderr.is_empty());
    let verbose = bin()
        .args(["field", PHOTO, "-v", "--out"])
        .arg(&out)
        .assert()
        .success();
    let text = String::from_utf8_lossy(&verbose.get_output().stderr).into_owned();
    assert!(
        text.contains("timings: reading") && text.contains("metric"),
        "{text}"
    );
}

#[test]
fn missing_file() {
    expect_bad_input(
        "no/such/photo.png",
        &[],
        &["no/such/photo.png", "No such file"],
    );
}

#[test]
fn unreadable_file_a_directory() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().join("folder.png");
    std::fs::create_dir(&d).unwrap();
    expect_bad_input(d.to_str().unwrap(), &[], &["folder.png"]);
}

#[test]
fn empty_file() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("empty.png");
    std::fs::write(&p, b"").unwrap();
    expect_bad_input(p.to_str().unwrap(), &[], &["empty.png", "empty file"]);
}

#[test]
fn truncated_png() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("cut.png");
    let bytes = std::fs::read(PHOTO).unwrap();
    std::fs::write(&p, &bytes[..bytes.len() / 3]).unwrap();
    expect_bad_input(p.to_str().unwrap(), &[], &["cut.png", "cannot decode"]);
}

#[test]
fn text_with_an_image_extension() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("notes.jpg");
    std::fs::write(&p, b"this is not a picture\n").unwrap();
    expect_bad_input(p.to_str().unwrap(), &[], &["notes.jpg", "not a PNG"]);
}

#[test]
fn png_with_a_jpeg_extension_is_read_by_content() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("really-a-png.jpg");
    std::fs::copy(PHOTO, &p).unwrap();
    bin().arg("field").arg(&p).assert().success();
}

#[test]
fn decompression_bomb_is_refused_before_decoding() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("bomb.png");
    std::fs::write(&p, png_header_only(60_000, 60_000)).unwrap();
    expect_bad_input(
        p.to_str().unwrap(),
        &[],
        &["bomb.png", "too large", "60000x60000"],
    );
}

#[test]
fn zero_sized_image() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("zero.png");
    std::fs::write(&p, png_header_only(0, 10)).unwrap();
    expect_bad_input(p.to_str().unwrap(), &[], &["zero.png"]);
}

#[test]
fn npy_of_the_wrong_shape() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("flat.npy");
    write_npy_f64(&p, &[4, 5, 2], &[1.0; 40]);
    expect_bad_input(p.to_str().unwrap(), &[], &["flat.npy", "shape [4, 5, 2]"]);
}

#[test]
fn npy_of_the_wrong_dtype() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("ints.npy");
    let mut out = Vec::new();
    let mut w = npyz::WriteOptions::new()
        .default_dtype()
        .shape(&[2, 2, 3])
        .writer(&mut out)
        .begin_nd()
        .unwrap();
    w.extend([1i32; 12]).unwrap();
    w.finish().unwrap();
    std::fs::write(&p, out).unwrap();
    expect_bad_input(
        p.to_str().unwrap(),
        &[],
        &["ints.npy", "<i4", "float32 or float64"],
    );
}

#[test]
fn npy_truncated() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("short.npy");
    write_npy_f64(&p, &[40, 50, 3], &vec![1.0; 6000]);
    let bytes = std::fs::read(&p).unwrap();
    std::fs::write(&p, &bytes[..bytes.len() - 100]).unwrap();
    expect_bad_input(p.to_str().unwrap(), &[], &["short.npy", "truncated"]);
}

#[test]
fn npy_with_nan_names_the_pixel() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("nan.npy");
    let mut v: Vec<f64> = (0..20).flat_map(|_| [2.0, 0.0, 2.0]).collect();
    // Row 1, column 3 of a 4x5 field.
    v[(5 + 3) * 3 + 1] = f64::NAN;
    write_npy_f64(&p, &[4, 5, 3], &v);
    expect_bad_input(
        p.to_str().unwrap(),
        &[],
        &["nan.npy", "non-finite", "pixel (3, 1)"],
    );
    v[(5 + 3) * 3 + 1] = f64::INFINITY;
    write_npy_f64(&p, &[4, 5, 3], &v);
    expect_bad_input(p.to_str().unwrap(), &[], &["pixel (3, 1)"]);
}

#[test]
fn declared_metric_that_is_not_positive_definite() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("bad-metric.npy");
    let mut v: Vec<f64> = (0..20).flat_map(|_| [2.0, 0.0, 2.0]).collect();
    v[(2 * 5 + 4) * 3..(2 * 5 + 4) * 3 + 3].copy_from_slice(&[1.0, 3.0, 1.0]);
    write_npy_f64(&p, &[4, 5, 3], &v);
    expect_bad_input(
        p.to_str().unwrap(),
        &["--tensor", "metric"],
        &["bad-metric.npy", "not positive definite", "pixel (4, 2)"],
    );
}

#[test]
fn width_only_for_analytic_inputs() {
    expect_bad_input(PHOTO, &["--width", "100"], &["--width"]);
}

#[test]
fn unknown_analytic_field_lists_the_known_ones() {
    expect_bad_input("analytic:vortex", &[], &["vortex", "two-point-load"]);
    expect_bad_input("analytic:constant:anisotropy=0.5", &[], &["anisotropy"]);
}

#[test]
fn unwritable_output_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("missing-folder").join("m.npy");
    let assert = bin()
        .args(["field", PHOTO, "--out"])
        .arg(&out)
        .assert()
        .code(2);
    let stderr = String::from_utf8_lossy(&assert.get_output().stderr).into_owned();
    assert!(stderr.contains("missing-folder"), "{stderr}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn never_overwrites_the_input() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("photo.png");
    std::fs::copy(PHOTO, &p).unwrap();
    let before = std::fs::read(&p).unwrap();
    bin()
        .arg("field")
        .arg(&p)
        .arg("--preview")
        .arg(&p)
        .assert()
        .code(2)
        .stderr(predicates::str::contains("is the input file"));
    assert_eq!(std::fs::read(&p).unwrap(), before);
}

#[test]
fn usage_errors_exit_2_and_help_exits_0() {
    bin().args(["field"]).assert().code(2);
    bin().args(["frobnicate"]).assert().code(2);
    bin()
        .args(["field", "--help"])
        .assert()
        .success()
        .stdout(predicates::str::contains("Examples:"));
}
