//! The one error type of the Z-map code: bad files, shapes, values and options, and cancel.

/// Why a Z-map could not be built, read or used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ZmapError {
    /// A line of the Z-map file is malformed.
    #[error("line {line}: {message}")]
    Parse {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// The grid has no values or inconsistent sizes.
    #[error("bad grid shape: {0}")]
    Shape(String),
    /// A value is NaN or infinite.
    #[error("value at row {row}, column {col} is not finite")]
    NonFinite {
        /// 1-based row.
        row: usize,
        /// 1-based column.
        col: usize,
    },
    /// An option is out of range.
    #[error("invalid option: {0}")]
    Option(String),
    /// The work was cancelled.
    #[error("cancelled")]
    Cancelled,
}
