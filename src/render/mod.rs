//! Pictures from samples (paper sections 6 and 7). The samples' generalized Voronoi cells, or cells
//! that stop at the photo's edges, rasterised onto the output ([`cells`]); lines read from the
//! photo and the field that several looks share ([`lines`]); what every look reads ([`scene`]); the
//! looks, one folder each, and the [`Look`] that picks one ([`looks`]); their vector form
//! ([`vector`]); outlines and highlights laid over them (`overlay`); contact sheets ([`sheet`]) and
//! previews of fields and samplings ([`preview`]); colour, hashes and rounding below them all
//! ([`support`]). Everything runs on the CPU with rayon, at any output size: the cells are
//! resolution independent. Imports go one way, `support` → `cells` → `lines` → `scene` → `vector` →
//! `looks` (`ARCHITECTURE.md`, checked by `tests/architecture.rs`).

pub mod cells;
pub mod lines;
pub mod looks;
mod overlay;
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

use crate::field::TensorField;
use image::{DynamicImage, RgbImage};
use lines::outline::OutlineParams;
use overlay::Overlays;

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

/// Draws `look` over `cells` (the paper's, or edge-following ones from
/// [`cells::CellSites`]) of the metric `field`, then the outlines and highlights `outline`
/// asks for over a photo (given with its structure tensor), and the SVG form of the same
/// picture when `svg` is set. The paint pipeline (`paint::draw`) is its one caller.
pub fn draw(
    look: &Look,
    cells: VoronoiCells,
    field: &TensorField,
    photo: Option<(&DynamicImage, &TensorField)>,
    outline: &OutlineParams,
    size: RenderSize,
    svg: bool,
) -> crate::Result<(RgbImage, Option<String>)> {
    if svg {
        look.check_vector_form()?;
    }
    let overlays = photo.map(|photo| Overlays::new(look, photo, field.domain(), outline));
    let share = overlays.as_ref().and_then(|o| o.share(look));
    let mut scene = Scene::new(
        cells,
        field,
        photo.map(|(p, _)| p),
        size.width,
        size.height,
        size.supersample,
    );
    scene.outline_share = share.as_ref();
    let (mut image, laid) = match look {
        // The glyphs the picture lays are the SVG's: found once.
        Look::Glyphs(p) if svg => {
            let (image, laid) = looks::glyphs::painted(&scene, p);
            (image, Some(laid))
        }
        _ => (look.render(&scene), None),
    };
    if let Some(overlays) = &overlays {
        overlays.draw(&mut image);
    }
    let svg = svg.then(|| {
        vector::document(&scene.raster, |out| {
            look.write_svg(out, &scene, laid);
            if let Some(overlays) = &overlays {
                overlays.write_svg(out, size);
            }
        })
    });
    Ok((image, svg))
}
