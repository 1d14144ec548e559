//! Contact sheets for style experiments: one input painted in several presets, or in one
//! preset with one key swept over a few values (`--vary look.border_width=0,1.5,3`), laid out
//! as a labelled grid by [`render::sheet`](crate::render::sheet).
//!
//! A photo is decoded once and, when it is wider than twice the tile, reduced to twice the
//! tile width before painting; the painting is then reduced to the tile. Preset lengths are
//! fractions of the image diagonal, so a tile shows the same cells as a thumbnail of the
//! full-size painting, in a fraction of the time.

use super::{apply_sets, load, Preset};
use crate::error::{Error, Result};
use crate::field::{FieldOptions, Input};
use crate::render::sheet::{contact_sheet, SheetLayout, Tile};
use image::imageops::FilterType;
use image::{DynamicImage, RgbImage};

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
    Ok(())
}

/// How a sheet is laid out and painted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SheetOptions {
    /// Width of each tile in pixels.
    pub tile_width: u32,
    /// Tiles per row (0: about square).
    pub columns: usize,
    /// Seed for every tile, over the presets' own.
    pub seed: Option<u64>,
}

/// Paints `input` in every variant and lays the tiles out; `on_tile` is called after each
/// tile with its index.
pub fn paint_sheet(
    input: &Input,
    options: &FieldOptions,
    variants: &[Variant],
    sheet: SheetOptions,
    on_tile: &dyn Fn(usize),
) -> Result<RgbImage> {
    if !(16..=4096).contains(&sheet.tile_width) {
        return Err(Error::param(
            "--tile-width",
            "must be between 16 and 4096 pixels",
        ));
    }
    let photo = match input {
        Input::Photo(path) => Some(reduced(crate::io::read_photo(path)?, 2 * sheet.tile_width)),
        _ => None,
    };
    let mut tiles = Vec::with_capacity(variants.len());
    for (k, v) in variants.iter().enumerate() {
        let metric = v.preset.metric()?;
        let loaded = match &photo {
            Some(p) => crate::field::photo_field(p.clone(), &metric),
            None => crate::field::load_field(
                input,
                &FieldOptions {
                    metric,
                    ..options.clone()
                },
            )?,
        };
        let mut sampler = v.preset.sampler();
        if let Some(seed) = sheet.seed {
            sampler.seed = seed;
        }
        let painting = super::paint_loaded(
            &loaded,
            &v.preset.look()?,
            v.preset.supersample(),
            &sampler,
            false,
            &crate::progress::Silent,
        )?;
        let image = painting.image;
        let tile_height = (f64::from(sheet.tile_width) * f64::from(image.height())
            / f64::from(image.width()))
        .round()
        .max(1.0) as u32;
        let image =
            image::imageops::resize(&image, sheet.tile_width, tile_height, FilterType::Triangle);
        tiles.push(Tile {
            label: v.label.clone(),
            image,
        });
        on_tile(k);
    }
    let layout = SheetLayout::new(tiles.len(), sheet.tile_width, sheet.columns);
    Ok(contact_sheet(&tiles, layout))
}

/// `photo` reduced to at most `width` pixels wide (never enlarged).
fn reduced(photo: DynamicImage, width: u32) -> DynamicImage {
    if photo.width() <= width {
        return photo;
    }
    let height = (f64::from(width) * f64::from(photo.height()) / f64::from(photo.width()))
        .round()
        .max(1.0) as u32;
    photo.resize_exact(width, height, FilterType::Triangle)
}
