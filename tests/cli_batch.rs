//! `anisopaint batch` through the real binary: good files painted, bad ones listed with their
//! cause and exit 1, folder structure kept, resumed runs skip what exists, `--force` redoes,
//! shards partition the work (also three at once under GNU parallel), a batch killed midway
//! (SIGKILL) completes on a rerun with no damaged outputs, nothing painted twice and without
//! the temporary files the killed run left, and an output folder that cannot be written stops
//! the batch before any painting.

mod common;

use assert_cmd::Command;
use std::path::{Path, PathBuf};

fn bin() -> Command {
    Command::cargo_bin("anisopaint").unwrap()
}

/// A folder with two good photos (one in a subfolder) and a truncated one.
fn folder(root: &Path) -> PathBuf {
    let input = root.join("in");
    std::fs::create_dir_all(input.join("sub")).unwrap();
    std::fs::copy("samples/chelsea.png", input.join("cat.png")).unwrap();
    std::fs::copy("samples/coffee.png", input.join("sub/cup.png")).unwrap();
    let jpeg = std::fs::read("samples/astronaut.jpg").unwrap();
    std::fs::write(input.join("broken.jpg"), &jpeg[..500]).unwrap();
    input
}

/// Adds every other kind of bad file to `input`; returns (file name, expected cause).
fn bad_files(input: &Path) -> Vec<(&'static str, &'static str)> {
    std::fs::write(input.join("empty.png"), b"").unwrap();
    std::fs::write(input.join("notes.jpg"), b"shopping list: eggs\n").unwrap();
    std::fs::write(
        input.join("sub/bomb.png"),
        common::png_header_only(60_000, 60_000),
    )
    .unwrap();
    let mut bad = vec![
        ("broken.jpg", "cannot decode"),
        ("empty.png", "empty file"),
        ("notes.jpg", "not a PNG, JPEG, TIFF, WebP, GIF, BMP or PNM"),
        ("bomb.png", "too large"),
    ];
    let locked = input.join("locked.png");
    std::fs::copy("samples/chelsea.png", &locked).unwrap();
    if common::make_unreadable(&locked) {
        bad.push(("locked.png", "ermission denied"));
    } else {
        // As root the permission is not enforced: the file is simply painted.
        std::fs::remove_file(&locked).unwrap();
    }
    bad
}

/// Runs `anisopaint batch ARGS`, checks its exit code and returns its standard output.
fn batch(args: &[&std::ffi::OsStr], code: i32) -> String {
    let run = bin().arg("batch").args(args).assert().code(code);
    String::from_utf8_lossy(&run.get_output().stdout).to_string()
}

fn pngs(dir: &Path) -> Vec<PathBuf> {
    common::files_under(dir)
}

#[test]
fn good_files_painted_bad_ones_listed_and_resumed() {
    let dir = tempfile::tempdir().unwrap();
    let input = folder(dir.path());
    let bad = bad_files(&input);
    let out = dir.path().join("out");
    let all = [
        input.as_os_str(),
        "-s".as_ref(),
        "mosaic".as_ref(),
        "--recursive".as_ref(),
        "-o".as_ref(),
        out.as_os_str(),
    ];
    let stdout = batch(&all, 1);
    assert!(stdout.contains("2 painted"), "{stdout}");
    assert!(
        stdout.contains(&format!("{} failed", bad.len())),
        "{stdout}"
    );
    for (name, cause) in &bad {
        let line = stdout
            .lines()
            .find(|l| l.contains("failed:") && l.contains(name))
            .unwrap_or_else(|| panic!("{name} not listed: {stdout}"));
        assert!(line.contains(cause), "{name}: {line}");
    }
    assert_eq!(
        pngs(&out),
        vec![out.join("cat.mosaic.png"), out.join("sub/cup.mosaic.png")]
    );
    // No partial files anywhere.
    assert!(pngs(&out).iter().all(|p| image::open(p).is_ok()));
    let modified = || {
        std::fs::metadata(out.join("cat.mosaic.png"))
            .unwrap()
            .modified()
            .unwrap()
    };
    let before = modified();
    let stdout = batch(&all, 1);
    assert!(stdout.contains("0 painted, 2 skipped"), "{stdout}");
    assert_eq!(before, modified());
    let cat = input.join("cat.png");
    let stdout = batch(
        &[
            cat.as_os_str(),
            "-s".as_ref(),
            "mosaic".as_ref(),
            "--force".as_ref(),
            "-o".as_ref(),
            out.as_os_str(),
        ],
        0,
    );
    assert!(stdout.contains("1 painted"), "{stdout}");
}

#[test]
fn unwritable_output_folder_stops_before_painting() {
    let dir = tempfile::tempdir().unwrap();
    let input = folder(dir.path());
    let blocker = dir.path().join("not-a-folder");
    std::fs::write(&blocker, b"x").unwrap();
    for out in [blocker.clone(), blocker.join("out")] {
        let run = bin()
            .arg("batch")
            .arg(&input)
            .args(["-s", "mosaic", "-o"])
            .arg(&out)
            .assert()
            .code(2);
        let stderr = common::stderr_of(&run);
        assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
        assert!(stderr.contains("not-a-folder"), "{stderr}");
    }
    assert_eq!(std::fs::read(&blocker).unwrap(), b"x");
}

#[test]
fn shards_split_the_work_without_overlap() {
    let dir = tempfile::tempdir().unwrap();
    let input = folder(dir.path());
    std::fs::remove_file(input.join("broken.jpg")).unwrap();
    let out = dir.path().join("out");
    for shard in ["1/2", "2/2"] {
        let run = bin()
            .arg("batch")
            .arg(&input)
            .args(["-s", "glyphs", "--recursive", "--shard", shard, "-o"])
            .arg(&out)
            .assert()
            .success();
        let stdout = String::from_utf8_lossy(&run.get_output().stdout).to_string();
        assert!(stdout.contains("1 files: 1 painted"), "{shard}: {stdout}");
    }
    assert_eq!(pngs(&out).len(), 2);
    bin()
        .arg("batch")
        .arg(&input)
        .args(["--shard", "3/2", "-o"])
        .arg(&out)
        .assert()
        .code(2);
}

#[test]
fn a_killed_batch_completes_on_rerun() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in");
    std::fs::create_dir_all(&input).unwrap();
    for k in 0..6 {
        std::fs::copy("samples/astronaut.jpg", input.join(format!("p{k}.jpg"))).unwrap();
    }
    let out = dir.path().join("out");
    let exe = assert_cmd::cargo::cargo_bin("anisopaint");
    let mut child = std::process::Command::new(&exe)
        .arg("batch")
        .arg(&input)
        .args(["-s", "fabric", "--jobs", "1", "-q", "-o"])
        .arg(&out)
        .spawn()
        .unwrap();
    // Kill it once the first picture is there (or after a while).
    for _ in 0..400 {
        if out.exists() && !pngs(&out).is_empty() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(25));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    // Whatever was written is whole.
    let written: Vec<PathBuf> = pngs(&out)
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .collect();
    for p in &written {
        assert!(image::open(p).is_ok(), "{} is damaged", p.display());
    }
    assert!(written.len() < 6, "the kill came after the whole batch");
    // Each written picture as the killed run left it: its inode (a rewrite renames a new file
    // into place) and its bytes.
    let identity = |p: &Path| {
        #[cfg(unix)]
        let inode = std::os::unix::fs::MetadataExt::ino(&std::fs::metadata(p).unwrap());
        #[cfg(not(unix))]
        let inode = 0u64;
        (inode, std::fs::read(p).unwrap())
    };
    let before: Vec<_> = written.iter().map(|p| (p.clone(), identity(p))).collect();
    bin()
        .arg("batch")
        .arg(&input)
        .args(["-s", "fabric", "-q", "-o"])
        .arg(&out)
        .assert()
        .success();
    let done: Vec<PathBuf> = pngs(&out)
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .collect();
    assert_eq!(done.len(), 6);
    assert!(done.iter().all(|p| image::open(p).is_ok()));
    // Nothing was painted twice: what the killed run finished is untouched.
    for (p, was) in &before {
        assert!(identity(p) == *was, "{} was painted again", p.display());
    }
    if Path::new("/proc/self").exists() {
        // The rerun removed what the killed run left half-written.
        assert_eq!(pngs(&out), done, "only whole pictures remain");
    }
}

#[test]
fn temporary_files_of_killed_runs_are_removed_others_kept() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in");
    std::fs::create_dir_all(&input).unwrap();
    std::fs::copy("samples/chelsea.png", input.join("cat.png")).unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir_all(out.join("sub")).unwrap();
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|h| h.trim().to_string())
        .unwrap_or_else(|_| "host".into());
    // A process id that runs no process now.
    let dead = (100_000u32..)
        .find(|pid| !Path::new(&format!("/proc/{pid}")).exists())
        .unwrap();
    let alive = std::process::id();
    let stale = out.join(format!("sub/.anisopaint-{host}-{dead}-abc123.partial"));
    let running = out.join(format!(".anisopaint-{host}-{alive}-def456.partial"));
    let elsewhere = out.join(format!(".anisopaint-other-machine-{dead}-ghi789.partial"));
    for p in [&stale, &running, &elsewhere] {
        std::fs::write(p, b"half a picture").unwrap();
    }
    let run = bin()
        .arg("batch")
        .arg(&input)
        .args(["-s", "mosaic", "-o"])
        .arg(&out)
        .assert()
        .success();
    let stderr = common::stderr_of(&run);
    if Path::new("/proc/self").exists() {
        assert!(!stale.exists(), "a dead process's file is removed");
        assert!(stderr.contains("removed 1 temporary file"), "{stderr}");
    }
    assert!(
        running.exists() && elsewhere.exists(),
        "others' files are kept"
    );
}

#[test]
fn gif_bmp_and_pnm_photos_in_a_folder_are_painted() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in");
    std::fs::create_dir_all(&input).unwrap();
    let cat = image::open("samples/chelsea.png").unwrap();
    for name in ["cat.gif", "cat.bmp", "cat.ppm"] {
        cat.save(input.join(name)).unwrap();
    }
    let out = dir.path().join("out");
    bin()
        .args(["batch", "-q", "-o"])
        .arg(&out)
        .arg(&input)
        .assert()
        .success();
    let mut written: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    written.sort();
    // Three inputs with the same stem: the later ones keep their extension in the name.
    assert_eq!(written.len(), 3, "{written:?}");
    for name in &written {
        let img = image::open(out.join(name)).unwrap();
        assert_eq!((img.width(), img.height()), (451, 300), "{name}");
    }
}

/// Three shards of one batch run at the same time, as `parallel anisopaint batch … --shard
/// {}/3 ::: 1 2 3` runs them (the command `anisopaint batch --help` suggests): together they
/// paint every file exactly once and nothing else. With GNU parallel (Debian package
/// `parallel`, which CI installs) when it is there; otherwise the three processes are started
/// side by side here, which is what parallel does.
#[test]
fn concurrent_shards_paint_every_file_exactly_once() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in");
    std::fs::create_dir_all(&input).unwrap();
    let sources = [
        "samples/chelsea.png",
        "samples/coffee.png",
        "samples/astronaut.jpg",
    ];
    let mut names = Vec::new();
    for k in 0..7 {
        let from = sources[k % sources.len()];
        let ext = Path::new(from).extension().unwrap().to_str().unwrap();
        let name = format!("p{k}");
        std::fs::copy(from, input.join(format!("{name}.{ext}"))).unwrap();
        names.push(name);
    }
    let out = dir.path().join("out");
    let exe = assert_cmd::cargo::cargo_bin("anisopaint");
    let common_args = |shard: &str| -> Vec<std::ffi::OsString> {
        let mut a: Vec<std::ffi::OsString> = vec!["batch".into(), input.clone().into_os_string()];
        for s in ["-s", "mosaic", "--shard", shard, "-o"] {
            a.push(s.into());
        }
        a.push(out.clone().into_os_string());
        a
    };
    let has_parallel = std::process::Command::new("parallel")
        .arg("--version")
        .output()
        .map(|o| o.status.success() && String::from_utf8_lossy(&o.stdout).contains("GNU"))
        .unwrap_or(false);
    let stdout = if has_parallel {
        let mut cmd = std::process::Command::new("parallel");
        cmd.args(["--will-cite", "-j3", "--halt", "never"])
            .arg(&exe);
        cmd.args(common_args("{}/3"));
        cmd.args([":::", "1", "2", "3"]);
        let o = cmd.output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).to_string()
    } else {
        let children: Vec<_> = (1..=3)
            .map(|i| {
                std::process::Command::new(&exe)
                    .args(common_args(&format!("{i}/3")))
                    .stdout(std::process::Stdio::piped())
                    .spawn()
                    .unwrap()
            })
            .collect();
        children
            .into_iter()
            .map(|c| {
                let o = c.wait_with_output().unwrap();
                assert!(o.status.success());
                String::from_utf8_lossy(&o.stdout).to_string()
            })
            .collect()
    };
    // Every shard's summary "N files: N painted, …": the painted counts add up to the files.
    let painted: usize = stdout
        .lines()
        .filter_map(|l| l.split_once(" painted").map(|(head, _)| head))
        .filter_map(|head| head.rsplit(' ').next()?.parse::<usize>().ok())
        .sum();
    assert_eq!(painted, names.len(), "{stdout}");
    let written: Vec<String> = pngs(&out)
        .iter()
        .map(|p| p.file_stem().unwrap().to_string_lossy().to_string())
        .collect();
    let mut want: Vec<String> = names.iter().map(|n| format!("{n}.mosaic")).collect();
    want.sort();
    assert_eq!(written, want, "parallel: {has_parallel}");
}

#[test]
fn batch_writes_the_format_asked_for() {
    // `--format jpg`: every output is a JPEG named STEM.STYLE.jpg, of its photo's size, and a
    // second run finds them and skips them; a format that is not offered is bad usage.
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in");
    std::fs::create_dir_all(input.join("sub")).unwrap();
    std::fs::copy("samples/chelsea.png", input.join("cat.png")).unwrap();
    std::fs::copy("samples/coffee.png", input.join("sub/cup.png")).unwrap();
    let out = dir.path().join("out");
    let run = || {
        bin()
            .arg("batch")
            .arg(&input)
            .args(["--recursive", "--format", "jpg", "-o"])
            .arg(&out)
            .assert()
            .success()
    };
    run();
    let mut written = common::files_under(&out);
    written.sort();
    assert_eq!(
        written,
        vec![out.join("cat.mosaic.jpg"), out.join("sub/cup.mosaic.jpg")]
    );
    for (painting, photo) in written
        .iter()
        .zip(["samples/chelsea.png", "samples/coffee.png"])
    {
        let bytes = std::fs::read(painting).unwrap();
        assert_eq!(
            image::guess_format(&bytes).unwrap(),
            image::ImageFormat::Jpeg
        );
        let want = image::image_dimensions(photo).unwrap();
        assert_eq!(
            image::load_from_memory(&bytes)
                .unwrap()
                .to_rgb8()
                .dimensions(),
            want
        );
    }
    let again = run();
    let text = String::from_utf8_lossy(&again.get_output().stderr).into_owned();
    assert!(text.contains("exists, skipped"), "{text}");
    bin()
        .arg("batch")
        .arg(&input)
        .args(["--format", "gif", "-o"])
        .arg(&out)
        .assert()
        .code(2);
}
