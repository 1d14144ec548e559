//! The sampler against the quality targets of its issue, each measured by an independent
//! evaluator written here: brute-force nearest neighbours over all pairs, coverage and overlap
//! on a raster, spade's own Delaunay triangulation as the oracle for the anisotropic one, and
//! random placement and the seed alone as baselines that must score clearly worse.

use anisopaint::field::{self, AnalyticField, Tensor, TensorField};
use anisopaint::input::{self, FieldOptions, Input};
use anisopaint::sampling::{
    self, quality, rng::Rng, seeding, AnisotropicDelaunay, SamplerParams, Sampling, Seeding,
};
use glam::DVec2;
use std::collections::BTreeSet;

fn analytic(spec: &str, w: usize, h: usize) -> TensorField {
    let a = AnalyticField::parse(spec).unwrap();
    let raw = a.field(w, h);
    if a.is_metric() {
        raw
    } else {
        field::metric::metric_from_general(&raw, &field::MappingParams::default())
    }
}

fn photo_metric(path: &str) -> TensorField {
    let options = FieldOptions::default();
    input::load_field(&Input::parse(path).unwrap(), &options)
        .unwrap()
        .metric
        .as_ref()
        .clone()
}

/// Brute-force nearest-neighbour summary, coverage and overlap of a sampling.
fn evaluate(s: &Sampling, field: &TensorField) -> quality::Quality {
    let nn = quality::brute_force_nearest(&s.positions, &s.metrics);
    let mut q = quality::summarize(&nn);
    let (coverage, overlap) =
        quality::coverage_and_overlap(&s.positions, &s.metrics, field.domain());
    q.count = s.positions.len();
    q.coverage = coverage;
    q.overlap = overlap;
    q
}

fn check_inside(s: &Sampling, field: &TensorField) {
    let d = field.domain();
    for (p, m) in s.positions.iter().zip(&s.metrics) {
        assert!(
            p.x.is_finite() && p.y.is_finite() && m.is_finite(),
            "{p:?} {m:?}"
        );
        assert!(
            p.x >= 0.0 && p.y >= 0.0 && p.x <= d.x && p.y <= d.y,
            "outside: {p:?}"
        );
    }
    s.mesh.sanity_check(&s.positions, &[]).unwrap();
}

/// The bounds the issue sets for constant fields.
fn assert_constant_field_targets(q: &quality::Quality, estimate: f64, what: &str) {
    assert!(
        (0.95..=1.05).contains(&q.nn_mean),
        "{what}: nn mean {}",
        q.nn_mean
    );
    assert!(q.nn_p5 >= 0.90, "{what}: nn p5 {}", q.nn_p5);
    assert!(q.nn_min >= 0.80, "{what}: nn min {}", q.nn_min);
    assert!(q.coverage >= 0.87, "{what}: coverage {}", q.coverage);
    assert!(q.overlap <= 0.01, "{what}: overlap {}", q.overlap);
    let ratio = q.count as f64 / estimate;
    assert!(
        (0.9..=1.1).contains(&ratio),
        "{what}: {} samples for {estimate:.0}",
        q.count
    );
}

#[test]
fn constant_isotropic_field_meets_the_targets() {
    let field = analytic("constant:size=0.01", 512, 512);
    for seed in [0, 1] {
        let params = SamplerParams {
            seed,
            ..SamplerParams::default()
        };
        let s = sampling::sample(&field, &params).unwrap();
        check_inside(&s, &field);
        let q = evaluate(&s, &field);
        assert_constant_field_targets(&q, s.stats.estimated_count, &format!("seed {seed}"));
    }
}

#[test]
fn constant_anisotropic_field_meets_the_targets_and_matches_spade() {
    let field = analytic("constant:size=0.008,angle=30,anisotropy=4", 480, 400);
    let s = sampling::sample(&field, &SamplerParams::default()).unwrap();
    check_inside(&s, &field);
    let q = evaluate(&s, &field);
    assert_constant_field_targets(&q, s.stats.estimated_count, "4:1 at 30°");

    // Oracle: spade's Delaunay triangulation of the points mapped by m⁻¹.
    let inv = field.node(0, 0).inverse().unwrap();
    let mapped: Vec<DVec2> = s.positions.iter().map(|&p| inv.mul_vec(p)).collect();
    let (oracle, missing) = AnisotropicDelaunay::isotropic(&mapped);
    assert!(missing.is_empty());
    // Edges between two boundary samples are left out: mapped by m⁻¹, the samples of one
    // domain edge are collinear only up to rounding, and spade then adds slivers along it.
    let fixed = s.fixed as u32;
    let edges = |m: &AnisotropicDelaunay| -> BTreeSet<(u32, u32)> {
        m.triangles()
            .flat_map(|[a, b, c]| [(a, b), (b, c), (c, a)])
            .map(|(x, y)| (x.min(y), x.max(y)))
            .filter(|&(_, y)| y >= fixed)
            .collect()
    };
    let (ours, theirs) = (edges(&s.mesh), edges(&oracle));
    // Equal up to cocircular ties: a tie is a quad whose four mapped points are cocircular,
    // where either diagonal is Delaunay. Check every difference is such a tie.
    let mine_only: Vec<_> = ours.difference(&theirs).collect();
    let theirs_only: Vec<_> = theirs.difference(&ours).collect();
    assert_eq!(mine_only.len(), theirs_only.len());
    for &&(a, b) in &mine_only {
        let quad: Vec<DVec2> = [a, b].iter().map(|&v| mapped[v as usize]).collect();
        // Find the two opposite vertices in our mesh.
        let opposite: Vec<DVec2> = s
            .mesh
            .triangles()
            .filter(|t| t.contains(&a) && t.contains(&b))
            .map(|t| mapped[*t.iter().find(|&&v| v != a && v != b).unwrap() as usize])
            .collect();
        assert_eq!(opposite.len(), 2);
        let c = |p: DVec2| robust::Coord { x: p.x, y: p.y };
        let det = robust::incircle(c(quad[0]), c(quad[1]), c(opposite[0]), c(opposite[1]));
        assert!(
            det.abs() < 1e-6,
            "edge {a}-{b} differs from spade and is no tie ({det})"
        );
    }
}

fn assert_varying_field_targets(name: &str, field: &TensorField) {
    let s = sampling::sample(field, &SamplerParams::default()).unwrap();
    check_inside(&s, field);
    let q = evaluate(&s, field);
    assert!(q.coverage >= 0.85, "{name}: coverage {}", q.coverage);
    assert!(q.overlap <= 0.02, "{name}: overlap {}", q.overlap);
    assert_eq!(s.stats.flip_cap_hits, 0, "{name}: flip cap hit");
}

/// The degenerate-point field at several sizes and seeds: its turning, stretched ellipses are
/// where insertion used to overcrowd the packing (overlap 1.4–2.2 % before the pressure rule).
#[test]
fn degenerate_point_packs_within_the_overlap_bound() {
    for (w, h, seed) in [(400, 400, 0), (512, 512, 1), (700, 500, 2)] {
        let field = analytic("degenerate-point", w, h);
        let s = sampling::sample(
            &field,
            &SamplerParams {
                seed,
                ..SamplerParams::default()
            },
        )
        .unwrap();
        check_inside(&s, &field);
        let q = evaluate(&s, &field);
        assert!(
            q.coverage >= 0.85 && q.overlap <= 0.02,
            "{w}x{h} seed {seed}: {q:?}"
        );
        assert_eq!(
            s.stats.flip_cap_hits, 0,
            "{w}x{h} seed {seed}: flip cap hit"
        );
    }
}

#[test]
fn varying_fields_pack_without_holes_or_overlaps() {
    let cases = [
        ("two-point-load", analytic("two-point-load", 450, 300)),
        ("circular", analytic("circular", 500, 500)),
        ("astronaut", photo_metric("samples/astronaut.jpg")),
        ("chelsea", photo_metric("samples/chelsea.png")),
        ("coffee", photo_metric("samples/coffee.png")),
    ];
    for (name, field) in cases {
        assert_varying_field_targets(name, &field);
    }
}

/// The relaxation against random placement and against the paper's dart-throwing seed alone.
/// (A lattice seed places nothing closer than its ρ = 0.95, so its nearest-neighbour
/// distances start above the relaxed ones; what relaxation adds to it is coverage.)
#[test]
fn relaxed_beats_random_placement_and_the_seed_alone() {
    let field = photo_metric("samples/chelsea.png");
    let darts = SamplerParams {
        seeding: Seeding::Darts,
        ..SamplerParams::default()
    };
    let relaxed = sampling::sample(&field, &darts).unwrap();
    let seeded = sampling::sample(
        &field,
        &SamplerParams {
            iterations: 0,
            ..darts.clone()
        },
    )
    .unwrap();
    let lattice = |iterations| {
        let params = SamplerParams {
            seeding: Seeding::Lattice,
            iterations,
            ..SamplerParams::default()
        };
        evaluate(&sampling::sample(&field, &params).unwrap(), &field)
    };
    let (lattice_relaxed, lattice_seeded) = (lattice(100), lattice(0));
    assert!(
        lattice_relaxed.coverage > lattice_seeded.coverage + 0.1,
        "{lattice_relaxed:?} {lattice_seeded:?}"
    );
    let random_positions =
        seeding::random_positions(&field, relaxed.positions.len(), &mut Rng::new(5, 1));
    let random_metrics: Vec<Tensor> = random_positions.iter().map(|&p| field.sample(p)).collect();
    let nn = quality::brute_force_nearest(&random_positions, &random_metrics);
    let mut random = quality::summarize(&nn);
    (random.coverage, random.overlap) =
        quality::coverage_and_overlap(&random_positions, &random_metrics, field.domain());

    let (r, s, x) = (
        evaluate(&relaxed, &field),
        evaluate(&seeded, &field),
        random,
    );
    assert!(
        r.coverage > s.coverage + 0.05 && r.coverage > x.coverage + 0.15,
        "{r:?} {s:?} {x:?}"
    );
    assert!(r.overlap < x.overlap / 5.0, "{r:?} {x:?}");
    assert!(
        r.nn_p5 > x.nn_p5 + 0.3 && r.nn_p5 > s.nn_p5,
        "{r:?} {s:?} {x:?}"
    );
    assert!(
        (r.nn_mean - 1.0).abs() < (s.nn_mean - 1.0).abs(),
        "{r:?} {s:?}"
    );
}

#[test]
fn one_ring_nearest_neighbours_agree_with_brute_force() {
    let field = photo_metric("samples/coffee.png");
    let s = sampling::sample(&field, &SamplerParams::default()).unwrap();
    let reported = quality::measure(&s.positions, &s.metrics, &s.mesh, &field);
    let brute = quality::summarize(&quality::brute_force_nearest(&s.positions, &s.metrics));
    assert!((reported.nn_min - brute.nn_min).abs() < 1e-12);
    assert!((reported.nn_p5 - brute.nn_p5).abs() < 1e-12);
    assert!((reported.nn_mean - brute.nn_mean).abs() < 1e-9);
}

#[test]
fn same_seed_same_samples_at_any_thread_count() {
    let field = analytic("degenerate-point", 300, 260);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| sampling::sample(&field, &SamplerParams::default()).unwrap())
    };
    let (one, two) = (run(1), run(2));
    let bits = |s: &Sampling| -> Vec<u64> {
        s.positions
            .iter()
            .flat_map(|p| [p.x.to_bits(), p.y.to_bits()])
            .collect()
    };
    assert_eq!(bits(&one), bits(&two));
    assert_eq!(
        one.mesh.triangles().collect::<Vec<_>>(),
        two.mesh.triangles().collect::<Vec<_>>()
    );
    let other_seed = sampling::sample(
        &field,
        &SamplerParams {
            seed: 9,
            ..SamplerParams::default()
        },
    )
    .unwrap();
    assert_ne!(bits(&one), bits(&other_seed));
}

#[test]
fn unusable_fields_are_refused_before_any_work() {
    let mut bad = TensorField::constant(20, 10, Tensor::isotropic(3.0));
    bad.data_mut()[15] = [f32::NAN, 0.0, 1.0];
    let err = sampling::sample(&bad, &SamplerParams::default())
        .unwrap_err()
        .to_string();
    assert!(err.contains("pixel (15, 0)"), "{err}");
    bad.data_mut()[15] = [-1.0, 0.0, 1.0];
    assert!(sampling::sample(&bad, &SamplerParams::default()).is_err());
    bad.data_mut()[15] = [0.0, 0.0, 0.0];
    assert!(sampling::sample(&bad, &SamplerParams::default()).is_err());
    bad.data_mut()[15] = [1e9, 0.0, 1.0];
    assert!(sampling::sample(&bad, &SamplerParams::default()).is_err());
    // Tiny ellipses: far too many samples for the limit.
    let tiny = TensorField::constant(4000, 3000, Tensor::isotropic(0.05));
    let err = sampling::sample(&tiny, &SamplerParams::default())
        .unwrap_err()
        .to_string();
    assert!(err.contains("--max-samples"), "{err}");
}

#[test]
fn tiny_domains_work() {
    for (w, h) in [(1, 1), (1, 40), (40, 1), (3, 3)] {
        let field = TensorField::constant(w, h, Tensor::isotropic(0.8));
        let s = sampling::sample(&field, &SamplerParams::default()).unwrap();
        assert!(s.positions.len() >= 4, "{w}x{h}");
        assert!(s.positions.iter().all(|p| p.is_finite()));
    }
}

/// The lattice seed on constant fields, measured by brute force: close to the hexagonal
/// packing (coverage 0.907, no overlap) after relaxation, with the estimated count once the
/// boundary's half-ellipses are counted as halves, and no nearest neighbour much closer than
/// touching. Measured on 700×600 at 2:1 and 4:1, several angles: coverage 0.894-0.903,
/// overlap 0.6-0.95 %, p5 0.910-0.929 (darts on the same fields: coverage 0.870-0.879, p5
/// 0.918-0.934; the 5th percentile sits among the samples next to the fixed boundary).
#[test]
fn lattice_seed_packs_constant_fields_nearly_hexagonally() {
    for (anisotropy, angle) in [(2.0, 20.0), (4.0, -35.0)] {
        let spec = format!("constant:anisotropy={anisotropy},angle={angle},size=0.01");
        let field = analytic(&spec, 700, 600);
        let params = SamplerParams {
            seeding: Seeding::Lattice,
            ..SamplerParams::default()
        };
        let s = sampling::sample(&field, &params).unwrap();
        check_inside(&s, &field);
        let q = evaluate(&s, &field);
        assert!(q.coverage >= 0.89, "{spec}: coverage {}", q.coverage);
        assert!(q.overlap <= 0.01, "{spec}: overlap {}", q.overlap);
        assert!(q.nn_p5 >= 0.9, "{spec}: p5 {}", q.nn_p5);
        let effective = (s.positions.len() - s.fixed) as f64 + 0.5 * s.fixed as f64;
        let estimate = seeding::estimate_count(&field);
        assert!(
            (effective / estimate - 1.0).abs() <= 0.05,
            "{spec}: {effective} of {estimate}"
        );
    }
}

#[test]
fn small_constant_fields_are_seeded_as_a_lattice() {
    // About 1 450 estimated samples, under the 2 000 from which any field gets the lattice: a
    // constant metric gets it anyway (`LATTICE_FROM_COUNT_UNIFORM`), with a row along the
    // walls (`lattice::wall_phase`). Measured here by brute force: darts packed this field to
    // 86.8 % (p5 0.932), the lattice at its default angle to 89.8 % with p5 0.923 (the rows
    // meeting the walls compressed), along the walls 89.8 % with p5 0.946.
    let field = analytic("constant:anisotropy=3,angle=20,size=0.01", 800, 600);
    let s = sampling::sample(&field, &SamplerParams::default()).unwrap();
    check_inside(&s, &field);
    let q = evaluate(&s, &field);
    assert!(q.coverage >= 0.885, "coverage {}", q.coverage);
    assert!(q.overlap <= 0.01, "overlap {}", q.overlap);
    assert!(q.nn_p5 >= 0.93, "nn p5 {}", q.nn_p5);
    assert!(q.nn_min >= 0.8, "nn min {}", q.nn_min);
    // A field that is not constant keeps the darts there: the same sizes, one node changed.
    let t = field.node(0, 0);
    let corner = Tensor::new(t.xx * 1.01, t.xy * 1.01, t.yy * 1.01);
    let varied = TensorField::from_fn(
        800,
        600,
        |p| {
            if p.x < 1.0 && p.y < 1.0 {
                corner
            } else {
                t
            }
        },
    );
    let darts = sampling::sample(&varied, &SamplerParams::default()).unwrap();
    let lattice = sampling::sample(
        &varied,
        &SamplerParams {
            seeding: Seeding::Lattice,
            ..SamplerParams::default()
        },
    )
    .unwrap();
    assert_ne!(darts.positions, lattice.positions);
}

/// A 4:1 field whose long axes follow a vector field with sources, sinks and saddles (its
/// orientation turns all the way round each of them at full anisotropy: not smooth there).
/// Particles near those points never come to rest; the moves that turn a triangle over are
/// taken back instead of the whole triangulation being rebuilt each time, and the packing
/// stays within bounds that hold for smooth fields too.
#[test]
fn orientation_singularities_keep_the_triangulation_without_rebuilds() {
    let period = 256.0;
    let field = TensorField::from_fn(512, 512, |p| {
        let w = std::f64::consts::TAU / period;
        let angle = (w * p.y).sin().atan2((w * p.x).sin());
        Tensor::from_eigen(angle, 12.0, 3.0)
    });
    let s = sampling::sample(&field, &SamplerParams::default()).unwrap();
    check_inside(&s, &field);
    let q = evaluate(&s, &field);
    // Measured: 2 builds, coverage 84.2 %, overlap 1.5 %, nearest d at least 0.77 (each
    // turned triangle rebuilding the whole mesh: 21 builds, 84.6 %, 1.6 %, 0.56).
    assert!(s.stats.rebuilds <= 3, "{} rebuilds", s.stats.rebuilds);
    assert!(q.coverage >= 0.83 && q.overlap <= 0.025, "{q:?}");
    assert!(q.nn_min >= 0.6, "{q:?}");
}
