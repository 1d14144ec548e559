//! Progress of the long stages of a painting, reported to an [`Observer`] the caller chooses:
//! the binary draws indicatif bars and prints per-stage timings with `-v`; the library's
//! plain functions report to [`Silent`]. Reports come from the driving thread between
//! stages and once per relaxation iteration, never from inside a parallel loop.

use std::time::{Duration, Instant};

/// A long stage of the chain from input to painting.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Decoding the photo or reading the tensor field.
    Reading,
    /// Structure tensor and metric (paper sections 4 and 5).
    Metric,
    /// Boundary samples and relaxation dart throwing (section 3.1).
    Seeding,
    /// Force iterations with triangulation repairs and population control (3.2–3.4).
    Relaxation,
    /// Voronoi cells and the look (sections 6 and 7).
    Rendering,
    /// Encoding and writing the output.
    Writing,
}

impl Stage {
    /// The stage's name as shown to users.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Stage::Reading => "reading",
            Stage::Metric => "metric",
            Stage::Seeding => "seeding",
            Stage::Relaxation => "relaxation",
            Stage::Rendering => "rendering",
            Stage::Writing => "writing",
        }
    }
}

/// Receives progress reports. Every method does nothing by default.
pub trait Observer: Sync {
    /// `stage` starts; `total` is its number of steps when known (relaxation: iterations).
    fn begin(&self, _stage: Stage, _total: Option<u64>) {}
    /// `done` steps of `stage` are complete.
    fn advance(&self, _stage: Stage, _done: u64) {}
    /// `stage` ended after `elapsed`; `steps` steps were done when it counts them.
    fn end(&self, _stage: Stage, _elapsed: Duration, _steps: Option<u64>) {}
}

/// An observer that ignores every report.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Observer for Silent {}

/// Runs `work` as `stage` (a stage without steps), reporting its start and its duration.
pub fn timed<T>(observer: &dyn Observer, stage: Stage, work: impl FnOnce() -> T) -> T {
    observer.begin(stage, None);
    let start = Instant::now();
    let out = work();
    observer.end(stage, start.elapsed(), None);
    out
}
