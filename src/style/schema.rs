//! The keys a preset may set, declared once: for each its section and name, what it takes
//! (a number in a range, a colour, one of some names…), which looks read it, and one line
//! saying what it does. The conversion to parameters takes its ranges from here, a preset is
//! checked against it (a key the chosen look does not read is an error naming the nearest key
//! that look does read), and `anisopaint styles keys` prints it with each look's defaults. It
//! can be walked at run time ([`KEYS`]), so anything that offers the keys to a user (a form,
//! a binding) is built from it.

use crate::render::Look;

/// What a key takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// A number in `[min, max]` (inclusive; `f64::INFINITY` for no upper bound).
    Number {
        /// The least value.
        min: f64,
        /// The largest value.
        max: f64,
    },
    /// A number over 0, at most `max`.
    Positive {
        /// The largest value.
        max: f64,
    },
    /// A whole number in `[min, max]`.
    Integer {
        /// The least value.
        min: u64,
        /// The largest value.
        max: u64,
    },
    /// `true` or `false`.
    Bool,
    /// `#rrggbb`.
    Colour,
    /// `#rrggbb` or one of these words.
    ColourOr(&'static [&'static str]),
    /// One of these names.
    Choice(&'static [&'static str]),
    /// A glyph shape: `ellipse`, `rectangle`, `brush` or `superquadric:P`.
    Shape,
    /// A path to a file (relative to the preset's folder) or a built-in texture's name.
    Path,
}

impl Value {
    /// The values it takes, as a user would read them.
    #[must_use]
    pub fn describe(&self) -> String {
        match *self {
            Value::Number { min, max } if max.is_infinite() => format!("number ≥ {min}"),
            Value::Number { min, max } => format!("number in [{min}, {max}]"),
            Value::Positive { max } if max.is_infinite() => "number over 0".into(),
            Value::Positive { max } => format!("number in (0, {max}]"),
            Value::Integer { min, max } => format!("whole number in [{min}, {max}]"),
            Value::Bool => "true or false".into(),
            Value::Colour => "#rrggbb".into(),
            Value::ColourOr(words) => format!("#rrggbb or {}", words.join(", ")),
            Value::Choice(names) => names.join(", "),
            Value::Shape => "ellipse, rectangle, brush or superquadric:P".into(),
            Value::Path => "a PNG tile's path or a built-in texture".into(),
        }
    }
}

/// Which looks read a key.
#[derive(Clone, Copy, Debug)]
pub enum Readers {
    /// Every look.
    All,
    /// The look kinds (names as `look.kind` takes them) for which this says yes.
    Only(fn(&str) -> bool),
}

impl Readers {
    /// Whether the look `kind` reads the key.
    #[must_use]
    pub fn include(&self, kind: &str) -> bool {
        match self {
            Readers::All => true,
            Readers::Only(reads) => reads(kind),
        }
    }

    /// The looks that read the key, in [`Look::NAMES`]' order.
    #[must_use]
    pub fn looks(&self) -> Vec<&'static str> {
        Look::NAMES
            .into_iter()
            .filter(|k| self.include(k))
            .collect()
    }
}

/// One key of a preset.
#[derive(Clone, Copy, Debug)]
pub struct Key {
    /// `section.name`, as `--set` takes it.
    pub path: &'static str,
    /// What it takes.
    pub value: Value,
    /// Which looks read it.
    pub readers: Readers,
    /// What it does, in one line.
    pub doc: &'static str,
}

impl Key {
    /// The section (`metric`, `sampler`, `cells`, `outlines`, `highlights` or `look`).
    #[must_use]
    pub fn section(&self) -> &'static str {
        self.path.split_once('.').map_or(self.path, |(s, _)| s)
    }

    /// The name within the section.
    #[must_use]
    pub fn name(&self) -> &'static str {
        self.path.split_once('.').map_or(self.path, |(_, n)| n)
    }
}

/// The textured looks: lines or dots in each cell's frame.
fn textures(kind: &str) -> bool {
    matches!(kind, "hatch" | "crosshatch" | "line" | "stroke" | "stipple")
}

/// The looks that paint cells (fabric, LIC and the engraving draw across them).
fn cell_looks(kind: &str) -> bool {
    kind == "mosaic" || textures(kind) || kind == "glyphs"
}

/// The looks of one ink over paper in the photo's tone.
fn one_ink(kind: &str) -> bool {
    matches!(kind, "hatch" | "crosshatch" | "engraving")
}

/// The looks of lines or dots in ink.
fn inked(kind: &str) -> bool {
    textures(kind) || kind == "engraving"
}

/// The looks that lay their lines, strokes or threads at an angle where the field has none.
fn with_flat_angle(kind: &str) -> bool {
    inked(kind) || matches!(kind, "glyphs" | "fabric" | "lic")
}

/// The looks with borders between cells.
fn bordered(kind: &str) -> bool {
    kind == "mosaic" || textures(kind)
}

fn mosaic(kind: &str) -> bool {
    kind == "mosaic"
}

fn glyphs(kind: &str) -> bool {
    kind == "glyphs"
}

fn mosaic_or_glyphs(kind: &str) -> bool {
    mosaic(kind) || glyphs(kind)
}

fn engraving(kind: &str) -> bool {
    kind == "engraving"
}

fn fabrics(kind: &str) -> bool {
    matches!(kind, "fabric" | "lic")
}

const fn number(min: f64, max: f64) -> Value {
    Value::Number { min, max }
}

const UNIT: Value = number(0.0, 1.0);
const WIDTH_PX: Value = number(0.0, 50.0);
const ANGLE: Value = number(-360.0, 360.0);

const fn key(path: &'static str, value: Value, readers: Readers, doc: &'static str) -> Key {
    Key {
        path,
        value,
        readers,
        doc,
    }
}

use Readers::{All, Only};

/// Keys of earlier presets and where they went: a preset that sets one is told what to write.
pub const MOVED: &[(&str, &str)] = &[
    ("look.cells", "cells.kind"),
    ("look.colour_weight", "cells.colour_weight"),
    ("look.cell_iterations", "cells.iterations"),
    ("look.cell_reach", "cells.reach"),
    ("look.cell_blur_px", "cells.blur_px"),
    ("look.supersample", "cells.supersample"),
    ("look.outlines", "outlines.strength"),
    ("look.outline_scale", "outlines.scale"),
    ("look.outline_ink", "outlines.ink"),
    ("look.highlights", "highlights.strength"),
];

/// Every key a preset may set, section by section.
#[rustfmt::skip]
pub const KEYS: &[Key] = &[
    key("metric.min_size", Value::Positive { max: 1.0 }, All, "smallest ellipse (the most detailed tenth of the photo), as a share of the diagonal"),
    key("metric.max_size", Value::Positive { max: 1.0 }, All, "largest ellipse (flat areas), as a share of the diagonal"),
    key("metric.max_anisotropy", number(1.0, 100.0), All, "longest an ellipse may be against its width, along coherent edges"),
    key("metric.gradation", Value::Positive { max: f64::INFINITY }, All, "how fast ellipse sizes may change, in pixels per pixel"),
    key("metric.smoothing", number(0.0, 1.0), All, "smoothing of the structure tensor, as a share of the diagonal (under 1)"),
    key("metric.detail_quantile", Value::Positive { max: 1.0 }, All, "the share of the photo whose detail gets the smallest ellipses"),
    key("sampler.iterations", Value::Integer { min: 0, max: 10_000 }, All, "relaxation iterations of the particle sampler (the paper never needed over 1 000)"),
    key("sampler.seed", Value::Integer { min: 0, max: u64::MAX }, All, "seed of every random choice (the same seed, the same picture)"),
    key("sampler.seeding", Value::Choice(&["auto", "lattice", "darts"]), All, "how samples are seeded: a metric-aligned lattice, the paper's dart throwing, or by size"),
    key("cells.kind", Value::Choice(&["edges", "voronoi"]), Only(cell_looks), "cells that stop at the photo's edges, or the paper's Voronoi cells"),
    key("cells.colour_weight", number(0.0, 1e6), Only(cell_looks), "weight of colour against distance in edge-following cells"),
    key("cells.iterations", Value::Integer { min: 0, max: 20 }, Only(cell_looks), "assign-and-move rounds of edge-following cells"),
    key("cells.reach", number(0.0, f64::INFINITY), Only(cell_looks), "how far past the paper's border an edge-following cell may reach, in ellipse radii"),
    key("cells.blur_px", number(0.0, 20.0), Only(cell_looks), "blur (photo pixels) of the colours edge-following cells compare"),
    key("cells.supersample", Value::Integer { min: 1, max: 4 }, All, "raster points per pixel along each axis where a border crosses it"),
    key("outlines.strength", UNIT, All, "ink of the outlines along the photo's edges (0: none)"),
    key("outlines.scale", number(0.25, 4.0), All, "width of the outlines against the default"),
    key("outlines.ink", Value::ColourOr(&["pixel"]), All, "the outlines' ink: a colour, or the photo's colour under each point"),
    key("highlights.strength", UNIT, Only(one_ink), "paper laid along the photo's thin light lines (0: none)"),
    key("look.kind", Value::Choice(&Look::NAMES), All, "which look paints the cells"),
    key("look.border_width", WIDTH_PX, Only(bordered), "width of the borders between cells, in pixels of a one-megapixel picture"),
    key("look.border_colour", Value::Colour, Only(mosaic_or_glyphs), "colour of the mosaic's leading, or of the glyphs' outlines"),
    key("look.relief", UNIT, Only(mosaic), "how strongly each tessera is lit as a dome, from the upper left"),
    key("look.jitter", UNIT, Only(mosaic), "random brightness change of each tessera"),
    key("look.lines_per_cell", number(0.1, 100.0), Only(textures), "lines (or dot rows) across a cell's short axis"),
    key("look.min_spacing_px", number(0.5, 200.0), Only(inked), "least distance between lines or dot rows, in output pixels"),
    key("look.ink", Value::ColourOr(&["black", "cell", "pixel"]), Only(inked), "the ink: black, a colour, the cell's colour or the photo's colour under each point"),
    key("look.ink_darken", UNIT, Only(textures), "how much cell or pixel ink is darkened"),
    key("look.paper", Value::Colour, Only(inked), "the paper's colour"),
    key("look.gamma", number(0.05, 20.0), Only(inked), "tone curve of the ink (1: the photo's tones as they are)"),
    key("look.fade_anisotropy", number(0.0, 100.0), Only(textures), "anisotropy under which a cell counts as having no direction"),
    key("look.texture", Value::Path, Only(textures), "a greyscale tile (dark = ink) spanning one cell"),
    key("look.placement", Value::Choice(&["relaxed", "grid", "random"]), Only(glyphs), "where glyphs go: at the samples, on a grid or at random"),
    key("look.shape", Value::Shape, Only(glyphs), "the glyph's outline"),
    key("look.underpaint", Value::Bool, Only(glyphs), "paint the cells in their colours under the glyphs"),
    key("look.ground", UNIT, Only(glyphs), "how much of its cell's colour the ground under a glyph takes"),
    key("look.refine", UNIT, Only(glyphs), "canvas-to-photo difference above which finer and detail strokes are laid"),
    key("look.glyph_scale", number(0.05, 4.0), Only(glyphs), "glyph size against its ellipse"),
    key("look.outline_width", WIDTH_PX, Only(glyphs), "width of each glyph's outline, in pixels"),
    key("look.background", Value::Colour, Only(glyphs), "colour behind the glyphs"),
    key("look.kernel_px", number(1.0, 100.0), Only(fabrics), "length of the line integral convolution, in pixels of a one-megapixel picture"),
    key("look.cross_weight", UNIT, Only(fabrics), "weight of the threads across the field's direction"),
    key("look.thickness", number(0.01, 2.0), Only(fabrics), "thread thickness against the ellipse's short axis"),
    key("look.contrast", UNIT, Only(fabrics), "how far the threads move the photo's luma"),
    key("look.line_spacing", number(0.0005, 0.2), Only(engraving), "distance between the engraving's lines, as a share of the diagonal"),
    key("look.edge_break", number(0.0, 10.0), Only(engraving), "lightness step over one spacing along a line that breaks it"),
    key("look.flat_angle", ANGLE, Only(with_flat_angle), "direction (degrees) of lines, strokes or threads where the field has none"),
    key("look.cell_tone", Value::Bool, Only(textures), "one tone per cell (the paper's) instead of the photo's tone point by point"),
    key("look.tone", UNIT, Only(engraving), "lightness of a tensor field engraved without a photo"),
];

/// The key at `path` (`section.name`).
#[must_use]
pub fn key_at(path: &str) -> Option<&'static Key> {
    KEYS.iter().find(|k| k.path == path)
}

/// The range of the numeric key at `path`, as `f64`; `None` for a key that is not numeric or
/// not in the schema.
#[must_use]
pub fn range(path: &str) -> Option<(f64, f64)> {
    match key_at(path)?.value {
        Value::Number { min, max } => Some((min, max)),
        Value::Positive { max } => Some((f64::MIN_POSITIVE, max)),
        // Integer bounds as f64: exact up to 2⁵³, and the seed's whole range is allowed.
        Value::Integer { min, max } => Some((min as f64, max as f64)),
        _ => None,
    }
}

/// The keys of `section` the look `kind` reads.
pub fn read_by<'a>(kind: &'a str, section: &'a str) -> impl Iterator<Item = &'static Key> + 'a {
    KEYS.iter()
        .filter(move |k| k.section() == section && k.readers.include(kind))
}

/// Of the keys of `section` the look `kind` reads, the one nearest `name` in spelling (the
/// fewest single-letter edits), if any is near enough to be a likely slip.
#[must_use]
pub fn nearest(kind: &str, section: &str, name: &str) -> Option<&'static Key> {
    read_by(kind, section)
        .map(|k| (edits(name, k.name()), k))
        .filter(|&(d, k)| d <= (k.name().len() / 3).max(1))
        .min_by_key(|&(d, _)| d)
        .map(|(_, k)| k)
}

/// Levenshtein distance between two names.
fn edits(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let substitution = diagonal + usize::from(ca != cb);
            diagonal = row[j + 1];
            row[j + 1] = substitution.min(row[j] + 1).min(row[j + 1] + 1);
        }
    }
    row[b.len()]
}

/// The keys as a Markdown reference, section by section: each key, what it takes, which
/// looks read it and what it does (`docs/keys.md` is this text; a test keeps it current).
#[must_use]
pub fn reference_markdown() -> String {
    let mut out = String::from(
        "# Preset keys\n\nEvery key a preset may set, from the schema the presets are checked \
         against (`anisopaint::style::schema::KEYS`). `anisopaint styles keys NAME` lists the \
         keys a preset's look reads with the values it paints with. A key its look does not \
         read is an error.\n",
    );
    let mut section = "";
    for k in KEYS {
        if k.section() != section {
            section = k.section();
            out.push_str(&format!(
                "\n## [{section}]\n\n| key | takes | read by | what it does |\n|---|---|---|---|\n"
            ));
        }
        let readers = match k.readers {
            Readers::All => "every look".to_string(),
            Readers::Only(_) => k.readers.looks().join(", "),
        };
        out.push_str(&format!(
            "| `{}` | {} | {readers} | {} |\n",
            k.name(),
            k.value.describe(),
            k.doc
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `docs/keys.md` is [`reference_markdown`]'s text (`REGENERATE=1` rewrites it).
    #[test]
    fn the_key_reference_in_the_docs_is_current() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/keys.md");
        let text = reference_markdown();
        if std::env::var_os("REGENERATE").is_some() {
            std::fs::write(&path, &text).unwrap();
        }
        let written = std::fs::read_to_string(&path).unwrap_or_default();
        assert!(
            written == text,
            "docs/keys.md is not the schema's reference: REGENERATE=1 cargo test --lib \
             the_key_reference rewrites it"
        );
    }

    #[test]
    fn every_key_is_listed_once_and_read_by_some_look() {
        for (i, k) in KEYS.iter().enumerate() {
            assert!(
                KEYS[..i].iter().all(|o| o.path != k.path),
                "{} twice",
                k.path
            );
            assert!(
                Look::NAMES.iter().any(|kind| k.readers.include(kind)),
                "{} is read by no look",
                k.path
            );
        }
    }

    #[test]
    fn near_slips_find_their_key_and_far_names_none() {
        assert_eq!(edits("kitten", "sitting"), 3);
        assert_eq!(edits("", "abc"), 3);
        let found = |kind, name| nearest(kind, "look", name).map(|k| k.path);
        assert_eq!(found("mosaic", "releif"), Some("look.relief"));
        assert_eq!(found("hatch", "line_per_cell"), Some("look.lines_per_cell"));
        // A key of another look is not offered.
        assert_eq!(found("mosaic", "lines_per_cell"), None);
        assert_eq!(found("mosaic", "zzzzzzzz"), None);
    }
}
