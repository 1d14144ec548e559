//! `batch`: folders of photos painted in one preset over workers with a memory budget,
//! resumable, with an overall progress bar and a summary; exit 1 when some files failed.

use super::bars;
use crate::error::Result;
use crate::input::{FieldOptions, Input};
use crate::paint::{save_painting, PaintRecord, Recipe};
use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;

pub(super) const BATCH_EXAMPLES: &str = "\
Examples:
  anisopaint batch photos/ -s pen-hatch -o painted/ --recursive --jobs 2
  anisopaint batch a.jpg b.jpg c.png -s mosaic -o out/
  parallel anisopaint batch photos/ -s mosaic -o out/ --shard {}/8 ::: 1 2 3 4 5 6 7 8
  (Slurm) anisopaint batch photos/ -s mosaic -o out/ --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT

Exit status: 0 when every file was painted or skipped, 1 when some failed, 2 for bad usage.";

#[derive(Debug, Args)]
pub(super) struct BatchArgs {
    /// Folders (their images) and image files.
    #[arg(required = true)]
    sources: Vec<PathBuf>,
    /// A built-in preset or a .toml file.
    #[arg(short, long, default_value = crate::style::DEFAULT_STYLE)]
    style: String,
    /// Output folder (created); the folder structure below each source folder is kept.
    #[arg(short, long)]
    out: PathBuf,
    /// Format of the outputs, named STEM.STYLE.FORMAT: JPEG at quality 90, TIFF, or lossless
    /// WebP instead of PNG.
    #[arg(long, default_value = "png", value_parser = clap::builder::PossibleValuesParser::new(crate::batch::OUTPUT_FORMATS))]
    format: String,
    /// Also paint the images in subfolders.
    #[arg(long)]
    recursive: bool,
    /// Images painted at once (memory is bounded as well, see --memory).
    #[arg(long, default_value_t = 2)]
    jobs: usize,
    /// Memory the images painted at once may use together, estimated from their sizes, e.g.
    /// 800M or 2G: a photo that would exceed it waits for the others (one larger than it runs
    /// alone).
    #[arg(long, default_value = "3G")]
    memory: String,
    /// Paint again over outputs that exist (otherwise they are skipped).
    #[arg(long)]
    force: bool,
    /// Paint only the i-th of n equal shares of the sorted file list, e.g. 2/8.
    #[arg(long)]
    shard: Option<String>,
    /// Seed of the sampler (overrides the preset's).
    #[arg(long)]
    seed: Option<u64>,
    /// Override one preset key (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// No progress bar or per-file lines: only failures and the summary.
    #[arg(short, long)]
    quiet: bool,
    /// Print the time each file took.
    #[arg(short, long)]
    verbose: bool,
}

/// Runs a batch; its exit status is its own (1 when some items failed).
pub(super) fn run_batch(args: &BatchArgs) -> ExitCode {
    match batch(args) {
        Ok(failed) if failed > 0 => ExitCode::from(1),
        Ok(_) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("anisopaint: error: {e}");
            ExitCode::from(2)
        }
    }
}

/// Plans and runs a batch; returns how many items failed.
pub(super) fn batch(args: &BatchArgs) -> Result<usize> {
    use crate::batch::{check_output_dir, parse_shard, plan, run, Outcome};
    let mut preset = crate::style::load(&args.style)?;
    crate::style::apply_sets(&mut preset, &args.sets)?;
    let recipe = Recipe::from_preset(&preset, FieldOptions::default(), args.seed)?;
    let shard = match &args.shard {
        Some(s) => parse_shard(s)?,
        None => (1, 1),
    };
    let budget = crate::batch::parse_memory(&args.memory)?;
    let items = plan(
        &args.sources,
        args.recursive,
        &args.out,
        (&preset.name, &args.format),
        shard,
    )?;
    check_output_dir(&args.out)?;
    let stale = crate::io::remove_stale_partials(&args.out);
    if stale > 0 && !args.quiet {
        eprintln!("removed {stale} temporary file(s) left by an interrupted run");
    }
    let total = items.len();
    let bar = bars::counted(total, &preset.name, "files", args.quiet);
    let done_count = std::sync::atomic::AtomicUsize::new(0);
    let outcomes = run(
        &items,
        args.jobs,
        args.force,
        budget,
        |item| {
            let input = Input::Photo(item.input.clone());
            let img = crate::paint::paint(&input, &recipe)?;
            let record = PaintRecord {
                input: item.input.display().to_string(),
                style: args.style.clone(),
                preset: preset.name.clone(),
                sets: args.sets.clone(),
                seed: recipe.sampler.seed,
            };
            save_painting(&item.output, &img, &record)
        },
        |k, outcome, took| {
            let n = done_count.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
            bar.inc(1);
            let mut what = match outcome {
                Outcome::Done => "painted".to_string(),
                Outcome::Skipped => "exists, skipped".to_string(),
                // The library's errors name the file already.
                Outcome::Failed(why) => format!("FAILED: {}", one_line(why)),
            };
            if args.verbose {
                what.push_str(&format!(" ({:.2} s)", took.as_secs_f64()));
            }
            if !args.quiet || matches!(outcome, Outcome::Failed(_)) {
                let line = format!("[{n}/{total}] {}: {what}", items[k].input.display());
                if bar.is_hidden() {
                    eprintln!("{line}");
                } else {
                    bar.println(line);
                }
            }
        },
    );
    bar.finish_and_clear();
    let count = |f: fn(&Outcome) -> bool| outcomes.iter().filter(|o| f(o)).count();
    let (done, skipped) = (
        count(|o| *o == Outcome::Done),
        count(|o| *o == Outcome::Skipped),
    );
    let failed: Vec<(usize, &String)> = outcomes
        .iter()
        .enumerate()
        .filter_map(|(k, o)| match o {
            Outcome::Failed(why) => Some((k, why)),
            _ => None,
        })
        .collect();
    println!(
        "{total} files: {done} painted, {skipped} skipped (already there), {} failed",
        failed.len()
    );
    for (_, why) in &failed {
        println!("  failed: {}", one_line(why));
    }
    Ok(failed.len())
}

/// `text` with its line breaks folded, for one-line reports.
pub(super) fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}
