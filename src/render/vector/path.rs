//! What every SVG the looks write is made of (the looks' `svg.rs`, the traced cells of
//! [`super`] and its [`outlines`](super::outlines)): colours as `#rrggbb` and
//! path data with coordinates at a tenth of a pixel.

use crate::render::support::colour::{to_srgb, Linear};
use std::fmt::Write;

/// `c` as `#rrggbb`.
pub(crate) fn hex(c: Linear) -> String {
    hex_of_srgb(c.map(to_srgb))
}

/// sRGB bytes as `#rrggbb`.
pub(crate) fn hex_of_srgb([r, g, b]: [u8; 3]) -> String {
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// Appends `M x y x y … [Z]` for `points`.
pub(crate) fn path_data(d: &mut String, points: &[[f32; 2]], close: bool) {
    for (k, p) in points.iter().enumerate() {
        let _ = write!(
            d,
            "{}{} {}",
            if k == 0 { "M" } else { " " },
            num(p[0]),
            num(p[1])
        );
    }
    if close {
        d.push('Z');
    }
}

/// A coordinate printed with at most one decimal (no allocation: it formats in place).
#[derive(Clone, Copy)]
pub(crate) struct Num(f32);

impl std::fmt::Display for Num {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let r = (self.0 * 10.0).round() / 10.0;
        if r == r.trunc() {
            write!(f, "{}", r as i64)
        } else {
            write!(f, "{r:.1}")
        }
    }
}

/// `v` as [`Num`] prints it.
pub(crate) fn num(v: f32) -> Num {
    Num(v)
}
