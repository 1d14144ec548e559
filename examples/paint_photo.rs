//! Paints a photo with a built-in preset (or a preset file) and saves it with how it was made.
//!
//! ```sh
//! cargo run --release --example paint_photo -- samples/chelsea.png pen-hatch chelsea-ink.png
//! ```

use anisopaint::{load_style, paint, save_painting, Input, PaintRecord, Recipe};
use std::path::Path;

fn main() -> anisopaint::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [photo, style, out] = args.as_slice() else {
        eprintln!("usage: paint_photo PHOTO STYLE OUT.png");
        std::process::exit(2);
    };
    let preset = load_style(style)?;
    let seed = 7;
    let recipe = Recipe::from_preset(&preset, Default::default(), Some(seed))?;
    let picture = paint(&Input::parse(photo)?, &recipe)?;
    let record = PaintRecord {
        input: photo.clone(),
        style: style.clone(),
        preset: preset.name.clone(),
        sets: Vec::new(),
        seed,
    };
    save_painting(Path::new(out), &picture, &record)?;
    println!("wrote {out} ({}×{})", picture.width(), picture.height());
    Ok(())
}
