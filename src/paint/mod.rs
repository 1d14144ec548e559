//! The paint pipeline: the one chain every command and every library user goes through.
//!
//! input → [`field`](crate::field) (structure tensor → metric, paper sections 3-4) →
//! [`sampling`](crate::sampling) (seeding, force spline, anisotropic Delaunay, population
//! control, section 5) → [`render`](crate::render) (generalized Voronoi cells, section 6, and a
//! look, section 7). A [`Recipe`] is what a preset decides for that chain; [`paint`] runs it on
//! an input, [`paint_loaded`] on a field already loaded, and [`draw`] draws a look from samples
//! already made (the `render` command reuses samples written by `sample`). [`record`] writes
//! paintings with how they were made; [`sheet`] paints contact sheets.

pub mod record;
pub mod sheet;

pub use record::{save_painting, PaintRecord};
pub use sheet::{paint_sheet, SheetOptions};

use crate::error::Result;
use crate::field::{Tensor, TensorField};
use crate::input::{FieldOptions, Input, LoadedField};
use crate::progress::{timed, Observer, Silent, Stage};
use crate::render::cells::{CellKind, CellParams, CellSites};
use crate::render::lines::outline::OutlineParams;
use crate::render::{label_map, Look, Raster, RenderSize};
use crate::sampling::{AnisotropicDelaunay, SamplerParams};
use crate::style::Preset;
use glam::DVec2;
use image::RgbImage;

/// Everything that decides a painting besides its input: how the input becomes a metric, how
/// the metric is sampled, and the look drawn from the samples.
#[derive(Clone, Debug, PartialEq)]
pub struct Recipe {
    /// Input → metric.
    pub field: FieldOptions,
    /// The sampler.
    pub sampler: SamplerParams,
    /// The look and its parameters.
    pub look: Look,
    /// Raster points per pixel along each axis where a cell border crosses the pixel.
    pub supersample: usize,
    /// Which cells the look paints.
    pub cells: CellParams,
    /// The outlines laid over the look (a photo's only).
    pub outline: OutlineParams,
}

impl Recipe {
    /// A recipe of defaults that draws `look`: the default metric and sampler, 2×2
    /// supersampling where borders cross a pixel, edge-following cells and no outlines.
    #[must_use]
    pub fn new(look: Look) -> Recipe {
        Recipe {
            field: FieldOptions::default(),
            sampler: SamplerParams::default(),
            look,
            supersample: 2,
            cells: CellParams::default(),
            outline: OutlineParams::default(),
        }
    }

    /// The recipe of `preset`: its metric, sampler and look over `field`'s other options
    /// (how `.npy` files are read, the analytic domain), with `seed` over the preset's.
    pub fn from_preset(preset: &Preset, field: FieldOptions, seed: Option<u64>) -> Result<Recipe> {
        let mut sampler = preset.sampler()?;
        if let Some(seed) = seed {
            sampler.seed = seed;
        }
        let mut look = preset.look()?;
        if let (Look::Glyphs(glyphs), Some(seed)) = (&mut look, seed) {
            glyphs.seed = seed; // random placement follows the seed too
        }
        Ok(Recipe {
            field: FieldOptions {
                metric: preset.metric()?,
                ..field
            },
            sampler,
            look,
            supersample: preset.supersample()?,
            cells: preset.cells()?,
            outline: preset.outline()?,
        })
    }
}

/// The samples a look is drawn from.
#[derive(Clone, Debug)]
pub struct Samples {
    /// Sample positions in pixels of the input.
    pub positions: Vec<DVec2>,
    /// The metric at each sample.
    pub metrics: Vec<Tensor>,
    /// Their anisotropic Delaunay triangulation.
    pub mesh: AnisotropicDelaunay,
}

/// What [`draw`] makes besides the raster picture.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Extras {
    /// The SVG form of the picture.
    pub svg: bool,
    /// The label map of the cells as drawn.
    pub labels: bool,
}

/// A painting, and what else was asked for.
#[derive(Clone, Debug)]
pub struct Painting {
    /// The raster picture.
    pub image: RgbImage,
    /// The SVG document of the same picture.
    pub svg: Option<String>,
    /// For every output pixel (row-major), the index of the sample whose cell holds it, or -1.
    pub labels: Option<Vec<i32>>,
}

/// Paints `input` with `recipe`: the whole chain, silently.
pub fn paint(input: &Input, recipe: &Recipe) -> Result<RgbImage> {
    Ok(paint_observed(input, recipe, Extras::default(), &Silent)?.image)
}

/// [`paint`] with `extras`, reporting every stage to `observer`. A look without a vector form
/// fails before any work when the SVG is asked for.
pub fn paint_observed(
    input: &Input,
    recipe: &Recipe,
    extras: Extras,
    observer: &dyn Observer,
) -> Result<Painting> {
    if extras.svg {
        recipe.look.check_vector_form()?;
    }
    let loaded = crate::input::load_field_observed(input, &recipe.field, observer)?;
    paint_loaded(&loaded, recipe, extras, observer)
}

/// Sampling and look of a field already loaded (`recipe.field` is not read again), at the
/// field's size.
pub fn paint_loaded(
    loaded: &LoadedField,
    recipe: &Recipe,
    extras: Extras,
    observer: &dyn Observer,
) -> Result<Painting> {
    // What the cells read of the photo (its blur) does not depend on the samples: it is made
    // while the sampler runs, on the cores the sampler's sequential steps leave idle.
    let (samples, photo_read) = rayon::join(
        || sample(&loaded.metric, &recipe.sampler, observer),
        || CellSites::photo_read(loaded.photo.as_ref(), &cell_params(recipe)),
    );
    let size = field_size(&loaded.metric, recipe.supersample);
    draw_reading(loaded, &samples?, recipe, size, extras, observer, || {
        photo_read
    })
}

/// The samples of `field`.
pub fn sample(
    field: &TensorField,
    params: &SamplerParams,
    observer: &dyn Observer,
) -> Result<Samples> {
    let s = crate::sampling::sample_observed(field, params, observer)?;
    Ok(Samples {
        positions: s.positions,
        metrics: s.metrics,
        mesh: s.mesh,
    })
}

/// The output size of a painting at the field's own size.
#[must_use]
pub fn field_size(field: &TensorField, supersample: usize) -> RenderSize {
    let d = field.domain();
    RenderSize {
        width: d.x.round().max(1.0) as usize,
        height: d.y.round().max(1.0) as usize,
        supersample,
    }
}

/// Draws `recipe`'s look from `samples` of `loaded` at `size`, over the cells the recipe
/// asks for, with `extras` (the label map is that of the same cells).
pub fn draw(
    loaded: &LoadedField,
    samples: &Samples,
    recipe: &Recipe,
    size: RenderSize,
    extras: Extras,
    observer: &dyn Observer,
) -> Result<Painting> {
    draw_reading(loaded, samples, recipe, size, extras, observer, || {
        CellSites::photo_read(loaded.photo.as_ref(), &cell_params(recipe))
    })
}

/// [`draw`], `photo_read` giving what the cells read of the photo
/// ([`CellSites::photo_read`] of [`cell_params`]), perhaps made already.
fn draw_reading(
    loaded: &LoadedField,
    samples: &Samples,
    recipe: &Recipe,
    size: RenderSize,
    extras: Extras,
    observer: &dyn Observer,
    photo_read: impl FnOnce() -> Option<RgbImage>,
) -> Result<Painting> {
    timed(observer, Stage::Rendering, || {
        let sites = cell_sites(loaded, samples, recipe, photo_read());
        let labels = extras.labels.then(|| {
            let raster = Raster {
                width: size.width,
                height: size.height,
                supersample: 1,
                domain: loaded.metric.domain(),
            };
            label_map(&sites.cells(), &raster)
        });
        let (image, svg) = crate::render::draw(
            &recipe.look,
            sites.cells(),
            &loaded.metric,
            loaded.photo.as_ref().map(|p| (p, loaded.raw.as_ref())),
            &recipe.outline,
            size,
            extras.svg,
        )?;
        Ok(Painting { image, svg, labels })
    })
}

/// The cells `recipe` asks for. Fabric and LIC lay their threads from the samples as the
/// sampler packed them, and the engraving's lines cross cells (it seeds from the samples), so
/// they always take the paper's cells.
fn cell_params(recipe: &Recipe) -> CellParams {
    let mut params = recipe.cells.clone();
    if matches!(recipe.look, Look::Fabric(_) | Look::Engraving(_)) {
        params.kind = CellKind::Voronoi;
    }
    params
}

/// The cells of `samples` that [`cell_params`] asks for, `photo_read` what they read of the
/// photo ([`CellSites::photo_read`]).
fn cell_sites(
    loaded: &LoadedField,
    samples: &Samples,
    recipe: &Recipe,
    photo_read: Option<RgbImage>,
) -> CellSites {
    CellSites::with_photo_read(
        samples.positions.clone(),
        samples.metrics.clone(),
        samples.mesh.clone(),
        &loaded.metric,
        photo_read,
        &cell_params(recipe),
    )
}
