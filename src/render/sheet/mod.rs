//! Contact sheets: pictures of equal size laid out in a grid, each labelled underneath with
//! the [`font`], on a light background. Used to compare presets, or one preset
//! with one parameter swept, on the same photo.

pub mod font;

use font::{draw_text, text_width, GLYPH_HEIGHT};
use image::{Rgb, RgbImage};

/// Background of the sheet, sRGB.
pub const SHEET_BACKGROUND: [u8; 3] = [244, 242, 238];
/// Colour of the labels, sRGB.
pub const LABEL_COLOUR: [u8; 3] = [40, 38, 36];

/// One picture and its label.
#[derive(Clone, Debug)]
pub struct Tile {
    /// Shown under the picture.
    pub label: String,
    /// The picture; every tile of a sheet has the same size.
    pub image: RgbImage,
}

/// The layout of a sheet, in pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SheetLayout {
    /// Tiles per row.
    pub columns: u32,
    /// Rows of tiles.
    pub rows: u32,
    /// Space around and between tiles.
    pub margin: u32,
    /// Font pixels per label pixel.
    pub font_scale: u32,
    /// Height of the label band under each tile.
    pub label_height: u32,
}

impl SheetLayout {
    /// A layout for `count` tiles of `tile_width` pixels in `columns` columns (0: one row
    /// for up to 4 tiles, else about square).
    #[must_use]
    pub fn new(count: usize, tile_width: u32, columns: usize) -> Self {
        let count = count.max(1) as u32;
        let columns = if columns == 0 && count <= 4 {
            count
        } else if columns == 0 {
            (f64::from(count).sqrt().ceil() as u32).clamp(1, 4)
        } else {
            (columns as u32).clamp(1, count)
        };
        let font_scale = (tile_width / 160).clamp(1, 4);
        let margin = 8 * font_scale;
        SheetLayout {
            columns,
            rows: count.div_ceil(columns),
            margin,
            font_scale,
            label_height: GLYPH_HEIGHT * font_scale + margin,
        }
    }
}

/// Lays `tiles` out as `layout` says. Tiles must all have the size of the first.
#[must_use]
pub fn contact_sheet(tiles: &[Tile], layout: SheetLayout) -> RgbImage {
    let (tw, th) = tiles.first().map_or((1, 1), |t| t.image.dimensions());
    let cell_w = tw + layout.margin;
    let cell_h = th + layout.label_height + layout.margin;
    let width = layout.columns * cell_w + layout.margin;
    let height = layout.rows * cell_h + layout.margin;
    let mut sheet = RgbImage::from_pixel(width, height, Rgb(SHEET_BACKGROUND));
    for (k, tile) in tiles.iter().enumerate() {
        let (col, row) = (k as u32 % layout.columns, k as u32 / layout.columns);
        let (x, y) = (layout.margin + col * cell_w, layout.margin + row * cell_h);
        image::imageops::replace(&mut sheet, &tile.image, i64::from(x), i64::from(y));
        let label = fit(&tile.label, tw, layout.font_scale);
        let lw = text_width(&label, layout.font_scale);
        let lx = i64::from(x) + i64::from(tw.saturating_sub(lw) / 2);
        let ly = i64::from(y + th + layout.margin / 2);
        draw_text(&mut sheet, lx, ly, &label, layout.font_scale, LABEL_COLOUR);
    }
    sheet
}

/// `label`, shortened with `..` in the middle to fit `width` pixels.
fn fit(label: &str, width: u32, scale: u32) -> String {
    if text_width(label, scale) <= width {
        return label.to_string();
    }
    let chars: Vec<char> = label.chars().collect();
    for keep in (2..chars.len()).rev() {
        let head: String = chars[..keep / 2].iter().collect();
        let tail: String = chars[chars.len() - (keep - keep / 2)..].iter().collect();
        let s = format!("{head}..{tail}");
        if text_width(&s, scale) <= width {
            return s;
        }
    }
    String::new()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_land_in_their_cells_with_labels_under_them() {
        let colours = [[200, 0, 0], [0, 200, 0], [0, 0, 200]];
        let tiles: Vec<Tile> = colours
            .iter()
            .map(|&c| Tile {
                label: "x".repeat(3),
                image: RgbImage::from_pixel(60, 40, Rgb(c)),
            })
            .collect();
        assert_eq!(SheetLayout::new(3, 60, 0).columns, 3);
        assert_eq!(SheetLayout::new(8, 60, 0).columns, 3);
        let layout = SheetLayout::new(3, 60, 2);
        assert_eq!((layout.columns, layout.rows), (2, 2));
        let sheet = contact_sheet(&tiles, layout);
        let m = layout.margin;
        let cell_h = 40 + layout.label_height + m;
        for (k, c) in colours.iter().enumerate() {
            let (col, row) = (k as u32 % 2, k as u32 / 2);
            let (x, y) = (m + col * (60 + m), m + row * cell_h);
            assert_eq!(sheet.get_pixel(x + 30, y + 20).0, *c);
            // Some label ink in the band under the tile.
            let inked = (y + 40..y + 40 + layout.label_height)
                .flat_map(|yy| (x..x + 60).map(move |xx| (xx, yy)))
                .any(|(xx, yy)| sheet.get_pixel(xx, yy).0 == LABEL_COLOUR);
            assert!(inked, "tile {k} has a label");
        }
    }

    #[test]
    fn long_labels_are_shortened_to_fit() {
        let s = fit("look.lines_per_cell=12", 60, 1);
        assert!(s.contains(".."), "{s}");
        assert!(text_width(&s, 1) <= 60);
        assert_eq!(fit("ok", 60, 1), "ok");
    }
}
