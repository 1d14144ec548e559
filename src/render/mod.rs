//! Pictures: the generalized Voronoi cells of the samples ([`voronoi`], paper section 6), or
//! cells that stop at the photo's edges ([`cells`]), rasterised onto the output ([`raster`]),
//! and the looks drawn from them: a [`Scene`] holds
//! what every look reads ([`scene`]); [`Look`] picks one ([`look`]): mosaics ([`mosaic`]),
//! textured cells ([`texture`]), glyphs ([`glyphs`], paper 7.1), fabric and LIC ([`fabric`],
//! paper 7.3), in linear-light colour ([`colour`]); vector output ([`svg`]) of cells traced
//! from the label map ([`trace`]) and of glyphs; contact sheets ([`sheet`]) with a small
//! bitmap [`font`]; previews of fields and samplings ([`preview`]). Everything runs on the CPU
//! with rayon, at any output size: the cells are resolution independent. Imports go one way:
//! `look` → the looks → `scene` → `raster` → `voronoi`, and `cells` → `raster`, `voronoi`.

mod blurred_photo;
pub mod border_distance;
pub mod buffer;
pub mod cellmap;
pub mod cells;
mod chroma_edges;
pub mod colour;
pub mod colour_term;
mod disjoint;
mod dot_order;
mod edge_dog;
mod edge_stop;
pub mod engrave;
mod engrave_tone;
pub mod fabric;
mod flat_strokes;
pub mod font;
mod frames;
pub mod glyphs;
mod hatch_lines;
pub mod highlights;
mod lic_field;
mod lic_grid;
pub mod line_field;
mod local_tone;
pub mod look;
pub mod mosaic;
pub mod node_grid;
pub mod outline;
pub mod outline_ink;
pub mod outline_rigger;
pub mod outline_share;
mod photo_stats;
pub mod pieces;
pub mod preview;
mod quiet_cells;
pub mod raster;
mod refine;
pub mod rounding;
pub mod scene;
pub mod sheet;
pub mod stipple;
pub mod streamlines;
mod stripes;
pub mod sums;
pub mod svg;
mod svg_engraved;
pub mod svg_outlines;
mod svg_path;
pub mod texture;
pub mod trace;
pub mod voronoi;

pub use look::Look;
pub use preview::{ellipses_preview, field_preview, PreviewMode};
pub use raster::{label_map, owner_map, Raster};
pub use scene::Scene;
pub use voronoi::{Owner, VoronoiCells};

use crate::field::{Tensor, TensorField};
use crate::sampling::AnisotropicDelaunay;
use glam::DVec2;
use image::{DynamicImage, RgbImage};
use outline_share::OutlineShare;

/// Output size and anti-aliasing of a render.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RenderSize {
    /// Output width in pixels.
    pub width: usize,
    /// Output height in pixels.
    pub height: usize,
    /// Raster points per pixel along each axis (2 means 2x2).
    pub supersample: usize,
}

/// Renders `look` from samples (`positions`, `metrics`, their anisotropic Delaunay `mesh`)
/// of `field`, coloured from `photo` when there is one.
#[must_use]
pub fn render(
    look: &Look,
    positions: &[DVec2],
    metrics: &[Tensor],
    mesh: &AnisotropicDelaunay,
    field: &TensorField,
    photo: Option<&DynamicImage>,
    size: RenderSize,
) -> RgbImage {
    let cells = VoronoiCells::new(positions, metrics, mesh);
    look.render(&scene(cells, field, photo, size))
}

fn scene<'a>(
    cells: VoronoiCells<'a>,
    field: &'a TensorField,
    photo: Option<&'a DynamicImage>,
    size: RenderSize,
) -> Scene<'a> {
    Scene::new(
        cells,
        field,
        photo,
        size.width,
        size.height,
        size.supersample,
    )
}

/// [`render`], and the SVG form of the same picture when `svg` is set (see [`svg::svg`]).
/// Fails before any work for a look without a vector form.
#[allow(clippy::too_many_arguments)] // `render`'s arguments and the one switch
pub fn render_with_svg(
    look: &Look,
    positions: &[DVec2],
    metrics: &[Tensor],
    mesh: &AnisotropicDelaunay,
    field: &TensorField,
    photo: Option<&DynamicImage>,
    size: RenderSize,
    svg: bool,
) -> crate::Result<(RgbImage, Option<String>)> {
    draw(
        look,
        VoronoiCells::new(positions, metrics, mesh),
        field,
        (photo, None),
        size,
        svg,
    )
}

/// Draws `look` over `cells` (the paper's, or edge-following ones from
/// [`cells::CellSites`]), and its SVG form when `svg` is set.
pub fn draw(
    look: &Look,
    cells: VoronoiCells,
    field: &TensorField,
    (photo, outline_share): (Option<&DynamicImage>, Option<&OutlineShare>),
    size: RenderSize,
    svg: bool,
) -> crate::Result<(RgbImage, Option<String>)> {
    if svg {
        look.check_vector_form()?;
    }
    let mut scene = scene(cells, field, photo, size);
    scene.outline_share = outline_share;
    if let (Look::Glyphs(p), true) = (look, svg) {
        // The glyphs the picture lays are the SVG's: painted once.
        let (image, laid) = glyphs::painted(&scene, p);
        return Ok((image, Some(svg::svg_of_laid(look, &scene, Some(laid))?)));
    }
    let image = look.render(&scene);
    let svg = if svg {
        Some(svg::svg(look, &scene)?)
    } else {
        None
    };
    Ok((image, svg))
}
