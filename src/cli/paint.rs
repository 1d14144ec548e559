//! The commands users paint with: `paint` (a preset over one input, PNG and SVG), `styles`
//! (list and show presets), `contact-sheet` (one input in several presets) and `info` (how a
//! PNG was made).

use super::bars::{self, StageBars};
use super::{
    check_output, check_outputs, check_raster_format, is_svg, write_svg, InputArgs, VerbosityArgs,
};
use crate::error::{Error, Result};
use crate::input::Input;
use crate::paint::{paint_observed, save_painting, Extras, PaintRecord, Recipe};
use crate::progress::{timed, Stage};
use clap::{Args, Subcommand};
use image::DynamicImage;
use std::path::PathBuf;

pub(super) const STYLES_EXAMPLES: &str = "\
Examples:
  anisopaint styles                                   # names and one-line descriptions
  anisopaint styles show pen-hatch > my-ink.toml      # a preset to copy and edit
  anisopaint styles show my-ink.toml --full           # every key it paints with, extends followed
  anisopaint paint photo.jpg -s my-ink.toml";

pub(super) const INFO_EXAMPLES: &str = "\
Examples:
  anisopaint info samples/astronaut.mosaic.png        # preset, --set keys, seed, version, command";

#[derive(Debug, Args)]
pub(super) struct InfoArgs {
    /// A PNG written by `anisopaint paint`.
    file: PathBuf,
}

pub(super) const PAINT_EXAMPLES: &str = "\
Examples:
  anisopaint paint samples/astronaut.jpg                 # mosaic, writes samples/astronaut.mosaic.png
  anisopaint paint photo.jpg -s pen-hatch -o ink.png
  anisopaint paint - -o - < photo.jpg > painting.png     # standard input and output
  anisopaint paint photo.jpg -s crosshatch --set look.lines_per_cell=6 --seed 3
  anisopaint paint photo.jpg -s my-style.toml
  anisopaint paint analytic:two-point-load -s fabric
  anisopaint paint photo.jpg -s glyphs --svg glyphs.svg     # also a vector version";

#[derive(Debug, Args)]
pub(super) struct PaintArgs {
    #[command(flatten)]
    input: InputArgs,
    /// A built-in preset (see `anisopaint styles`) or a .toml file.
    #[arg(short, long, default_value = crate::style::DEFAULT_STYLE)]
    style: String,
    /// Output image (PNG, JPEG, TIFF, WebP, or SVG for the vector form only); default
    /// INPUT-STEM.STYLE.png beside the input. `-` writes a PNG to standard output; a device
    /// or named pipe is written in place; a symbolic link keeps pointing at the new picture.
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

pub(super) const SHEET_EXAMPLES: &str = "\
Examples:
  anisopaint contact-sheet samples/chelsea.png -o sheet.png                 # every built-in preset
  anisopaint contact-sheet photo.jpg -s mosaic,pen-hatch,glyphs -o three.png
  anisopaint contact-sheet photo.jpg -s crosshatch --vary look.lines_per_cell=3,5,8 -o lines.png
  anisopaint contact-sheet photo.jpg -s my-style.toml --vary metric.max_anisotropy=1,3,6,10 -o a.png";

#[derive(Debug, Args)]
pub(super) struct SheetArgs {
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

#[derive(Debug, Args)]
pub(super) struct StylesArgs {
    #[command(subcommand)]
    action: Option<StylesAction>,
}

#[derive(Debug, Subcommand)]
pub(super) enum StylesAction {
    /// Print a built-in preset's TOML, or with --full any preset with every key it paints with.
    Show {
        /// A built-in preset name (or, with --full, a .toml file).
        name: String,
        /// Every key the look reads, with the value it paints with: `extends` followed and
        /// the defaults filled in, ready to copy into a file.
        #[arg(long)]
        full: bool,
        /// With --full: override keys first, as `paint --set` does (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE", requires = "full")]
        sets: Vec<String>,
    },
    /// Every key a preset's look reads: what it takes, the value it paints with, what it does.
    Keys {
        /// A built-in preset name or a .toml file [default: mosaic].
        name: Option<String>,
        /// Override keys first, as `paint --set` does (repeatable; `look.kind=hatch` shows
        /// another look's keys).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
    },
}

pub(super) fn run_styles(args: &StylesArgs) -> Result<()> {
    use crate::style::{built_in, load, BUILT_IN};
    match &args.action {
        None => {
            for (name, _) in BUILT_IN {
                let description = load(name)?.file.description.unwrap_or_default();
                println!("{name:<12} {description}");
            }
        }
        Some(StylesAction::Show { name, full, sets }) if *full => {
            let mut preset = load(name)?;
            crate::style::apply_sets(&mut preset, sets)?;
            print!("{}", crate::style::full_toml(&preset)?);
        }
        Some(StylesAction::Keys { name, sets }) => {
            let name = name.as_deref().unwrap_or(crate::style::DEFAULT_STYLE);
            let mut preset = load(name)?;
            crate::style::apply_sets(&mut preset, sets)?;
            print!("{}", keys_table(&preset)?);
        }
        Some(StylesAction::Show { name, .. }) => {
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

/// The keys `preset`'s look reads as aligned text: key, what it takes, value, what it does.
fn keys_table(preset: &crate::style::Preset) -> Result<String> {
    let rows = crate::style::key_values(preset)?;
    let kind = preset.file.look_kind();
    let mut out = format!(
        "# {} ({kind}): the keys its look reads, the value it paints with, what each takes\n",
        preset.name
    );
    let width = rows.iter().map(|(k, _)| k.path.len()).max().unwrap_or(0);
    for (key, value) in rows {
        let value = value.unwrap_or_else(|| "(unset)".into());
        out.push_str(&format!(
            "{:width$}  {value:<10}  {}: {}\n",
            key.path,
            key.value.describe(),
            key.doc,
        ));
    }
    Ok(out)
}

pub(super) fn run_paint(args: &PaintArgs) -> Result<()> {
    let (input, options) = args.input.plan()?;
    let mut preset = crate::style::load(&args.style)?;
    crate::style::apply_sets(&mut preset, &args.sets)?;
    let recipe = Recipe::from_preset(&preset, options, args.seed)?;
    let out = match &args.out {
        Some(out) => out.clone(),
        None if input == Input::Photo(crate::io::STDOUT.into()) => {
            return Err(Error::param(
                "--out",
                "the input is standard input: name the output (-o - for standard output)",
            ))
        }
        None => default_output(&input, &preset.name),
    };
    // `-o picture.svg` asks for the vector form only.
    let svg_only = is_svg(&out);
    let svg_path = if svg_only {
        Some(out.as_path())
    } else {
        check_raster_format(&out)?;
        args.svg.as_deref()
    };
    check_outputs(&input, std::iter::once(out.as_path()).chain(svg_path))?;
    let bars = StageBars::new(args.verbosity.get());
    let extras = Extras {
        svg: svg_path.is_some(),
        labels: false,
    };
    let painting = paint_observed(&input, &recipe, extras, &bars)?;
    let record = PaintRecord {
        input: args.input.input.clone(),
        style: args.style.clone(),
        preset: preset.name.clone(),
        sets: args.sets.clone(),
        seed: recipe.sampler.seed,
    };
    timed(&bars, Stage::Writing, || -> Result<()> {
        if !svg_only {
            save_painting(&out, &painting.image, &record)?;
        }
        write_svg(svg_path, painting.svg.as_deref())
    })?;
    bars.print_timings();
    Ok(())
}

pub(super) fn run_sheet(args: &SheetArgs) -> Result<()> {
    use crate::paint::{paint_sheet, SheetOptions};
    use crate::style::sheet::variants;
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

pub(super) fn run_info(args: &InfoArgs) -> Result<()> {
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
pub(super) fn default_output(input: &Input, style: &str) -> PathBuf {
    let name = format!("{}.{style}.png", input.stem());
    match input {
        Input::Photo(p) | Input::Npy(p) => p.with_file_name(name),
        Input::Analytic(_) => PathBuf::from(name),
    }
}
