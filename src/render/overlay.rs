//! What is laid over a photo's look: outlines along its edges and highlights along its thin
//! light lines, both found once from the same edge responses (a flow-based difference of
//! Gaussians, `lines::outline`), on the raster and in the SVG. An ink look (hatching,
//! engraving) leaves out of its own tone the share the outlines will ink and the highlights
//! leave bare ([`Overlays::share`]), so the picture keeps the photo's tone under them.

use super::lines::highlights::highlights_of;
use super::lines::outline::{
    draw_highlights, draw_outlines, lines_of, outline_mask, picture_values, EdgeResponses,
    OutlineParams,
};
use super::lines::outline_ink::{self, OutlineInk, PhotoInk};
use super::lines::outline_share::OutlineShare;
use super::looks::Look;
use super::vector::outlines as svg_outlines;
use super::RenderSize;
use crate::field::TensorField;
use image::{DynamicImage, RgbImage};

/// The outlines and highlights of one photo under one look.
pub(crate) struct Overlays<'a> {
    photo: &'a DynamicImage,
    /// The photo's structure tensor, on whose grid the line maps lie.
    tensor: &'a TensorField,
    /// The picture's domain (the metric's).
    domain: glam::DVec2,
    outline: &'a OutlineParams,
    /// The outlines' line map (empty without outlines).
    lines: Vec<f32>,
    /// How the highlights are laid (the look's paper as ink) and their map.
    highlights: Option<(OutlineParams, Vec<f32>)>,
}

impl<'a> Overlays<'a> {
    /// What `outline` lays over `look` on `photo` (whose structure tensor is `tensor`) in a
    /// picture of `domain`.
    pub fn new(
        look: &Look,
        (photo, tensor): (&'a DynamicImage, &'a TensorField),
        domain: glam::DVec2,
        outline: &'a OutlineParams,
    ) -> Self {
        let paper = highlight_params(look, outline);
        let responses = (outline.strength > 0.0 || paper.is_some())
            .then(|| EdgeResponses::new(photo, tensor, outline));
        let lines = match &responses {
            Some(r) if outline.strength > 0.0 => lines_of(r, outline.ink),
            _ => Vec::new(),
        };
        let highlights = paper.zip(responses.as_ref().map(highlights_of));
        Overlays {
            photo,
            tensor,
            domain,
            outline,
            lines,
            highlights,
        }
    }

    /// How much the outlines ink and the highlights leave bare around each point, for a look
    /// that lays one ink in the photo's tone ([`Look::inks_its_tone`]); `None` where neither
    /// takes from the look's tone. (Outlines in the photo's own colour darken little: the look
    /// keeps its tone.)
    pub fn share(&self, look: &Look) -> Option<OutlineShare> {
        let dark =
            !self.lines.is_empty() && look.inks_its_tone() && self.outline.ink != OutlineInk::Pixel;
        (dark || self.highlights.is_some()).then(|| {
            let ink = if dark { self.lines.as_slice() } else { &[] };
            let share = OutlineShare::new(ink, self.tensor, self.outline.strength);
            match &self.highlights {
                Some((paper, map)) => share.with_highlights(map, paper.strength),
                None => share,
            }
        })
    }

    /// Lays the outlines, then the highlights, over `image`.
    pub fn draw(&self, image: &mut RgbImage) {
        draw_outlines(
            image,
            self.photo,
            (self.tensor, &self.lines),
            self.domain,
            self.outline,
        );
        if let Some((paper, map)) = &self.highlights {
            draw_highlights(image, self.photo, (self.tensor, map), self.domain, paper);
        }
    }

    /// Writes the outlines', then the highlights', vector form into an SVG body of `size`.
    pub fn write_svg(&self, out: &mut String, size: RenderSize) {
        self.write_svg_outlines(out, size);
        if let Some((paper, map)) = &self.highlights {
            self.write_svg_highlights(out, map, size, paper);
        }
    }

    /// The outlines' vector form: in one ink, every piece of the lines darkened where the
    /// photo's mean colour under it is darker than the ink (as the raster darkens it per
    /// pixel); in the photo's own ink, the photo itself inside the lines' shapes.
    fn write_svg_outlines(&self, out: &mut String, size: RenderSize) {
        let params = self.outline;
        if params.strength <= 0.0 {
            return;
        }
        let (w, h) = (size.width, size.height);
        let mask = outline_mask((self.tensor, &self.lines), self.domain, (w, h), params);
        let photo_ink = PhotoInk::new(self.photo, (w, h));
        let ink = match params.ink {
            OutlineInk::Colour(ink) => ink,
            OutlineInk::Pixel => {
                let inked: Vec<i32> = mask.iter().map(|&m| if m != 0 { 0 } else { -1 }).collect();
                let d = svg_outlines::label_paths(&inked, w, h, 1);
                let picture = RgbImage::from_fn(w as u32, h as u32, |x, y| {
                    let c = photo_ink.at(x as usize, y as usize);
                    image::Rgb(c.map(|v| v.round().clamp(0.0, 255.0) as u8))
                });
                out.push_str(&svg_outlines::photo_in_shapes(
                    &d[0],
                    &picture,
                    params.strength,
                    "rigger",
                ));
                return;
            }
        };
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
        out.push_str(&svg_outlines::outlines(&labels, w, h, &inks));
    }

    /// The highlights' vector form: `map` laid in `params`' ink (the look's paper). The paper
    /// the raster lays is `strength × map` at each pixel, and the map of a dim highlight stays
    /// under half (it is no lighter than the photo there): every piece where it reaches
    /// [`HIGHLIGHT_TRACE`] is traced and filled at its mean, so the SVG lays about the paper
    /// the raster does (traced only where it is at least half, as the outlines are, dim masts
    /// and faint stars would be missing).
    fn write_svg_highlights(
        &self,
        out: &mut String,
        map: &[f32],
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
        let values = picture_values((self.tensor, map), self.domain, (w, h));
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
        out.push_str(&svg_outlines::outlines(&labels, w, h, &inks));
    }
}

/// Where the highlights' map is traced for the SVG ([`Overlays::write_svg`]).
const HIGHLIGHT_TRACE: f32 = 0.25;

/// How highlights are laid over `look`: the outline parameters that draw them (the look's
/// paper as ink, at the highlights' strength); `None` for a look without one paper, or none
/// asked for.
fn highlight_params(look: &Look, outline: &OutlineParams) -> Option<OutlineParams> {
    let paper = look.paper()?;
    (outline.highlights > 0.0).then_some(OutlineParams {
        strength: outline.highlights,
        ink: OutlineInk::Colour(paper),
        ..*outline
    })
}
