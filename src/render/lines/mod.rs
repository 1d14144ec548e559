//! Lines several looks share, all read from the photo or the field rather than from the
//! cells: outlines along the photo's edges as a flow-based difference of Gaussians
//! ([`outline`], its first step `edge_dog`, the chroma's share `chroma_edges`, the per-node
//! reads [`node_grid`], their inks [`outline_ink`] and [`outline_rigger`]); the photo's thin
//! light lines ([`highlights`]) and how much
//! tone outlines and highlights take from a look ([`outline_share`]); the field's line
//! directions ([`line_field`]), evenly spaced streamlines along them ([`streamlines`]) and
//! the share of a pixel that evenly spaced lines ink (`stripes`).

pub(crate) mod chroma_edges;
pub(crate) mod edge_dog;
pub mod highlights;
pub mod line_field;
pub mod node_grid;
pub mod outline;
pub mod outline_ink;
pub mod outline_rigger;
pub mod outline_share;
pub mod streamlines;
pub(crate) mod stripes;
