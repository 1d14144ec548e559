//! Folder batches: which files to paint and where each result goes ([`plan`]), and running the
//! items over a few worker threads with bounded memory ([`run`]), going on past bad files.
//!
//! Outputs keep the folder structure below each source folder and are named `STEM.STYLE.EXT`, `EXT`
//! one of [`OUTPUT_FORMATS`] (PNG unless asked). An output that exists is skipped unless forced,
//! and every output is written atomically (temporary file, then rename), so a batch that was
//! interrupted is resumed by running it again. `--shard i/n` keeps every n-th item of the sorted
//! list, so the same batch can be spread over machines (GNU parallel, Slurm job arrays) with no
//! overlap.

use crate::error::{Error, Result};
use std::path::{Path, PathBuf};
use std::sync::{Condvar, Mutex};

/// One file to paint.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Item {
    /// The input file.
    pub input: PathBuf,
    /// Where its painting goes.
    pub output: PathBuf,
}

/// What happened to an item.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Painted and written.
    Done,
    /// Its output existed already.
    Skipped,
    /// It failed; the reason, one line.
    Failed(String),
}

/// File extensions taken from folders (any file named explicitly is tried).
pub const IMAGE_EXTENSIONS: [&str; 13] = [
    "png", "jpg", "jpeg", "tif", "tiff", "webp", "gif", "bmp", "pnm", "ppm", "pgm", "pbm", "pam",
];

/// The extensions `batch --format` takes for its outputs: PNG, JPEG (quality 90, see
/// [`crate::io::save_rgb`]), TIFF and lossless WebP.
pub const OUTPUT_FORMATS: [&str; 4] = ["png", "jpg", "tif", "webp"];

/// Default memory the running items may use together (`batch --memory`), estimated from their
/// pixel counts: a large photo does not run beside others when together they would exceed it.
pub const MEMORY_BUDGET: u64 = 3 << 30;

/// Bytes from a size as users write it: a number with an optional `K`, `M`, `G` or `T` (powers
/// of 1024, `B`/`iB` allowed after them, any case), e.g. `800M`, `2G`, `1.5GiB`, `3000000000`.
pub fn parse_memory(text: &str) -> Result<u64> {
    let bad = || {
        Error::param(
            "--memory",
            format!("'{text}' is not a size such as 800M, 2G or 1.5GiB"),
        )
    };
    let t = text.trim().to_ascii_lowercase();
    let t = t
        .strip_suffix("ib")
        .or_else(|| t.strip_suffix('b'))
        .unwrap_or(&t);
    let (number, unit) = match t.char_indices().last() {
        Some((i, c)) if c.is_ascii_alphabetic() => (&t[..i], c),
        _ => (t, ' '),
    };
    let scale: f64 = match unit {
        ' ' => 1.0,
        'k' => 1024.0,
        'm' => 1024.0 * 1024.0,
        'g' => 1024.0 * 1024.0 * 1024.0,
        't' => 1024.0 * 1024.0 * 1024.0 * 1024.0,
        _ => return Err(bad()),
    };
    let value: f64 = number.trim().parse().map_err(|_| bad())?;
    let bytes = value * scale;
    // At least a byte, and within u64 (2⁶⁴ ≈ 1.84e19).
    if !(1.0..1.8e19).contains(&bytes) {
        return Err(bad());
    }
    Ok(bytes as u64)
}

/// Estimated peak bytes per input pixel of one painting (measured: a 12 MP photo peaks near
/// 500 MB in `paint`, about 40 B per pixel, with room to spare).
pub const BYTES_PER_PIXEL: u64 = 48;

/// The items of a batch: files named in `sources`, and the images in folders named there
/// (their subfolders too with `recursive`), sorted by output path, sharded as `shard`
/// (1-based index, count). Outputs are named `STEM.STYLE.EXT` under `out_dir`, `EXT` being
/// `extension`.
pub fn plan(
    sources: &[PathBuf],
    recursive: bool,
    out_dir: &Path,
    (style, extension): (&str, &str),
    shard: (usize, usize),
) -> Result<Vec<Item>> {
    let (index, count) = shard;
    if count == 0 || index == 0 || index > count {
        return Err(Error::param(
            "--shard",
            format!("{index}/{count}: expected i/n with 1 ≤ i ≤ n"),
        ));
    }
    let mut found: Vec<(PathBuf, PathBuf)> = Vec::new();
    for source in sources {
        let meta = std::fs::metadata(source).map_err(|e| Error::io(source, e))?;
        if meta.is_dir() {
            collect(source, source, recursive, &mut found)?;
        } else {
            let name = source.file_name().map(PathBuf::from).unwrap_or_default();
            found.push((source.clone(), name));
        }
    }
    let mut items: Vec<Item> = found
        .into_iter()
        .map(|(input, relative)| {
            let stem = relative
                .file_stem()
                .map_or_else(|| "image".into(), |s| s.to_string_lossy().into_owned());
            let output = out_dir
                .join(relative.parent().unwrap_or(Path::new("")))
                .join(format!("{stem}.{style}.{extension}"));
            Item { input, output }
        })
        .collect();
    items.sort_by(|a, b| a.output.cmp(&b.output).then(a.input.cmp(&b.input)));
    // Inputs with the same stem in one folder (a.jpg, a.png, a.gif): all but the first keep
    // their extension in the name.
    let mut used = std::collections::HashSet::new();
    for item in &mut items {
        if !used.insert(item.output.clone()) {
            let name = item.input.file_name().unwrap_or_default().to_string_lossy();
            let parent = item.output.parent().unwrap_or(Path::new("")).to_path_buf();
            item.output = parent.join(format!("{name}.{style}.{extension}"));
            used.insert(item.output.clone());
        }
    }
    Ok(items
        .into_iter()
        .enumerate()
        .filter(|(k, _)| k % count == index - 1)
        .map(|(_, item)| item)
        .collect())
}

/// Adds the images of `dir` (below `root`) to `found` as (path, path relative to root).
fn collect(
    root: &Path,
    dir: &Path,
    recursive: bool,
    found: &mut Vec<(PathBuf, PathBuf)>,
) -> Result<()> {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| Error::io(dir, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            if recursive {
                collect(root, &path, recursive, found)?;
            }
            continue;
        }
        let is_image = path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| IMAGE_EXTENSIONS.contains(&e.to_ascii_lowercase().as_str()));
        if is_image {
            let relative = path.strip_prefix(root).unwrap_or(&path).to_path_buf();
            found.push((path, relative));
        }
    }
    Ok(())
}

/// Runs `paint` on every item over `jobs` threads, skipping existing outputs unless `force`,
/// with at most `budget` bytes of estimated memory ([`BYTES_PER_PIXEL`] per input pixel) in
/// use at once (an item larger than the budget runs alone). `progress` is called after each
/// item with its index, its outcome and how long it took. An item whose `paint` panics fails
/// with "internal error: …" and gives its memory back; the others are painted. Returns the
/// outcomes in item order.
pub fn run<P, F>(
    items: &[Item],
    jobs: usize,
    force: bool,
    budget: u64,
    paint: P,
    progress: F,
) -> Vec<Outcome>
where
    P: Fn(&Item) -> Result<()> + Sync,
    F: Fn(usize, &Outcome, std::time::Duration) + Sync,
{
    let weights: Vec<u64> = items
        .iter()
        .map(|item| {
            image::image_dimensions(&item.input)
                .map_or(0, |(w, h)| u64::from(w) * u64::from(h) * BYTES_PER_PIXEL)
        })
        .collect();
    let outcomes: Vec<Mutex<Option<Outcome>>> = items.iter().map(|_| Mutex::new(None)).collect();
    // (next item, bytes in use), and a condition to wait on for memory.
    let state = Mutex::new((0usize, 0u64));
    let freed = Condvar::new();
    // Each worker paints on its own share of the cores: jobs that fight over one pool of
    // threads are slower than one job alone (measured: 12 one-megapixel photos, 3.1 s with one
    // job, 3.6 s with two sharing the pool). Results do not depend on the thread count.
    let jobs = jobs.max(1);
    let threads = (rayon::current_num_threads() / jobs).max(1);
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build();
            let (items, weights, outcomes, state, freed, paint, progress) = (
                items, &weights, &outcomes, &state, &freed, &paint, &progress,
            );
            scope.spawn(move || loop {
                let (k, weight) = {
                    let mut s = state.lock().expect("batch state");
                    if s.0 >= items.len() {
                        return;
                    }
                    let k = s.0;
                    s.0 += 1;
                    let weight = weights[k].min(budget);
                    while s.1 > 0 && s.1 + weight > budget {
                        s = freed.wait(s).expect("batch state");
                    }
                    s.1 += weight;
                    (k, weight)
                };
                // An item too large to share the budget with another of its size paints on
                // every core (measured: three 12 MP photos under --memory 800M, one at a time,
                // 13.7 s on a worker's single thread).
                let alone = 2 * weight > budget;
                let item = &items[k];
                let start = std::time::Instant::now();
                let outcome = if !force && item.output.exists() {
                    Outcome::Skipped
                } else {
                    let made = item
                        .output
                        .parent()
                        .map_or(Ok(()), std::fs::create_dir_all)
                        .map_err(|e| Error::io(&item.output, e));
                    // A panic in one item (a bug) fails that item only: its share of the
                    // budget is given back below and the other workers go on.
                    let painted = made.map(|()| {
                        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| match &pool {
                            Ok(pool) if !alone => pool.install(|| paint(item)),
                            _ => paint(item),
                        }))
                    });
                    match painted {
                        Ok(Ok(Ok(()))) => Outcome::Done,
                        Ok(Ok(Err(e))) | Err(e) => Outcome::Failed(e.to_string()),
                        Ok(Err(panic)) => Outcome::Failed(format!(
                            "internal error: {} (please report this)",
                            panic_message(panic.as_ref())
                        )),
                    }
                };
                progress(k, &outcome, start.elapsed());
                *outcomes[k].lock().expect("outcome") = Some(outcome);
                state.lock().expect("batch state").1 -= weight;
                freed.notify_all();
            });
        }
    });
    outcomes
        .into_iter()
        .map(|o| {
            o.into_inner()
                .expect("outcome")
                .unwrap_or_else(|| Outcome::Failed("not run".into()))
        })
        .collect()
}

/// The text a panic was raised with.
fn panic_message(payload: &(dyn std::any::Any + Send)) -> &str {
    if let Some(s) = payload.downcast_ref::<&str>() {
        s
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s
    } else {
        "panic"
    }
}

/// Creates `out_dir` if needed and checks that files can be written in it (a probe file is
/// created and removed), so a batch whose output cannot be written stops before painting.
pub fn check_output_dir(out_dir: &Path) -> Result<()> {
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    tempfile::Builder::new()
        .prefix(".anisopaint-probe-")
        .tempfile_in(out_dir)
        .map(drop)
        .map_err(|e| Error::io(out_dir, e))
}

/// Parses `i/n`.
pub fn parse_shard(text: &str) -> Result<(usize, usize)> {
    let bad = || Error::param("--shard", format!("{text}: expected i/n, e.g. 2/8"));
    let (i, n) = text.split_once('/').ok_or_else(bad)?;
    Ok((
        i.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_the_batch() {
        let dir = tempfile::tempdir().unwrap();
        for name in ["a.png", "b.jpg", "c.png", "notes.txt", "sub/d.png"] {
            let p = dir.path().join(name);
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(p, b"x").unwrap();
        }
        let out = Path::new("/out");
        let all = plan(&[dir.path().into()], true, out, ("mosaic", "png"), (1, 1)).unwrap();
        assert_eq!(all.len(), 4);
        assert!(all.iter().any(|i| i.output == out.join("sub/d.mosaic.png")));
        let flat = plan(&[dir.path().into()], false, out, ("mosaic", "png"), (1, 1)).unwrap();
        assert_eq!(flat.len(), 3);
        let mut union: Vec<Item> = (1..=3)
            .flat_map(|i| plan(&[dir.path().into()], true, out, ("mosaic", "png"), (i, 3)).unwrap())
            .collect();
        union.sort_by(|a, b| a.output.cmp(&b.output));
        assert_eq!(union, all);
        assert!(plan(&[dir.path().into()], true, out, ("m", "png"), (0, 3)).is_err());
        assert!(plan(&[dir.path().into()], true, out, ("m", "png"), (4, 3)).is_err());
        assert_eq!(parse_shard("2/8").unwrap(), (2, 8));
        assert!(parse_shard("2").is_err());
    }

    #[test]
    fn same_stem_gets_distinct_outputs() {
        let dir = tempfile::tempdir().unwrap();
        for name in ["a.png", "a.jpg"] {
            std::fs::write(dir.path().join(name), b"x").unwrap();
        }
        let items = plan(
            &[dir.path().into()],
            false,
            Path::new("o"),
            ("s", "jpg"),
            (1, 1),
        )
        .unwrap();
        assert_ne!(items[0].output, items[1].output);
    }
}
