//! The command line: clap parses raw arguments, each command validates them into a plan, runs
//! the library and maps failures to exit codes (0 ok, 1 some items of a batch failed, 2 bad
//! usage or input). Everything here is a thin layer; the work lives in the other modules.

use crate::error::{Error, Result};
use crate::field::{self, FieldOptions, Input, TensorKind};
use crate::render::{field_preview, PreviewMode};
use clap::{Args, Parser, Subcommand, ValueEnum};
use image::DynamicImage;
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Turns photos and 2-D tensor fields into painterly images by anisotropic particle sampling.
#[derive(Debug, Parser)]
#[command(name = "anisopaint", version, about, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Compute the metric (field of ellipses) of a photo, .npy tensor field or analytic field.
    #[command(after_help = FIELD_EXAMPLES)]
    Field(FieldArgs),
}

const FIELD_EXAMPLES: &str = "\
Examples:
  anisopaint field samples/astronaut.png --preview astronaut-field.png
  anisopaint field photo.jpg --out metric.npy --preview-mode orientation --preview dirs.png
  anisopaint field analytic:two-point-load --width 600 --height 400 --preview load.png
  anisopaint field stress.npy --tensor general --out metric.npy";

/// Options shared by every command that reads an input.
#[derive(Debug, Args)]
struct InputArgs {
    /// A photo (PNG, JPEG, TIFF, WebP), a .npy tensor field (H, W, 3) of (t11, t12, t22), or
    /// analytic:NAME[:key=value,...] with NAME one of constant, circular, degenerate-point,
    /// two-point-load.
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

#[derive(Clone, Copy, Debug, ValueEnum)]
enum PreviewArg {
    Ellipses,
    Orientation,
}

#[derive(Debug, Args)]
struct FieldArgs {
    #[command(flatten)]
    input: InputArgs,
    /// Write the metric as float32 .npy (H, W, 3) of (m11, m12, m22), at the input's size.
    #[arg(long)]
    out: Option<PathBuf>,
    /// With --out: write the raw tensor (a photo's structure tensor Jxx, Jxy, Jyy) instead.
    #[arg(long, requires = "out")]
    raw: bool,
    /// Draw a preview picture (PNG or JPEG) of the metric.
    #[arg(long)]
    preview: Option<PathBuf>,
    /// What the preview shows.
    #[arg(long, value_enum, default_value_t = PreviewArg::Ellipses)]
    preview_mode: PreviewArg,
}

/// Runs the command line with the process's arguments.
#[must_use]
pub fn main() -> ExitCode {
    run(std::env::args_os())
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
    let result = match cli.command {
        Command::Field(args) => run_field(&args),
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
                let (dw, dh) = field::DEFAULT_ANALYTIC_SIZE;
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

/// Refuses to write an output over the input file.
fn check_output(input: &Input, out: &Path) -> Result<()> {
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

fn run_field(args: &FieldArgs) -> Result<()> {
    let (input, options) = args.input.plan()?;
    for out in args.out.iter().chain(&args.preview) {
        check_output(&input, out)?;
    }
    let loaded = field::load_field(&input, &options)?;
    if let Some(out) = &args.out {
        let which = if args.raw {
            &loaded.raw
        } else {
            &loaded.metric
        };
        let d = which.domain();
        let full = which.resampled(d.x.round() as usize, d.y.round() as usize);
        crate::io::write_npy(out, &full)?;
    }
    if let Some(path) = &args.preview {
        let mode = match args.preview_mode {
            PreviewArg::Ellipses => PreviewMode::Ellipses,
            PreviewArg::Orientation => PreviewMode::Orientation,
        };
        let img = field_preview(&loaded.metric, loaded.photo.as_ref(), mode);
        crate::io::save_image(path, &DynamicImage::ImageRgba8(img))?;
    }
    Ok(())
}
