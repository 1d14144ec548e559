//! Style presets: TOML files holding every parameter of the chain (metric, sampler, look), the
//! next stage after [`render`](crate::render) in the data's way through the program.
//!
//! A preset may `extends = "NAME"` another (built-in or a path) and change a few keys; `--set
//! key.path=value` overrides one key for one run. Every section accepts only its own keys:
//! an unknown key or a wrong type is an error naming the file, line and column and, for an
//! unknown key, the valid ones (serde's `deny_unknown_fields`). Built-in presets live in
//! `styles/` and are compiled into the binary, so `--style mosaic` works from any folder.
//! Lengths in `[metric]` are fractions of the image diagonal, as in [`MetricParams`].

pub mod sheet;

use crate::error::{Error, Result};
use crate::field::MetricParams;
use crate::render::fabric::FabricParams;
use crate::render::glyphs::{GlyphParams, Placement, Shape};
use crate::render::mosaic::MosaicParams;
use crate::render::texture::{Ink, TextureKind, TextureParams};
use crate::render::Look;
use crate::sampling::SamplerParams;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// The built-in presets: name and TOML text.
pub const BUILT_IN: [(&str, &str); 9] = [
    ("mosaic", include_str!("../../styles/mosaic.toml")),
    ("pen-hatch", include_str!("../../styles/pen-hatch.toml")),
    ("crosshatch", include_str!("../../styles/crosshatch.toml")),
    ("strokes", include_str!("../../styles/strokes.toml")),
    ("pointillist", include_str!("../../styles/pointillist.toml")),
    ("glyphs", include_str!("../../styles/glyphs.toml")),
    ("fabric", include_str!("../../styles/fabric.toml")),
    ("lic", include_str!("../../styles/lic.toml")),
    ("engraving", include_str!("../../styles/engraving.toml")),
];

/// The built-in textures (`styles/textures/`): file name and PNG bytes. A preset's
/// `look.texture` is looked for beside the preset file first, then here.
pub const BUILT_IN_TEXTURES: [(&str, &[u8]); 1] = [(
    "engraving.png",
    include_bytes!("../../styles/textures/engraving.png"),
)];

/// The preset `paint` uses when none is given.
pub const DEFAULT_STYLE: &str = "mosaic";

/// A preset as written: every key optional, so a preset that extends another says only what
/// it changes.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PresetFile {
    /// One line saying what the preset looks like.
    pub description: Option<String>,
    /// The preset this one changes (a built-in name or a path).
    pub extends: Option<String>,
    /// Photo → metric.
    #[serde(default)]
    pub metric: MetricSection,
    /// The sampler.
    #[serde(default)]
    pub sampler: SamplerSection,
    /// The look and its parameters.
    #[serde(default)]
    pub look: LookSection,
}

/// `[metric]`: see [`MetricParams`] for the meaning of each key.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct MetricSection {
    pub min_size: Option<f64>,
    pub max_size: Option<f64>,
    pub max_anisotropy: Option<f64>,
    pub gradation: Option<f64>,
    pub smoothing: Option<f64>,
    pub detail_quantile: Option<f64>,
}

/// `[sampler]`.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SamplerSection {
    /// Maximum relaxation iterations.
    pub iterations: Option<usize>,
    /// Seed.
    pub seed: Option<u64>,
}

/// `[look]`: `kind` picks the renderer; the other keys are its parameters (a key another
/// kind uses is accepted and ignored, so a preset can switch kind with one key).
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct LookSection {
    /// mosaic, hatch, crosshatch, line, stroke, stipple, glyphs, fabric or lic.
    pub kind: Option<String>,
    pub supersample: Option<usize>,
    pub border_width: Option<f32>,
    pub border_colour: Option<String>,
    pub relief: Option<f32>,
    pub jitter: Option<f32>,
    pub lines_per_cell: Option<f32>,
    pub min_spacing_px: Option<f32>,
    /// "black", "cell", "pixel" or "#rrggbb".
    pub ink: Option<String>,
    pub ink_darken: Option<f32>,
    pub paper: Option<String>,
    pub gamma: Option<f32>,
    pub fade_anisotropy: Option<f32>,
    /// A greyscale PNG tile (dark = ink), relative to the preset file.
    pub texture: Option<PathBuf>,
    pub placement: Option<String>,
    /// Glyph outline: "ellipse", "rectangle", "brush" or "superquadric:P".
    pub shape: Option<String>,
    /// Paint the cells in their colours under the glyphs.
    pub underpaint: Option<bool>,
    pub glyph_scale: Option<f32>,
    pub outline_width: Option<f32>,
    pub background: Option<String>,
    pub kernel_px: Option<f32>,
    pub cross_weight: Option<f32>,
    pub thickness: Option<f32>,
    pub contrast: Option<f32>,
}

/// A preset resolved down its `extends` chain, with its name.
#[derive(Clone, Debug, PartialEq)]
pub struct Preset {
    /// The name it was asked by (built-in name or file stem).
    pub name: String,
    /// Every key of the chain, the most specific winning.
    pub file: PresetFile,
    /// The folder relative paths (textures) are taken from; `None` for built-ins.
    pub dir: Option<PathBuf>,
}

/// Parses preset text; errors name `origin`, the line and the column.
pub fn parse(text: &str, origin: &str) -> Result<PresetFile> {
    toml::from_str(text).map_err(|e| {
        let (line, column) = e
            .span()
            .map(|s| line_column(text, s.start))
            .unwrap_or((1, 1));
        Error::param(
            format!("style {origin}:{line}:{column}"),
            e.message().replace('\n', " "),
        )
    })
}

/// 1-based line and column of byte `offset` in `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

/// The text of the built-in preset `name`.
#[must_use]
pub fn built_in(name: &str) -> Option<&'static str> {
    BUILT_IN.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
}

/// Loads `style` (a built-in name, or a path to a `.toml` file), following `extends`.
pub fn load(style: &str) -> Result<Preset> {
    load_chain(style, 0)
}

fn load_chain(style: &str, depth: usize) -> Result<Preset> {
    if depth > 8 {
        return Err(Error::param(
            "extends",
            format!("{style}: chain deeper than 8 (a loop?)"),
        ));
    }
    let (name, text, dir) = match built_in(style) {
        Some(text) => (style.to_string(), text.to_string(), None),
        None => {
            let path = Path::new(style);
            if !(style.ends_with(".toml") || path.exists()) {
                let names: Vec<&str> = BUILT_IN.iter().map(|(n, _)| *n).collect();
                return Err(Error::param(
                    "style",
                    format!("unknown style {style}; built-in: {}", names.join(", ")),
                ));
            }
            let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
            let name = path
                .file_stem()
                .map_or_else(|| style.to_string(), |s| s.to_string_lossy().into_owned());
            (name, text, path.parent().map(Path::to_path_buf))
        }
    };
    let file = parse(&text, style)?;
    let file = match &file.extends {
        Some(base) => {
            let base = load_chain(base, depth + 1)?;
            merge(base.file, file)
        }
        None => file,
    };
    Ok(Preset { name, file, dir })
}

/// Applies `key.path=value` overrides, each checked like a preset line.
pub fn apply_sets(preset: &mut Preset, sets: &[String]) -> Result<()> {
    for set in sets {
        let Some((key, value)) = set.split_once('=') else {
            return Err(Error::param(
                "--set",
                format!("{set}: expected key.path=value"),
            ));
        };
        let (key, value) = (key.trim(), value.trim());
        let Some((section, field)) = key.split_once('.') else {
            return Err(Error::param(
                "--set",
                format!("{key}: expected section.key (metric, sampler or look)"),
            ));
        };
        // A value that is not valid TOML (a bare word) is taken as a string.
        let value = if toml::from_str::<toml::Table>(&format!("v = {value}")).is_ok() {
            value.to_string()
        } else {
            format!("{value:?}")
        };
        let text = format!("[{section}]\n{field} = {value}\n");
        let over = parse(&text, &format!("--set {set}"))?;
        preset.file = merge(preset.file.clone(), over);
    }
    Ok(())
}

/// `over`'s keys over `base`'s.
#[must_use]
pub fn merge(base: PresetFile, over: PresetFile) -> PresetFile {
    let m = (base.metric, over.metric);
    let s = (base.sampler, over.sampler);
    let (b, o) = (base.look, over.look);
    PresetFile {
        description: over.description.or(base.description),
        extends: None,
        metric: MetricSection {
            min_size: m.1.min_size.or(m.0.min_size),
            max_size: m.1.max_size.or(m.0.max_size),
            max_anisotropy: m.1.max_anisotropy.or(m.0.max_anisotropy),
            gradation: m.1.gradation.or(m.0.gradation),
            smoothing: m.1.smoothing.or(m.0.smoothing),
            detail_quantile: m.1.detail_quantile.or(m.0.detail_quantile),
        },
        sampler: SamplerSection {
            iterations: s.1.iterations.or(s.0.iterations),
            seed: s.1.seed.or(s.0.seed),
        },
        look: LookSection {
            kind: o.kind.or(b.kind),
            supersample: o.supersample.or(b.supersample),
            border_width: o.border_width.or(b.border_width),
            border_colour: o.border_colour.or(b.border_colour),
            relief: o.relief.or(b.relief),
            jitter: o.jitter.or(b.jitter),
            lines_per_cell: o.lines_per_cell.or(b.lines_per_cell),
            min_spacing_px: o.min_spacing_px.or(b.min_spacing_px),
            ink: o.ink.or(b.ink),
            ink_darken: o.ink_darken.or(b.ink_darken),
            paper: o.paper.or(b.paper),
            gamma: o.gamma.or(b.gamma),
            fade_anisotropy: o.fade_anisotropy.or(b.fade_anisotropy),
            texture: o.texture.or(b.texture),
            shape: o.shape.or(b.shape),
            underpaint: o.underpaint.or(b.underpaint),
            placement: o.placement.or(b.placement),
            glyph_scale: o.glyph_scale.or(b.glyph_scale),
            outline_width: o.outline_width.or(b.outline_width),
            background: o.background.or(b.background),
            kernel_px: o.kernel_px.or(b.kernel_px),
            cross_weight: o.cross_weight.or(b.cross_weight),
            thickness: o.thickness.or(b.thickness),
            contrast: o.contrast.or(b.contrast),
        },
    }
}

/// `#rrggbb` → bytes.
fn glyph_shape(v: &str) -> Result<Shape> {
    let bad = || {
        Error::param(
            "look.shape",
            format!("{v}: expected ellipse, rectangle, brush or superquadric:P (P > 0)"),
        )
    };
    Ok(match v {
        "ellipse" => Shape::Ellipse,
        "rectangle" => Shape::Rectangle,
        "brush" => Shape::Brush,
        other => {
            let power: f32 = other
                .strip_prefix("superquadric:")
                .and_then(|p| p.parse().ok())
                .ok_or_else(bad)?;
            if !(power > 0.0 && power.is_finite()) {
                return Err(bad());
            }
            Shape::Superquadric(power)
        }
    })
}

fn colour(key: &str, v: &str) -> Result<[u8; 3]> {
    let hex = v.strip_prefix('#').unwrap_or(v);
    let bad = || Error::param(key, format!("{v}: expected #rrggbb"));
    if hex.len() != 6 {
        return Err(bad());
    }
    let byte = |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).map_err(|_| bad());
    Ok([byte(0)?, byte(2)?, byte(4)?])
}

impl Preset {
    /// The metric parameters: defaults with the preset's keys.
    pub fn metric(&self) -> Result<MetricParams> {
        let m = &self.file.metric;
        let d = MetricParams::default();
        let p = MetricParams {
            min_size: m.min_size.unwrap_or(d.min_size),
            max_size: m.max_size.unwrap_or(d.max_size),
            max_anisotropy: m.max_anisotropy.unwrap_or(d.max_anisotropy),
            gradation: m.gradation.unwrap_or(d.gradation),
            smoothing: m.smoothing.unwrap_or(d.smoothing),
            detail_quantile: m.detail_quantile.unwrap_or(d.detail_quantile),
            ..d
        };
        p.validate()?;
        Ok(p)
    }

    /// The sampler parameters.
    #[must_use]
    pub fn sampler(&self) -> SamplerParams {
        let s = &self.file.sampler;
        let d = SamplerParams::default();
        SamplerParams {
            iterations: s.iterations.unwrap_or(d.iterations),
            seed: s.seed.unwrap_or(d.seed),
            ..d
        }
    }

    /// Raster points per pixel at cell borders (default 2).
    #[must_use]
    pub fn supersample(&self) -> usize {
        self.file.look.supersample.unwrap_or(2).clamp(1, 4)
    }

    /// The look with the preset's parameters.
    pub fn look(&self) -> Result<Look> {
        let l = &self.file.look;
        let kind = l.kind.as_deref().unwrap_or("mosaic");
        let mut look = Look::named(kind).ok_or_else(|| {
            Error::param(
                "look.kind",
                format!("{kind}: expected one of {}", Look::NAMES.join(", ")),
            )
        })?;
        match &mut look {
            Look::Mosaic(p) => self.mosaic(p)?,
            Look::Texture(p) => self.texture(p)?,
            Look::Glyphs(p) => self.glyphs(p)?,
            Look::Fabric(p) => self.fabric(p),
        }
        Ok(look)
    }

    fn mosaic(&self, p: &mut MosaicParams) -> Result<()> {
        let l = &self.file.look;
        p.border_width = l.border_width.unwrap_or(p.border_width).max(0.0);
        if let Some(c) = &l.border_colour {
            p.border_colour = colour("look.border_colour", c)?;
        }
        p.relief = l.relief.unwrap_or(p.relief).clamp(0.0, 1.0);
        p.jitter = l.jitter.unwrap_or(p.jitter).clamp(0.0, 1.0);
        Ok(())
    }

    fn texture(&self, p: &mut TextureParams) -> Result<()> {
        let l = &self.file.look;
        p.lines_per_cell = l.lines_per_cell.unwrap_or(p.lines_per_cell).max(0.1);
        p.min_spacing_px = l.min_spacing_px.unwrap_or(p.min_spacing_px).max(0.5);
        p.gamma = l.gamma.unwrap_or(p.gamma).clamp(0.05, 20.0);
        p.fade_anisotropy = l.fade_anisotropy.unwrap_or(p.fade_anisotropy).max(0.0);
        p.border_width = l.border_width.unwrap_or(p.border_width).max(0.0);
        if let Some(c) = &l.paper {
            p.paper = colour("look.paper", c)?;
        }
        let darken = l.ink_darken.unwrap_or(0.3).clamp(0.0, 1.0);
        if let Some(ink) = &l.ink {
            p.ink = match ink.as_str() {
                "black" => Ink::Fixed([20, 18, 16]),
                "cell" => Ink::Cell(darken),
                "pixel" => Ink::Pixel(darken),
                other => Ink::Fixed(colour("look.ink", other)?),
            };
        }
        if let Some(tile) = &l.texture {
            p.kind = TextureKind::Image(self.texture_tile(tile)?);
        }
        Ok(())
    }

    /// The tile `look.texture` names: a file beside the preset (or an absolute path), else a
    /// built-in texture of that name.
    fn texture_tile(&self, tile: &Path) -> Result<image::GrayImage> {
        let path = match &self.dir {
            Some(dir) if tile.is_relative() => dir.join(tile),
            _ => tile.to_path_buf(),
        };
        if path.exists() {
            return Ok(crate::io::read_photo(&path)?.to_luma8());
        }
        let built_in = BUILT_IN_TEXTURES
            .iter()
            .find(|(name, _)| Path::new(name) == tile);
        match built_in {
            Some((name, bytes)) => Ok(image::load_from_memory(bytes)
                .map_err(|e| Error::Decode {
                    path: PathBuf::from(name),
                    reason: e.to_string(),
                })?
                .to_luma8()),
            None => {
                let names: Vec<&str> = BUILT_IN_TEXTURES.iter().map(|(n, _)| *n).collect();
                Err(Error::param(
                    "look.texture",
                    format!(
                        "{}: no such file, and not a built-in texture ({})",
                        path.display(),
                        names.join(", ")
                    ),
                ))
            }
        }
    }

    fn glyphs(&self, p: &mut GlyphParams) -> Result<()> {
        let l = &self.file.look;
        p.scale = l.glyph_scale.unwrap_or(p.scale).clamp(0.05, 4.0);
        p.outline_width = l.outline_width.unwrap_or(p.outline_width).max(0.0);
        if let Some(c) = &l.background {
            p.background = colour("look.background", c)?;
        }
        if let Some(c) = &l.border_colour {
            p.outline = colour("look.border_colour", c)?;
        }
        if let Some(place) = &l.placement {
            p.placement = match place.as_str() {
                "relaxed" => Placement::Relaxed,
                "grid" => Placement::Grid,
                "random" => Placement::Random,
                other => {
                    return Err(Error::param(
                        "look.placement",
                        format!("{other}: expected relaxed, grid or random"),
                    ))
                }
            };
        }
        if let Some(shape) = &l.shape {
            p.shape = glyph_shape(shape)?;
        }
        p.underpaint = l.underpaint.unwrap_or(p.underpaint);
        p.seed = self.sampler().seed;
        Ok(())
    }

    fn fabric(&self, p: &mut FabricParams) {
        let l = &self.file.look;
        p.kernel_px = l.kernel_px.unwrap_or(p.kernel_px).clamp(1.0, 100.0);
        p.cross_weight = l.cross_weight.unwrap_or(p.cross_weight).clamp(0.0, 1.0);
        p.thickness = l.thickness.unwrap_or(p.thickness).clamp(0.01, 2.0);
        p.contrast = l.contrast.unwrap_or(p.contrast).clamp(0.0, 1.0);
    }
}

/// Metric, sampling and look of `preset` for one input: the whole chain.
pub fn paint(
    input: &crate::field::Input,
    options: &crate::field::FieldOptions,
    preset: &Preset,
    sampler: &SamplerParams,
) -> Result<image::RgbImage> {
    let painting = paint_observed(
        input,
        options,
        preset,
        sampler,
        false,
        &crate::progress::Silent,
    )?;
    Ok(painting.image)
}

/// A painting, and its vector form when asked for.
#[derive(Clone, Debug)]
pub struct Painting {
    /// The raster picture.
    pub image: image::RgbImage,
    /// The SVG document of the same picture.
    pub svg: Option<String>,
}

/// [`paint`], with the SVG form when `svg` is set (an error before any work for looks
/// without one), reporting every stage to `observer`.
pub fn paint_observed(
    input: &crate::field::Input,
    options: &crate::field::FieldOptions,
    preset: &Preset,
    sampler: &SamplerParams,
    svg: bool,
    observer: &dyn crate::progress::Observer,
) -> Result<Painting> {
    let look = preset.look()?;
    if svg {
        look.check_vector_form()?;
    }
    let loaded = crate::field::load_field_observed(input, options, observer)?;
    paint_loaded(&loaded, &look, preset.supersample(), sampler, svg, observer)
}

/// Sampling and look for a field already loaded: `look` at the field's size with
/// `supersample²` points per pixel at borders, and its SVG form when `svg` is set.
pub fn paint_loaded(
    loaded: &crate::field::LoadedField,
    look: &Look,
    supersample: usize,
    sampler: &SamplerParams,
    svg: bool,
    observer: &dyn crate::progress::Observer,
) -> Result<Painting> {
    use crate::progress::{timed, Stage};
    use crate::render::{render_with_svg, RenderSize};
    let field = &loaded.metric;
    let s = crate::sampling::sample_observed(field, sampler, observer)?;
    let d = field.domain();
    let size = RenderSize {
        width: d.x.round().max(1.0) as usize,
        height: d.y.round().max(1.0) as usize,
        supersample,
    };
    let (image, svg) = timed(observer, Stage::Rendering, || {
        render_with_svg(
            look,
            &s.positions,
            &s.metrics,
            &s.mesh,
            field,
            loaded.photo.as_ref(),
            size,
            svg,
        )
    })?;
    Ok(Painting { image, svg })
}

/// How a painting was made, recorded in its PNG so that it can be made again.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PaintRecord {
    /// The input as given.
    pub input: String,
    /// The style as given (name or path).
    pub style: String,
    /// The preset's name.
    pub preset: String,
    /// The `--set` overrides.
    pub sets: Vec<String>,
    /// The sampler's seed.
    pub seed: u64,
}

/// Writes a painting atomically; a PNG (or a file without a known extension) carries the
/// record as text chunks, other formats are written plainly.
pub fn save_painting(out: &Path, img: &image::RgbImage, record: &PaintRecord) -> Result<()> {
    let is_png = matches!(
        image::ImageFormat::from_path(out),
        Ok(image::ImageFormat::Png) | Err(_)
    );
    if !is_png {
        return crate::io::save_image(out, &image::DynamicImage::ImageRgb8(img.clone()));
    }
    let mut command = format!(
        "anisopaint paint {} -s {} --seed {}",
        record.input, record.style, record.seed
    );
    for set in &record.sets {
        command.push_str(&format!(" --set {set}"));
    }
    let texts = [
        (
            "Software",
            format!("anisopaint {}", env!("CARGO_PKG_VERSION")),
        ),
        ("anisopaint:style", record.preset.clone()),
        ("anisopaint:set", record.sets.join("; ")),
        ("anisopaint:seed", record.seed.to_string()),
        ("anisopaint:command", command),
    ]
    .map(|(k, v)| (k.to_string(), v));
    crate::io::save_png_with_text(out, img, &texts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn textures_come_from_beside_the_preset_or_the_built_in_ones() {
        let dir = tempfile::tempdir().unwrap();
        let own = dir.path().join("mine.toml");
        std::fs::write(&own, "extends = \"engraving\"\n").unwrap();
        let look = load(own.to_str().unwrap()).unwrap().look().unwrap();
        let Look::Texture(p) = look else {
            panic!("engraving is a textured look")
        };
        assert_eq!(
            p.kind,
            TextureKind::Image(crate::render::texture::engraving_tile(64))
        );
        // A tile beside the preset wins over the built-in one of the same name.
        let tile = image::GrayImage::from_pixel(8, 8, image::Luma([7]));
        tile.save(dir.path().join("engraving.png")).unwrap();
        let Look::Texture(p) = load(own.to_str().unwrap()).unwrap().look().unwrap() else {
            panic!("textured")
        };
        assert_eq!(p.kind, TextureKind::Image(tile));
        std::fs::write(&own, "[look]\nkind = \"hatch\"\ntexture = \"nope.png\"\n").unwrap();
        let err = load(own.to_str().unwrap())
            .unwrap()
            .look()
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("nope.png") && err.contains("engraving.png"),
            "{err}"
        );
    }

    #[test]
    fn built_in_textures_are_the_ones_the_project_makes() {
        // REGENERATE=1 rewrites the file from its generator.
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("styles/textures/engraving.png");
        let made = crate::render::texture::engraving_tile(64);
        if std::env::var_os("REGENERATE").is_some() {
            made.save(&path).unwrap();
        }
        let committed = image::open(&path).unwrap().to_luma8();
        assert_eq!(committed, made, "styles/textures/engraving.png is stale");
        let (_, bytes) = BUILT_IN_TEXTURES[0];
        assert_eq!(image::load_from_memory(bytes).unwrap().to_luma8(), made);
    }

    #[test]
    fn every_built_in_preset_loads_and_builds() {
        for (name, _) in BUILT_IN {
            let p = load(name).unwrap();
            assert!(p.file.description.is_some(), "{name} has no description");
            p.metric().unwrap();
            p.look().unwrap();
        }
    }

    #[test]
    fn unknown_keys_and_wrong_types_name_line_column_and_valid_keys() {
        let e = parse("[look]\nkind = \"mosaic\"\nborder_widht = 2\n", "x.toml").unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("x.toml:3:1"), "{msg}");
        assert!(msg.contains("border_width"), "lists the valid keys: {msg}");
        let e = parse("[metric]\nmax_anisotropy = \"lots\"\n", "y.toml").unwrap_err();
        assert!(e.to_string().contains("y.toml:2:18"), "{e}");
    }

    #[test]
    fn extends_and_set_override_the_base() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("mine.toml");
        std::fs::write(&path, "extends = \"mosaic\"\n[look]\nborder_width = 4.0\n").unwrap();
        let mut p = load(path.to_str().unwrap()).unwrap();
        let base = load("mosaic").unwrap();
        assert_eq!(p.file.look.kind, base.file.look.kind);
        assert_eq!(p.file.look.border_width, Some(4.0));
        apply_sets(
            &mut p,
            &["metric.max_anisotropy=6".into(), "look.ink=pixel".into()],
        )
        .unwrap();
        assert_eq!(p.metric().unwrap().max_anisotropy, 6.0);
        assert_eq!(p.file.look.ink.as_deref(), Some("pixel"));
        assert!(apply_sets(&mut p, &["look.nope=1".into()]).is_err());
        assert!(apply_sets(&mut p, &["nodot=1".into()]).is_err());
    }
}
