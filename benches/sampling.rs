//! Speed of the sampler: N = 10 k on a photo's metric (seeding, 100 iterations with
//! triangulation updates), N = 100 k and 1 M end to end, per-iteration cost against N.
//!
//! `seeding` compares the lattice seed with the paper's relaxation dart throwing on the photo's
//! metric and on the rotating 4:1 field the metric meshers are compared on. `end_to_end` runs the sampler on that rotating field and on one whose
//! orientation has singular points (ellipses along a vector field's direction).
//!
//! Run: `cargo bench --bench sampling`. Stage times come from the sampler's own stats through
//! `iter_custom`, so "iterations" excludes seeding. The 1 M case takes about 40 s per run and
//! is measured only with `ANISOPAINT_BENCH_1M=1`.

use anisopaint::field::{AnalyticField, MetricParams, Tensor, TensorField};
use anisopaint::sampling::{self, SamplerParams, Seeding};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use std::time::Duration;

/// The astronaut's metric with cell sizes scaled so that it needs about `n` samples.
fn photo_field(n: f64) -> TensorField {
    let photo = image::open("samples/astronaut.jpg").expect("samples/astronaut.jpg");
    sampling::seeding::photo_metric_for_count(&photo, &MetricParams::default(), n).1
}

/// A constant isotropic field on a `side²` domain needing about `n` samples.
fn constant_field(n: f64, side: usize) -> TensorField {
    let diag = (2.0f64).sqrt() * side as f64;
    let radius = ((side * side) as f64 / (2.0 * 3f64.sqrt() * n)).sqrt();
    AnalyticField::parse(&format!("constant:size={}", radius / diag))
        .unwrap()
        .field(side, side)
}

/// 4:1 ellipses whose axes turn by π across a `side²` square (the angle grows along x and y),
/// sized for about `n` samples: the field of `benches/packing.py field rotating`.
fn rotating_field(n: f64, side: usize) -> TensorField {
    let b = ((side * side) as f64 / n / (2.0 * 3f64.sqrt()) / 4.0).sqrt();
    let s = side as f64;
    TensorField::from_fn(side, side, |p| {
        let angle = std::f64::consts::PI * (0.6 * p.x / s + 0.4 * p.y / s);
        Tensor::from_eigen(angle, 4.0 * b, b)
    })
}

/// 4:1 ellipses along the direction of the vector field `(sin ωx, sin ωy)` with four periods
/// across a `side²` square, sized for about `n` samples: its sources, sinks and saddles are
/// singular points of the orientation at full anisotropy (the field of a flow's direction).
fn singular_field(n: f64, side: usize) -> TensorField {
    let b = ((side * side) as f64 / n / (2.0 * 3f64.sqrt()) / 4.0).sqrt();
    let w = std::f64::consts::TAU * 4.0 / side as f64;
    TensorField::from_fn(side, side, |p| {
        let angle = (w * p.y).sin().atan2((w * p.x).sin());
        Tensor::from_eigen(angle, 4.0 * b, b)
    })
}

fn stage(
    field: &TensorField,
    pick: fn(&sampling::Stats) -> Duration,
) -> impl FnMut(u64) -> Duration + '_ {
    stage_with(field, SamplerParams::default(), pick)
}

fn stage_with(
    field: &TensorField,
    params: SamplerParams,
    pick: fn(&sampling::Stats) -> Duration,
) -> impl FnMut(u64) -> Duration + '_ {
    move |iters| {
        (0..iters)
            .map(|_| pick(&sampling::sample(field, &params).unwrap().stats))
            .sum()
    }
}

fn seeding(c: &mut Criterion) {
    let fields = [
        ("photo_10k", photo_field(10_000.0)),
        ("rotating_11k", rotating_field(11_000.0, 1024)),
    ];
    let mut g = c.benchmark_group("seeding");
    g.sample_size(10);
    for (name, field) in &fields {
        for method in [Seeding::Lattice, Seeding::Darts] {
            let params = SamplerParams {
                seeding: method,
                iterations: 0,
                ..SamplerParams::default()
            };
            g.bench_function(BenchmarkId::new(method.name(), name), |b| {
                b.iter_custom(stage_with(field, params.clone(), |s| s.seeding_time))
            });
        }
    }
    g.finish();
}

fn photo_10k(c: &mut Criterion) {
    let field = photo_field(10_000.0);
    let mut g = c.benchmark_group("photo_metric_10k");
    g.sample_size(10);
    g.bench_function("seeding", |b| {
        b.iter_custom(stage(&field, |s| s.seeding_time))
    });
    g.bench_function("100_iterations", |b| {
        b.iter_custom(stage(&field, |s| {
            s.relaxation_time + s.triangulation_time + s.population_time
        }))
    });
    g.finish();
}

fn scaling(c: &mut Criterion) {
    let mut sizes = vec![(10_000.0, 1024), (100_000.0, 1024)];
    if std::env::var_os("ANISOPAINT_BENCH_1M").is_some() {
        sizes.push((1_000_000.0, 2048));
    }
    let mut g = c.benchmark_group("constant_field");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(20));
    for (n, side) in sizes {
        let field = constant_field(n, side);
        g.bench_with_input(BenchmarkId::new("end_to_end", n as u64), &field, |b, f| {
            b.iter(|| sampling::sample(f, &SamplerParams::default()).unwrap())
        });
        g.bench_with_input(
            BenchmarkId::new("per_iteration", n as u64),
            &field,
            |b, f| {
                b.iter_custom(|iters| {
                    (0..iters)
                        .map(|_| {
                            let s = sampling::sample(f, &SamplerParams::default())
                                .unwrap()
                                .stats;
                            (s.relaxation_time + s.triangulation_time + s.population_time)
                                / s.iterations.max(1) as u32
                        })
                        .sum()
                })
            },
        );
    }
    g.finish();
}

/// A whole run on a smooth field and on one with singular points, both 11 k samples: the
/// triangulation's upkeep where particles never come to rest.
fn singular(c: &mut Criterion) {
    let fields = [
        ("rotating_11k", rotating_field(11_000.0, 1024)),
        ("singular_11k", singular_field(11_000.0, 1024)),
    ];
    let mut g = c.benchmark_group("end_to_end");
    g.sample_size(10);
    for (name, field) in &fields {
        g.bench_function(*name, |b| {
            b.iter(|| sampling::sample(field, &SamplerParams::default()).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, seeding, photo_10k, scaling, singular);
criterion_main!(benches);
