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
        /// Line of the element, 1-based (0 for what the reader made itself: a base joint).
        line: u32,
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
            Self::File { file, reason } => {
                write!(f, "{}: {}", file.display(), shorten_quotes(reason))
            }
            Self::Syntax { file, line, reason } => {
                write!(f, "{}:{line}: {}", file.display(), shorten_quotes(reason))
            }
            Self::Element {
                file,
                line,
                element,
                reason,
            } => write!(
                f,
                "{}:{line}: <{}>: {}",
                file.display(),
                shorten_quotes(element),
                shorten_quotes(reason)
            ),
            Self::World {
                file,
                line,
                element,
                source,
            } => {
                // The world's message names its arguments; in a file they are values.
                let message = source.to_string().replacen("argument `", "`", 1);
                let element = shorten_quotes(element);
                match line {
                    0 => write!(f, "{}: <{element}>: {message}", file.display()),
                    _ => write!(f, "{}:{line}: <{element}>: {message}", file.display()),
                }
            }
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

/// Longest quoted value a message shows whole, in characters.
const LONGEST_QUOTE: usize = 48;

/// `text` with every double-quoted run longer than [`LONGEST_QUOTE`] characters cut to its
/// start and its length: a file's 2 MB attribute is named, not repeated.
pub(crate) fn shorten_quotes(text: &str) -> std::borrow::Cow<'_, str> {
    let quoted_runs_are_short = text
        .split('"')
        .skip(1)
        .step_by(2)
        .all(|run| run.chars().count() <= LONGEST_QUOTE);
    if quoted_runs_are_short {
        return text.into();
    }
    let mut out = String::with_capacity(LONGEST_QUOTE * 4);
    let mut rest = text;
    while let Some(open) = rest.find('"') {
        out.push_str(&rest[..=open]);
        let after = &rest[open + 1..];
        let Some(close) = after.find('"') else {
            rest = after;
            break;
        };
        let run = &after[..close];
        if run.chars().count() > LONGEST_QUOTE {
            out.extend(run.chars().take(LONGEST_QUOTE - 8));
            out.push_str(&format!("…\" ({} bytes)", run.len()));
            // The closing quote is written above.
            rest = &after[close + 1..];
        } else {
            out.push_str(run);
            out.push('"');
            rest = &after[close + 1..];
        }
    }
    out.push_str(rest);
    out.into()
}
