//! Presets as files: the TOML sections `[metric]`, `[sampler]`, `[cells]`, `[outlines]`,
//! `[highlights]` and `[look]` of optional keys,
//! the built-in presets and textures compiled in from `styles/`, loading down an `extends`
//! chain, and `--set key.path=value` overrides checked like preset lines. Every section
//! accepts only its own keys (serde's `deny_unknown_fields`), and only those the preset's look
//! reads ([`schema`]): an unknown key or a wrong type is an error naming the file, line and
//! column, and for a key the look does not read, the nearest one it does.

use super::schema;
use crate::error::{Error, Result};
use crate::render::Look;
use serde::{Deserialize, Serialize};
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
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
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
    /// Which cells the look paints.
    #[serde(default)]
    pub cells: CellsSection,
    /// The outlines along the photo's edges, over any look.
    #[serde(default)]
    pub outlines: OutlinesSection,
    /// Paper along the photo's thin light lines, over the one-ink looks.
    #[serde(default)]
    pub highlights: HighlightsSection,
    /// The look and its parameters.
    #[serde(default)]
    pub look: LookSection,
}

impl PresetFile {
    /// The look's kind: `look.kind`, or the default look's.
    #[must_use]
    pub fn look_kind(&self) -> &str {
        self.look.kind.as_deref().unwrap_or(Look::DEFAULT_NAME)
    }
}

/// `[cells]`: which cells the look paints (see [`schema::KEYS`] for each key).
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CellsSection {
    /// "edges" (cells that stop at the photo's edges) or "voronoi" (the paper's cells).
    pub kind: Option<String>,
    /// Weight of the colour term of edge-following cells.
    pub colour_weight: Option<f64>,
    /// Assign-and-move rounds of edge-following cells.
    pub iterations: Option<usize>,
    /// How far past the paper's border an edge-following cell may reach (in `δ`).
    pub reach: Option<f64>,
    /// σ in photo pixels of the blur the colour term of edge-following cells sees.
    pub blur_px: Option<f32>,
    /// Raster points per pixel along each axis where a border crosses it.
    pub supersample: Option<usize>,
}

/// `[outlines]`: lines along the photo's edges over any look.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct OutlinesSection {
    /// Their ink, 0 (none) to 1.
    pub strength: Option<f32>,
    /// Their width relative to the default.
    pub scale: Option<f32>,
    /// What they are drawn in: `#rrggbb`, or `pixel` for the photo's colour under every pixel
    /// of the lines.
    pub ink: Option<String>,
}

/// `[highlights]`: paper along the photo's thin light lines (whiskers, masts, stars) over the
/// one-ink looks (hatching, cross-hatching, engraving).
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct HighlightsSection {
    /// How much paper, 0 (none) to 1.
    pub strength: Option<f32>,
}

/// `[metric]`: see [`MetricParams`](crate::field::MetricParams) for the meaning of each key.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
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
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SamplerSection {
    /// Maximum relaxation iterations.
    pub iterations: Option<usize>,
    /// Seed.
    pub seed: Option<u64>,
    /// "auto" (lattice for large fields, darts for small), "lattice" (a metric-aligned
    /// hexagonal lattice grown as a front) or "darts" (the
    /// paper's relaxation dart throwing).
    pub seeding: Option<String>,
}

/// `[look]`: `kind` picks the renderer; the other keys are its parameters, each read by the
/// looks [`schema::KEYS`] names (a key the look does not read is an error).
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct LookSection {
    /// mosaic, hatch, crosshatch, line, stroke, stipple, glyphs, engraving, fabric or lic.
    pub kind: Option<String>,
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
    /// Glyphs: how much of its cell's colour the ground under a glyph takes (0 to 1).
    pub ground: Option<f32>,
    /// Brush strokes: the canvas-to-photo difference above which a finer stroke, or a detail
    /// stroke, is laid (0: every stroke, no details).
    pub refine: Option<f32>,
    pub glyph_scale: Option<f32>,
    pub outline_width: Option<f32>,
    pub background: Option<String>,
    pub kernel_px: Option<f32>,
    pub cross_weight: Option<f32>,
    pub thickness: Option<f32>,
    pub contrast: Option<f32>,
    /// Engraving: spacing of the lines as a fraction of the diagonal.
    pub line_spacing: Option<f32>,
    /// Engraving: lightness step over one spacing along a line that breaks it.
    pub edge_break: Option<f32>,
    /// Hatchings and engraving: direction of the lines where the field has none; brush
    /// strokes: of the strokes across flat areas (degrees).
    pub flat_angle: Option<f32>,
    /// Hatch and cross-hatch over a photo: one tone per cell (the paper's), instead of the
    /// photo's tone point by point.
    pub cell_tone: Option<bool>,
    /// Engraving: lightness of a field without a photo.
    pub tone: Option<f32>,
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

impl Preset {
    /// The preset of no file: every key at the library's default (a mosaic), but the
    /// paper's own generalized Voronoi cells (`cells.kind = "voronoi"`), so that the explore
    /// commands without `-s` show the paper's method and their label maps are its cells.
    #[must_use]
    pub fn defaults() -> Preset {
        let mut file = PresetFile::default();
        file.cells.kind = Some("voronoi".into());
        Preset {
            name: "defaults".into(),
            file,
            dir: None,
        }
    }
}

/// Parses preset text; errors name `origin`, the line and the column, and for an unknown key
/// the nearest key the preset's look reads.
pub fn parse(text: &str, origin: &str) -> Result<PresetFile> {
    toml::from_str(text).map_err(|e| {
        let (line, column) = e
            .span()
            .map(|s| line_column(text, s.start))
            .unwrap_or((1, 1));
        Error::param(
            format!("style {origin}:{line}:{column}"),
            explained(&e, text),
        )
    })
}

/// A TOML error's message on one line; for an unknown key, a "did you mean" naming the
/// nearest key of its section that the look of `text` reads, instead of every key there is.
fn explained(e: &toml::de::Error, text: &str) -> String {
    let message = e.message().replace('\n', " ");
    let Some(name) = message
        .strip_prefix("unknown field `")
        .and_then(|rest| rest.split('`').next())
    else {
        return message;
    };
    // The section and the look kind, read loosely (the text did not deserialize).
    let before = &text[..e.span().map_or(0, |s| s.start.min(text.len()))];
    let section = before
        .lines()
        .rev()
        .find_map(|l| l.trim().strip_prefix('[')?.strip_suffix(']'))
        .unwrap_or("");
    let kind = toml::from_str::<toml::Table>(text)
        .ok()
        .and_then(|t| t.get("look")?.get("kind")?.as_str().map(str::to_string))
        .unwrap_or_else(|| Look::DEFAULT_NAME.to_string());
    unknown_key(section, name, &kind)
}

/// The message for `section.name`, which the look `kind` does not read: which looks do read
/// it (for a key of another look), and the nearest key `kind` reads, or all of them.
fn unknown_key(section: &str, name: &str, kind: &str) -> String {
    if section.is_empty() {
        return format!(
            "unknown key {name}: a preset has description, extends and the sections \
             [metric], [sampler], [cells], [outlines], [highlights] and [look]"
        );
    }
    let path = format!("{section}.{name}");
    if let Some((_, to)) = schema::MOVED.iter().find(|(from, _)| *from == path) {
        let (new_section, new_name) = to.split_once('.').unwrap_or((to, ""));
        return format!("{path} is now {to}: write `{new_name} = …` under [{new_section}]");
    }
    let mut message = match schema::key_at(&path) {
        Some(key) => {
            format!(
                "{section}.{name} is not read by the {kind} look (only by {})",
                key.readers.looks().join(", ")
            )
        }
        None => format!("unknown key {section}.{name}"),
    };
    match schema::nearest(kind, section, name) {
        Some(k) => message.push_str(&format!("; did you mean {}?", k.path)),
        None => {
            let keys: Vec<&str> = schema::read_by(kind, section).map(|k| k.name()).collect();
            message.push_str(&format!(
                "; the {kind} look reads {section}.{}",
                keys.join(", ")
            ));
        }
    }
    message
}

/// Fails when `file` sets a key its look does not read, naming the nearest one it does.
fn check_look_keys(file: &PresetFile, origin: &str) -> Result<()> {
    let kind = file.look_kind();
    if !Look::NAMES.contains(&kind) {
        return Ok(()); // the conversion names the bad kind and the good ones
    }
    for (section, names) in set_keys(file) {
        for name in names {
            let read = schema::key_at(&format!("{section}.{name}"))
                .is_some_and(|k| k.readers.include(kind));
            if !read {
                return Err(Error::param(
                    format!("style {origin}"),
                    unknown_key(&section, &name, kind),
                ));
            }
        }
    }
    Ok(())
}

/// Every section `file` sets keys in, with the names of those keys.
fn set_keys(file: &PresetFile) -> Vec<(String, Vec<String>)> {
    let Ok(table) = toml::Table::try_from(file) else {
        return Vec::new();
    };
    table
        .into_iter()
        .filter_map(|(section, keys)| match keys {
            toml::Value::Table(keys) => Some((section, keys.keys().cloned().collect())),
            _ => None,
        })
        .collect()
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

/// Loads `style` (a built-in name, or a path to a `.toml` file), following `extends`. A key the
/// preset's look does not read is an error (keys inherited from a preset of another look
/// are dropped where the kind changes: see [`merge`]).
pub fn load(style: &str) -> Result<Preset> {
    let preset = load_chain(style, 0)?;
    check_look_keys(&preset.file, style)?;
    Ok(preset)
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
            merge(base.file, file)?
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
                format!("{key}: expected section.key (metric, sampler, cells, outlines, highlights or look)"),
            ));
        };
        // A value that is not valid TOML (a bare word) is taken as a string.
        let value = if toml::from_str::<toml::Table>(&format!("v = {value}")).is_ok() {
            value.to_string()
        } else {
            format!("{value:?}")
        };
        let text = format!("[{section}]\n{field} = {value}\n");
        // The line and column `parse` would give point into this one-line text, not
        // anything the user wrote: the override itself is named instead.
        let over: PresetFile = toml::from_str(&text).map_err(|e| {
            let kind = preset.file.look_kind();
            let message = match e.message().strip_prefix("unknown field `") {
                Some(_) => unknown_key(section, field, kind),
                None => e.message().replace('\n', " "),
            };
            Error::param(format!("style --set {set}"), message)
        })?;
        preset.file = merge(preset.file.clone(), over)?;
        check_look_keys(&preset.file, &format!("--set {set}"))?;
    }
    Ok(())
}

/// `over`'s keys over `base`'s. Where `over` changes the look's kind, `base`'s keys that the
/// new look does not read are left behind, so a preset can switch look with one key.
pub fn merge(base: PresetFile, over: PresetFile) -> Result<PresetFile> {
    let old_kind = base.look_kind().to_string();
    let mut merged = table(&base)?;
    match &over.look.kind {
        Some(kind) if old_kind != *kind => {
            for (section, keys) in merged.iter_mut() {
                if let toml::Value::Table(keys) = keys {
                    keys.retain(|name, _| {
                        schema::key_at(&format!("{section}.{name}"))
                            .is_some_and(|k| k.readers.include(kind))
                    });
                }
            }
        }
        _ => {}
    }
    for (name, value) in table(&over)? {
        match (merged.get_mut(&name), value) {
            (Some(toml::Value::Table(section)), toml::Value::Table(keys)) => section.extend(keys),
            (_, value) => {
                merged.insert(name, value);
            }
        }
    }
    merged.remove("extends");
    merged
        .try_into()
        .map_err(|e| Error::param("style", format!("merging presets: {e}")))
}

/// A preset file as a TOML table of the keys it sets.
fn table(file: &PresetFile) -> Result<toml::Table> {
    toml::Table::try_from(file).map_err(|e| Error::param("style", format!("{e}")))
}
