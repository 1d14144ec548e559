//! Where outputs go, through the real binary: `-` is standard output (and, as the input,
//! standard input); a named pipe, and `/dev/stdout` on a pipe, are written in place (the pipe
//! stays a pipe), and a reader that hangs up is an error (exit 2, "Broken pipe"); a symbolic
//! link stays a link and its target gets the picture; a missing folder is reported with the
//! user's path, never the temporary file's. Devices are not touched here (`/dev/full` was checked by hand, see docs/cli.md):
//! a regression would replace the machine's device node.

use assert_cmd::Command;
use std::path::Path;

fn bin() -> Command {
    Command::cargo_bin("anisopaint").unwrap()
}

const PHOTO: &str = "samples/chelsea.png";

/// `paint PHOTO -s glyphs --seed 4` into `out`, as the command ran.
fn paint_to(out: &Path) -> assert_cmd::assert::Assert {
    bin()
        .args(["paint", PHOTO, "-s", "glyphs", "--seed", "4", "-q", "-o"])
        .arg(out)
        .assert()
}

fn pixels(bytes: &[u8]) -> image::RgbImage {
    image::load_from_memory(bytes)
        .expect("a whole picture")
        .to_rgb8()
}

#[test]
fn dash_is_standard_output_and_standard_input() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("file.png");
    paint_to(&file).success();
    let expected = pixels(&std::fs::read(&file).unwrap());
    let run = paint_to(Path::new("-")).success();
    let out = run.get_output();
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        &out.stdout[..8],
        b"\x89PNG\r\n\x1a\n",
        "a PNG on standard output"
    );
    assert!(
        pixels(&out.stdout) == expected,
        "the same picture as -o FILE"
    );
    assert!(!Path::new("-").exists(), "no file named '-'");
    // Standard input in, standard output out.
    let piped = bin()
        .args(["paint", "-", "-s", "glyphs", "--seed", "4", "-q", "-o", "-"])
        .pipe_stdin(PHOTO)
        .unwrap()
        .assert()
        .success();
    assert!(pixels(&piped.get_output().stdout) == expected);
    // Reading standard input needs an output name; two outputs cannot share stdout.
    bin()
        .args(["paint", "-", "-q"])
        .pipe_stdin(PHOTO)
        .unwrap()
        .assert()
        .code(2)
        .stderr(predicates::str::contains("standard input"));
    bin()
        .args(["paint", PHOTO, "-q", "-o", "-", "--svg", "-"])
        .assert()
        .code(2)
        .stderr(predicates::str::contains("only one output"));
    // A cut photo on standard input is refused like a cut file.
    let whole = std::fs::read(PHOTO).unwrap();
    bin()
        .args(["paint", "-", "-q", "-o", "-"])
        .write_stdin(whole[..whole.len() / 2].to_vec())
        .assert()
        .code(2)
        .stdout(predicates::str::is_empty())
        .stderr(predicates::str::contains("standard input"));
}

#[cfg(unix)]
#[test]
fn dev_stdout_on_a_pipe_is_written_in_place() {
    // `/dev/stdout` links to `/proc/self/fd/1`, which for a pipe (as here: the test reads the
    // command's output through one) names no file: the pipe gets the picture, or the samples.
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("file.png");
    paint_to(&file).success();
    let run = paint_to(Path::new("/dev/stdout")).success();
    assert!(pixels(&run.get_output().stdout) == pixels(&std::fs::read(&file).unwrap()));
    let samples = |out: &str| {
        bin()
            .args([
                "sample",
                "analytic:constant",
                "--width",
                "64",
                "--height",
                "48",
                "-q",
            ])
            .args(["--out", out])
            .assert()
            .success()
            .get_output()
            .stdout
            .clone()
    };
    let piped = samples("/dev/stdout");
    assert!(piped.starts_with(b"x,y,m11,m12,m22\n"), "the samples' CSV");
    assert_eq!(piped, samples("-"));
}

#[cfg(unix)]
fn mkfifo(path: &Path) {
    let status = std::process::Command::new("mkfifo")
        .arg(path)
        .status()
        .expect("mkfifo runs");
    assert!(status.success());
}

#[cfg(unix)]
#[test]
fn a_named_pipe_is_written_in_place_and_a_hang_up_is_an_error() {
    use std::io::Read;
    use std::os::unix::fs::FileTypeExt;
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe.png");
    mkfifo(&fifo);
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            std::fs::File::open(&fifo)
                .unwrap()
                .read_to_end(&mut bytes)
                .unwrap();
            bytes
        })
    };
    paint_to(&fifo).success();
    let bytes = reader.join().unwrap();
    let file = dir.path().join("file.png");
    paint_to(&file).success();
    assert!(pixels(&bytes) == pixels(&std::fs::read(&file).unwrap()));
    let kind = std::fs::symlink_metadata(&fifo).unwrap().file_type();
    assert!(kind.is_fifo(), "the pipe is still a pipe");
    // A reader that opens the pipe and hangs up at once: the write fails (the picture is far
    // larger than a pipe's buffer), exit 2 with the cause.
    let quitter = {
        let fifo = fifo.clone();
        std::thread::spawn(move || drop(std::fs::File::open(&fifo).unwrap()))
    };
    paint_to(&fifo)
        .code(2)
        .stderr(predicates::str::contains("pipe.png: Broken pipe"));
    quitter.join().unwrap();
    assert!(std::fs::symlink_metadata(&fifo)
        .unwrap()
        .file_type()
        .is_fifo());
}

#[cfg(unix)]
#[test]
fn a_symbolic_link_keeps_pointing_at_the_new_picture() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("sub");
    std::fs::create_dir(&sub).unwrap();
    let target = dir.path().join("target.png");
    std::fs::write(&target, b"old").unwrap();
    // A relative link in another folder, through a second link.
    let link = sub.join("link.png");
    std::os::unix::fs::symlink("../target.png", &link).unwrap();
    let outer = dir.path().join("outer.png");
    std::os::unix::fs::symlink("sub/link.png", &outer).unwrap();
    paint_to(&outer).success();
    for l in [&link, &outer] {
        assert!(std::fs::symlink_metadata(l)
            .unwrap()
            .file_type()
            .is_symlink());
    }
    let written = std::fs::read(&target).unwrap();
    assert_eq!(image::load_from_memory(&written).unwrap().width(), 451);
    // A dangling link gets its target created; a loop of links is an error.
    let dangling = dir.path().join("dangling.png");
    std::os::unix::fs::symlink("new.png", &dangling).unwrap();
    paint_to(&dangling).success();
    assert!(dir.path().join("new.png").is_file());
    let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
    std::os::unix::fs::symlink(&b, &a).unwrap();
    std::os::unix::fs::symlink(&a, &b).unwrap();
    paint_to(&a).code(2);
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().ends_with(".partial"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

#[test]
fn a_missing_folder_is_named_as_the_user_gave_it() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("no-such-folder").join("x.png");
    let run = paint_to(&out).code(2);
    let stderr = String::from_utf8_lossy(&run.get_output().stderr).into_owned();
    assert!(stderr.contains(&out.display().to_string()), "{stderr}");
    assert!(stderr.contains("No such file or directory"), "{stderr}");
    assert!(
        !stderr.contains("partial"),
        "the temporary file is named: {stderr}"
    );
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
}

/// The horizontal and vertical sampling factors of every component in a baseline JPEG's frame
/// header (SOF0), read from the bytes.
fn jpeg_sampling_factors(jpeg: &[u8]) -> Vec<u8> {
    let at = jpeg
        .windows(2)
        .position(|w| w == [0xFF, 0xC0])
        .expect("a baseline frame header");
    // FFC0, length (2), precision (1), height (2), width (2), component count (1), then
    // three bytes per component: id, sampling factors, quantisation table.
    let components = usize::from(jpeg[at + 9]);
    (0..components).map(|c| jpeg[at + 10 + 3 * c + 1]).collect()
}

#[test]
fn jpeg_outputs_keep_full_colour_resolution_and_the_picture() {
    // The same painting as PNG and as JPEG: the JPEG keeps every component at full resolution
    // (4:4:4, no chroma subsampling to smear the looks' fine coloured lines and dots) and stays
    // close to the PNG: these glyphs read 38.9 dB at quality 90, 36.1 dB at `image`'s default
    // of 75, which the outputs had before.
    let dir = tempfile::tempdir().unwrap();
    let (png, jpg) = (dir.path().join("p.png"), dir.path().join("p.jpg"));
    paint_to(&png).success();
    paint_to(&jpg).success();
    let jpeg = std::fs::read(&jpg).unwrap();
    assert_eq!(jpeg_sampling_factors(&jpeg), vec![0x11; 3]);
    let (a, b) = (pixels(&std::fs::read(&png).unwrap()), pixels(&jpeg));
    assert_eq!(a.dimensions(), b.dimensions());
    let mse = a
        .as_raw()
        .iter()
        .zip(b.as_raw())
        .map(|(&p, &q)| (f64::from(p) - f64::from(q)).powi(2))
        .sum::<f64>()
        / a.as_raw().len() as f64;
    let psnr = 10.0 * (255.0f64 * 255.0 / mse).log10();
    assert!(psnr >= 37.5, "JPEG against PNG: {psnr:.2} dB");
}
