//! The command line: clap parses raw arguments, each command validates them into a plan, runs
//! the library and maps failures to exit codes (0 ok, 1 some items of a batch failed, 2 bad
//! usage or input). Everything here is a thin layer; the work lives in the other modules.

mod bars;

use crate::error::{Error, Result};
use crate::field::{self, FieldOptions, Input, TensorKind};
use crate::progress::{timed, Stage};
use crate::render::{field_preview, PreviewMode};
use bars::{StageBars, Verbosity};
use clap::{Args, Parser, Subcommand, ValueEnum};
use image::DynamicImage;
use std::ffi::OsString;
use std::path::{Path, PathBuf};
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
    #[command(after_help = PAINT_EXAMPLES)]
    Paint(PaintArgs),
    /// Paint every image of folders or a file list in one style, in parallel, resumable.
    #[command(after_help = BATCH_EXAMPLES)]
    Batch(BatchArgs),
    /// One photo in several presets (or one preset with a key swept), as a labelled grid.
    #[command(after_help = SHEET_EXAMPLES)]
    ContactSheet(SheetArgs),
    /// List the built-in style presets, or print one (`styles show NAME`) to copy and edit.
    #[command(after_help = STYLES_EXAMPLES)]
    Styles(StylesArgs),
    /// Print how a PNG written by `paint` was made: preset, overridden keys, seed, version.
    #[command(after_help = INFO_EXAMPLES)]
    Info(InfoArgs),
    /// Compute the metric (field of ellipses) of a photo, .npy tensor field or analytic field.
    #[command(after_help = FIELD_EXAMPLES)]
    Field(FieldArgs),
    /// Pack the field's ellipses with the anisotropic particle sampler (paper section 5).
    #[command(after_help = SAMPLE_EXAMPLES)]
    Sample(SampleArgs),
    /// Draw a look from the samples: Voronoi mosaics, textured cells, glyphs, fabric, LIC.
    #[command(after_help = RENDER_EXAMPLES)]
    Render(RenderArgs),
    /// Print a shell completion script, e.g. `anisopaint completions bash > anisopaint.bash`.
    #[command(after_help = COMPLETIONS_EXAMPLES)]
    Completions {
        /// bash, zsh, fish, elvish or powershell.
        shell: clap_complete::Shell,
    },
}

const STYLES_EXAMPLES: &str = "\
Examples:
  anisopaint styles                                   # names and one-line descriptions
  anisopaint styles show pen-hatch > my-ink.toml      # a preset to copy and edit
  anisopaint paint photo.jpg -s my-ink.toml";

const INFO_EXAMPLES: &str = "\
Examples:
  anisopaint info samples/astronaut.mosaic.png        # preset, --set keys, seed, version, command";

const COMPLETIONS_EXAMPLES: &str = "\
Examples:
  anisopaint completions bash > ~/.local/share/bash-completion/completions/anisopaint
  anisopaint completions zsh > ~/.zfunc/_anisopaint
  anisopaint completions fish > ~/.config/fish/completions/anisopaint.fish";

#[derive(Debug, Args)]
struct InfoArgs {
    /// A PNG written by `anisopaint paint`.
    file: PathBuf,
}

const PAINT_EXAMPLES: &str = "\
Examples:
  anisopaint paint samples/astronaut.jpg                 # mosaic, writes samples/astronaut.mosaic.png
  anisopaint paint photo.jpg -s pen-hatch -o ink.png
  anisopaint paint photo.jpg -s crosshatch --set look.lines_per_cell=6 --seed 3
  anisopaint paint photo.jpg -s my-style.toml
  anisopaint paint analytic:two-point-load -s fabric
  anisopaint paint photo.jpg -s glyphs --svg glyphs.svg     # also a vector version";

#[derive(Debug, Args)]
struct PaintArgs {
    #[command(flatten)]
    input: InputArgs,
    /// A built-in preset (see `anisopaint styles`) or a .toml file.
    #[arg(short, long, default_value = crate::style::DEFAULT_STYLE)]
    style: String,
    /// Output image (PNG, JPEG, TIFF, WebP, or SVG for the vector form only); default
    /// INPUT-STEM.STYLE.png beside the input.
    #[arg(short, long)]
    out: Option<PathBuf>,
    /// Seed of the sampler (overrides the preset's).
    #[arg(long)]
    seed: Option<u64>,
    /// Override one preset key for this run, e.g. --set metric.max_anisotropy=6 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Also write the painting as SVG: glyphs as ellipses, cells as traced polygons in their
    /// colours (not for fabric and LIC).
    #[arg(long, value_name = "OUT.svg")]
    svg: Option<PathBuf>,
    #[command(flatten)]
    verbosity: VerbosityArgs,
}

const SHEET_EXAMPLES: &str = "\
Examples:
  anisopaint contact-sheet samples/chelsea.png -o sheet.png                 # every built-in preset
  anisopaint contact-sheet photo.jpg -s mosaic,pen-hatch,glyphs -o three.png
  anisopaint contact-sheet photo.jpg -s crosshatch --vary look.lines_per_cell=3,5,8 -o lines.png
  anisopaint contact-sheet photo.jpg -s my-style.toml --vary metric.max_anisotropy=1,3,6,10 -o a.png";

#[derive(Debug, Args)]
struct SheetArgs {
    #[command(flatten)]
    input: InputArgs,
    /// Presets to compare, comma-separated (built-in names or .toml files); every built-in
    /// preset when not given.
    #[arg(short, long, value_delimiter = ',', conflicts_with = "all_styles")]
    style: Vec<String>,
    /// Every built-in preset (the default without -s).
    #[arg(long, conflicts_with = "vary")]
    all_styles: bool,
    /// Sweep one key of one preset: KEY=V1,V2,... (one tile per value).
    #[arg(long, value_name = "KEY=V1,V2,...")]
    vary: Option<String>,
    /// The sheet (PNG or JPEG).
    #[arg(short, long)]
    out: PathBuf,
    /// Width of each tile in pixels.
    #[arg(long, default_value_t = 360)]
    tile_width: u32,
    /// Tiles per row; 0 puts up to 4 tiles in one row, more in an about square grid.
    #[arg(long, default_value_t = 0)]
    columns: usize,
    /// Seed of the sampler for every tile (overrides the presets').
    #[arg(long)]
    seed: Option<u64>,
    /// Override one key in every preset (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
}

const BATCH_EXAMPLES: &str = "\
Examples:
  anisopaint batch photos/ -s pen-hatch -o painted/ --recursive --jobs 2
  anisopaint batch a.jpg b.jpg c.png -s mosaic -o out/
  parallel anisopaint batch photos/ -s mosaic -o out/ --shard {}/8 ::: 1 2 3 4 5 6 7 8
  (Slurm) anisopaint batch photos/ -s mosaic -o out/ --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT

Exit status: 0 when every file was painted or skipped, 1 when some failed, 2 for bad usage.";

#[derive(Debug, Args)]
struct BatchArgs {
    /// Folders (their images) and image files.
    #[arg(required = true)]
    sources: Vec<PathBuf>,
    /// A built-in preset or a .toml file.
    #[arg(short, long, default_value = crate::style::DEFAULT_STYLE)]
    style: String,
    /// Output folder (created); the folder structure below each source folder is kept.
    #[arg(short, long)]
    out: PathBuf,
    /// Also paint the images in subfolders.
    #[arg(long)]
    recursive: bool,
    /// Images painted at once (memory is bounded as well).
    #[arg(long, default_value_t = 2)]
    jobs: usize,
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

#[derive(Debug, Args)]
struct StylesArgs {
    #[command(subcommand)]
    action: Option<StylesAction>,
}

#[derive(Debug, Subcommand)]
enum StylesAction {
    /// Print a preset's full TOML.
    Show {
        /// A built-in preset name.
        name: String,
    },
}

const RENDER_EXAMPLES: &str = "\
Examples:
  anisopaint render samples/astronaut.jpg --look mosaic -o mosaic.png
  anisopaint render samples/chelsea.png --look crosshatch -o ink.png --scale 2
  anisopaint sample photo.jpg --out s.csv && anisopaint render photo.jpg --samples s.csv --look hatch -o h.png
  anisopaint render analytic:two-point-load --width 600 --height 400 --look fabric -o load.png
  anisopaint render photo.jpg --look mosaic -o m.png --labels labels.npy
  anisopaint render photo.jpg --look glyphs --placement grid -o grid-glyphs.png
  anisopaint render photo.jpg --look hatch --texture my-tile.png -o tiled.png";

#[derive(Debug, Args)]
struct RenderArgs {
    #[command(flatten)]
    input: InputArgs,
    /// The look.
    #[arg(long, default_value = "mosaic", value_parser = clap::builder::PossibleValuesParser::new(crate::render::Look::NAMES))]
    look: String,
    /// Output image (PNG or JPEG).
    #[arg(short, long)]
    out: PathBuf,
    /// Reuse samples written by `sample --out` instead of sampling again.
    #[arg(long)]
    samples: Option<PathBuf>,
    /// Also write the label map: int32 .npy (H, W), the samples.csv row owning each pixel.
    #[arg(long)]
    labels: Option<PathBuf>,
    /// Also write the picture as SVG: glyphs as ellipses, cells as traced polygons in their
    /// colours (not for fabric and LIC).
    #[arg(long, value_name = "OUT.svg")]
    svg: Option<PathBuf>,
    /// Output size as a multiple of the input's.
    #[arg(long, conflicts_with = "out_width")]
    scale: Option<f64>,
    /// Output width in pixels (the height follows the input's aspect).
    #[arg(long)]
    out_width: Option<usize>,
    /// Raster points per pixel along each axis, used where a cell border crosses the pixel.
    #[arg(long, default_value_t = 2)]
    supersample: usize,
    /// For the textured looks: fill cells with this greyscale PNG tile (dark = ink) instead.
    #[arg(long)]
    texture: Option<PathBuf>,
    /// For --look glyphs: where the glyphs go (grid and random reproduce the paper's
    /// comparison with the relaxed samples).
    #[arg(long, value_enum, default_value_t = PlacementArg::Relaxed)]
    placement: PlacementArg,
    /// Seed of the sampler.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Maximum number of relaxation iterations of the sampler.
    #[arg(long, default_value_t = 100)]
    iterations: usize,
    #[command(flatten)]
    verbosity: VerbosityArgs,
}

const SAMPLE_EXAMPLES: &str = "\
Examples:
  anisopaint sample samples/astronaut.jpg --preview glyphs.png --report
  anisopaint sample analytic:constant:angle=30,anisotropy=4,size=0.01 --out s.csv --triangles t.csv
  anisopaint sample photo.jpg --iterations 300 --seed 7 --report-json report.json
  anisopaint sample analytic:degenerate-point --compare";

const FIELD_EXAMPLES: &str = "\
Examples:
  anisopaint field samples/astronaut.png --preview astronaut-field.png
  anisopaint field photo.jpg --out metric.npy --preview-mode orientation --preview dirs.png
  anisopaint field analytic:two-point-load --width 600 --height 400 --preview load.png
  anisopaint field stress.npy --tensor general --out metric.npy";

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
enum PlacementArg {
    Relaxed,
    Grid,
    Random,
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

#[derive(Debug, Args)]
struct SampleArgs {
    #[command(flatten)]
    input: InputArgs,
    /// Write the samples as CSV: x,y,m11,m12,m22 in pixels.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Write the anisotropic Delaunay triangles as CSV: a,b,c (rows of --out).
    #[arg(long)]
    triangles: Option<PathBuf>,
    /// Maximum number of relaxation iterations.
    #[arg(long, default_value_t = 100)]
    iterations: usize,
    /// Seed of the random numbers: the same seed gives the same samples.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Repair the triangulation and control the population every this many iterations.
    #[arg(long, default_value_t = 8)]
    repair_every: usize,
    /// Refuse fields that need more samples than this.
    #[arg(long, default_value_t = crate::sampling::DEFAULT_MAX_SAMPLES)]
    max_samples: usize,
    /// Insert a sample into triangles whose fill rate is at most this (0 disables insertion).
    #[arg(long)]
    insert_fill_rate: Option<f64>,
    /// Insert only where the corners' mean pressure is at most this.
    #[arg(long)]
    insert_max_pressure: Option<f64>,
    /// Delete samples whose pressure (sum of repelling forces) exceeds this.
    #[arg(long)]
    delete_pressure: Option<f64>,
    /// Draw the samples' ellipses over the faded photo (PNG or JPEG).
    #[arg(long)]
    preview: Option<PathBuf>,
    /// Print per-stage times and counts and the quality figures.
    #[arg(long)]
    report: bool,
    /// Write the report as JSON to this file ('-' for standard output).
    #[arg(long)]
    report_json: Option<PathBuf>,
    /// Also measure random placement and the seed alone (0 iterations), side by side.
    #[arg(long)]
    compare: bool,
    #[command(flatten)]
    verbosity: VerbosityArgs,
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

fn run_sample(args: &SampleArgs) -> Result<()> {
    use crate::sampling::{self, quality, report, SamplerParams};
    let (input, options) = args.input.plan()?;
    let json_path = args.report_json.as_ref().filter(|p| p.as_os_str() != "-");
    for out in [&args.out, &args.triangles, &args.preview]
        .into_iter()
        .flatten()
        .chain(json_path)
    {
        check_output(&input, out)?;
    }
    let defaults = SamplerParams::default();
    let params = SamplerParams {
        iterations: args.iterations,
        seed: args.seed,
        repair_every: args.repair_every,
        max_samples: args.max_samples,
        insert_fill_rate: args.insert_fill_rate.unwrap_or(defaults.insert_fill_rate),
        insert_max_pressure: args
            .insert_max_pressure
            .unwrap_or(defaults.insert_max_pressure),
        delete_pressure: args.delete_pressure.unwrap_or(defaults.delete_pressure),
        ..defaults
    };
    let bars = StageBars::new(args.verbosity.get());
    let loaded = field::load_field_observed(&input, &options, &bars)?;
    let field = &loaded.metric;
    let result = sampling::sample_observed(field, &params, &bars)?;
    bars.print_timings();
    if let Some(out) = &args.out {
        crate::io::write_samples_csv(out, &result.positions, &result.metrics)?;
    }
    if let Some(out) = &args.triangles {
        crate::io::write_triangles_csv(out, result.mesh.triangles())?;
    }
    if let Some(path) = &args.preview {
        let d = field.domain();
        let img = crate::render::ellipses_preview(
            &result.positions,
            &result.metrics,
            loaded.photo.as_ref(),
            d.x.round() as u32,
            d.y.round() as u32,
        );
        crate::io::save_image(path, &DynamicImage::ImageRgba8(img))?;
    }
    if !(args.report || args.report_json.is_some() || args.compare) {
        return Ok(());
    }
    let relaxed = quality::measure(&result.positions, &result.metrics, &result.mesh, field);
    let mut baselines = Vec::new();
    if args.compare {
        let seeded = sampling::sample(
            field,
            &SamplerParams {
                iterations: 0,
                ..params.clone()
            },
        )?;
        let seeded_q = quality::measure(&seeded.positions, &seeded.metrics, &seeded.mesh, field);
        let mut rng = sampling::rng::Rng::new(params.seed, 1);
        let random = sampling::seeding::random_positions(field, result.positions.len(), &mut rng);
        let random_metrics: Vec<_> = random.iter().map(|&p| field.sample(p)).collect();
        let (random_mesh, _) = sampling::AnisotropicDelaunay::build(&random, field);
        let random_q = quality::measure(&random, &random_metrics, &random_mesh, field);
        baselines.push(("random", random_q));
        baselines.push(("seed only", seeded_q));
    }
    let labelled: Vec<(&str, &quality::Quality)> = baselines.iter().map(|(l, q)| (*l, q)).collect();
    if args.report || args.compare {
        print!("{}", report::text(&result.stats, Some(&relaxed)));
    }
    if args.compare {
        let mut rows = labelled.clone();
        rows.push(("relaxed", &relaxed));
        print!("{}", report::comparison(&rows));
    }
    if let Some(path) = &args.report_json {
        let text = report::json(&result.stats, Some(&relaxed), &labelled);
        if path.as_os_str() == "-" {
            println!("{text}");
        } else {
            crate::io::write_text(path, &format!("{text}\n"))?;
        }
    }
    Ok(())
}

fn run_render(args: &RenderArgs) -> Result<()> {
    use crate::render::{render_with_svg, Look, RenderSize};
    use crate::sampling::{self, AnisotropicDelaunay, SamplerParams};
    let (input, options) = args.input.plan()?;
    for out in std::iter::once(&args.out)
        .chain(&args.labels)
        .chain(&args.svg)
    {
        check_output(&input, out)?;
    }
    // `-o picture.svg` asks for the vector form only.
    let svg_only = is_svg(&args.out);
    let svg_path = if svg_only {
        Some(args.out.as_path())
    } else {
        check_raster_format(&args.out)?;
        args.svg.as_deref()
    };
    if !(1..=4).contains(&args.supersample) {
        return Err(Error::param("--supersample", "must be 1, 2, 3 or 4"));
    }
    let mut look = Look::named(&args.look)
        .ok_or_else(|| Error::param("--look", format!("unknown look {}", args.look)))?;
    if svg_path.is_some() {
        look.check_vector_form()?;
    }
    match (&mut look, &args.texture) {
        (Look::Texture(params), Some(path)) => {
            let tile = crate::io::read_photo(path)?.to_luma8();
            params.kind = crate::render::texture::TextureKind::Image(tile);
        }
        (_, Some(_)) => {
            return Err(Error::param(
                "--texture",
                "only the textured looks (hatch, crosshatch, line, stroke, stipple) take a tile",
            ))
        }
        _ => {}
    }
    if let Look::Glyphs(params) = &mut look {
        use crate::render::glyphs::Placement;
        params.placement = match args.placement {
            PlacementArg::Relaxed => Placement::Relaxed,
            PlacementArg::Grid => Placement::Grid,
            PlacementArg::Random => Placement::Random,
        };
        params.seed = args.seed;
    }
    let bars = StageBars::new(args.verbosity.get());
    let loaded = field::load_field_observed(&input, &options, &bars)?;
    let field = &loaded.metric;
    let domain = field.domain();
    let scale = match (args.scale, args.out_width) {
        (Some(s), _) => s,
        (None, Some(w)) => w as f64 / domain.x,
        (None, None) => 1.0,
    };
    let (width, height) = ((domain.x * scale).round(), (domain.y * scale).round());
    if !(scale > 0.0 && scale.is_finite() && width >= 1.0 && height >= 1.0)
        || width * height > crate::io::MAX_PIXELS as f64
    {
        return Err(Error::param(
            "--scale/--out-width",
            format!(
                "the output must have between 1 and {} pixels",
                crate::io::MAX_PIXELS
            ),
        ));
    }
    let (positions, metrics, mesh) = match &args.samples {
        Some(path) => {
            let (positions, metrics) = crate::io::read_samples_csv(path)?;
            if let Some(p) = positions
                .iter()
                .find(|p| !(p.x >= 0.0 && p.y >= 0.0 && p.x <= domain.x && p.y <= domain.y))
            {
                return Err(Error::param(
                    "--samples",
                    format!(
                        "{}: sample ({}, {}) lies outside the input's {}x{} domain",
                        path.display(),
                        p.x,
                        p.y,
                        domain.x,
                        domain.y
                    ),
                ));
            }
            let (mesh, missing) = AnisotropicDelaunay::build(&positions, field);
            if !missing.is_empty() {
                return Err(Error::param(
                    "--samples",
                    format!("{}: {} duplicate samples", path.display(), missing.len()),
                ));
            }
            (positions, metrics, mesh)
        }
        None => {
            let params = SamplerParams {
                seed: args.seed,
                iterations: args.iterations,
                ..SamplerParams::default()
            };
            let s = sampling::sample_observed(field, &params, &bars)?;
            (s.positions, s.metrics, s.mesh)
        }
    };
    let size = RenderSize {
        width: width as usize,
        height: height as usize,
        supersample: args.supersample,
    };
    if let Some(path) = &args.labels {
        let cells = crate::render::VoronoiCells::new(&positions, &metrics, &mesh);
        let raster = crate::render::Raster {
            width: size.width,
            height: size.height,
            supersample: 1,
            domain,
        };
        let labels = crate::render::label_map(&cells, &raster);
        crate::io::write_labels_npy(path, &labels, size.width, size.height)?;
    }
    let (img, svg) = timed(&bars, Stage::Rendering, || {
        render_with_svg(
            &look,
            &positions,
            &metrics,
            &mesh,
            field,
            loaded.photo.as_ref(),
            size,
            svg_path.is_some(),
        )
    })?;
    timed(&bars, Stage::Writing, || -> Result<()> {
        if !svg_only {
            crate::io::save_image(&args.out, &DynamicImage::ImageRgb8(img))?;
        }
        write_svg(svg_path, svg.as_deref())
    })?;
    bars.print_timings();
    Ok(())
}

fn run_styles(args: &StylesArgs) -> Result<()> {
    use crate::style::{built_in, load, BUILT_IN};
    match &args.action {
        None => {
            for (name, _) in BUILT_IN {
                let description = load(name)?.file.description.unwrap_or_default();
                println!("{name:<12} {description}");
            }
        }
        Some(StylesAction::Show { name }) => {
            let text = built_in(name).ok_or_else(|| {
                let names: Vec<&str> = BUILT_IN.iter().map(|(n, _)| *n).collect();
                Error::param(
                    "style",
                    format!("unknown style {name}; built-in: {}", names.join(", ")),
                )
            })?;
            print!("{text}");
        }
    }
    Ok(())
}

fn run_paint(args: &PaintArgs) -> Result<()> {
    let (input, mut options) = args.input.plan()?;
    let mut preset = crate::style::load(&args.style)?;
    crate::style::apply_sets(&mut preset, &args.sets)?;
    options.metric = preset.metric()?;
    let mut sampler = preset.sampler();
    if let Some(seed) = args.seed {
        sampler.seed = seed;
    }
    let out = match &args.out {
        Some(out) => out.clone(),
        None => default_output(&input, &preset.name),
    };
    check_output(&input, &out)?;
    // `-o picture.svg` asks for the vector form only.
    let svg_only = is_svg(&out);
    let svg_path = if svg_only {
        Some(out.as_path())
    } else {
        check_raster_format(&out)?;
        args.svg.as_deref()
    };
    if let Some(svg) = svg_path {
        check_output(&input, svg)?;
    }
    let bars = StageBars::new(args.verbosity.get());
    let painting = crate::style::paint_observed(
        &input,
        &options,
        &preset,
        &sampler,
        svg_path.is_some(),
        &bars,
    )?;
    let record = crate::style::PaintRecord {
        input: args.input.input.clone(),
        style: args.style.clone(),
        preset: preset.name.clone(),
        sets: args.sets.clone(),
        seed: sampler.seed,
    };
    timed(&bars, Stage::Writing, || -> Result<()> {
        if !svg_only {
            crate::style::save_painting(&out, &painting.image, &record)?;
        }
        write_svg(svg_path, painting.svg.as_deref())
    })?;
    bars.print_timings();
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

fn run_sheet(args: &SheetArgs) -> Result<()> {
    use crate::style::sheet::{paint_sheet, variants, SheetOptions};
    let (input, options) = args.input.plan()?;
    check_output(&input, &args.out)?;
    let styles: Vec<String> = match (&args.style[..], &args.vary) {
        ([], Some(_)) => vec![crate::style::DEFAULT_STYLE.to_string()],
        ([], None) => crate::style::BUILT_IN
            .iter()
            .map(|(name, _)| (*name).to_string())
            .collect(),
        (styles, _) => styles.to_vec(),
    };
    let variants = variants(&styles, args.vary.as_deref(), &args.sets)?;
    let bar = bars::counted(variants.len(), "contact sheet", "tiles", args.quiet);
    let sheet = paint_sheet(
        &input,
        &options,
        &variants,
        SheetOptions {
            tile_width: args.tile_width,
            columns: args.columns,
            seed: args.seed,
        },
        &|_| bar.inc(1),
    )?;
    bar.finish_and_clear();
    crate::io::save_image(&args.out, &DynamicImage::ImageRgb8(sheet))
}

fn run_info(args: &InfoArgs) -> Result<()> {
    let texts = crate::io::read_png_text(&args.file)?;
    if texts.is_empty() {
        println!(
            "{}: no text chunks (not written by anisopaint paint?)",
            args.file.display()
        );
    }
    for (key, text) in texts {
        println!("{key}: {text}");
    }
    Ok(())
}

/// `INPUT-STEM.STYLE.png` beside a file input, in the current folder for an analytic one.
fn default_output(input: &Input, style: &str) -> PathBuf {
    let name = format!("{}.{style}.png", input.stem());
    match input {
        Input::Photo(p) | Input::Npy(p) => p.with_file_name(name),
        Input::Analytic(_) => PathBuf::from(name),
    }
}

/// Runs a batch; its exit status is its own (1 when some items failed).
fn run_batch(args: &BatchArgs) -> ExitCode {
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
fn batch(args: &BatchArgs) -> Result<usize> {
    use crate::batch::{check_output_dir, parse_shard, plan, run, Outcome};
    let mut preset = crate::style::load(&args.style)?;
    crate::style::apply_sets(&mut preset, &args.sets)?;
    let options = FieldOptions {
        metric: preset.metric()?,
        ..FieldOptions::default()
    };
    let mut sampler = preset.sampler();
    if let Some(seed) = args.seed {
        sampler.seed = seed;
    }
    preset.look()?;
    let shard = match &args.shard {
        Some(s) => parse_shard(s)?,
        None => (1, 1),
    };
    let items = plan(
        &args.sources,
        args.recursive,
        &args.out,
        &preset.name,
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
        |item| {
            let input = Input::Photo(item.input.clone());
            let img = crate::style::paint(&input, &options, &preset, &sampler)?;
            let record = crate::style::PaintRecord {
                input: item.input.display().to_string(),
                style: args.style.clone(),
                preset: preset.name.clone(),
                sets: args.sets.clone(),
                seed: sampler.seed,
            };
            crate::style::save_painting(&item.output, &img, &record)
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
fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}
