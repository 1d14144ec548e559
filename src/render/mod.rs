//! Pictures from samples (paper sections 6 and 7). The samples' generalized Voronoi cells, or
//! cells that stop at the photo's edges, rasterised onto the output ([`cells`]); lines read
//! from the photo and the field that several looks share ([`lines`]); what every look reads
//! ([`scene`]); the looks, one folder each, and the [`Look`] that picks one ([`looks`]); their
//! vector form ([`vector`]); contact sheets ([`sheet`]) and previews of fields and samplings
//! ([`preview`]); colour, hashes and rounding below them all ([`support`]). Everything runs on
//! the CPU with rayon, at any output size: the cells are resolution independent. Imports go
//! one way, `support` → `cells` → `lines` → `scene` → `vector` → `looks` (`ARCHITECTURE.md`,
//! checked by `tests/architecture.rs`).

pub mod cells;
pub mod lines;
pub mod looks;
pub mod preview;
pub mod scene;
pub mod sheet;
pub mod support;
pub mod vector;

pub use cells::raster::{label_map, owner_map, Raster};
pub use cells::voronoi::{Owner, VoronoiCells};
pub use looks::Look;
pub use preview::{ellipses_preview, field_preview, PreviewMode};
pub use scene::Scene;

use crate::field::{Tensor, TensorField};
use crate::sampling::AnisotropicDelaunay;
use glam::DVec2;
use image::{DynamicImage, RgbImage};
use lines::outline_share::OutlineShare;

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

/// [`render`], and the SVG form of the same picture when `svg` is set (see [`Look::svg`]).
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
        let (image, laid) = looks::glyphs::painted(&scene, p);
        return Ok((image, Some(look.svg_of_laid(&scene, Some(laid))?)));
    }
    let image = look.render(&scene);
    let svg = if svg { Some(look.svg(&scene)?) } else { None };
    Ok((image, svg))
}
