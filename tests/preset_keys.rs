//! Every numeric key of every built-in preset, fed values a user might type by mistake
//! (negative, zero, NaN, infinities, tiny and huge): each run either fails with one clean
//! error naming the key and what is allowed, or paints a whole picture — never a panic, and
//! never a silent stand-in for a value outside the key's range. Values are set with `--set`'s
//! own parser, so they are checked exactly as a user's are; the keys come from the schema.

use anisopaint::input::photo_field;
use anisopaint::paint::{paint_loaded, Extras, Recipe};
use anisopaint::progress::Silent;
use anisopaint::style::{self, schema, schema::Value};

/// Every key that takes a number, with whether it takes a whole one, and the keys that take
/// a name or a shape (users give them numbers by mistake too): from the schema, so a new key
/// is checked here without a line of this file.
fn numeric_keys() -> Vec<(&'static schema::Key, bool)> {
    schema::KEYS
        .iter()
        .filter_map(|k| match k.value {
            Value::Number { .. } | Value::Positive { .. } => Some((k, false)),
            Value::Integer { .. } => Some((k, true)),
            Value::Choice(_) | Value::Shape => Some((k, false)),
            _ => None,
        })
        .collect()
}

const FLOATS: [&str; 9] = [
    "-5", "0", "nan", "inf", "-inf", "1e-9", "1e9", "1e30", "0.5",
];
const INTEGERS: [&str; 5] = ["-1", "0", "1000000000", "18446744073709551615", "3"];

/// A small photo with an edge and a line, so every look has something to draw.
fn photo() -> image::DynamicImage {
    let img = image::RgbImage::from_fn(40, 28, |x, y| {
        if x == 20 {
            image::Rgb([20, 20, 20])
        } else if x + y > 30 {
            image::Rgb([200, 80, 40])
        } else {
            image::Rgb([240, 235, 220])
        }
    });
    image::DynamicImage::ImageRgb8(img)
}

/// What happened to one `--set`.
enum Outcome {
    Refused(String),
    Painted,
}

fn run(preset_name: &str, set: &str) -> Outcome {
    let mut preset = style::load(preset_name).unwrap();
    let refused = |e: anisopaint::Error| Outcome::Refused(e.to_string());
    if let Err(e) = style::apply_sets(&mut preset, &[set.to_string()]) {
        return refused(e);
    }
    let recipe = match Recipe::from_preset(&preset, Default::default(), None) {
        Ok(r) => r,
        Err(e) => return refused(e),
    };
    let loaded = photo_field(photo(), &recipe.field.metric);
    match paint_loaded(&loaded, &recipe, Extras::default(), &Silent) {
        Ok(p) => {
            assert_eq!(p.image.dimensions(), (40, 28), "{preset_name} {set}");
            Outcome::Painted
        }
        Err(e) => refused(e),
    }
}

#[test]
fn every_numeric_key_of_every_preset_is_checked() {
    let mut painted = 0;
    let mut refused = 0;
    let keys = numeric_keys();
    assert!(keys.len() > 35, "{} keys", keys.len());
    for (preset, _) in style::BUILT_IN {
        let kind = style::load(preset).unwrap().file.look.kind.unwrap();
        // The keys this preset's look reads (any other is refused before its value is read).
        for &(key, integer) in keys.iter().filter(|(k, _)| k.readers.include(&kind)) {
            let key = key.path;
            let values: &[&str] = if integer { &INTEGERS } else { &FLOATS };
            for value in values {
                let set = format!("{key}={value}");
                let started = std::time::Instant::now();
                let outcome = std::panic::catch_unwind(|| run(preset, &set))
                    .unwrap_or_else(|_| panic!("{preset} --set {set} panicked"));
                let took = started.elapsed();
                assert!(
                    took.as_secs_f64() < 20.0,
                    "{preset} --set {set} took {took:?} on a 40x28 photo"
                );
                match outcome {
                    Outcome::Painted => painted += 1,
                    Outcome::Refused(message) => {
                        refused += 1;
                        // Sizes within range can still ask for more samples than the
                        // sampler takes: that refusal names the count and the cure.
                        let short = key.rsplit('.').next().unwrap();
                        let names_it = message.contains(short)
                            || (key.ends_with("_size") && message.contains("samples"));
                        assert!(
                            names_it && !message.contains('\n'),
                            "{preset} --set {set}: the error must name the key in one line: \
                             {message}"
                        );
                    }
                }
            }
        }
    }
    // Both outcomes happen: the test sees values in range and out of it.
    assert!(
        painted > 100 && refused > 100,
        "{painted} painted, {refused} refused"
    );
}

/// The values the issue named, with the message a user reads.
#[test]
fn out_of_range_values_say_the_key_the_value_and_the_range() {
    for (set, expected) in [
        (
            "look.border_width=-5",
            "invalid look.border_width: -5 must be in [0, 50]",
        ),
        (
            "look.relief=nan",
            "invalid look.relief: NaN must be in [0, 1]",
        ),
        (
            "cells.supersample=9",
            "invalid cells.supersample: 9 must be in [1, 4]",
        ),
        (
            "sampler.iterations=1000000",
            "invalid sampler.iterations: 1000000 must be in [0, 10000]",
        ),
        (
            "look.kernel_px=inf",
            "invalid look.kernel_px: inf must be in [1, 100]",
        ),
    ] {
        let look = if set.contains("kernel") {
            "fabric"
        } else {
            "mosaic"
        };
        match run(look, set) {
            Outcome::Refused(message) => assert_eq!(message, expected),
            Outcome::Painted => panic!("{set} was accepted"),
        }
    }
}
