//! Saving a painting with how it was made: a PNG carries the preset, the `--set` keys, the
//! seed, the version and the whole command as text chunks (`anisopaint info` prints them), so
//! the same painting can be made again; other formats are written plainly. Every write is
//! atomic ([`crate::io::write_atomic`]).

use crate::error::Result;
use std::path::Path;

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
        return crate::io::save_rgb(out, img);
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
