//! Speed of the looks as `paint` draws them (cells, look, outlines and highlights) from a
//! sampling made once outside the timing: a mosaic of a 2048² photo with about 40 k cells,
//! the fabric of the same, pen-hatch and cross-hatch of a 12 MP photo.
//!
//! Run: `cargo bench --bench render`.

use anisopaint::field::{MetricParams, TensorField};
use anisopaint::input::{photo_field, FieldOptions};
use anisopaint::paint::{self, Extras, Recipe, Samples};
use anisopaint::progress::Silent;
use anisopaint::render::RenderSize;
use anisopaint::sampling::{self, SamplerParams, Sampling};
use anisopaint::style;
use criterion::measurement::WallTime;
use criterion::{criterion_group, criterion_main, BenchmarkGroup, Criterion};
use image::DynamicImage;
use std::time::Duration;

/// The astronaut resized to `w × h`, its metric scaled to about `n` samples, and a sampling.
fn scene(w: u32, h: u32, n: f64) -> (DynamicImage, TensorField, Sampling) {
    let photo = image::open("samples/astronaut.jpg").expect("samples/astronaut.jpg");
    let photo = photo.resize_exact(w, h, image::imageops::FilterType::Triangle);
    let (_, field) = sampling::seeding::photo_metric_for_count(&photo, &MetricParams::default(), n);
    let s = sampling::sample(&field, &SamplerParams::default()).unwrap();
    (photo, field, s)
}

/// `style`'s look drawn through the paint pipeline (its cells, outlines and highlights), from
/// the sampling of `setup`.
fn bench_look(
    g: &mut BenchmarkGroup<WallTime>,
    name: &str,
    style: &str,
    setup: &(DynamicImage, TensorField, Sampling),
) {
    let (photo, field, s) = setup;
    let size = RenderSize {
        width: photo.width() as usize,
        height: photo.height() as usize,
        supersample: 2,
    };
    let preset = style::load(style).unwrap();
    let recipe = Recipe::from_preset(&preset, FieldOptions::default(), None).unwrap();
    let mut loaded = photo_field(photo.clone(), &recipe.field.metric);
    loaded.metric = std::sync::Arc::new(field.clone());
    let samples = Samples {
        positions: s.positions.clone(),
        metrics: s.metrics.clone(),
        mesh: s.mesh.clone(),
    };
    g.bench_function(name, |b| {
        b.iter(|| {
            paint::draw(&loaded, &samples, &recipe, size, Extras::default(), &Silent).unwrap()
        })
    });
}

fn renderers(c: &mut Criterion) {
    let square = scene(2048, 2048, 40_000.0);
    eprintln!("2048² scene: {} cells", square.2.positions.len());
    let large = scene(4000, 3000, 60_000.0);
    eprintln!("12 MP scene: {} cells", large.2.positions.len());
    let mut g = c.benchmark_group("render");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(15));
    bench_look(&mut g, "mosaic_2048_40k_cells", "mosaic", &square);
    bench_look(&mut g, "fabric_2048", "fabric", &square);
    bench_look(&mut g, "pen-hatch_12mp", "pen-hatch", &large);
    bench_look(&mut g, "crosshatch_12mp", "crosshatch", &large);
    g.finish();
}

criterion_group!(benches, renderers);
criterion_main!(benches);
