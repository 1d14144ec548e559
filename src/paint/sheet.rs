//! Contact sheets for style experiments: one input painted in every variant of
//! [`style::sheet`](crate::style::sheet), laid out as a labelled grid by
//! [`render::sheet`](crate::render::sheet).
//!
//! A photo is decoded once and, when it is wider than twice the tile, reduced to twice the
//! tile width before painting; the painting is then reduced to the tile. Preset lengths are
//! fractions of the image diagonal, so a tile shows the same cells as a thumbnail of the
//! full-size painting, in a fraction of the time.

use super::{paint_loaded, Extras, Recipe};
use crate::error::{Error, Result};
use crate::input::{FieldOptions, Input};
use crate::render::sheet::{contact_sheet, SheetLayout, Tile};
use crate::style::sheet::Variant;
use image::imageops::FilterType;
use image::{DynamicImage, RgbImage};

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
        let recipe = Recipe::from_preset(&v.preset, options.clone(), sheet.seed)?;
        let loaded = match &photo {
            Some(p) => crate::input::photo_field(p.clone(), &recipe.field.metric),
            None => crate::input::load_field(input, &recipe.field)?,
        };
        let painting = paint_loaded(
            &loaded,
            &recipe,
            Extras::default(),
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
