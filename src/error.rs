//! The one error type of arbor.

/// Everything that can go wrong in arbor.
///
/// Every variant says what was wrong and where; the same text reaches C hosts through
/// `arbor_last_error_message`. New variants may be added, so match with a wildcard arm.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A parameter is out of its documented range (NaN, infinite, negative, unknown value).
    #[error("invalid argument `{field}`: {reason}")]
    InvalidArgument {
        /// The parameter or struct field at fault, e.g. `"r1"` or `"radial_segments"`.
        field: &'static str,
        /// What was found and what was expected.
        reason: String,
    },
    /// The output would pass a size limit; nothing was allocated for it.
    #[error(
        "limit exceeded: {what} would reach {requested}{}, the limit `{limit_name}` is {limit}",
        step.map(|s| format!(" at step {s}")).unwrap_or_default()
    )]
    LimitExceeded {
        /// The limit that was crossed, e.g. `"max_branches"`.
        limit_name: &'static str,
        /// What was being counted, e.g. `"branches"`.
        what: &'static str,
        /// The limit's value.
        limit: u64,
        /// How many were needed when the limit was crossed (a lower bound; saturates).
        requested: u64,
        /// The rewriting step at which the limit was crossed, where one applies.
        step: Option<u32>,
    },
    /// A caller-provided buffer is too small; nothing was written.
    #[error("buffer too small: `{buffer}` holds {capacity} elements, {required} are needed")]
    BufferTooSmall {
        /// Which buffer, e.g. `"vertices"`.
        buffer: &'static str,
        /// How many elements are needed.
        required: usize,
        /// How many elements the buffer holds.
        capacity: usize,
    },
    /// Grammar text could not be read.
    #[error("parse error at line {line}, column {column}: {message}")]
    Parse {
        /// 1-based line.
        line: u32,
        /// 1-based column, in characters.
        column: u32,
        /// What was found and what was expected, or the unsupported construct.
        message: String,
    },
    /// Evaluating the grammar gave an unusable value (NaN or infinity), e.g. from
    /// `log(-1)` or a division by zero.
    #[error("evaluation error at step {step}: {message}")]
    Eval {
        /// The rewriting step (0 for the axiom, or the step whose string the turtle read).
        step: u32,
        /// Which module and value.
        message: String,
    },
    /// Reading or writing a file or stream failed.
    #[error("I/O error: {0}")]
    Io(#[from] std::io::Error),
    /// A model named a file it may not read, or one that cannot be read; the message
    /// names the path and why, never the file's content.
    #[error("file `{path}` not read: {reason}")]
    FileAccess {
        /// The path as the model (or the host) named it.
        path: String,
        /// Why: the file access policy that refuses it, or the system's error.
        reason: String,
    },
    /// The files of one load would pass their byte budget (`max_file_bytes`); reading
    /// stopped there.
    #[error(
        "limit exceeded: reading {file} would bring the files of this load to {requested} \
         bytes, the limit `max_file_bytes` is {limit}"
    )]
    FileBudget {
        /// The file being read and what it is for, e.g. ``the #include `big.h` ``.
        file: String,
        /// The budget.
        limit: u64,
        /// Bytes the load would have read (a lower bound).
        requested: u64,
    },
    /// An allocation in proportion to the input failed; nothing was built.
    #[error("out of memory: allocating {what} failed")]
    OutOfMemory {
        /// What was being allocated, with its size where known.
        what: String,
    },
    /// A progress callback asked to stop; nothing was built.
    #[error("cancelled by the progress callback during {stage}")]
    Cancelled {
        /// The stage that was running (`"derivation"`, `"interpretation"`, `"growth"`).
        stage: &'static str,
    },
}

/// `Result` with arbor's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    pub(crate) fn invalid(field: &'static str, reason: impl Into<String>) -> Self {
        Error::InvalidArgument {
            field,
            reason: reason.into(),
        }
    }
}

// Every fallible call of the hot loops (derivation, the turtle) moves a `Result<_, Error>`:
// the error stays as small as the largest variant had it before files were read (a
// growth here showed as 4% more instructions in `Turtle::module`).
const _: () = assert!(std::mem::size_of::<Error>() <= 56);
