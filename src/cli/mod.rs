//! The command line: clap parses raw arguments, each command validates them into a plan, runs
//! the library and maps failures to exit codes (0 ok, 1 some items of a batch failed, 2 bad
//! usage or input). Everything here is a thin layer; the work lives in the other modules.
//! This file holds the command enum, the options every input-reading command shares and the
//! output checks; `paint.rs` the painting commands, `batch.rs` folder batches, `explore.rs` the
//! stage-by-stage commands, `bars.rs` the progress bars.

mod bars;
mod batch;
mod explore;
mod paint;

use batch::{run_batch, BatchArgs};
use explore::{run_field, run_render, run_sample, FieldArgs, RenderArgs, SampleArgs};
use paint::{
    run_info, run_paint, run_sheet, run_styles, InfoArgs, PaintArgs, SheetArgs, StylesArgs,
};

use crate::error::{Error, Result};
use crate::input::{self, FieldOptions, Input, TensorKind};
use bars::Verbosity;
use clap::{Args, Parser, Subcommand, ValueEnum};
use std::ffi::OsString;
use std::path::Path;
use std::process::ExitCode;

/// Turns photos and 2-D tensor fields into painterly images by anisotropic particle sampling.
#[derive(Debug, Parser)]
#[command(
    name = "anisopaint",
    version,
    about,
    propagate_version = true,
    after_help = START_HERE
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

const START_HERE: &str = "\
Start with:
  anisopaint paint photo.jpg                        # writes photo.mosaic.png beside it
  anisopaint contact-sheet photo.jpg -o sheet.png   # every preset side by side
  anisopaint styles                                 # the presets, a line each";

#[derive(Debug, Subcommand)]
enum Command {
    /// Paint a photo or field in a style preset: metric, sampling and look in one go.
    #[command(after_help = paint::PAINT_EXAMPLES)]
    Paint(PaintArgs),
    /// Paint every image of folders or a file list in one style, in parallel, resumable.
    #[command(after_help = batch::BATCH_EXAMPLES)]
    Batch(BatchArgs),
    /// One photo in several presets (or one preset with a key swept), as a labelled grid.
    #[command(after_help = paint::SHEET_EXAMPLES)]
    ContactSheet(SheetArgs),
    /// List the built-in style presets, or print one (`styles show NAME`) to copy and edit.
    #[command(after_help = paint::STYLES_EXAMPLES)]
    Styles(StylesArgs),
    /// Print how a PNG written by `paint` was made: preset, overridden keys, seed, version.
    #[command(after_help = paint::INFO_EXAMPLES)]
    Info(InfoArgs),
    /// Compute the metric (field of ellipses) of a photo, .npy tensor field or analytic field.
    #[command(after_help = explore::FIELD_EXAMPLES)]
    Field(FieldArgs),
    /// Pack the field's ellipses with the anisotropic particle sampler (paper section 5).
    #[command(after_help = explore::SAMPLE_EXAMPLES)]
    Sample(SampleArgs),
    /// Draw a look from the samples: Voronoi mosaics, textured cells, glyphs, fabric, LIC.
    #[command(after_help = explore::RENDER_EXAMPLES)]
    Render(RenderArgs),
    /// Print a shell completion script, e.g. `anisopaint completions bash > anisopaint.bash`.
    #[command(after_help = COMPLETIONS_EXAMPLES)]
    Completions {
        /// bash, zsh, fish, elvish or powershell.
        shell: clap_complete::Shell,
    },
}

const COMPLETIONS_EXAMPLES: &str = "\
Examples:
  anisopaint completions bash > ~/.local/share/bash-completion/completions/anisopaint
  anisopaint completions zsh > ~/.zfunc/_anisopaint
  anisopaint completions fish > ~/.config/fish/completions/anisopaint.fish";

/// How much a command prints while it works.
#[derive(Debug, Args)]
struct VerbosityArgs {
    /// No progress bars (errors and failures still print).
    #[arg(short, long)]
    quiet: bool,
    /// Print the time each stage took (reading, metric, seeding, relaxation, rendering,
    /// writing).
    #[arg(short, long)]
    verbose: bool,
}

impl VerbosityArgs {
    fn get(&self) -> Verbosity {
        Verbosity {
            quiet: self.quiet,
            verbose: self.verbose,
        }
    }
}

/// The preset an explore command (`field`, `sample`, `render`) takes its parameters from.
#[derive(Debug, Args)]
struct PresetArgs {
    /// A built-in preset or a .toml file whose metric, sampler, look and cells this command
    /// uses [default: the library's defaults with the paper's generalized Voronoi cells].
    #[arg(short, long)]
    style: Option<String>,
    /// Override one preset key for this run, e.g. --set metric.max_anisotropy=6 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
}

impl PresetArgs {
    /// The preset named (or the defaults) with the overrides applied.
    fn load(&self) -> Result<crate::style::Preset> {
        let mut preset = match &self.style {
            Some(style) => crate::style::load(style)?,
            None => crate::style::Preset::defaults(),
        };
        crate::style::apply_sets(&mut preset, &self.sets)?;
        Ok(preset)
    }
}

/// Options shared by every command that reads an input.
#[derive(Debug, Args)]
struct InputArgs {
    /// A photo (PNG, JPEG, TIFF, WebP, GIF, BMP, PNM), a .npy tensor field (H, W, 3) of (t11, t12,
    /// t22), or analytic:NAME[:key=value,...] with NAME one of constant, circular,
    /// degenerate-point, two-point-load.
    input: String,
    /// Width of an analytic field's domain in pixels [default: 512].
    #[arg(long)]
    width: Option<usize>,
    /// Height of an analytic field's domain in pixels [default: 512].
    #[arg(long)]
    height: Option<usize>,
    /// How to read a .npy field: as a metric (semi-axes in pixels), as a general tensor (mapped
    /// by the anti-symmetric mapping), or auto (metric if all tensors are positive definite).
    #[arg(long, value_enum, default_value_t = TensorArg::Auto)]
    tensor: TensorArg,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum TensorArg {
    Auto,
    Metric,
    General,
}

/// Runs the command line with the process's arguments.
#[must_use]
pub fn main() -> ExitCode {
    run(std::env::args_os())
}

/// Makes the calling thread (the main one) thread 0 of rayon's global pool, before any parallel
/// work. Parallel loops then start from inside the pool: their work is split there, instead of
/// each loop being handed from the main thread to the pool while the main thread sleeps and is
/// woken again (a painting makes hundreds of loops, the sampler three per relaxation
/// iteration), and the pool has the configured number of threads, the main one among them.
/// The main thread keeps its own heap, where the sampler's large sequential buffers come from
/// (run on another worker instead, a million samples would peak about a tenth higher). Not
/// for `batch`,
/// whose workers are threads of their own: one that paints outside its pool hands its loops to
/// the global pool, which must then have threads other than the waiting main one. A pool
/// already built (a second call) is kept.
fn main_thread_joins_the_pool() {
    let _ = rayon::ThreadPoolBuilder::new()
        .use_current_thread()
        .build_global();
}

/// Runs the command line with `args` (the first is the program name).
pub fn run<I, T>(args: I) -> ExitCode
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => {
            // Help and version go to stdout with status 0; usage errors exit 2.
            let _ = e.print();
            return ExitCode::from(if e.use_stderr() { 2 } else { 0 });
        }
    };
    if !matches!(cli.command, Command::Batch(_)) {
        main_thread_joins_the_pool();
    }
    let result = match cli.command {
        Command::Field(args) => run_field(&args),
        Command::Sample(args) => run_sample(&args),
        Command::Render(args) => run_render(&args),
        Command::Paint(args) => run_paint(&args),
        Command::ContactSheet(args) => run_sheet(&args),
        Command::Styles(args) => run_styles(&args),
        Command::Batch(args) => return run_batch(&args),
        Command::Info(args) => run_info(&args),
        Command::Completions { shell } => {
            use clap::CommandFactory;
            clap_complete::generate(
                shell,
                &mut Cli::command(),
                "anisopaint",
                &mut std::io::stdout(),
            );
            Ok(())
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("anisopaint: error: {e}");
            ExitCode::from(2)
        }
    }
}

impl InputArgs {
    /// Validates the input options into what the library needs.
    fn plan(&self) -> Result<(Input, FieldOptions)> {
        let input = Input::parse(&self.input)?;
        let analytic_size = match (&input, self.width, self.height) {
            (_, None, None) => None,
            (Input::Analytic(_), w, h) => {
                let (dw, dh) = input::DEFAULT_ANALYTIC_SIZE;
                Some((w.unwrap_or(dw), h.unwrap_or(dh)))
            }
            _ => {
                return Err(Error::param(
                    "--width/--height",
                    "they set the domain of analytic: inputs only",
                ))
            }
        };
        let tensor_kind = match self.tensor {
            TensorArg::Auto => TensorKind::Auto,
            TensorArg::Metric => TensorKind::Metric,
            TensorArg::General => TensorKind::General,
        };
        Ok((
            input,
            FieldOptions {
                tensor_kind,
                analytic_size,
                ..FieldOptions::default()
            },
        ))
    }
}

/// Refuses outputs over the input file, and more than one output on standard output (`-`).
fn check_outputs<'a>(input: &Input, outs: impl IntoIterator<Item = &'a Path>) -> Result<()> {
    let mut on_stdout = 0;
    for out in outs {
        check_output(input, out)?;
        on_stdout += usize::from(crate::io::is_stdout(out));
    }
    if on_stdout > 1 {
        return Err(Error::param(
            "output",
            "only one output can go to standard output (-)",
        ));
    }
    Ok(())
}

/// Refuses to write an output over the input file.
fn check_output(input: &Input, out: &Path) -> Result<()> {
    if crate::io::is_stdout(out) {
        return Ok(());
    }
    if let Input::Photo(p) | Input::Npy(p) = input {
        let same = match (p.canonicalize(), out.canonicalize()) {
            (Ok(a), Ok(b)) => a == b,
            _ => p == out,
        };
        if same {
            return Err(Error::param(
                "output",
                format!("{} is the input file; choose another name", out.display()),
            ));
        }
    }
    Ok(())
}

/// Whether `path` names an SVG file.
fn is_svg(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"))
}

/// Refuses, before any work, an output whose extension names a format we do not write.
fn check_raster_format(path: &Path) -> Result<()> {
    let Some(ext) = path.extension().and_then(|e| e.to_str()) else {
        return Ok(()); // no extension: PNG
    };
    let known = ["png", "jpg", "jpeg", "tif", "tiff", "webp"];
    if known.contains(&ext.to_ascii_lowercase().as_str()) {
        return Ok(());
    }
    Err(Error::param(
        "output",
        format!(
            "{}: .{ext} is not a format anisopaint writes (png, jpg, tif, webp; svg with paint \
             and render)",
            path.display()
        ),
    ))
}

/// Writes the SVG document when both a path and a document are there.
fn write_svg(path: Option<&Path>, svg: Option<&str>) -> Result<()> {
    match (path, svg) {
        (Some(path), Some(svg)) => crate::io::write_text(path, svg),
        _ => Ok(()),
    }
}
