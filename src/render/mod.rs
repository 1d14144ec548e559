//! Pictures of the pipeline's data. For now: previews of a metric field and of a sampling (the grid of its
//! ellipses over the faded photo, or orientation as hue and anisotropy as saturation), drawn
//! anti-aliased with tiny-skia. The Voronoi, texture, glyph and fabric looks of paper
//! sections 6 and 7 come here next.

pub mod preview;

pub use preview::{ellipses_preview, field_preview, PreviewMode};
