//! anisopaint turns photographs and 2-D tensor fields into painterly images by particle-based
//! anisotropic sampling (Kratz, Meyer, Hotz: "Particle-Based Anisotropic Sampling for
//! Two-Dimensional Tensor Field Visualization").
//!
//! The data flows through the modules in order: [`field`] (tensors, structure tensor, metric)
//! → [`sampling`] (seeding, forces, anisotropic Delaunay, population
//! control, quality) → [`render`] (Voronoi cells, mosaics, textures, glyphs, fabric) →
//! [`style`] (presets) → [`cli`]. [`io`] reads inputs and writes outputs atomically;
//! [`batch`] plans and runs folder batches; [`progress`] carries stage reports to the CLI's bars; [`error`] is the one error type.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod batch;
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
