//! The mosaic's vector form: the traced cells filled with their glass (a gradient per cell
//! where it has relief) and the leading stroked between them at each cell's width, in each
//! border's lead colour.

use super::{glass, lead_between, relief_ramps, MosaicParams};
use crate::render::scene::Scene;
use crate::render::vector::{self, LeadInk, Leading};

/// Writes the body of `p`'s SVG over `scene`.
pub(crate) fn write(out: &mut String, scene: &Scene, p: &MosaicParams) {
    let glass = glass(scene, p, scene.border_px(p.border_width));
    let ink = |l: usize, r: usize| lead_between(&glass.leads, l as u32, r as u32);
    let border =
        (p.border_width > 0.0).then_some((&ink as LeadInk, Leading::PerCell(&glass.leading)));
    let ramps = relief_ramps(scene, p, &glass.colours);
    vector::cells(out, scene, (&glass.colours, ramps.as_deref()), border);
}
