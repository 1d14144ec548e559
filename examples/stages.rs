//! The pipeline's stages one by one: a photo's metric, its samples (reused for two looks), and
//! each look drawn at twice the photo's size with its SVG, as `anisopaint field`, `sample` and
//! `render` do.
//!
//! ```sh
//! cargo run --release --example stages -- samples/chelsea.png
//! ```

use anisopaint::io::{save_image, write_text};
use anisopaint::progress::Silent;
use anisopaint::style::apply_sets;
use anisopaint::{draw, load_field, load_style, sample, Extras, Input, Recipe, RenderSize};
use image::DynamicImage;
use std::path::Path;

fn main() -> anisopaint::Result<()> {
    let Some(photo) = std::env::args().nth(1) else {
        eprintln!("usage: stages PHOTO");
        std::process::exit(2);
    };
    let mut preset = load_style("mosaic")?;
    let recipe = Recipe::from_preset(&preset, Default::default(), Some(3))?;
    let loaded = load_field(&Input::parse(&photo)?, &recipe.field)?;
    let samples = sample(&loaded.metric, &recipe.sampler, &Silent)?;
    println!("{} samples", samples.positions.len());
    let domain = loaded.metric.domain();
    let size = RenderSize {
        width: (2.0 * domain.x).round() as usize,
        height: (2.0 * domain.y).round() as usize,
        supersample: recipe.supersample,
    };
    let extras = Extras {
        svg: true,
        labels: false,
    };
    // The same samples as a mosaic, then as stained glass with a stronger relief.
    for (name, sets) in [
        ("mosaic", vec![]),
        ("glass", vec!["look.relief=0.8".to_string()]),
    ] {
        apply_sets(&mut preset, &sets)?;
        let recipe = Recipe::from_preset(&preset, Default::default(), Some(3))?;
        let painting = draw(&loaded, &samples, &recipe, size, extras, &Silent)?;
        let png = format!("stages-{name}.png");
        save_image(Path::new(&png), &DynamicImage::ImageRgb8(painting.image))?;
        if let Some(svg) = painting.svg {
            write_text(Path::new(&format!("stages-{name}.svg")), &svg)?;
        }
        println!("wrote stages-{name}.png and .svg");
    }
    Ok(())
}
