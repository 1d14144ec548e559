//! A preset written out in full (`anisopaint styles show NAME --full`): every key its look
//! reads, with the value the painting uses once `extends` is followed and the library's
//! defaults fill what no file says, as TOML ready to copy into a preset of one's own. The
//! values are read back from the converted parameters ([`convert`](super::convert)), so what
//! is printed is what paints, and printing it again after loading it changes nothing.

use super::preset::{
    CellsSection, HighlightsSection, LookSection, MetricSection, OutlinesSection, Preset,
    PresetFile, SamplerSection,
};
use super::schema::{self, Key};
use crate::error::{Error, Result};
use crate::render::lines::outline_ink::OutlineInk;
use crate::render::looks::glyphs::{Placement, Shape};
use crate::render::looks::texture::Ink;
use crate::render::support::colour::BLACK_INK;
use crate::render::Look;

/// `preset` with every key its look uses, as TOML.
pub fn full_toml(preset: &Preset) -> Result<String> {
    let file = full(preset)?;
    let text = toml::to_string(&file)
        .map_err(|e| Error::param("style", format!("cannot write it as TOML: {e}")))?;
    Ok(format!(
        "# {}: every key with the value it paints with (extends followed, defaults filled)\n{text}",
        preset.name
    ))
}

/// `preset`'s file with every key its look uses set.
pub fn full(preset: &Preset) -> Result<PresetFile> {
    let m = preset.metric()?;
    let s = preset.sampler()?;
    let outline = preset.outline()?;
    let file = PresetFile {
        description: preset.file.description.clone(),
        extends: None,
        metric: MetricSection {
            min_size: Some(m.min_size),
            max_size: Some(m.max_size),
            max_anisotropy: Some(m.max_anisotropy),
            gradation: Some(m.gradation),
            smoothing: Some(m.smoothing),
            detail_quantile: Some(m.detail_quantile),
        },
        sampler: SamplerSection {
            iterations: Some(s.iterations),
            seed: Some(s.seed),
            seeding: Some(s.seeding.name().to_string()),
        },
        cells: cells_section(preset)?,
        outlines: OutlinesSection {
            strength: Some(outline.strength),
            scale: Some(outline.scale),
            ink: Some(match outline.ink {
                OutlineInk::Colour(c) => hex(c),
                OutlineInk::Pixel => OutlineInk::PIXEL.into(),
            }),
        },
        highlights: HighlightsSection {
            strength: Some(outline.highlights),
        },
        look: look_section(preset)?,
    };
    only_what_the_look_reads(&file)
}

/// `[cells]` as `preset` paints it.
fn cells_section(preset: &Preset) -> Result<CellsSection> {
    let cells = preset.cells()?;
    Ok(CellsSection {
        kind: Some(
            match cells.kind {
                crate::render::cells::CellKind::Edges => "edges",
                crate::render::cells::CellKind::Voronoi => "voronoi",
            }
            .into(),
        ),
        colour_weight: Some(cells.colour_weight),
        iterations: Some(cells.iterations),
        reach: Some(cells.reach),
        blur_px: Some(cells.blur_px),
        supersample: Some(preset.supersample()?),
    })
}

/// `[look]` as `preset` paints it: its kind and every key of its look's parameters.
fn look_section(preset: &Preset) -> Result<LookSection> {
    let given = &preset.file.look;
    let mut look = LookSection {
        kind: Some(given.kind.clone().unwrap_or(Look::DEFAULT_NAME.into())),
        ..LookSection::default()
    };
    match preset.look()? {
        Look::Mosaic(p) => {
            look.border_width = Some(p.border_width);
            look.border_colour = Some(hex(p.border_colour));
            look.relief = Some(p.relief);
            look.jitter = Some(p.jitter);
        }
        Look::Texture(p) => {
            look.lines_per_cell = Some(p.lines_per_cell);
            look.min_spacing_px = Some(p.min_spacing_px);
            look.gamma = Some(p.gamma);
            look.fade_anisotropy = Some(p.fade_anisotropy);
            look.border_width = Some(p.border_width);
            look.flat_angle = p.flat_angle;
            look.cell_tone = Some(p.cell_tone);
            look.paper = Some(hex(p.paper));
            let (ink, darken) = match p.ink {
                Ink::Fixed(c) if c == BLACK_INK => ("black".to_string(), None),
                Ink::Fixed(c) => (hex(c), None),
                Ink::Cell(d) => ("cell".to_string(), Some(d)),
                Ink::Pixel(d) => ("pixel".to_string(), Some(d)),
            };
            look.ink = Some(ink);
            look.ink_darken = darken;
            look.texture.clone_from(&given.texture);
        }
        Look::Glyphs(p) => {
            look.glyph_scale = Some(p.scale);
            look.outline_width = Some(p.outline_width);
            look.border_colour = Some(hex(p.outline));
            look.background = Some(hex(p.background));
            look.placement = Some(
                match p.placement {
                    Placement::Relaxed => "relaxed",
                    Placement::Grid => "grid",
                    Placement::Random => "random",
                }
                .into(),
            );
            look.shape = Some(match p.shape {
                Shape::Ellipse => "ellipse".into(),
                Shape::Rectangle => "rectangle".into(),
                Shape::Brush => "brush".into(),
                Shape::Superquadric(power) => format!("superquadric:{power}"),
            });
            look.underpaint = Some(p.underpaint);
            look.ground = Some(p.ground);
            look.refine = Some(p.refine);
            look.flat_angle = p.flat_angle;
        }
        Look::Engraving(p) => {
            look.line_spacing = Some(p.line_spacing);
            look.min_spacing_px = Some(p.min_spacing_px);
            look.gamma = Some(p.gamma);
            look.edge_break = Some(p.edge_break);
            look.flat_angle = Some(p.flat_angle);
            look.tone = Some(p.tone);
            look.paper = Some(hex(p.paper));
            look.ink = Some(if p.ink == BLACK_INK {
                "black".to_string()
            } else {
                hex(p.ink)
            });
        }
        Look::Fabric(p) => {
            look.kernel_px = Some(p.kernel_px);
            look.cross_weight = Some(p.cross_weight);
            look.thickness = Some(p.thickness);
            look.contrast = Some(p.contrast);
            look.flat_angle = Some(p.flat_angle);
        }
    }
    Ok(look)
}

/// `file` without the keys its look does not read (the cells', outlines' and highlights' keys
/// are filled in above for every look).
fn only_what_the_look_reads(file: &PresetFile) -> Result<PresetFile> {
    let kind = file.look.kind.clone().unwrap_or_default();
    let bad = |e: String| Error::param("style", format!("cannot write it as TOML: {e}"));
    let mut table = toml::Table::try_from(file).map_err(|e| bad(e.to_string()))?;
    for (section, keys) in table.iter_mut() {
        if let toml::Value::Table(keys) = keys {
            keys.retain(|name, _| {
                schema::key_at(&format!("{section}.{name}"))
                    .is_some_and(|k| k.readers.include(&kind))
            });
        }
    }
    table.retain(|_, keys| !matches!(keys, toml::Value::Table(k) if k.is_empty()));
    table
        .try_into()
        .map_err(|e: toml::de::Error| bad(e.to_string()))
}

/// Every key `preset`'s look reads ([`schema::read_by`]), in the schema's order, with the
/// value it paints with as TOML would write it (`None` where the key has no value: a texture
/// not given, a flat angle left to the field).
pub fn key_values(preset: &Preset) -> Result<Vec<(&'static Key, Option<String>)>> {
    let file = full(preset)?;
    let table = toml::Table::try_from(&file)
        .map_err(|e| Error::param("style", format!("cannot write it as TOML: {e}")))?;
    let kind = file.look.kind.clone().unwrap_or_default();
    Ok(schema::KEYS
        .iter()
        .filter(|k| k.readers.include(&kind))
        .map(|k| {
            let value = table
                .get(k.section())
                .and_then(|s| s.get(k.name()))
                .map(|v| match v {
                    // An `f32` key's value as the shortest text that reads back as it.
                    toml::Value::Float(f) if f64::from(*f as f32) == *f => (*f as f32).to_string(),
                    v => v.to_string(),
                });
            (k, value)
        })
        .collect())
}

/// `#rrggbb`.
fn hex([r, g, b]: [u8; 3]) -> String {
    format!("#{r:02x}{g:02x}{b:02x}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::style::{load, parse, BUILT_IN};

    /// For every look, the keys written out in full are the keys the schema says it reads
    /// (but those without a value where nothing sets them: a texture, a flat angle, an ink's
    /// darkening).
    #[test]
    fn the_full_preset_writes_the_keys_the_schema_names() {
        for kind in Look::NAMES {
            let mut preset = Preset::defaults();
            preset.file.cells.kind = None;
            crate::style::apply_sets(&mut preset, &[format!("look.kind={kind}")]).unwrap();
            for (key, value) in key_values(&preset).unwrap() {
                let optional = matches!(key.name(), "texture" | "flat_angle" | "ink_darken");
                assert!(
                    value.is_some() || optional,
                    "{kind}: {} has no value",
                    key.path
                );
            }
            let file = full(&preset).unwrap();
            for (section, keys) in toml::Table::try_from(&file).unwrap() {
                let toml::Value::Table(keys) = keys else {
                    continue;
                };
                for name in keys.keys() {
                    let key = schema::key_at(&format!("{section}.{name}")).unwrap();
                    assert!(key.readers.include(kind), "{kind} writes {section}.{name}");
                }
            }
        }
    }

    /// Written out in full and read back, every built-in preset paints with the same
    /// parameters, and writing it again gives the same text.
    #[test]
    fn the_full_preset_paints_the_same_and_is_a_fixed_point() {
        for (name, _) in BUILT_IN {
            let preset = load(name).unwrap();
            let text = full_toml(&preset).unwrap();
            let again = Preset {
                name: name.to_string(),
                file: parse(&text, name).unwrap(),
                dir: None,
            };
            assert_eq!(again.metric().unwrap(), preset.metric().unwrap(), "{name}");
            assert_eq!(
                again.sampler().unwrap(),
                preset.sampler().unwrap(),
                "{name}"
            );
            assert_eq!(again.cells().unwrap(), preset.cells().unwrap(), "{name}");
            assert_eq!(again.look().unwrap(), preset.look().unwrap(), "{name}");
            assert_eq!(full_toml(&again).unwrap(), text, "{name}");
            // Every key the preset file itself sets is there (`extends` is followed).
            let own = crate::style::built_in(name).unwrap();
            for line in own
                .lines()
                .filter(|l| l.contains(" = ") && !l.starts_with("extends"))
            {
                let key = line.split(" = ").next().unwrap().trim();
                assert!(
                    text.lines().any(|l| l.starts_with(&format!("{key} = "))),
                    "{name}: {key} missing"
                );
            }
        }
    }
}
