//! A preset's keys converted into the library's parameters: [`MetricParams`] (photo → metric,
//! paper sections 3-4), [`SamplerParams`] (section 5) and the [`Look`] with its parameters
//! (sections 6-7). Every numeric key is checked against the range [`schema`] declares for it,
//! and colours, kinds, shapes and placements are parsed, with errors naming the key, the value
//! and what is allowed.

use super::preset::{Preset, BUILT_IN_TEXTURES};
use super::schema;
use crate::error::{Error, Result};
use crate::field::MetricParams;
use crate::render::cells::{CellKind, CellParams};
use crate::render::lines::outline::OutlineParams;
use crate::render::lines::outline_ink::OutlineInk;
use crate::render::looks::engraving::EngravingParams;
use crate::render::looks::fabric::FabricParams;
use crate::render::looks::glyphs::{GlyphParams, Placement, Shape};
use crate::render::looks::mosaic::MosaicParams;
use crate::render::looks::texture::{Ink, TextureKind, TextureParams};
use crate::render::support::colour::BLACK_INK;
use crate::render::Look;
use crate::sampling::{SamplerParams, Seeding};
use std::path::{Path, PathBuf};

/// `ellipse`, `rectangle`, `brush` or `superquadric:P` → the glyph outline.
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

/// `#rrggbb` (or `rrggbb`) → bytes; errors name `key`.
fn colour(key: &str, v: &str) -> Result<[u8; 3]> {
    let hex = v.strip_prefix('#').unwrap_or(v);
    let bad = || Error::param(key, format!("{v}: expected #rrggbb"));
    if hex.len() != 6 {
        return Err(bad());
    }
    let byte = |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).map_err(|_| bad());
    Ok([byte(0)?, byte(2)?, byte(4)?])
}

/// The value of a key that takes one of `names`, or an error naming the key and the choices.
fn named<T>(
    key: &str,
    name: &str,
    lookup: impl Fn(&str) -> Option<T>,
    names: &[&str],
) -> Result<T> {
    lookup(name)
        .ok_or_else(|| Error::param(key, format!("{name}: expected one of {}", names.join(", "))))
}

/// `value`, or `default` when the preset leaves it out, checked against the range the schema
/// declares for `key` ([`schema::range`]): NaN and values outside are errors naming the key,
/// the value and the range (a preset's numbers are never clamped in silence). A key the schema
/// does not declare as a number is an error too, so no key goes unchecked.
fn ranged<T: Number>(key: &str, value: Option<T>, default: T) -> Result<T> {
    let v = value.unwrap_or(default);
    let (lo, hi) = schema::range(key)
        .ok_or_else(|| Error::param(key, "not a numeric key of the preset schema"))?;
    if lo <= v.as_f64() && v.as_f64() <= hi {
        Ok(v)
    } else {
        Err(Error::param(key, format!("{v} must be in [{lo}, {hi}]")))
    }
}

/// The numbers preset keys hold.
trait Number: Copy + std::fmt::Display {
    fn as_f64(self) -> f64;
}

impl Number for f32 {
    fn as_f64(self) -> f64 {
        f64::from(self)
    }
}

impl Number for f64 {
    fn as_f64(self) -> f64 {
        self
    }
}

impl Number for usize {
    fn as_f64(self) -> f64 {
        self as f64
    }
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

    /// The sampler parameters: `sampler.iterations` in the schema's range, any seed,
    /// `sampler.seeding` "auto" (the default), "lattice" or "darts".
    pub fn sampler(&self) -> Result<SamplerParams> {
        let s = &self.file.sampler;
        let d = SamplerParams::default();
        let seeding = match s.seeding.as_deref() {
            None => d.seeding,
            Some(name) => named("sampler.seeding", name, Seeding::named, &Seeding::NAMES)?,
        };
        Ok(SamplerParams {
            iterations: ranged("sampler.iterations", s.iterations, d.iterations)?,
            seed: s.seed.unwrap_or(d.seed),
            seeding,
            ..d
        })
    }

    /// Which cells the looks paint: `cells.kind` ("edges" by default, or "voronoi"),
    /// `cells.colour_weight`, `cells.iterations`, `cells.reach` and `cells.blur_px`.
    pub fn cells(&self) -> Result<CellParams> {
        let c = &self.file.cells;
        let d = CellParams::default();
        let kind = match c.kind.as_deref() {
            None => d.kind,
            Some(name) => named("cells.kind", name, CellKind::named, &CellKind::NAMES)?,
        };
        Ok(CellParams {
            kind,
            colour_weight: ranged("cells.colour_weight", c.colour_weight, d.colour_weight)?,
            iterations: ranged("cells.iterations", c.iterations, d.iterations)?,
            reach: ranged("cells.reach", c.reach, d.reach)?,
            blur_px: ranged("cells.blur_px", c.blur_px, d.blur_px)?,
        })
    }

    /// The outlines over the look: `outlines.strength` (ink, default none), `outlines.scale`
    /// (line width) and `outlines.ink` (`#rrggbb`, or `pixel` for the photo's colour under
    /// the lines); `highlights.strength` (paper along thin light lines, default none).
    pub fn outline(&self) -> Result<OutlineParams> {
        let o = &self.file.outlines;
        let d = OutlineParams::default();
        let ink = match o.ink.as_deref() {
            None => d.ink,
            Some(OutlineInk::PIXEL) => OutlineInk::Pixel,
            Some(c) => OutlineInk::Colour(colour("outlines.ink", c).map_err(|_| {
                Error::param(
                    "outlines.ink",
                    format!("{c}: expected #rrggbb or {}", OutlineInk::PIXEL),
                )
            })?),
        };
        Ok(OutlineParams {
            strength: ranged("outlines.strength", o.strength, d.strength)?,
            scale: ranged("outlines.scale", o.scale, d.scale)?,
            ink,
            highlights: ranged(
                "highlights.strength",
                self.file.highlights.strength,
                d.highlights,
            )?,
        })
    }

    /// Raster points per pixel at cell borders (`cells.supersample`, default 2).
    pub fn supersample(&self) -> Result<usize> {
        ranged("cells.supersample", self.file.cells.supersample, 2)
    }

    /// The look with the preset's parameters.
    pub fn look(&self) -> Result<Look> {
        let kind = self.file.look_kind();
        let mut look = named("look.kind", kind, Look::named, &Look::NAMES)?;
        self.configure(&mut look)?;
        Ok(look)
    }

    /// `look`'s parameters from the preset's keys.
    fn configure(&self, look: &mut Look) -> Result<()> {
        match look {
            Look::Mosaic(p) => self.mosaic(p),
            Look::Texture(p) => self.texture(p),
            Look::Glyphs(p) => self.glyphs(p),
            Look::Fabric(p) => self.fabric(p),
            Look::Engraving(p) => self.engraving(p),
        }
    }

    /// `look.border_width` (the mosaic's leading, a texture's cell borders), or `default`.
    fn border_width(&self, default: f32) -> Result<f32> {
        ranged("look.border_width", self.file.look.border_width, default)
    }

    /// `look.min_spacing_px` (hatch lines, stipple rows, engraving lines), or `default`.
    fn min_spacing_px(&self, default: f32) -> Result<f32> {
        let l = &self.file.look;
        ranged("look.min_spacing_px", l.min_spacing_px, default)
    }

    /// `look.flat_angle` (hatchings' lines and brush strokes where the field has no
    /// direction; degrees), or `default`. (The engraving's, the fabric's and the LIC's have a
    /// value always.)
    fn flat_angle(&self, default: Option<f32>) -> Result<Option<f32>> {
        match self.file.look.flat_angle {
            Some(a) => Ok(Some(ranged("look.flat_angle", Some(a), a)?)),
            None => Ok(default),
        }
    }

    /// `look.gamma`, the ink looks' tone curve, or `default`.
    fn gamma(&self, default: f32) -> Result<f32> {
        ranged("look.gamma", self.file.look.gamma, default)
    }

    fn mosaic(&self, p: &mut MosaicParams) -> Result<()> {
        let l = &self.file.look;
        p.border_width = self.border_width(p.border_width)?;
        if let Some(c) = &l.border_colour {
            p.border_colour = colour("look.border_colour", c)?;
        }
        p.relief = ranged("look.relief", l.relief, p.relief)?;
        p.jitter = ranged("look.jitter", l.jitter, p.jitter)?;
        Ok(())
    }

    fn texture(&self, p: &mut TextureParams) -> Result<()> {
        let l = &self.file.look;
        p.lines_per_cell = ranged("look.lines_per_cell", l.lines_per_cell, p.lines_per_cell)?;
        p.min_spacing_px = self.min_spacing_px(p.min_spacing_px)?;
        p.gamma = self.gamma(p.gamma)?;
        p.fade_anisotropy = ranged("look.fade_anisotropy", l.fade_anisotropy, p.fade_anisotropy)?;
        p.border_width = self.border_width(p.border_width)?;
        p.flat_angle = self.flat_angle(p.flat_angle)?;
        p.cell_tone = l.cell_tone.unwrap_or(p.cell_tone);
        if let Some(c) = &l.paper {
            p.paper = colour("look.paper", c)?;
        }
        let darken = ranged("look.ink_darken", l.ink_darken, 0.3)?;
        if let Some(ink) = &l.ink {
            p.ink = match ink.as_str() {
                "black" => Ink::Fixed(BLACK_INK),
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
        p.scale = ranged("look.glyph_scale", l.glyph_scale, p.scale)?;
        p.outline_width = ranged("look.outline_width", l.outline_width, p.outline_width)?;
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
        p.ground = ranged("look.ground", l.ground, p.ground)?;
        p.refine = ranged("look.refine", l.refine, p.refine)?;
        p.flat_angle = self.flat_angle(p.flat_angle)?;
        p.seed = self.sampler()?.seed;
        Ok(())
    }

    fn engraving(&self, p: &mut EngravingParams) -> Result<()> {
        let l = &self.file.look;
        p.line_spacing = ranged("look.line_spacing", l.line_spacing, p.line_spacing)?;
        p.min_spacing_px = self.min_spacing_px(p.min_spacing_px)?;
        p.gamma = self.gamma(p.gamma)?;
        p.edge_break = ranged("look.edge_break", l.edge_break, p.edge_break)?;
        p.flat_angle = ranged("look.flat_angle", l.flat_angle, p.flat_angle)?;
        p.tone = ranged("look.tone", l.tone, p.tone)?;
        if let Some(c) = &l.paper {
            p.paper = colour("look.paper", c)?;
        }
        match l.ink.as_deref() {
            None => {}
            Some("black") => p.ink = BLACK_INK,
            Some(other) => {
                p.ink = colour("look.ink", other).map_err(|_| {
                    Error::param(
                        "look.ink",
                        format!("{other}: an engraving's ink is \"black\" or #rrggbb"),
                    )
                })?;
            }
        }
        Ok(())
    }

    fn fabric(&self, p: &mut FabricParams) -> Result<()> {
        let l = &self.file.look;
        p.kernel_px = ranged("look.kernel_px", l.kernel_px, p.kernel_px)?;
        p.cross_weight = ranged("look.cross_weight", l.cross_weight, p.cross_weight)?;
        p.thickness = ranged("look.thickness", l.thickness, p.thickness)?;
        p.contrast = ranged("look.contrast", l.contrast, p.contrast)?;
        p.flat_angle = ranged("look.flat_angle", l.flat_angle, p.flat_angle)?;
        Ok(())
    }
}
