//! Speed of the renderers (issue targets on two cores: Voronoi label map + mosaic fill of a
//! 2048x2048 image with about 40 k cells and 2x2 supersampling ≤ 0.25 s; a 12 MP textured
//! render ≤ 1.5 s; fabric texture 2048² ≤ 1.5 s). Sampling happens once, outside the timing.
//!
//! Run: `cargo bench --bench render`.

use anisopaint::field::{MetricParams, TensorField};
use anisopaint::render::{render, Look, RenderSize};
use anisopaint::sampling::{self, SamplerParams, Sampling};
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

fn bench_look(
    g: &mut BenchmarkGroup<WallTime>,
    name: &str,
    look: &str,
    setup: &(DynamicImage, TensorField, Sampling),
) {
    let (photo, field, s) = setup;
    let size = RenderSize {
        width: photo.width() as usize,
        height: photo.height() as usize,
        supersample: 2,
    };
    let look = Look::named(look).unwrap();
    g.bench_function(name, |b| {
        b.iter(|| {
            render(
                &look,
                &s.positions,
                &s.metrics,
                &s.mesh,
                field,
                Some(photo),
                size,
            )
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
    bench_look(&mut g, "mosaic_2048_40k_cells_2x2", "mosaic", &square);
    bench_look(&mut g, "fabric_2048", "fabric", &square);
    bench_look(&mut g, "hatch_12mp_2x2", "hatch", &large);
    bench_look(&mut g, "crosshatch_12mp_2x2", "crosshatch", &large);
    g.finish();
}

criterion_group!(benches, renderers);
criterion_main!(benches);
