//! Scene errors: where (a line and column of the file, or a path into the scene such as
//! `bodies[3].mass`) and what was expected.

use thiserror::Error;

/// What is wrong with a scene.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SceneError {
    /// The text is not a scene: bad JSON, a wrong type, an unknown or missing field.
    #[error("line {line}, column {column}: {message}")]
    Parse {
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What was expected there.
        message: String,
    },
    /// A version this crate does not read.
    #[error("`version`: this is version {found}, but only version {expected} can be read")]
    Version {
        /// The file's version.
        found: u32,
        /// The version supported.
        expected: u32,
    },
    /// A value the physics refuses, or a reference to something missing.
    #[error("`{place}`: {message}")]
    Invalid {
        /// Where in the scene, e.g. `bodies[2].shapes[0]`.
        place: String,
        /// What is wrong.
        message: String,
    },
}

impl SceneError {
    /// An invalid-value error at `place`.
    pub(crate) fn at(place: impl Into<String>, message: impl std::fmt::Display) -> Self {
        Self::Invalid {
            place: place.into(),
            message: message.to_string(),
        }
    }
}

impl From<serde_json::Error> for SceneError {
    fn from(e: serde_json::Error) -> Self {
        // serde_json appends " at line L column C"; keep the message without it.
        let text = e.to_string();
        let message = match text.rfind(" at line ") {
            Some(i) => text[..i].to_string(),
            None => text,
        };
        Self::Parse {
            line: e.line(),
            column: e.column(),
            message,
        }
    }
}
