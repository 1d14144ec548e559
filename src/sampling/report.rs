//! The `--report` of the sampler: per stage the time and counts, then the quality figures,
//! as aligned text for people or as one JSON object for scripts.

use super::quality::Quality;
use super::Stats;
use std::fmt::Write;

fn ms(d: std::time::Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

/// The report as text, with `label`s naming the runs in a side-by-side comparison.
#[must_use]
pub fn text(stats: &Stats, quality: Option<&Quality>) -> String {
    let mut s = String::new();
    let total = stats.seeding_time
        + stats.relaxation_time
        + stats.triangulation_time
        + stats.population_time;
    let _ = writeln!(s, "stage           time       counts");
    let _ = writeln!(
        s,
        "seeding     {:9.1} ms   estimate {:.0}, boundary {}, seeded {}, final rho {:.2}",
        ms(stats.seeding_time),
        stats.estimated_count,
        stats.boundary,
        stats.seeded,
        stats.final_rho
    );
    let _ = writeln!(
        s,
        "relaxation  {:9.1} ms   iterations {}, last step {:.2e} of the size",
        ms(stats.relaxation_time),
        stats.iterations,
        stats.last_step
    );
    let _ = writeln!(
        s,
        "triangles   {:9.1} ms   rebuilds {}, flips {}, flip cap hits {}",
        ms(stats.triangulation_time),
        stats.rebuilds,
        stats.flips,
        stats.flip_cap_hits
    );
    let _ = writeln!(
        s,
        "population  {:9.1} ms   inserted {}, deleted {}",
        ms(stats.population_time),
        stats.inserted,
        stats.deleted
    );
    let _ = writeln!(s, "total       {:9.1} ms", ms(total));
    if let Some(q) = quality {
        let _ = writeln!(s, "{}", quality_line(q));
    }
    s
}

/// One line of quality figures.
#[must_use]
pub fn quality_line(q: &Quality) -> String {
    format!(
        "quality: {} samples; nearest-neighbour d min {:.3}, p5 {:.3}, median {:.3}, mean {:.3}; \
         coverage {:.4}, overlap {:.4}; triangle quality {:.3}",
        q.count,
        q.nn_min,
        q.nn_p5,
        q.nn_median,
        q.nn_mean,
        q.coverage,
        q.overlap,
        q.triangle_quality
    )
}

/// Side-by-side quality of several runs (e.g. random, seed only, relaxed).
#[must_use]
pub fn comparison(rows: &[(&str, &Quality)]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<12} {:>8} {:>7} {:>7} {:>7} {:>7} {:>9} {:>8} {:>9}",
        "placement",
        "samples",
        "nn min",
        "nn p5",
        "median",
        "mean",
        "coverage",
        "overlap",
        "tri qual"
    );
    for (label, q) in rows {
        let _ = writeln!(
            s,
            "{:<12} {:>8} {:>7.3} {:>7.3} {:>7.3} {:>7.3} {:>9.4} {:>8.4} {:>9.3}",
            label,
            q.count,
            q.nn_min,
            q.nn_p5,
            q.nn_median,
            q.nn_mean,
            q.coverage,
            q.overlap,
            q.triangle_quality
        );
    }
    s
}

fn quality_json(q: &Quality) -> String {
    format!(
        "{{\"count\": {}, \"nn_min\": {}, \"nn_p5\": {}, \"nn_median\": {}, \"nn_mean\": {}, \
         \"coverage\": {}, \"overlap\": {}, \"triangle_quality\": {}}}",
        q.count,
        num(q.nn_min),
        num(q.nn_p5),
        num(q.nn_median),
        num(q.nn_mean),
        num(q.coverage),
        num(q.overlap),
        num(q.triangle_quality)
    )
}

/// JSON numbers cannot be NaN or infinite.
fn num(v: f64) -> String {
    if v.is_finite() {
        format!("{v}")
    } else {
        "null".into()
    }
}

/// The report as one JSON object; `baselines` are extra labelled quality figures.
#[must_use]
pub fn json(stats: &Stats, quality: Option<&Quality>, baselines: &[(&str, &Quality)]) -> String {
    let mut s = String::from("{");
    let _ = write!(
        s,
        "\"estimated_count\": {}, \"boundary\": {}, \"seeded\": {}, \"final_rho\": {}, \
         \"inserted\": {}, \"deleted\": {}, \"flips\": {}, \"flip_cap_hits\": {}, \
         \"rebuilds\": {}, \"iterations\": {}, \"last_step\": {}, \
         \"seconds\": {{\"seeding\": {}, \"relaxation\": {}, \"triangulation\": {}, \"population\": {}}}",
        num(stats.estimated_count),
        stats.boundary,
        stats.seeded,
        num(stats.final_rho),
        stats.inserted,
        stats.deleted,
        stats.flips,
        stats.flip_cap_hits,
        stats.rebuilds,
        stats.iterations,
        num(stats.last_step),
        stats.seeding_time.as_secs_f64(),
        stats.relaxation_time.as_secs_f64(),
        stats.triangulation_time.as_secs_f64(),
        stats.population_time.as_secs_f64()
    );
    if let Some(q) = quality {
        let _ = write!(s, ", \"quality\": {}", quality_json(q));
    }
    if !baselines.is_empty() {
        s.push_str(", \"baselines\": {");
        for (i, (label, q)) in baselines.iter().enumerate() {
            if i > 0 {
                s.push_str(", ");
            }
            let _ = write!(s, "\"{label}\": {}", quality_json(q));
        }
        s.push('}');
    }
    s.push('}');
    s
}
