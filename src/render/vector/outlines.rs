//! The outlines' vector form, to go over a look's SVG: the line map's pieces traced and
//! simplified like the cells, filled in one ink each ([`outlines`]); or, for outlines drawn in
//! the photo's own colour pixel by pixel (a rigger brush, `outlines.ink = "pixel"`), their
//! traced shapes clipping an embedded copy of the photo at the picture's size
//! ([`photo_in_shapes`]), so the vector form shows the colours the raster lays. Filled instead
//! with one mean colour per piece, the pieces had to be cut into 4 px tiles to keep a lattice
//! tower's colour local, and every wide stretch of line (an ear, a hairline, a lit rim)
//! showed those tiles as squares.
//!
//! The copy is a PNG (RGB, 8 bits) in a `data:` URI, base64 as RFC 4648 writes it.

use crate::render::support::colour::linear_of;
use crate::render::vector::path::{hex, path_data};
use crate::render::vector::trace::{rings, simplify, Borders};
use crate::render::vector::TRACE_TOLERANCE_PX;
use image::{ImageEncoder, RgbImage};
use std::fmt::Write as _;

/// The outlines as vector shapes, to go over a look's SVG: `labels` (output pixels,
/// row-major: where the outlines' ink is at least half, the index of the ink in `inks`, −1
/// elsewhere) traced and simplified like the cells, each label's shapes filled with its ink at
/// its opacity (`inks` holds colour and opacity per label).
#[must_use]
pub fn outlines(labels: &[i32], width: usize, height: usize, inks: &[([u8; 3], f32)]) -> String {
    let mut out = String::new();
    for (d, &(ink, opacity)) in label_paths(labels, width, height, inks.len())
        .iter()
        .zip(inks)
    {
        if !d.is_empty() {
            let _ = writeln!(
                out,
                "<path fill=\"{}\" fill-opacity=\"{}\" fill-rule=\"evenodd\" d=\"{d}\"/>",
                hex(linear_of(ink)),
                opacity.clamp(0.0, 1.0)
            );
        }
    }
    out
}

/// The path data (even-odd rings) of each of the `count` labels of `labels` (output pixels,
/// row-major, −1 for none), traced and simplified like the cells; empty for a label with no
/// pixels.
#[must_use]
pub fn label_paths(labels: &[i32], width: usize, height: usize, count: usize) -> Vec<String> {
    let borders = Borders::trace(labels, width, height);
    let simplified: Vec<Vec<[f32; 2]>> = borders
        .chains
        .iter()
        .map(|c| simplify(&c.points, TRACE_TOLERANCE_PX))
        .collect();
    rings(&borders, &simplified, count)
        .iter()
        .map(|ring_set| {
            let mut d = String::new();
            for ring in ring_set {
                path_data(&mut d, ring, true);
            }
            d
        })
        .collect()
}

/// An SVG fragment: `photo` (the picture's size, at the origin) shown only inside the shapes
/// of the path data `d` (even-odd rings, output pixels), at `opacity`. `id` names the clip
/// path and must be unique in the document. Empty for empty `d`.
#[must_use]
pub fn photo_in_shapes(d: &str, photo: &RgbImage, opacity: f32, id: &str) -> String {
    if d.is_empty() {
        return String::new();
    }
    let mut png = Vec::new();
    let encoded = image::codecs::png::PngEncoder::new(&mut png).write_image(
        photo.as_raw(),
        photo.width(),
        photo.height(),
        image::ExtendedColorType::Rgb8,
    );
    if encoded.is_err() {
        return String::new();
    }
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<clipPath id=\"{id}\"><path clip-rule=\"evenodd\" d=\"{d}\"/></clipPath>"
    );
    let _ = writeln!(
        out,
        "<image x=\"0\" y=\"0\" width=\"{}\" height=\"{}\" preserveAspectRatio=\"none\" \
         opacity=\"{}\" clip-path=\"url(#{id})\" xlink:href=\"data:image/png;base64,{}\"/>",
        photo.width(),
        photo.height(),
        opacity.clamp(0.0, 1.0),
        base64(&png)
    );
    out
}

/// `bytes` in base64 (RFC 4648, with padding).
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(char::from(ALPHABET[(n >> (18 - 6 * k)) as usize & 63]));
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_is_rfc_4648() {
        // RFC 4648, section 10.
        for (raw, want) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(raw.as_bytes()), want, "{raw}");
        }
        assert_eq!(base64(&[0xff, 0xfe, 0x00]), "//4A");
    }

    #[test]
    fn the_photo_is_embedded_whole_and_clipped() {
        let photo = RgbImage::from_fn(3, 2, |x, y| image::Rgb([x as u8 * 80, y as u8 * 90, 7]));
        let svg = photo_in_shapes("M0 0L2 0L2 2Z", &photo, 0.5, "ink");
        assert!(
            svg.contains("<clipPath id=\"ink\"><path clip-rule=\"evenodd\" d=\"M0 0L2 0L2 2Z\"/>")
        );
        assert!(svg.contains("clip-path=\"url(#ink)\"") && svg.contains("opacity=\"0.5\""));
        // The embedded PNG decodes to the photo.
        let start = svg.find("base64,").unwrap() + 7;
        let end = start + svg[start..].find('"').unwrap();
        let png = decode(&svg[start..end]);
        let back = image::load_from_memory(&png).unwrap().to_rgb8();
        assert_eq!(back, photo);
        assert!(photo_in_shapes("", &photo, 1.0, "ink").is_empty());
    }

    /// Base64 decoding, for the test: the inverse of [`base64`].
    fn decode(text: &str) -> Vec<u8> {
        let value = |c: u8| match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            _ => 63,
        };
        let mut out = Vec::new();
        for chunk in text.as_bytes().chunks(4) {
            let n = chunk
                .iter()
                .enumerate()
                .filter(|(_, &c)| c != b'=')
                .fold(0u32, |n, (k, &c)| n | u32::from(value(c)) << (18 - 6 * k));
            let bytes = chunk.iter().filter(|&&c| c != b'=').count() - 1;
            out.extend((0..bytes).map(|k| (n >> (16 - 8 * k)) as u8));
        }
        out
    }
}
