//! `anisopaint sample` through the real binary: the CSV files are what they claim to be, the
//! report is complete and machine-readable, and bad fields fail fast with exit code 2.

mod common;

use assert_cmd::Command;
use npyz::WriterBuilder;

fn bin() -> Command {
    Command::cargo_bin("anisopaint").unwrap()
}

fn read_csv(path: &std::path::Path) -> (String, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().to_string();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

#[test]
fn samples_triangles_preview_and_report() {
    let dir = tempfile::tempdir().unwrap();
    let (samples, tris, preview, json) = (
        dir.path().join("s.csv"),
        dir.path().join("t.csv"),
        dir.path().join("p.png"),
        dir.path().join("r.json"),
    );
    let out = bin()
        .args([
            "sample",
            "samples/chelsea.png",
            "--seed",
            "3",
            "--report",
            "--out",
        ])
        .arg(&samples)
        .arg("--triangles")
        .arg(&tris)
        .arg("--preview")
        .arg(&preview)
        .arg("--report-json")
        .arg(&json)
        .assert()
        .success();
    let stdout = String::from_utf8_lossy(&out.get_output().stdout).into_owned();
    for word in [
        "seeding",
        "relaxation",
        "flips",
        "flip cap hits",
        "inserted",
        "deleted",
        "coverage",
        "overlap",
    ] {
        assert!(stdout.contains(word), "report lacks {word}: {stdout}");
    }
    let (header, rows) = read_csv(&samples);
    assert_eq!(header, "x,y,m11,m12,m22");
    assert!(rows.len() > 500);
    for r in &rows {
        assert!(
            r[0] >= 0.0 && r[0] <= 451.0 && r[1] >= 0.0 && r[1] <= 300.0,
            "{r:?}"
        );
        assert!(
            r[2] > 0.0 && r[2] * r[4] - r[3] * r[3] > 0.0,
            "metric not positive definite: {r:?}"
        );
    }
    let (header, tri_rows) = read_csv(&tris);
    assert_eq!(header, "a,b,c");
    for t in &tri_rows {
        let p: Vec<&Vec<f64>> = t.iter().map(|&i| &rows[i as usize]).collect();
        let cross =
            (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
        assert!(cross > 0.0, "triangle {t:?} is not counter-clockwise");
    }
    // Euler: a triangulated rectangle has about twice as many triangles as vertices.
    assert!(tri_rows.len() > rows.len() && tri_rows.len() < 2 * rows.len());
    let report = std::fs::read_to_string(&json).unwrap();
    for key in [
        "\"seeded\"",
        "\"flips\"",
        "\"quality\"",
        "\"coverage\"",
        "\"nn_p5\"",
        "\"seconds\"",
    ] {
        assert!(report.contains(key), "{key} missing from {report}");
    }
    let img = image::open(&preview).unwrap();
    assert_eq!((img.width(), img.height()), (451, 300));
    assert!(common::distinct_colours(&preview) > 100, "an empty preview");
}

#[test]
fn same_seed_same_files_and_compare_lists_three_rows() {
    let dir = tempfile::tempdir().unwrap();
    let run = |name: &str, threads: &str| {
        let path = dir.path().join(name);
        bin()
            .env("RAYON_NUM_THREADS", threads)
            .args([
                "sample",
                "analytic:degenerate-point",
                "--width",
                "200",
                "--height",
                "150",
                "--seed",
                "11",
                "--out",
            ])
            .arg(&path)
            .assert()
            .success();
        std::fs::read(path).unwrap()
    };
    assert_eq!(run("a.csv", "1"), run("b.csv", "2"));
    let out = bin()
        .args([
            "sample",
            "analytic:two-point-load",
            "--width",
            "200",
            "--height",
            "150",
            "--compare",
        ])
        .assert()
        .success();
    let stdout = String::from_utf8_lossy(&out.get_output().stdout).into_owned();
    for row in ["random", "seed only", "relaxed"] {
        assert!(stdout.contains(row), "{stdout}");
    }
}

#[test]
fn bad_fields_fail_fast_with_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    // A metric with a zero tensor in it.
    let npy = dir.path().join("zero.npy");
    let mut values: Vec<f32> = (0..30 * 20).flat_map(|_| [2.0f32, 0.0, 2.0]).collect();
    values[(3 * 30 + 7) * 3..(3 * 30 + 7) * 3 + 3].copy_from_slice(&[0.0, 0.0, 0.0]);
    let mut bytes = Vec::new();
    let mut w = npyz::WriteOptions::new()
        .default_dtype()
        .shape(&[20, 30, 3])
        .writer(&mut bytes)
        .begin_nd()
        .unwrap();
    w.extend(values).unwrap();
    w.finish().unwrap();
    std::fs::write(&npy, bytes).unwrap();
    let out = dir.path().join("s.csv");
    bin()
        .arg("sample")
        .arg(&npy)
        .args(["--tensor", "metric"])
        .arg("--out")
        .arg(&out)
        .assert()
        .code(2)
        .stderr(predicates::str::contains("not positive definite"));
    assert!(!out.exists());
    // Far too many samples for the limit: refused at once, and --max-samples says how.
    bin()
        .args([
            "sample",
            "analytic:constant:size=0.00005",
            "--width",
            "4000",
            "--height",
            "3000",
        ])
        .assert()
        .code(2)
        .stderr(predicates::str::contains("--max-samples"));
    bin()
        .args(["sample", "analytic:constant", "--max-samples", "10"])
        .assert()
        .code(2)
        .stderr(predicates::str::contains("over the limit of 10"));
}
