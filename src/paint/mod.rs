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
use crate::render::lines::highlights::highlights_of;
use crate::render::lines::outline::{
    draw_highlights, draw_outlines, lines_of, outline_mask, picture_values, EdgeResponses,
    OutlineParams,
};
use crate::render::lines::outline_ink::{self, OutlineInk, PhotoInk};
use crate::render::lines::outline_share::OutlineShare;
use crate::render::vector::outlines as svg_outlines;
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
        // The outlines' line map and the highlights' map, found once from the same responses:
        // the ink looks leave the share the outlines will ink (and the highlights leave bare)
        // out of their own tone, then both are laid over the look.
        let paper = highlight_params(recipe);
        let responses = match &loaded.photo {
            Some(photo) if recipe.outline.strength > 0.0 || paper.is_some() => {
                Some(EdgeResponses::new(photo, &loaded.raw, &recipe.outline))
            }
            _ => None,
        };
        let lines = match &responses {
            Some(r) if recipe.outline.strength > 0.0 => lines_of(r, recipe.outline.ink),
            _ => Vec::new(),
        };
        let highlights = paper.zip(responses.as_ref().map(highlights_of));
        // (Outlines in the photo's own colour darken little: the look keeps its tone.)
        let dark = !lines.is_empty()
            && recipe.look.inks_its_tone()
            && recipe.outline.ink != OutlineInk::Pixel;
        // The highlights' paper too, with or without outlines.
        let share = (dark || highlights.is_some()).then(|| {
            let ink = if dark { lines.as_slice() } else { &[] };
            let share = OutlineShare::new(ink, &loaded.raw, recipe.outline.strength);
            match &highlights {
                Some((paper, map)) => share.with_highlights(map, paper.strength),
                None => share,
            }
        });
        let (mut image, mut svg) = crate::render::draw(
            &recipe.look,
            sites.cells(),
            &loaded.metric,
            (loaded.photo.as_ref(), share.as_ref()),
            size,
            extras.svg,
        )?;
        if let Some(photo) = &loaded.photo {
            draw_outlines(
                &mut image,
                photo,
                (&loaded.raw, &lines),
                loaded.metric.domain(),
                &recipe.outline,
            );
            if let Some(svg) = &mut svg {
                add_svg_outlines(svg, (loaded, &lines), photo, size, &recipe.outline);
            }
            if let Some((paper, map)) = &highlights {
                draw_highlights(
                    &mut image,
                    photo,
                    (&loaded.raw, map),
                    loaded.metric.domain(),
                    paper,
                );
                if let Some(svg) = &mut svg {
                    add_svg_highlights(svg, (loaded, map), size, paper);
                }
            }
        }
        Ok(Painting { image, svg, labels })
    })
}

/// How `recipe` lays highlights: the outline parameters that draw them (the look's paper as
/// ink, at the highlights' strength); `None` for a look without one paper, or none asked for.
fn highlight_params(recipe: &Recipe) -> Option<OutlineParams> {
    let paper = recipe.look.paper()?;
    (recipe.outline.highlights > 0.0).then_some(OutlineParams {
        strength: recipe.outline.highlights,
        ink: OutlineInk::Colour(paper),
        ..recipe.outline
    })
}

/// Adds the outlines' vector form over the look in `svg` (before its closing tag): `lines`,
/// their line map on `loaded`'s tensor grid.
fn add_svg_outlines(
    svg: &mut String,
    (loaded, lines): (&LoadedField, &[f32]),
    photo: &image::DynamicImage,
    size: RenderSize,
    params: &OutlineParams,
) {
    if params.strength <= 0.0 {
        return;
    }
    let (w, h) = (size.width, size.height);
    let mask = outline_mask((&loaded.raw, lines), loaded.metric.domain(), (w, h), params);
    let photo_ink = PhotoInk::new(photo, (w, h));
    let ink = match params.ink {
        OutlineInk::Colour(ink) => ink,
        OutlineInk::Pixel => {
            // The photo itself inside the lines' shapes, as the raster lays it pixel by pixel.
            let inked: Vec<i32> = mask.iter().map(|&m| if m != 0 { 0 } else { -1 }).collect();
            let d = svg_outlines::label_paths(&inked, w, h, 1);
            let picture = RgbImage::from_fn(w as u32, h as u32, |x, y| {
                let c = photo_ink.at(x as usize, y as usize);
                image::Rgb(c.map(|v| v.round().clamp(0.0, 255.0) as u8))
            });
            let shapes = svg_outlines::photo_in_shapes(&d[0], &picture, params.strength, "rigger");
            insert_before_end(svg, &shapes);
            return;
        }
    };
    // Every piece of the lines in the ink, darkened where the photo's mean colour under it is
    // darker than the ink (as the raster darkens it per pixel).
    let (labels, count) = outline_ink::pieces(&mask, w, h);
    let means = outline_ink::piece_colours(&labels, count, &photo_ink, w);
    let darker = outline_ink::DarkerInk::new(ink);
    let inks: Vec<([u8; 3], f32)> = means
        .iter()
        .map(|m| {
            let c = darker
                .under(m.map(f32::from))
                .map_or(ink, |c| c.map(|v| v.round().clamp(0.0, 255.0) as u8));
            (c, params.strength)
        })
        .collect();
    insert_before_end(svg, &svg_outlines::outlines(&labels, w, h, &inks));
}

/// Adds the highlights' vector form over the look in `svg`: `map`, the highlights' map on
/// `loaded`'s tensor grid, laid in `params`' ink (the look's paper). The paper the raster lays
/// is `strength × map` at each pixel, and the map of a dim highlight stays under half (it is
/// no lighter than the photo there): every piece where it reaches [`HIGHLIGHT_TRACE`] is traced
/// and filled at its mean, so the SVG lays about the paper the raster does. (Traced where it
/// is at least half at full strength, as the outlines are, the rocket's grey masts and the
/// dim galaxies of a deep field were missing from the SVG.)
fn add_svg_highlights(
    svg: &mut String,
    (loaded, map): (&LoadedField, &[f32]),
    size: RenderSize,
    params: &OutlineParams,
) {
    let OutlineInk::Colour(paper) = params.ink else {
        return;
    };
    if params.strength <= 0.0 {
        return;
    }
    let (w, h) = (size.width, size.height);
    let values = picture_values((&loaded.raw, map), loaded.metric.domain(), (w, h));
    let mask: Vec<i32> = values
        .iter()
        .map(|&v| i32::from(v >= HIGHLIGHT_TRACE))
        .collect();
    let (labels, count) = outline_ink::pieces(&mask, w, h);
    let mut sums = vec![(0.0f64, 0u32); count];
    for (&l, &v) in labels.iter().zip(&values) {
        if let Ok(l) = usize::try_from(l) {
            sums[l].0 += f64::from(v);
            sums[l].1 += 1;
        }
    }
    let inks: Vec<([u8; 3], f32)> = sums
        .iter()
        .map(|&(sum, n)| (paper, params.strength * (sum / f64::from(n.max(1))) as f32))
        .collect();
    insert_before_end(svg, &svg_outlines::outlines(&labels, w, h, &inks));
}

/// Where the highlights' map is traced for the SVG ([`add_svg_highlights`]).
const HIGHLIGHT_TRACE: f32 = 0.25;

/// Inserts `shapes` before `svg`'s closing tag.
fn insert_before_end(svg: &mut String, shapes: &str) {
    if let Some(end) = svg.rfind("</svg>") {
        svg.insert_str(end, shapes);
    }
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
