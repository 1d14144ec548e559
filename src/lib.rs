//! anisopaint turns photographs and 2-D tensor fields into painterly images by particle-based
//! anisotropic sampling (Kratz, Meyer, Hotz: "Particle-Based Anisotropic Sampling for
//! Two-Dimensional Tensor Field Visualization").
//!
//! The data flows through the modules in order: [`input`] (photos, `.npy` fields, analytic
//! fields) → [`field`] (tensors, structure tensor, metric) → [`sampling`] (seeding, forces,
//! anisotropic Delaunay, population control, quality) → [`render`] (Voronoi cells, mosaics,
//! textures, glyphs, fabric) → [`paint`](mod@paint), the one pipeline every command uses; [`style`]
//! describes presets, `cli` (feature `cli`, on by default) is the command line. [`io`] reads
//! and writes files atomically; [`batch`] plans and runs folder batches; [`progress`] carries
//! stage reports to the CLI's bars; [`error`] is the one error type.
//!
//! Painting a photo with a preset:
//!
//! ```
//! use anisopaint::{input::Input, paint, style};
//!
//! let photo = concat!(env!("CARGO_MANIFEST_DIR"), "/samples/chelsea.png");
//! let preset = style::load("pen-hatch")?;
//! let recipe = paint::Recipe::from_preset(&preset, Default::default(), Some(7))?;
//! let picture = paint::paint(&Input::parse(photo)?, &recipe)?;
//! assert_eq!(picture.dimensions(), (451, 300));
//! // Ink on paper: some pixels are dark, most are light.
//! let dark = picture.pixels().filter(|p| p.0[0] < 100).count();
//! assert!(dark > 1000 && dark < 451 * 300 / 2, "{dark} dark pixels");
//! picture.save(std::env::temp_dir().join("chelsea.pen-hatch.png")).expect("written");
//! # Ok::<(), anisopaint::Error>(())
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod batch;
#[cfg(feature = "cli")]
pub mod cli;
pub mod error;
pub mod field;
pub mod input;
pub mod io;
pub mod paint;
pub mod progress;
pub mod render;
pub mod sampling;
pub mod style;

pub use error::{Error, Result};
// What a library user needs first: load a style, load or make a field, paint (or sample and
// draw), save.
pub use input::{load_field, photo_field, tensor_field, FieldOptions, Input, LoadedField};
pub use paint::{
    draw, paint, sample, save_painting, Extras, PaintRecord, Painting, Recipe, Samples,
};
pub use render::{Look, RenderSize};
pub use style::{load as load_style, Preset};
