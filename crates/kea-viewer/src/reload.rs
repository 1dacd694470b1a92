//! Reloading the scene file: on the R key, and by itself when the file changes on disk (its
//! modification time is polled twice a second), so a scene can be edited and watched.

use kea_scene::Scene;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime};

/// How often the file's modification time is read.
pub const POLL: Duration = Duration::from_millis(500);

/// The scene file the Viewer was opened on.
pub struct SceneFile {
    path: PathBuf,
    stamp: Option<SystemTime>,
    polled: Instant,
}

impl SceneFile {
    /// Watches `path`, taking its present state as seen.
    #[must_use]
    pub fn new(path: &Path) -> Self {
        Self {
            path: path.to_path_buf(),
            stamp: modified(path),
            polled: Instant::now(),
        }
    }

    /// The file's path.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Whether the file changed since it was last read (checked at most every [`POLL`]).
    pub fn changed(&mut self) -> bool {
        if self.polled.elapsed() < POLL {
            return false;
        }
        self.changed_now()
    }

    /// Whether the file changed since it was last read, checked now.
    pub fn changed_now(&mut self) -> bool {
        self.polled = Instant::now();
        let now = modified(&self.path);
        now.is_some() && now != self.stamp
    }

    /// Reads and parses the file, taking its present state as seen. Errors name the file.
    pub fn read(&mut self) -> Result<Scene, String> {
        self.stamp = modified(&self.path);
        let name = self.path.display();
        let text = std::fs::read_to_string(&self.path).map_err(|e| format!("{name}: {e}"))?;
        Scene::from_json(&text).map_err(|e| format!("{name}: {e}"))
    }
}

fn modified(path: &Path) -> Option<SystemTime> {
    std::fs::metadata(path).and_then(|m| m.modified()).ok()
}
