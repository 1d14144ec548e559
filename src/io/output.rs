//! Where an output goes, and writing it there without ever leaving half a file:
//!
//! - `-` is standard output;
//! - a path that exists and is not a regular file or a folder (a device such as `/dev/null`,
//!   a named pipe, `/dev/stdout` on a pipe) is opened and written in place, never replaced:
//!   whatever reads the pipe gets the picture, and a write error there (no space, broken
//!   pipe) is an error;
//! - a symbolic link keeps being a link: the file it points to (through any chain of links)
//!   is the one replaced;
//! - everything else is written to a temporary file beside its final name, then renamed into
//!   place, so a reader sees the old file or the whole new one, never a part.
//!
//! Errors name the path the user gave, never the temporary file's.

use crate::error::{Error, Result};
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// The output name that means standard output.
pub const STDOUT: &str = "-";

/// Whether `path` means standard output.
#[must_use]
pub fn is_stdout(path: &Path) -> bool {
    path.as_os_str() == STDOUT
}

/// Where the bytes of an output path end up.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Destination {
    /// Standard output.
    Stdout,
    /// An existing file that is not a regular file (device, named pipe, socket): opened and
    /// written, never replaced.
    InPlace(PathBuf),
    /// A regular file (existing or not): a temporary file beside it, renamed over it.
    Replace(PathBuf),
}

/// Symbolic links followed at most before giving up (Linux's own limit).
const MAX_LINKS: usize = 40;

/// Where `path` writes to, following symbolic links to the file they name.
fn destination(path: &Path) -> std::io::Result<Destination> {
    if is_stdout(path) {
        return Ok(Destination::Stdout);
    }
    // What opening `path` reaches, as the system resolves it: a device, a pipe or a socket is
    // written in place. Asked of the path itself first: `/dev/stdout` links to
    // `/proc/self/fd/1`, whose link text for a pipe is no path (`pipe:[…]`).
    if let Ok(m) = std::fs::metadata(path) {
        if !m.is_file() && !m.is_dir() {
            return Ok(Destination::InPlace(path.to_path_buf()));
        }
    }
    let target = link_target(path)?;
    Ok(match std::fs::metadata(&target) {
        Ok(m) if !m.is_file() && !m.is_dir() => Destination::InPlace(target),
        _ => Destination::Replace(target),
    })
}

/// The file `path` names once every symbolic link on it is followed (a link may name a file
/// that does not exist yet: that file is the target).
fn link_target(path: &Path) -> std::io::Result<PathBuf> {
    let mut current = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match std::fs::symlink_metadata(&current) {
            Ok(m) if m.file_type().is_symlink() => {
                let next = std::fs::read_link(&current)?;
                current = match current.parent() {
                    Some(dir) if next.is_relative() => dir.join(next),
                    _ => next,
                };
            }
            _ => return Ok(current),
        }
    }
    Err(std::io::Error::other("too many levels of symbolic links"))
}

/// The OS error of `e` without the path a wrapping library may have put in its message (the
/// temporary file's name means nothing to the user).
fn plain(e: std::io::Error) -> std::io::Error {
    if let Some(code) = e.raw_os_error() {
        return std::io::Error::from_raw_os_error(code);
    }
    let mut source = e
        .get_ref()
        .map(|inner| inner as &(dyn std::error::Error + 'static));
    while let Some(s) = source {
        if let Some(code) = s
            .downcast_ref::<std::io::Error>()
            .and_then(std::io::Error::raw_os_error)
        {
            return std::io::Error::from_raw_os_error(code);
        }
        source = s.source();
    }
    e
}

/// Runs `write` on a buffered writer to `path`'s destination: standard output for
/// `-`, the file itself for a device or pipe, otherwise a temporary file beside the (link's)
/// target, renamed over it once whole. On any error a temporary file is removed and a
/// regular file at `path` is untouched; the error names `path`.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let name = if is_stdout(path) {
        Path::new("standard output")
    } else {
        path
    };
    let fail = |e: std::io::Error| Error::io(name, plain(e));
    match destination(path).map_err(fail)? {
        Destination::Stdout => {
            let stdout = std::io::stdout();
            let mut w = BufWriter::new(stdout.lock());
            write(&mut w).map_err(fail)?;
            w.flush().map_err(fail)
        }
        Destination::InPlace(target) => {
            let file = OpenOptions::new().write(true).open(&target).map_err(fail)?;
            let mut w = BufWriter::new(file);
            write(&mut w).map_err(fail)?;
            w.flush().map_err(fail)
        }
        Destination::Replace(target) => replace(&target, write).map_err(fail),
    }
}

/// Writes a temporary file beside `target` and renames it to `target`.
fn replace(
    target: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let dir = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    let prefix = temp_prefix();
    builder.prefix(&prefix).suffix(PARTIAL_SUFFIX);
    #[cfg(unix)]
    {
        // Ordinary file permissions (the umask applies), not tempfile's private 0600.
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut tmp = builder.tempfile_in(dir).map_err(|e| {
        // tempfile's message names the temporary file: say what is wrong with the folder.
        match std::fs::metadata(dir) {
            Err(why) => why,
            Ok(m) if !m.is_dir() => std::io::Error::from(std::io::ErrorKind::NotADirectory),
            Ok(_) => std::io::Error::from(e.kind()),
        }
    })?;
    {
        let file: &mut File = tmp.as_file_mut();
        let mut w = BufWriter::new(file);
        write(&mut w)?;
        w.flush()?;
    }
    tmp.persist(target).map_err(|e| e.error)?;
    Ok(())
}

const PARTIAL_PREFIX: &str = ".anisopaint-";
const PARTIAL_SUFFIX: &str = ".partial";

/// Name prefix of temporary files: `.anisopaint-HOST-PID-`, so that a later run can tell the
/// ones left behind by a process of this machine that no longer runs.
fn temp_prefix() -> String {
    format!("{PARTIAL_PREFIX}{}-{}-", host_name(), std::process::id())
}

/// This machine's name (Linux), or `host`.
fn host_name() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|h| h.trim().to_string())
        .ok()
        .filter(|h| !h.is_empty())
        .unwrap_or_else(|| "host".into())
}

/// Removes the temporary files under `dir` (and its subfolders) that a process of this
/// machine left when it was killed: a file named by [`write_atomic`] whose process no longer
/// runs. Files of running processes, and of other machines writing to a shared folder, are
/// left alone. Linux only (a process is looked up in `/proc`); elsewhere nothing is removed.
/// Returns how many files were removed.
pub fn remove_stale_partials(dir: &Path) -> usize {
    if !Path::new("/proc/self").exists() {
        return 0;
    }
    let host = host_name();
    let mut removed = 0;
    let Ok(entries) = std::fs::read_dir(dir) else {
        return 0;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            removed += remove_stale_partials(&path);
            continue;
        }
        let name = entry.file_name().to_string_lossy().into_owned();
        let Some(middle) = name
            .strip_prefix(PARTIAL_PREFIX)
            .and_then(|n| n.strip_suffix(PARTIAL_SUFFIX))
        else {
            continue;
        };
        // HOST-PID-RANDOM; the host name may hold dashes, the others do not.
        let mut parts = middle.rsplitn(3, '-');
        let (_random, pid, file_host) = (parts.next(), parts.next(), parts.next());
        let Some(pid) = pid.and_then(|p| p.parse::<u32>().ok()) else {
            continue;
        };
        let alive = Path::new("/proc").join(pid.to_string()).exists();
        if file_host == Some(host.as_str()) && !alive && std::fs::remove_file(&path).is_ok() {
            removed += 1;
        }
    }
    removed
}
