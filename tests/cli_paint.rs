//! `anisopaint paint` and `anisopaint styles` through the real binary: presets by name and by
//! file, `extends`, `--set`, the default output name beside the input, byte-identical output
//! for a seed, and one-line errors (exit 2) for bad presets.

mod common;

use assert_cmd::Command;

fn bin() -> Command {
    Command::cargo_bin("anisopaint").unwrap()
}

#[test]
fn styles_lists_and_shows_the_presets() {
    let out = bin()
        .arg("styles")
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let text = String::from_utf8(out).unwrap();
    for name in anisopaint::style::BUILT_IN.map(|(n, _)| n) {
        assert!(
            text.lines().any(|l| l.starts_with(name)),
            "{name} missing:\n{text}"
        );
    }
    assert!(text.lines().count() >= 9);
    let out = bin()
        .args(["styles", "show", "pen-hatch"])
        .assert()
        .success();
    let shown = String::from_utf8(out.get_output().stdout.clone()).unwrap();
    assert_eq!(shown, anisopaint::style::built_in("pen-hatch").unwrap());
    bin().args(["styles", "show", "nope"]).assert().code(2);
    // --full: the effective preset, `extends` followed, ready to save and paint with.
    let dir = tempfile::tempdir().unwrap();
    let full = bin()
        .args([
            "styles",
            "show",
            "crosshatch",
            "--full",
            "--set",
            "look.gamma=1.5",
        ])
        .assert()
        .success();
    let text = String::from_utf8(full.get_output().stdout.clone()).unwrap();
    assert!(!text.lines().any(|l| l.starts_with("extends")), "{text}");
    assert!(text.contains("gamma = 1.5"), "{text}");
    let saved = dir.path().join("mine.toml");
    std::fs::write(&saved, &text).unwrap();
    let mut expected = anisopaint::style::load("crosshatch").unwrap();
    anisopaint::style::apply_sets(&mut expected, &["look.gamma=1.5".into()]).unwrap();
    let mine = anisopaint::style::load(saved.to_str().unwrap()).unwrap();
    assert_eq!(mine.look().unwrap(), expected.look().unwrap());
    assert_eq!(mine.metric().unwrap(), expected.metric().unwrap());
    bin()
        .args(["styles", "show", "mosaic", "--set", "look.relief=0.2"])
        .assert()
        .code(2);
}

#[test]
fn styles_keys_lists_what_the_look_reads_and_a_slip_gets_a_suggestion() {
    let text = |args: &[&str]| {
        let out = bin().args(args).assert().success();
        String::from_utf8(out.get_output().stdout.clone()).unwrap()
    };
    let keys = text(&["styles", "keys", "pen-hatch"]);
    let row = keys
        .lines()
        .find(|l| l.starts_with("look.lines_per_cell "))
        .unwrap_or_else(|| panic!("{keys}"));
    assert!(
        row.contains(" 4 ") && row.contains("number in [0.1, 100]"),
        "{row}"
    );
    assert!(
        !keys.contains("look.relief"),
        "a mosaic key in pen-hatch's list:\n{keys}"
    );
    // Every row is a key of the schema read by the look, with its doc line.
    for line in keys.lines().skip(1) {
        let path = line.split_whitespace().next().unwrap();
        let key = anisopaint::style::schema::key_at(path).unwrap();
        assert!(
            key.readers.include("hatch") && line.ends_with(key.doc),
            "{line}"
        );
    }
    // Another look's keys through --set.
    let fabric = text(&["styles", "keys", "--set", "look.kind=fabric"]);
    assert!(fabric.contains("look.kernel_px") && !fabric.contains("look.border_width"));
    // What `paint -s STYLE --set SET` says on standard error (it must exit 2).
    let refused = |style: &str, set: &str| {
        let run = bin()
            .args([
                "paint",
                "samples/chelsea.png",
                "-s",
                style,
                "-o",
                "-",
                "--set",
                set,
            ])
            .assert()
            .code(2);
        common::stderr_of(&run)
    };
    // A slip: one line, the nearest key of that look.
    let stderr = refused("pen-hatch", "look.lines_per_cel=3");
    assert!(
        stderr.contains("did you mean look.lines_per_cell?"),
        "{stderr}"
    );
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    // A key another look reads: which looks read it, and what this one reads.
    let stderr = refused("mosaic", "look.lines_per_cell=3");
    assert!(
        stderr.contains("look.lines_per_cell is not read by the mosaic look (only by hatch")
            && stderr.contains("the mosaic look reads look.kind"),
        "{stderr}"
    );
}

#[test]
fn paint_writes_beside_the_input_and_is_reproducible() {
    let dir = tempfile::tempdir().unwrap();
    let photo = dir.path().join("cat.png");
    std::fs::copy("samples/chelsea.png", &photo).unwrap();
    bin().arg("paint").arg(&photo).assert().success();
    let default = dir.path().join("cat.mosaic.png");
    assert_eq!(image::image_dimensions(&default).unwrap(), (451, 300));
    for (style, name) in [("pen-hatch", "a.png"), ("pen-hatch", "b.png")] {
        bin()
            .arg("paint")
            .arg(&photo)
            .args(["-s", style, "--seed", "5", "-o"])
            .arg(dir.path().join(name))
            .assert()
            .success();
    }
    let (a, b) = (
        std::fs::read(dir.path().join("a.png")).unwrap(),
        std::fs::read(dir.path().join("b.png")).unwrap(),
    );
    assert_eq!(a, b, "same seed, same bytes");
    // The input is never the output.
    bin()
        .arg("paint")
        .arg(&photo)
        .arg("-o")
        .arg(&photo)
        .assert()
        .code(2);
}

#[test]
fn own_presets_extend_and_set_overrides() {
    let dir = tempfile::tempdir().unwrap();
    let mine = dir.path().join("thick.toml");
    std::fs::write(
        &mine,
        "description = \"mosaic with thick leading\"\nextends = \"mosaic\"\n[look]\nborder_width = 5.0\n",
    )
    .unwrap();
    let (thin, thick) = (dir.path().join("thin.png"), dir.path().join("thick.png"));
    bin()
        .args(["paint", "samples/coffee.png", "-s", "mosaic", "-o"])
        .arg(&thin)
        .assert()
        .success();
    bin()
        .args(["paint", "samples/coffee.png", "-s"])
        .arg(&mine)
        .arg("-o")
        .arg(&thick)
        .assert()
        .success();
    // Thicker leading: more dark pixels.
    let dark = |p: &std::path::Path| {
        image::open(p)
            .unwrap()
            .to_rgb8()
            .pixels()
            .filter(|px| px.0.iter().all(|&v| v < 60))
            .count()
    };
    assert!(
        dark(&thick) > dark(&thin) * 2,
        "{} vs {}",
        dark(&thick),
        dark(&thin)
    );
    let set = dir.path().join("set.png");
    bin()
        .args([
            "paint",
            "samples/coffee.png",
            "-s",
            "mosaic",
            "--set",
            "look.border_width=5.0",
        ])
        .arg("-o")
        .arg(&set)
        .assert()
        .success();
    // The same picture (the files differ in the text chunks that record how each was made).
    let pixels = |p: &std::path::Path| image::open(p).unwrap().to_rgb8().into_raw();
    assert!(pixels(&set) == pixels(&thick));
}

#[test]
fn bad_presets_fail_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "[look]\nkind = \"mosaic\"\nborder_widht = 2\n").unwrap();
    let wrong_type = dir.path().join("type.toml");
    std::fs::write(&wrong_type, "[metric]\nmax_anisotropy = \"lots\"\n").unwrap();
    let out = dir.path().join("o.png");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (vec!["-s".into(), bad.display().to_string()], "bad.toml:3:1"),
        (
            vec!["-s".into(), wrong_type.display().to_string()],
            "type.toml:2:18",
        ),
        (vec!["-s".into(), "nope".into()], "built-in: mosaic"),
        (
            vec!["--set".into(), "look.kind=watercolour".into()],
            "look.kind",
        ),
        (vec!["--set".into(), "look.bordr=1".into()], "border_width"),
        (
            vec!["--set".into(), "metric.max_size=-1".into()],
            "max_size",
        ),
        // The override named as written, not a line and column of a text the user never saw.
        (
            vec!["--set".into(), "look.relief=abc".into()],
            "--set look.relief=abc: invalid type",
        ),
    ];
    for (extra, expect) in cases {
        let assert = bin()
            .args(["paint", "samples/chelsea.png", "-o"])
            .arg(&out)
            .args(&extra)
            .assert()
            .code(2);
        let stderr = String::from_utf8_lossy(&assert.get_output().stderr).to_string();
        assert_eq!(stderr.trim().lines().count(), 1, "{extra:?}: {stderr}");
        assert!(stderr.contains(expect), "{extra:?}: {stderr}");
        assert!(!out.exists());
    }
}

#[test]
fn a_folder_to_paint_is_pointed_to_batch() {
    let dir = tempfile::tempdir().unwrap();
    let assert = bin()
        .args(["paint", "samples", "-o"])
        .arg(dir.path().join("o.png"))
        .assert()
        .code(2);
    let stderr = String::from_utf8_lossy(&assert.get_output().stderr).to_string();
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(stderr.contains("samples: a folder") && stderr.contains("anisopaint batch"));
}

#[test]
fn info_tells_how_a_picture_was_made() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.png");
    bin()
        .args([
            "paint",
            "samples/chelsea.png",
            "-s",
            "pen-hatch",
            "--seed",
            "9",
        ])
        .args(["--set", "look.lines_per_cell=6", "-o"])
        .arg(&out)
        .assert()
        .success();
    let printed = bin().arg("info").arg(&out).assert().success();
    let text = String::from_utf8(printed.get_output().stdout.clone()).unwrap();
    for expect in [
        "anisopaint:style: pen-hatch",
        "anisopaint:seed: 9",
        "anisopaint:set: look.lines_per_cell=6",
        "anisopaint:command: anisopaint paint samples/chelsea.png -s pen-hatch --seed 9 --set look.lines_per_cell=6",
        concat!("Software: anisopaint ", env!("CARGO_PKG_VERSION")),
    ] {
        assert!(text.contains(expect), "{expect} missing:\n{text}");
    }
    // The picture itself is an ordinary PNG.
    assert_eq!(image::image_dimensions(&out).unwrap(), (451, 300));
    bin()
        .args(["info", "samples/astronaut.jpg"])
        .assert()
        .code(2);
}

#[test]
fn completions_for_the_shells() {
    for shell in ["bash", "zsh", "fish"] {
        let out = bin().args(["completions", shell]).assert().success();
        let text = String::from_utf8(out.get_output().stdout.clone()).unwrap();
        assert!(
            text.contains("anisopaint") && text.contains("paint"),
            "{shell}"
        );
    }
    bin().args(["completions", "cmd.exe"]).assert().code(2);
}

#[test]
fn every_preset_is_byte_identical_with_one_and_two_threads() {
    let dir = tempfile::tempdir().unwrap();
    for (style, _) in anisopaint::style::BUILT_IN {
        let mut outputs = Vec::new();
        for threads in ["1", "2"] {
            let out = dir.path().join(format!("{style}-{threads}.png"));
            bin()
                .env("RAYON_NUM_THREADS", threads)
                .args(["paint", "samples/chelsea.png", "-s", style, "--seed", "9"])
                .arg("-o")
                .arg(&out)
                .assert()
                .success();
            outputs.push(std::fs::read(&out).unwrap());
        }
        assert!(outputs[0] == outputs[1], "{style}: 1 and 2 threads differ");
        let colours = common::distinct_colours(&dir.path().join(format!("{style}-1.png")));
        assert!(colours > 20, "{style}: only {colours} colours drawn");
    }
}

#[test]
fn verbose_prints_stage_timings_and_quiet_prints_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("v.png");
    let run = bin()
        .args(["paint", "samples/chelsea.png", "-v", "-o"])
        .arg(&out)
        .assert()
        .success();
    let stderr = common::stderr_of(&run);
    let line = stderr
        .lines()
        .find(|l| l.starts_with("timings:"))
        .unwrap_or_else(|| panic!("no timings: {stderr}"));
    for stage in [
        "reading",
        "metric",
        "seeding",
        "relaxation",
        "rendering",
        "writing",
        "total",
    ] {
        assert!(line.contains(stage), "{stage} missing: {line}");
    }
    // The iterations run: chelsea's 2 000-odd samples are seeded from a lattice, which runs
    // 70 of the default 100.
    assert!(line.contains("(70 it)"), "{line}");
    // Not a terminal: no bars, so nothing at all without -v.
    for quiet in [&["-q"][..], &[]] {
        bin()
            .args(["paint", "samples/chelsea.png", "-o"])
            .arg(&out)
            .args(quiet)
            .assert()
            .success()
            .stderr("")
            .stdout("");
    }
}
