//! Speed of the product end to end: `paint` of a 2048×2048 photo with `mosaic` including
//! decode and encode; a 12 MP photo with every preset; a batch of one-megapixel photos with 2 jobs against 1 job. Each iteration does what
//! the command does: decode the file, metric, sampling, look, encode and write atomically.
//! Peak memory is not measured here: run the binary under `/usr/bin/time -f %M`.
//!
//! Run: `cargo bench --bench paint` (about six minutes).

use anisopaint::batch::{self, Item};
use anisopaint::input::{FieldOptions, Input};
use anisopaint::paint::{self, PaintRecord, Recipe};
use anisopaint::style::{self, Preset, BUILT_IN};
use criterion::{criterion_group, criterion_main, Criterion};
use image::imageops::FilterType;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// A shared photo resized to `w × h`, written as PNG into `dir`.
fn photo(dir: &Path, source: &str, w: u32, h: u32, name: &str) -> PathBuf {
    let img = image::open(format!("samples/{source}")).expect("bundled sample photo");
    let path = dir.join(name);
    img.resize_exact(w, h, FilterType::Lanczos3)
        .to_rgb8()
        .save(&path)
        .unwrap();
    path
}

/// What `anisopaint paint INPUT -s STYLE -o OUT` does.
fn paint_file(input: &Path, preset: &Preset, out: &Path) {
    let recipe = Recipe::from_preset(preset, FieldOptions::default(), None).unwrap();
    let img = paint::paint(&Input::Photo(input.into()), &recipe).unwrap();
    let record = PaintRecord {
        input: input.display().to_string(),
        style: preset.name.clone(),
        preset: preset.name.clone(),
        sets: Vec::new(),
        seed: recipe.sampler.seed,
    };
    paint::save_painting(out, &img, &record).unwrap();
}

fn paint_benches(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap();
    let mut g = c.benchmark_group("paint");
    g.sample_size(10)
        .warm_up_time(Duration::from_secs(2))
        .measurement_time(Duration::from_secs(12));
    let square = photo(dir.path(), "astronaut.jpg", 2048, 2048, "square.png");
    let mosaic = style::load("mosaic").unwrap();
    let out = dir.path().join("out.png");
    g.bench_function("2048x2048 mosaic", |b| {
        b.iter(|| paint_file(&square, &mosaic, &out))
    });
    let big = photo(dir.path(), "coffee.png", 4243, 2822, "12mp.png");
    for (name, _) in BUILT_IN {
        let preset = style::load(name).unwrap();
        g.bench_function(format!("12 MP {name}"), |b| {
            b.iter(|| paint_file(&big, &preset, &out))
        });
    }
    g.finish();
}

fn batch_benches(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap();
    let sources = ["astronaut.jpg", "chelsea.png", "coffee.png"];
    let inputs: Vec<PathBuf> = (0..12)
        .map(|k| {
            let source = sources[k % sources.len()];
            photo(dir.path(), source, 1224, 816, &format!("in{k}.png"))
        })
        .collect();
    let preset = style::load("mosaic").unwrap();
    let mut g = c.benchmark_group("batch of 12 one-megapixel photos");
    g.sample_size(10)
        .warm_up_time(Duration::from_secs(2))
        .measurement_time(Duration::from_secs(40));
    for jobs in [1, 2] {
        let out = dir.path().join(format!("out{jobs}"));
        std::fs::create_dir_all(&out).unwrap();
        let items: Vec<Item> = inputs
            .iter()
            .enumerate()
            .map(|(k, input)| Item {
                input: input.clone(),
                output: out.join(format!("{k}.mosaic.png")),
            })
            .collect();
        g.bench_function(format!("{jobs} job(s)"), |b| {
            b.iter(|| {
                let outcomes = batch::run(
                    &items,
                    jobs,
                    true,
                    batch::MEMORY_BUDGET,
                    |item| {
                        paint_file(&item.input, &preset, &item.output);
                        Ok(())
                    },
                    |_, _, _| {},
                );
                assert!(outcomes.iter().all(|o| *o == batch::Outcome::Done));
            })
        });
    }
    g.finish();
}

criterion_group!(benches, paint_benches, batch_benches);
criterion_main!(benches);
