//! A tensor field made in code (the stress of a point load pressing on a half plane,
//! Boussinesq's solution, as the paper's Figure 7) painted as glyphs and as fabric: a general
//! tensor, so it is mapped to a metric by the paper's anti-symmetric mapping.
//!
//! ```sh
//! cargo run --release --example stress_field
//! ```

use anisopaint::field::{Tensor, TensorField};
use anisopaint::io::save_image;
use anisopaint::{load_style, paint::paint_loaded, tensor_field, Extras, Recipe};
use image::DynamicImage;
use std::path::Path;

/// Stress under a unit point load at `(x0, 0)` on the surface `y = 0` of a half plane (polar
/// form: a purely radial stress `−2P cos θ / (π r)`).
fn boussinesq(x: f64, y: f64, x0: f64) -> Tensor {
    let (dx, dy) = (x - x0, y.max(1e-3));
    let r2 = dx * dx + dy * dy;
    let radial = -2.0 * dy / (std::f64::consts::PI * r2);
    // σ = radial · r̂ r̂ᵀ.
    let (c, s) = (dx / r2.sqrt(), dy / r2.sqrt());
    Tensor::new(radial * c * c, radial * c * s, radial * s * s)
}

fn main() -> anisopaint::Result<()> {
    let (w, h) = (600, 400);
    let field = TensorField::from_fn(w, h, |p| boussinesq(p.x, p.y, 300.0));
    let loaded = tensor_field(field, &Default::default())?;
    for style in ["glyphs", "fabric"] {
        let recipe = Recipe::from_preset(&load_style(style)?, Default::default(), Some(1))?;
        let painting = paint_loaded(
            &loaded,
            &recipe,
            Extras::default(),
            &anisopaint::progress::Silent,
        )?;
        let out = format!("stress-{style}.png");
        save_image(Path::new(&out), &DynamicImage::ImageRgb8(painting.image))?;
        println!("wrote {out}");
    }
    Ok(())
}
