//! What every part of rendering reads and no part owns: sRGB and linear-light colour
//! ([`colour`]), per-site hashes ([`hash`]), bilinear reads (`bilinear`), `floor`/`ceil`
//! for per-pixel code ([`rounding`]), image-sized buffers filled by writing ([`buffer`]), a
//! union–find (`disjoint`). Nothing here knows cells, lines or looks.

pub(crate) mod bilinear;
pub mod buffer;
pub mod colour;
pub(crate) mod disjoint;
pub mod hash;
pub mod rounding;
