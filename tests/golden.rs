//! Every built-in preset painted as the `paint` command paints it (`paint::paint_observed`, the
//! whole chain from the file) on one small committed photo, compared with committed
//! references in `tests/references/golden/`: the PNG, and the SVG where the look has one,
//! rasterised by resvg (a renderer that shares no code with ours). A picture matches when
//! every channel lies within `TOLERANCE` levels of the reference for at least 99 % of pixels
//! and none is off by more than 64; on a mismatch a diff picture (four times the difference)
//! is written beside the reference. `REGENERATE=1 cargo test --release --test golden` rewrites
//! the references: look at them before committing.

mod common;

use anisopaint::input::{FieldOptions, Input};
use anisopaint::paint::{self, Extras, Recipe};
use anisopaint::progress::Silent;
use anisopaint::style::{self, BUILT_IN};
use common::Blend;
use std::path::{Path, PathBuf};

/// The photo: coffee (see `samples/SOURCES.md`), 180 × 120.
const PHOTO: &str = "tests/photos/coffee-180.png";

/// Levels a channel may move before a pixel counts as changed. The painting is deterministic
/// (the same bytes at any thread count), so this only leaves room for floating-point results
/// that differ between processors.
const TOLERANCE: u8 = 4;

fn reference(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/references/golden")
        .join(name)
}

#[test]
fn every_preset_matches_its_reference_pictures() {
    let input = Input::Photo(Path::new(env!("CARGO_MANIFEST_DIR")).join(PHOTO));
    let dir = tempfile::tempdir().unwrap();
    for (name, _) in BUILT_IN {
        let preset = style::load(name).unwrap();
        let recipe = Recipe::from_preset(&preset, FieldOptions::default(), None).unwrap();
        let extras = Extras {
            svg: recipe.look.check_vector_form().is_ok(),
            labels: false,
        };
        let painting = paint::paint_observed(&input, &recipe, extras, &Silent).unwrap();
        assert_eq!(painting.image.dimensions(), (180, 120), "{name}");
        common::check_reference(
            &painting.image,
            &reference(&format!("{name}.png")),
            TOLERANCE,
        );
        match painting.svg {
            Some(svg) => {
                let path = dir.path().join(format!("{name}.svg"));
                std::fs::write(&path, svg).unwrap();
                let drawn = common::rasterise_blended(&path, 1, Blend::Encoded);
                common::check_reference(&drawn, &reference(&format!("{name}.svg.png")), TOLERANCE);
            }
            None => assert!(matches!(name, "fabric" | "lic"), "{name} has no SVG"),
        }
    }
}
