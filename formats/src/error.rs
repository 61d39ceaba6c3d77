//! Errors that name the file, the place in it, and what was wrong.

use std::fmt;
use std::path::{Path, PathBuf};

/// The references a count of `noun`s numbered from `first` allows, for an out-of-range
/// message: `there are 4 nodes, numbered 1 to 4` (not a Rust range, which reads as one past
/// the last).
pub fn numbered(n: u64, noun: &str, first: i64) -> String {
    match n {
        0 => format!("there are no {noun}s"),
        1 => format!("there is one {noun}, numbered {first}"),
        _ => format!(
            "there are {n} {noun}s, numbered {first} to {}",
            (first as i128) + n as i128 - 1
        ),
    }
}

/// Where in a file a problem was found.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Place {
    /// The file as a whole (missing, unreadable, wrong format).
    File,
    /// A 1-based line number (text formats).
    Line(usize),
    /// A byte offset from the start of the file.
    Byte(u64),
    /// A named data array (or structural array such as `connectivity`).
    Array(String),
    /// Anything else, said in words (`piece 2`, `<AppendedData>`).
    Other(String),
}

impl fmt::Display for Place {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Place::File => Ok(()),
            Place::Line(l) => write!(f, "line {l}"),
            Place::Byte(b) => write!(f, "byte {b}"),
            Place::Array(a) => write!(f, "array '{a}'"),
            Place::Other(s) => f.write_str(s),
        }
    }
}

/// A read or write failure.
#[derive(Debug)]
pub struct FormatError {
    pub file: Option<PathBuf>,
    pub place: Place,
    pub message: String,
}

impl FormatError {
    pub fn new(place: Place, message: impl Into<String>) -> FormatError {
        FormatError {
            file: None,
            place,
            message: message.into(),
        }
    }

    pub fn at_line(line: usize, message: impl Into<String>) -> FormatError {
        FormatError::new(Place::Line(line), message)
    }

    pub fn at_byte(byte: u64, message: impl Into<String>) -> FormatError {
        FormatError::new(Place::Byte(byte), message)
    }

    pub fn in_array(name: &str, message: impl Into<String>) -> FormatError {
        FormatError::new(Place::Array(name.to_string()), message)
    }

    pub fn whole(message: impl Into<String>) -> FormatError {
        FormatError::new(Place::File, message)
    }

    /// Names the file, unless a more specific one (a piece of a .pvtu) is already named.
    pub fn with_file(mut self, path: &Path) -> FormatError {
        if self.file.is_none() {
            self.file = Some(path.to_path_buf());
        }
        self
    }

    pub fn io(path: &Path, err: std::io::Error) -> FormatError {
        FormatError::whole(err.to_string()).with_file(path)
    }
}

impl fmt::Display for FormatError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let file = self
            .file
            .as_ref()
            .map_or_else(|| "<input>".to_string(), |p| p.display().to_string());
        match self.place {
            Place::File => write!(f, "{file}: {}", self.message),
            _ => write!(f, "{file}: {}: {}", self.place, self.message),
        }
    }
}

impl std::error::Error for FormatError {}

pub type Result<T> = std::result::Result<T, FormatError>;

/// Runs `f`, a call into a crate that parses structures from untrusted bytes: its error becomes
/// its message, and a panic deep down (`catch_unwind` over `AssertUnwindSafe`: callers use
/// nothing the closure touched after a failure) becomes "the reader failed on a corrupt file".
pub(crate) fn guard_panics<R, E: fmt::Display>(
    f: impl FnOnce() -> std::result::Result<R, E>,
) -> std::result::Result<R, String> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(Ok(r)) => Ok(r),
        Ok(Err(e)) => Err(e.to_string()),
        Err(panic) => {
            let m = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            Err(format!("the reader failed on a corrupt file ({m})"))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::numbered;

    #[test]
    fn numbered_says_the_first_and_last_valid_number() {
        assert_eq!(numbered(0, "point", 0), "there are no points");
        assert_eq!(numbered(1, "node", 1), "there is one node, numbered 1");
        assert_eq!(
            numbered(4, "point", 0),
            "there are 4 points, numbered 0 to 3"
        );
        // No overflow at the ends of i64.
        assert_eq!(
            numbered(2, "node", i64::MAX),
            format!(
                "there are 2 nodes, numbered {} to {}",
                i64::MAX,
                i64::MAX as i128 + 1
            )
        );
    }
}
