//! The variants of a contact sheet: one input in several presets, or in one preset with one
//! key swept over a few values (`--vary look.border_width=0,1.5,3`), each checked before
//! anything is painted. [`paint::sheet`](crate::paint::sheet) paints them.

use super::{apply_sets, load, Preset};
use crate::error::{Error, Result};

/// One tile of a sheet: its label and the preset (with overrides) that paints it.
#[derive(Clone, Debug)]
pub struct Variant {
    /// Shown under the tile.
    pub label: String,
    /// The preset, overrides applied.
    pub preset: Preset,
}

/// The variants of a sheet: every style in `styles` with `sets`, or, with `vary` (`KEY=V1,V2,
/// ...`), the one style in `styles` once per value. Every preset and override is checked
/// here, before anything is painted.
pub fn variants(styles: &[String], vary: Option<&str>, sets: &[String]) -> Result<Vec<Variant>> {
    if styles.is_empty() {
        return Err(Error::param("--style", "give at least one style"));
    }
    let Some(vary) = vary else {
        return styles
            .iter()
            .map(|style| {
                let mut preset = load(style)?;
                apply_sets(&mut preset, sets)?;
                check(&preset)?;
                Ok(Variant {
                    label: preset.name.clone(),
                    preset,
                })
            })
            .collect();
    };
    let [style] = styles else {
        return Err(Error::param(
            "--vary",
            "sweeps one key of one style: give a single -s STYLE",
        ));
    };
    let Some((key, values)) = vary.split_once('=') else {
        return Err(Error::param(
            "--vary",
            format!("{vary}: expected key.path=v1,v2,..."),
        ));
    };
    let values: Vec<&str> = values.split(',').map(str::trim).collect();
    if values.iter().any(|v| v.is_empty()) {
        return Err(Error::param(
            "--vary",
            format!("{vary}: empty value in the list"),
        ));
    }
    let base = load(style)?;
    values
        .iter()
        .map(|value| {
            let mut preset = base.clone();
            let set = format!("{}={value}", key.trim());
            apply_sets(&mut preset, sets)?;
            apply_sets(&mut preset, std::slice::from_ref(&set))?;
            check(&preset)?;
            Ok(Variant { label: set, preset })
        })
        .collect()
}

/// Fails now for what would fail at painting time.
fn check(preset: &Preset) -> Result<()> {
    preset.metric()?;
    preset.look()?;
    preset.cells()?;
    Ok(())
}
