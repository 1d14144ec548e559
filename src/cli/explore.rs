//! The commands that expose the paint pipeline's stages one by one: `field` (the metric of an
//! input), `sample` (the anisotropic sampling, with its quality report) and `render` (a look
//! drawn from samples, optionally reused from a file, and the label map of its cells). Each
//! takes `-s STYLE` and `--set` like `paint`, so a preset's metric, samples and cells can be
//! exported and studied; without `-s` the library's defaults are used, with the paper's own
//! generalized Voronoi cells. The stages run through
//! [`crate::paint`], the chain `paint` itself uses.

use super::bars::StageBars;
use super::{
    check_outputs, check_raster_format, is_svg, write_svg, InputArgs, PresetArgs, VerbosityArgs,
};
use crate::error::{Error, Result};
use crate::input;
use crate::paint::{self, Extras, Recipe, Samples};
use crate::progress::{timed, Stage};
use crate::render::{field_preview, PreviewMode, RenderSize};
use clap::{Args, ValueEnum};
use image::DynamicImage;
use std::path::{Path, PathBuf};

pub(super) const RENDER_EXAMPLES: &str = "\
Examples:
  anisopaint render samples/astronaut.jpg --look mosaic -o mosaic.png
  anisopaint render samples/chelsea.png --look crosshatch -o ink.png --scale 2
  anisopaint sample photo.jpg --out s.csv && anisopaint render photo.jpg --samples s.csv --look hatch -o h.png
  anisopaint render analytic:two-point-load --width 600 --height 400 --look fabric -o load.png
  anisopaint render photo.jpg -s pen-hatch -o ink.png --labels labels.npy   # a preset's cells
  anisopaint render photo.jpg --look glyphs --placement grid -o grid-glyphs.png
  anisopaint render photo.jpg --look hatch --texture my-tile.png -o tiled.png";

#[derive(Debug, Args)]
pub(super) struct RenderArgs {
    #[command(flatten)]
    input: InputArgs,
    #[command(flatten)]
    preset: PresetArgs,
    /// The look, over the preset's (mosaic without a preset).
    #[arg(long, value_parser = clap::builder::PossibleValuesParser::new(crate::render::Look::NAMES))]
    look: Option<String>,
    /// Output image (PNG, JPEG, TIFF, WebP, or SVG for the vector form only; `-`: a PNG on
    /// standard output).
    #[arg(short, long)]
    out: PathBuf,
    /// Reuse samples written by `sample --out` instead of sampling again.
    #[arg(long)]
    samples: Option<PathBuf>,
    /// Also write the label map of the cells as drawn: int32 .npy (H, W), the samples.csv row
    /// owning each output pixel.
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
    /// Raster points per pixel along each axis, used where a cell border crosses the pixel
    /// [default: the preset's, 2].
    #[arg(long)]
    supersample: Option<usize>,
    /// For the textured looks: fill cells with this greyscale PNG tile (dark = ink) instead.
    #[arg(long)]
    texture: Option<PathBuf>,
    /// For --look glyphs: where the glyphs go (grid and random reproduce the paper's
    /// comparison with the relaxed samples) [default: the preset's, relaxed].
    #[arg(long, value_enum)]
    placement: Option<PlacementArg>,
    /// Seed of the sampler [default: the preset's, 0].
    #[arg(long)]
    seed: Option<u64>,
    /// Maximum number of relaxation iterations of the sampler [default: the preset's, 100].
    #[arg(long)]
    iterations: Option<usize>,
    #[command(flatten)]
    verbosity: VerbosityArgs,
}

pub(super) const SAMPLE_EXAMPLES: &str = "\
Examples:
  anisopaint sample samples/astronaut.jpg --preview glyphs.png --report
  anisopaint sample analytic:constant:angle=30,anisotropy=4,size=0.01 --out s.csv --triangles t.csv
  anisopaint sample photo.jpg --iterations 300 --seed 7 --report-json report.json
  anisopaint sample photo.jpg -s pointillist --out dots.csv --report    # a preset's samples
  anisopaint sample analytic:degenerate-point --compare";

pub(super) const FIELD_EXAMPLES: &str = "\
Examples:
  anisopaint field samples/astronaut.png --preview astronaut-field.png
  anisopaint field photo.jpg --out metric.npy --preview-mode orientation --preview dirs.png
  anisopaint field analytic:two-point-load --width 600 --height 400 --preview load.png
  anisopaint field stress.npy --tensor general --out metric.npy
  anisopaint field photo.jpg -s engraving --set metric.max_size=0.02 --out m.npy";

#[derive(Clone, Copy, Debug, ValueEnum)]
pub(super) enum PlacementArg {
    Relaxed,
    Grid,
    Random,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub(super) enum PreviewArg {
    Ellipses,
    Orientation,
}

#[derive(Debug, Args)]
pub(super) struct FieldArgs {
    #[command(flatten)]
    input: InputArgs,
    #[command(flatten)]
    preset: PresetArgs,
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
    #[command(flatten)]
    verbosity: VerbosityArgs,
}

#[derive(Debug, Args)]
pub(super) struct SampleArgs {
    #[command(flatten)]
    input: InputArgs,
    #[command(flatten)]
    preset: PresetArgs,
    /// Write the samples as CSV: x,y,m11,m12,m22 in pixels.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Write the anisotropic Delaunay triangles as CSV: a,b,c (rows of --out).
    #[arg(long)]
    triangles: Option<PathBuf>,
    /// Maximum number of relaxation iterations; a lattice seed runs 70 % of them [default:
    /// the preset's, 100].
    #[arg(long)]
    iterations: Option<usize>,
    /// Seed of the random numbers: the same seed gives the same samples [default: the
    /// preset's, 0].
    #[arg(long)]
    seed: Option<u64>,
    /// Repair the triangulation and control the population every this many iterations (a
    /// lattice seed controls it twice as often).
    #[arg(long, default_value_t = crate::sampling::SamplerParams::default().repair_every)]
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

pub(super) fn run_field(args: &FieldArgs) -> Result<()> {
    let (input, mut options) = args.input.plan()?;
    options.metric = args.preset.load()?.metric()?;
    check_outputs(
        &input,
        args.out.iter().chain(&args.preview).map(PathBuf::as_path),
    )?;
    let bars = StageBars::new(args.verbosity.get());
    let loaded = input::load_field_observed(&input, &options, &bars)?;
    bars.print_timings();
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

pub(super) fn run_sample(args: &SampleArgs) -> Result<()> {
    use crate::sampling::{self, quality, report, SamplerParams};
    let (input, mut options) = args.input.plan()?;
    let preset = args.preset.load()?;
    options.metric = preset.metric()?;
    // The text report prints on standard output, like an output named `-`.
    let report_text = (args.report || args.compare).then_some(Path::new(crate::io::STDOUT));
    check_outputs(
        &input,
        [&args.out, &args.triangles, &args.preview, &args.report_json]
            .into_iter()
            .flatten()
            .map(PathBuf::as_path)
            .chain(report_text),
    )?;
    let defaults = preset.sampler()?;
    let params = SamplerParams {
        iterations: args.iterations.unwrap_or(defaults.iterations),
        seed: args.seed.unwrap_or(defaults.seed),
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
    let loaded = input::load_field_observed(&input, &options, &bars)?;
    let field = &loaded.metric;
    let result = sampling::sample_observed(field, &params, &bars)?;
    bars.print_timings();
    if let Some(out) = &args.out {
        crate::io::write_samples_csv(out, &result.positions, &result.metrics)?;
    }
    if let Some(out) = &args.triangles {
        crate::io::write_triangles_csv(out, &result.mesh.triangles().collect::<Vec<_>>())?;
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
        crate::io::write_text(path, &format!("{text}\n"))?;
    }
    Ok(())
}

pub(super) fn run_render(args: &RenderArgs) -> Result<()> {
    let (input, options) = args.input.plan()?;
    check_outputs(
        &input,
        std::iter::once(&args.out)
            .chain(&args.labels)
            .chain(&args.svg)
            .map(PathBuf::as_path),
    )?;
    // `-o picture.svg` asks for the vector form only.
    let svg_only = is_svg(&args.out);
    let svg_path = if svg_only {
        Some(args.out.as_path())
    } else {
        check_raster_format(&args.out)?;
        args.svg.as_deref()
    };
    let mut preset = args.preset.load()?;
    if let Some(look) = &args.look {
        crate::style::apply_sets(&mut preset, &[format!("look.kind={look}")])?;
    }
    let mut recipe = Recipe::from_preset(&preset, options, args.seed)?;
    if let Some(iterations) = args.iterations {
        recipe.sampler.iterations = iterations;
    }
    if let Some(supersample) = args.supersample {
        if !(1..=4).contains(&supersample) {
            return Err(Error::param("--supersample", "must be 1, 2, 3 or 4"));
        }
        recipe.supersample = supersample;
    }
    apply_render_flags(args, &mut recipe.look)?;
    if svg_path.is_some() {
        recipe.look.check_vector_form()?;
    }
    let bars = StageBars::new(args.verbosity.get());
    let loaded = input::load_field_observed(&input, &recipe.field, &bars)?;
    let field = &loaded.metric;
    let size = output_size(args, field.domain(), recipe.supersample)?;
    let samples = match &args.samples {
        Some(path) => read_samples(path, field)?,
        None => paint::sample(field, &recipe.sampler, &bars)?,
    };
    let extras = Extras {
        svg: svg_path.is_some(),
        labels: args.labels.is_some(),
    };
    let painting = paint::draw(&loaded, &samples, &recipe, size, extras, &bars)?;
    if let (Some(path), Some(labels)) = (&args.labels, &painting.labels) {
        crate::io::write_labels_npy(path, labels, size.width, size.height)?;
    }
    timed(&bars, Stage::Writing, || -> Result<()> {
        if !svg_only {
            crate::io::save_image(&args.out, &DynamicImage::ImageRgb8(painting.image))?;
        }
        write_svg(svg_path, painting.svg.as_deref())
    })?;
    bars.print_timings();
    Ok(())
}

/// `--texture` and `--placement` over the preset's look.
fn apply_render_flags(args: &RenderArgs, look: &mut crate::render::Look) -> Result<()> {
    use crate::render::Look;
    match (&mut *look, &args.texture) {
        (Look::Texture(params), Some(path)) => {
            let tile = crate::io::read_photo(path)?.to_luma8();
            params.kind = crate::render::looks::texture::TextureKind::Image(tile);
        }
        (_, Some(_)) => {
            return Err(Error::param(
                "--texture",
                "only the textured looks (hatch, crosshatch, line, stroke, stipple) take a tile",
            ))
        }
        _ => {}
    }
    if let (Look::Glyphs(params), Some(placement)) = (look, args.placement) {
        use crate::render::looks::glyphs::Placement;
        params.placement = match placement {
            PlacementArg::Relaxed => Placement::Relaxed,
            PlacementArg::Grid => Placement::Grid,
            PlacementArg::Random => Placement::Random,
        };
    }
    Ok(())
}

/// The output size `--scale` or `--out-width` ask for (the input's by default).
fn output_size(args: &RenderArgs, domain: glam::DVec2, supersample: usize) -> Result<RenderSize> {
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
    Ok(RenderSize {
        width: width as usize,
        height: height as usize,
        supersample,
    })
}

/// Samples written by `sample --out`, checked against the field's domain and triangulated.
fn read_samples(path: &std::path::Path, field: &crate::field::TensorField) -> Result<Samples> {
    let domain = field.domain();
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
    let (mesh, missing) = crate::sampling::AnisotropicDelaunay::build(&positions, field);
    if !missing.is_empty() {
        return Err(Error::param(
            "--samples",
            format!("{}: {} duplicate samples", path.display(), missing.len()),
        ));
    }
    Ok(Samples {
        positions,
        metrics,
        mesh,
    })
}
