//! What goes wrong reading a robot file: every error names the file, and the line and element
//! where there is one.

use std::fmt;
use std::path::{Path, PathBuf};

/// A robot file that could not be read or built. Nothing was added to the world.
#[derive(Debug)]
pub enum ImportError {
    /// The file (or a mesh it names) could not be read or parsed as a whole.
    File {
        /// The file.
        file: PathBuf,
        /// Why.
        reason: String,
    },
    /// Text that is not well-formed XML (or not UTF-8), at a line.
    Syntax {
        /// The file.
        file: PathBuf,
        /// Line of the fault, 1-based.
        line: u32,
        /// What is wrong.
        reason: String,
    },
    /// An element with a bad, missing or unsupported value.
    Element {
        /// The file.
        file: PathBuf,
        /// Line of the element, 1-based.
        line: u32,
        /// The element's tag and, where it has one, its name: `joint "elbow"`.
        element: String,
        /// What is wrong, with the value.
        reason: String,
    },
    /// The world refused what the file describes (a shape, a mass, a joint frame).
    World {
        /// The file.
        file: PathBuf,
        /// The element that was being built.
        element: String,
        /// The world's error.
        source: crate::Error,
    },
}

impl ImportError {
    pub(crate) fn file(file: &Path, reason: impl Into<String>) -> Self {
        Self::File {
            file: file.to_path_buf(),
            reason: reason.into(),
        }
    }
}

impl fmt::Display for ImportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::File { file, reason } => write!(f, "{}: {reason}", file.display()),
            Self::Syntax { file, line, reason } => {
                write!(f, "{}:{line}: {reason}", file.display())
            }
            Self::Element {
                file,
                line,
                element,
                reason,
            } => write!(f, "{}:{line}: <{element}>: {reason}", file.display()),
            Self::World {
                file,
                element,
                source,
            } => write!(f, "{}: <{element}>: {source}", file.display()),
        }
    }
}

impl std::error::Error for ImportError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::World { source, .. } => Some(source),
            _ => None,
        }
    }
}
