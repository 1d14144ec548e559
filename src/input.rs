//! Inputs as users name them, turned into fields: a photo, a `.npy` tensor field or an
//! `analytic:` spec becomes a [`LoadedField`] (its metric, the raw tensor it came from, the
//! photo). Reading the files is [`crate::io`]'s, deriving the metric [`crate::field`]'s (paper
//! sections 3 and 4); this module only ties them together, so neither needs the other.

use crate::error::{Error, Result};
use crate::field::{
    flatten_on_paper, metric, photo_metric, AnalyticField, MappingParams, MetricParams, Tensor,
    TensorField,
};
use crate::progress::{timed, Observer, Silent, Stage};
use image::DynamicImage;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// What the user named as input.
#[derive(Clone, Debug, PartialEq)]
pub enum Input {
    /// A photo (PNG, JPEG, TIFF, WebP, GIF (its first frame), BMP, PNM), recognised by content.
    Photo(PathBuf),
    /// A `.npy` tensor field `(H, W, 3)`.
    Npy(PathBuf),
    /// `analytic:NAME[:key=value,...]`.
    Analytic(AnalyticField),
}

impl Input {
    /// Classifies a command-line argument: `analytic:…`, a `.npy` path, or a photo path.
    pub fn parse(arg: &str) -> Result<Input> {
        if let Some(spec) = arg.strip_prefix("analytic:") {
            return Ok(Input::Analytic(AnalyticField::parse(spec)?));
        }
        let path = PathBuf::from(arg);
        let is_npy = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("npy"));
        Ok(if is_npy {
            Input::Npy(path)
        } else {
            Input::Photo(path)
        })
    }

    /// A short name for messages and output names: the file stem or the analytic name.
    #[must_use]
    pub fn stem(&self) -> String {
        match self {
            Input::Photo(p) | Input::Npy(p) => p
                .file_stem()
                .map_or_else(|| "input".into(), |s| s.to_string_lossy().into_owned()),
            Input::Analytic(a) => a.name().to_string(),
        }
    }
}

/// How to read a tensor field from a file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TensorKind {
    /// A metric if every tensor is positive definite, a general tensor otherwise.
    #[default]
    Auto,
    /// Already a metric: used as is; a tensor that is not positive definite is an error.
    Metric,
    /// A general symmetric tensor, mapped by the anti-symmetric mapping.
    General,
}

/// Everything that decides how an input becomes a metric.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FieldOptions {
    /// Photo → metric parameters.
    pub metric: MetricParams,
    /// General tensor → metric parameters.
    pub mapping: MappingParams,
    /// How to read `.npy` files.
    pub tensor_kind: TensorKind,
    /// Domain size of analytic fields in pixels; `None` is 512x512.
    pub analytic_size: Option<(usize, usize)>,
}

/// An input turned into a metric.
#[derive(Clone, Debug)]
pub struct LoadedField {
    /// The metric: ellipse semi-axes in pixels.
    pub metric: Arc<TensorField>,
    /// What the metric was made from: the structure tensor of a photo, or the tensor field as
    /// read or generated. Shared with `metric` when the input already is a metric (a field of
    /// 4096² nodes takes 200 MB).
    pub raw: Arc<TensorField>,
    /// The photo, for previews and rendering.
    pub photo: Option<DynamicImage>,
}

/// Default domain of analytic fields.
pub const DEFAULT_ANALYTIC_SIZE: (usize, usize) = (512, 512);

/// Reads or generates the input and derives its metric.
pub fn load_field(input: &Input, options: &FieldOptions) -> Result<LoadedField> {
    load_field_observed(input, options, &Silent)
}

/// [`load_field`], reporting reading and the metric as stages to `observer`.
pub fn load_field_observed(
    input: &Input,
    options: &FieldOptions,
    observer: &dyn Observer,
) -> Result<LoadedField> {
    options.metric.validate()?;
    validate_mapping(&options.mapping)?;
    match input {
        Input::Photo(path) => {
            let photo = timed(observer, Stage::Reading, || crate::io::read_photo(path))?;
            Ok(timed(observer, Stage::Metric, || {
                photo_field(photo, &options.metric)
            }))
        }
        Input::Npy(path) => {
            let raw = Arc::new(timed(observer, Stage::Reading, || {
                crate::io::read_npy(path)
            })?);
            let metric = timed(observer, Stage::Metric, || {
                tensor_file_metric(path, &raw, options)
            })?;
            Ok(LoadedField {
                metric,
                raw,
                photo: None,
            })
        }
        Input::Analytic(a) => {
            let (w, h) = options.analytic_size.unwrap_or(DEFAULT_ANALYTIC_SIZE);
            if w == 0 || h == 0 || (w as u64) * (h as u64) > crate::io::MAX_PIXELS {
                return Err(Error::param(
                    "size",
                    format!(
                        "{w}x{h} must be non-empty and at most {} pixels",
                        crate::io::MAX_PIXELS
                    ),
                ));
            }
            let (raw, metric) = timed(observer, Stage::Metric, || {
                let raw = Arc::new(a.field(w, h));
                let metric = if a.is_metric() {
                    Arc::clone(&raw)
                } else {
                    Arc::new(metric::metric_from_general(&raw, &options.mapping))
                };
                (raw, metric)
            });
            Ok(LoadedField {
                metric,
                raw,
                photo: None,
            })
        }
    }
}

/// A tensor field already in memory (`(t11, t12, t22)` per node, as a `.npy` file holds it)
/// turned into a metric as such a file is: taken as it is when every tensor is positive
/// definite (or `options.tensor_kind` says it is a metric), else mapped by the paper's
/// anti-symmetric mapping (`options.mapping`).
pub fn tensor_field(raw: TensorField, options: &FieldOptions) -> Result<LoadedField> {
    validate_mapping(&options.mapping)?;
    let raw = Arc::new(raw);
    let metric = tensor_file_metric(Path::new("tensor field"), &raw, options)?;
    Ok(LoadedField {
        metric,
        raw,
        photo: None,
    })
}

/// A photo already in memory turned into a metric (`params` must be valid); the photo is
/// kept as the renderers read it ([`flatten_on_paper`]).
#[must_use]
pub fn photo_field(photo: DynamicImage, params: &MetricParams) -> LoadedField {
    let (raw, metric) = photo_metric(&photo, params);
    LoadedField {
        metric: Arc::new(metric),
        raw: Arc::new(raw),
        photo: Some(flatten_on_paper(photo)),
    }
}

fn validate_mapping(p: &MappingParams) -> Result<()> {
    if !(p.base_size > 0.0 && p.base_size < 1.0) {
        return Err(Error::param(
            "mapping.base_size",
            format!("{} must be in (0, 1)", p.base_size),
        ));
    }
    if !(p.kappa >= 0.0 && p.kappa <= 10.0) {
        return Err(Error::param(
            "mapping.kappa",
            format!("{} must be in [0, 10]", p.kappa),
        ));
    }
    Ok(())
}

/// The metric of a tensor read from a file, according to [`TensorKind`].
fn tensor_file_metric(
    path: &Path,
    raw: &Arc<TensorField>,
    options: &FieldOptions,
) -> Result<Arc<TensorField>> {
    let not_pd = |t: Tensor| !t.is_positive_definite();
    let first_bad = raw.first_node_where(not_pd);
    match (options.tensor_kind, first_bad) {
        (TensorKind::Metric, Some((x, y))) => {
            let e = raw.node(x, y).eigen();
            Err(Error::NotPositiveDefinite {
                path: path.into(),
                x,
                y,
                l1: e.l1,
                l2: e.l2,
            })
        }
        (TensorKind::Metric, None) | (TensorKind::Auto, None) => Ok(Arc::clone(raw)),
        (TensorKind::General, _) | (TensorKind::Auto, Some(_)) => {
            Ok(Arc::new(metric::metric_from_general(raw, &options.mapping)))
        }
    }
}
