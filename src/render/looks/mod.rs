//! The [`Look`] enum: which renderer draws a [`Scene`] and with which parameters (mosaic,
//! textured cells, glyphs, fabric/LIC; paper sections 6 and 7). It imports the looks; they
//! import only the scene.

pub mod engraving;
pub mod fabric;
pub mod glyphs;
pub mod mosaic;
pub mod texture;

use crate::field::Tensor;
use crate::render::scene::Scene;
use crate::render::support::colour::Linear;
use glam::DVec2;
use image::RgbImage;

/// A renderer and its parameters.
#[derive(Clone, Debug, PartialEq)]
pub enum Look {
    /// Cells filled with their colour, with borders (paper Figure 5e).
    Mosaic(mosaic::MosaicParams),
    /// Cells filled with a texture in the cell's frame (paper Figures 5f-g, 6d-f).
    Texture(texture::TextureParams),
    /// Ellipse glyphs at the samples (paper 7.1).
    Glyphs(glyphs::GlyphParams),
    /// LIC along the eigenvector fields of sample-seeded noise (paper 7.3).
    Fabric(fabric::FabricParams),
    /// Evenly spaced streamlines along the field, swelling with tone.
    Engraving(engraving::EngravingParams),
}

impl Look {
    /// The look a name on the command line means, with default parameters.
    #[must_use]
    pub fn named(name: &str) -> Option<Look> {
        use fabric::{FabricParams, Noise};
        use texture::{TextureKind, TextureParams};
        let texture = |kind| Look::Texture(TextureParams::for_kind(kind));
        Some(match name {
            "mosaic" => Look::Mosaic(mosaic::MosaicParams::default()),
            "hatch" => texture(TextureKind::Hatch),
            "crosshatch" => texture(TextureKind::CrossHatch),
            "line" => texture(TextureKind::Line),
            "stroke" => texture(TextureKind::Stroke),
            "stipple" => texture(TextureKind::Stipple),
            "glyphs" => Look::Glyphs(glyphs::GlyphParams::default()),
            "engraving" => Look::Engraving(engraving::EngravingParams::default()),
            "fabric" => Look::Fabric(FabricParams::default()),
            "lic" => Look::Fabric(FabricParams {
                noise: Noise::White,
                cross_weight: 0.0,
                ..FabricParams::default()
            }),
            _ => return None,
        })
    }

    /// The look of a preset that names none.
    pub const DEFAULT_NAME: &'static str = "mosaic";

    /// The names [`Look::named`] knows.
    pub const NAMES: [&'static str; 10] = [
        "mosaic",
        "hatch",
        "crosshatch",
        "line",
        "stroke",
        "stipple",
        "glyphs",
        "engraving",
        "fabric",
        "lic",
    ];

    /// Fails for the looks that have no SVG form (fabric and LIC).
    pub fn check_vector_form(&self) -> crate::Result<()> {
        match self {
            Look::Fabric(_) => Err(crate::Error::param(
                "--svg",
                "fabric and LIC looks have no vector form; SVG is written for the mosaic, \
                 textured and glyph looks",
            )),
            _ => Ok(()),
        }
    }

    /// Whether the look lays one ink over paper in the photo's tone (hatching, cross-hatching,
    /// engraving), and so leaves out of its tone what outlines laid over it will ink
    /// ([`Scene::outline_share`]).
    #[must_use]
    pub fn inks_its_tone(&self) -> bool {
        match self {
            Look::Texture(p) => {
                use texture::TextureKind;
                matches!(p.kind, TextureKind::Hatch | TextureKind::CrossHatch)
            }
            Look::Engraving(_) => true,
            _ => false,
        }
    }

    /// The paper of a look that lays one ink over paper ([`Self::inks_its_tone`]), which
    /// highlights lay along the photo's light lines; `None` where the paper is no lighter than
    /// a fixed ink (white lines on black: the light lines are the ink's, and the paper laid
    /// along them darkened them).
    #[must_use]
    pub fn paper(&self) -> Option<[u8; 3]> {
        use crate::render::support::colour::{lightness, linear_of};
        use texture::Ink;
        let lighter = |paper: [u8; 3], ink: [u8; 3]| {
            (lightness(linear_of(paper)) > lightness(linear_of(ink))).then_some(paper)
        };
        match self {
            Look::Texture(p) if self.inks_its_tone() => match p.ink {
                Ink::Fixed(ink) => lighter(p.paper, ink),
                Ink::Cell(_) | Ink::Pixel(_) => Some(p.paper),
            },
            Look::Engraving(p) => lighter(p.paper, p.ink),
            _ => None,
        }
    }

    /// Writes the body of this look's SVG over `scene` (a look without a vector form writes
    /// nothing: [`Self::check_vector_form`] refuses it first), `laid` the glyphs the raster
    /// picture laid when it was painted already ([`glyphs::painted`]), so they are not found
    /// twice.
    pub(crate) fn write_svg(
        &self,
        out: &mut String,
        scene: &Scene,
        laid: Option<Vec<(DVec2, Tensor, Linear)>>,
    ) {
        match self {
            Look::Mosaic(p) => mosaic::svg::write(out, scene, p),
            Look::Texture(p) => texture::svg::write(out, scene, p),
            Look::Glyphs(p) => {
                let laid = laid.unwrap_or_else(|| glyphs::laid(scene, p));
                glyphs::svg::write(out, scene, p, &laid);
            }
            Look::Engraving(p) => engraving::svg::engraved(out, scene, p),
            Look::Fabric(_) => {}
        }
    }

    /// Renders `scene`.
    #[must_use]
    pub fn render(&self, scene: &Scene) -> RgbImage {
        match self {
            Look::Mosaic(p) => mosaic::mosaic(scene, p),
            Look::Texture(p) => texture::textured(scene, p),
            Look::Glyphs(p) => glyphs::glyphs(scene, p),
            Look::Fabric(p) => fabric::fabric(scene, p),
            Look::Engraving(p) => engraving::engraving(scene, p),
        }
    }
}
