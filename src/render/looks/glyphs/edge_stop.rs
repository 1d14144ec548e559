//! Paint that stops at the photo's edges, over cells that follow them (paper section 6's cells
//! with the colour term): where a brush stroke or a glyph laid over a cell reads as a colour
//! the cell cannot have, it has reached across the cell's border from a neighbour of another
//! colour, and the cell's colour comes back there. Used by the glyph and brush looks
//! ([`super`]); colours are sRGB levels in `f32`.

use crate::field::blur::round_to_byte;
use crate::render::cells::raster::Raster;
use crate::render::scene::Scene;
use rayon::prelude::*;
use tiny_skia::Pixmap;

/// Colour difference (sRGB, RMS over channels, as a share of the range) from which paint gives
/// way to the cell under it: bristle shading stays below it (±15 %), a neighbour across an
/// edge above.
const EDGE_STOP: f32 = 0.12;

/// Over this much more difference the cell shows through fully.
const EDGE_STOP_RAMP: f32 = 0.1;

/// How far paint that differs from what its cell allows by `d2` (a squared distance in sRGB
/// levels, summed over channels) gives way to the cell: 0 under [`EDGE_STOP`], 1 from
/// `EDGE_STOP + EDGE_STOP_RAMP` on, eased between (so a stroke's end fades, not cuts).
fn give_way(d2: f32) -> f32 {
    let rms = (d2 / 3.0).sqrt() / 255.0;
    ((rms - EDGE_STOP) / EDGE_STOP_RAMP).clamp(0.0, 1.0).powi(2)
}

/// `p` moved a share `t` of the way to `target` (sRGB levels), as bytes.
fn toward(p: [f32; 3], target: [f32; 3], t: f32) -> [u8; 3] {
    std::array::from_fn(|k| round_to_byte(p[k] + (target[k] - p[k]) * t))
}

/// Strokes stop at edges: where a stroke laid over the underpainting `under` (RGB) of
/// edge-following cells differs from the cell under it by more than [`EDGE_STOP`], it has
/// crossed an edge from a neighbour of another colour, and the cell shows through again. A
/// stroke among cells of its own colour is untouched; a thin dark line overpainted by strokes
/// of the light ground around it comes back. `painted` is opaque RGBA.
pub(crate) fn stop_at_edges(painted: &mut [u8], under: &[u8]) {
    painted
        .par_chunks_mut(4)
        .zip(under.par_chunks(3))
        .for_each(|(p, u)| {
            let (p3, u3) = (levels([p[0], p[1], p[2]]), levels([u[0], u[1], u[2]]));
            let t = give_way((0..3).map(|k| (p3[k] - u3[k]).powi(2)).sum());
            if t > 0.0 {
                p[..3].copy_from_slice(&toward(p3, u3, t));
            }
        });
}

/// Glyphs stay on their side of an edge: a pixel of a cell whose colour is neither the cell's
/// wash, its glyph's nor a blend of the two (farther than [`EDGE_STOP`] from that segment) is a
/// neighbour's glyph reaching across the cell's border, and takes the cell's colour instead.
/// The cells follow the photo's edges, so an object's outline is the cells' border, not a rim
/// of ellipses poking out of it; where neighbours' colours are close, glyphs overlap as before.
/// `expected[site]` is the cell's wash, glyph and own colour (sRGB levels); `pixmap` is opaque.
pub(crate) fn keep_out_across_edges(
    scene: &Scene,
    expected: &[[[f32; 3]; 3]],
    pixmap: &mut Pixmap,
) {
    let r = scene.raster;
    let centres = Raster {
        supersample: 1,
        ..r
    };
    scene
        .cells
        .site_rows(&centres, pixmap.pixels_mut(), r.width, |_, sites, row| {
            for (px, &site) in row.iter_mut().zip(sites) {
                let Some(&[wash, glyph, cell]) = expected.get(site as usize) else {
                    continue;
                };
                let c = px.demultiply();
                let p = levels([c.red(), c.green(), c.blue()]);
                let t = give_way(distance2_to_segment(p, wash, glyph));
                if t > 0.0 {
                    let [r, g, b] = toward(p, cell, t);
                    *px = tiny_skia::ColorU8::from_rgba(r, g, b, 255).premultiply();
                }
            }
        });
}

/// Bytes as `f32` levels.
fn levels(c: [u8; 3]) -> [f32; 3] {
    c.map(f32::from)
}

/// Squared distance from `p` to the segment from `a` to `b`.
fn distance2_to_segment(p: [f32; 3], a: [f32; 3], b: [f32; 3]) -> f32 {
    let along: [f32; 3] = std::array::from_fn(|k| b[k] - a[k]);
    let length2: f32 = along.iter().map(|v| v * v).sum();
    let t = if length2 > 0.0 {
        ((0..3).map(|k| (p[k] - a[k]) * along[k]).sum::<f32>() / length2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (0..3).map(|k| (p[k] - (a[k] + t * along[k])).powi(2)).sum()
}
