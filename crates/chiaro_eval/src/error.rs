//! What can go wrong when reading, comparing or writing images.

use thiserror::Error;

/// An image that cannot be read, written or compared, with the file and the fault.
#[derive(Debug, Error)]
pub enum EvalError {
    /// The file could not be read or decoded.
    #[error("{path}: cannot read the image: {message}")]
    Read {
        /// The file.
        path: String,
        /// What failed.
        message: String,
    },
    /// The file could not be written.
    #[error("{path}: cannot write the image: {message}")]
    Write {
        /// The file.
        path: String,
        /// What failed.
        message: String,
    },
    /// The two images differ in size.
    #[error(
        "{test} is {test_size:?} (width, height) but {reference} is {reference_size:?}: compared images must have the same size"
    )]
    SizeMismatch {
        /// The image under test.
        test: String,
        /// Its width and height.
        test_size: (u32, u32),
        /// The reference image.
        reference: String,
        /// Its width and height.
        reference_size: (u32, u32),
    },
    /// An image holds NaN or infinite values, which no metric can weigh.
    #[error("{path}: {count} non-finite pixels (NaN or infinite), the first at x {x}, y {y}")]
    NonFinite {
        /// The image.
        path: String,
        /// How many pixels have a non-finite channel.
        count: usize,
        /// Column of the first.
        x: u32,
        /// Row of the first.
        y: u32,
    },
    /// A setting out of its range.
    #[error("{0}")]
    Settings(String),
}
