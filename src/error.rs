//! The library's error type: every failure names the file, pixel or key it concerns, so the
//! binary can print one clear line and exit with status 2 (bad input) without panicking.

use std::path::PathBuf;

/// Everything that can go wrong between reading an input and writing an output.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Reading or writing a file failed at the operating-system level.
    #[error("{path}: {source}")]
    Io {
        /// The file concerned.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The file exists but is not an image we can decode (corrupt, truncated, unsupported).
    #[error("{path}: cannot decode image: {reason}")]
    Decode {
        /// The file concerned.
        path: PathBuf,
        /// What the decoder said.
        reason: String,
    },
    /// The image has zero width or height.
    #[error("{path}: image is empty ({width}x{height})")]
    EmptyImage {
        /// The file concerned.
        path: PathBuf,
        /// Width in pixels.
        width: u64,
        /// Height in pixels.
        height: u64,
    },
    /// The image is larger than the documented pixel limit.
    #[error("{path}: image is too large: {width}x{height} exceeds the limit of {limit} pixels")]
    TooLarge {
        /// The file concerned.
        path: PathBuf,
        /// Width in pixels.
        width: u64,
        /// Height in pixels.
        height: u64,
        /// The limit in pixels.
        limit: u64,
    },
    /// A `.npy` file has the wrong layout or element type.
    #[error("{path}: {reason}")]
    Npy {
        /// The file concerned.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// A tensor field holds NaN or infinite values.
    #[error("{path}: non-finite value at pixel ({x}, {y})")]
    NonFinite {
        /// The file (or analytic field) concerned.
        path: PathBuf,
        /// Column of the first bad pixel.
        x: usize,
        /// Row of the first bad pixel.
        y: usize,
    },
    /// A field declared to be a metric holds a tensor that is not positive definite.
    #[error("{path}: tensor at pixel ({x}, {y}) is not positive definite (eigenvalues {l1:.4e}, {l2:.4e}); pass --tensor general to map it")]
    NotPositiveDefinite {
        /// The file concerned.
        path: PathBuf,
        /// Column of the first bad pixel.
        x: usize,
        /// Row of the first bad pixel.
        y: usize,
        /// Larger eigenvalue.
        l1: f64,
        /// Smaller eigenvalue.
        l2: f64,
    },
    /// A parameter has a value outside its valid range, or an unknown name.
    #[error("invalid {key}: {reason}")]
    InvalidParameter {
        /// The parameter's name as the user writes it.
        key: String,
        /// Why the value is rejected.
        reason: String,
    },
    /// A CSV file (samples) is malformed.
    #[error("{path}:{line}: {reason}")]
    Csv {
        /// The file concerned.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        reason: String,
    },
    /// Encoding an output image failed.
    #[error("{path}: cannot encode image: {reason}")]
    Encode {
        /// The file concerned.
        path: PathBuf,
        /// What the encoder said.
        reason: String,
    },
}

/// The library's result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// Wraps an I/O error with the path it concerns.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }

    /// [`Error::io`] for reading an input: a folder named as one says that `batch` paints
    /// folders, instead of the system's bare "Is a directory".
    pub fn input_io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        let path = path.into();
        if path.is_dir() {
            let hint = "a folder, not an image: `anisopaint batch FOLDER -s STYLE -o OUT` paints every image in it";
            return Error::io(path, std::io::Error::new(source.kind(), hint));
        }
        Error::io(path, source)
    }

    /// Builds an [`Error::InvalidParameter`].
    pub fn param(key: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::InvalidParameter {
            key: key.into(),
            reason: reason.into(),
        }
    }
}
