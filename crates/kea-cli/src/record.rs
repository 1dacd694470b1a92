//! Trajectories for `--csv` and `--json`: every body's pose and velocity after every step,
//! streamed to disk as the run goes (a long run would not fit in memory), into temporary files
//! that become the outputs only when the whole run has succeeded.

use kea::Real;
use kea3d::PhysicsWorld;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// An output being written: a temporary file beside its path, removed unless committed.
struct PartialFile {
    path: PathBuf,
    temporary: PathBuf,
    writer: Option<BufWriter<File>>,
}

impl PartialFile {
    fn create(path: &Path, flag: &str) -> Result<Self, String> {
        let temporary = kea_render::partial_path(path)
            .ok_or_else(|| format!("{flag} {}: not a file name", path.display()))?;
        let file =
            File::create(&temporary).map_err(|e| format!("{flag} {}: {e}", path.display()))?;
        Ok(Self {
            path: path.to_path_buf(),
            temporary,
            writer: Some(BufWriter::new(file)),
        })
    }

    fn write(&mut self, text: &str) -> Result<(), String> {
        let path = &self.path;
        match &mut self.writer {
            Some(w) => w
                .write_all(text.as_bytes())
                .map_err(|e| format!("{}: {e}", path.display())),
            None => Ok(()),
        }
    }

    /// Flushes and closes the temporary file.
    fn close(&mut self) -> Result<(), String> {
        if let Some(w) = self.writer.take() {
            let file = w
                .into_inner()
                .map_err(|e| format!("{}: {}", self.path.display(), e.error()))?;
            file.sync_all()
                .map_err(|e| format!("{}: {e}", self.path.display()))?;
        }
        Ok(())
    }
}

impl Drop for PartialFile {
    fn drop(&mut self) {
        // Still here: the run failed or was not committed. Leave nothing behind.
        let _ = std::fs::remove_file(&self.temporary);
    }
}

/// Streams samples to the requested outputs.
pub struct Recorder {
    names: Vec<String>,
    csv: Option<PartialFile>,
    json: Option<PartialFile>,
    rows: u64,
}

impl Recorder {
    /// A recorder writing the outputs asked for; fails, naming the flag, if one cannot be
    /// created.
    pub fn new(csv: Option<&Path>, json: Option<&Path>) -> Result<Self, String> {
        let mut csv = csv.map(|p| PartialFile::create(p, "--csv")).transpose()?;
        let mut json = json.map(|p| PartialFile::create(p, "--json")).transpose()?;
        if let Some(f) = &mut csv {
            f.write("t,body,x,y,z,qx,qy,qz,qw,vx,vy,vz\n")?;
        }
        if let Some(f) = &mut json {
            f.write("[")?;
        }
        Ok(Self {
            names: Vec::new(),
            csv,
            json,
            rows: 0,
        })
    }

    /// Records every body at time `t`: one CSV line and one JSON object per body.
    pub fn capture(&mut self, t: Real, built: &PhysicsWorld) -> Result<(), String> {
        if self.csv.is_none() && self.json.is_none() {
            return Ok(());
        }
        if self.names.is_empty() {
            self.names = built
                .named_bodies()
                .iter()
                .map(|(n, _)| n.clone())
                .collect();
        }
        for (i, (_, h)) in built.named_bodies().iter().enumerate() {
            let Ok(b) = built.dynamics().body(*h) else {
                continue;
            };
            let (p, q, v) = (b.position(), b.orientation(), b.linear_velocity());
            let name = &self.names[i];
            if let Some(f) = &mut self.csv {
                f.write(&format!(
                    "{t},{name},{},{},{},{},{},{},{},{},{},{}\n",
                    p.x, p.y, p.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z
                ))?;
            }
            if let Some(f) = &mut self.json {
                let row = serde_json::json!({
                    "t": t, "body": name, "position": p.to_array(),
                    "orientation": q.to_array(), "velocity": v.to_array()
                });
                let separator = if self.rows == 0 { "" } else { "," };
                f.write(&format!("{separator}{row}"))?;
            }
            self.rows += 1;
        }
        Ok(())
    }

    /// Finishes the files and puts them in place, all or none.
    pub fn commit(mut self) -> Result<(), String> {
        if let Some(f) = &mut self.json {
            f.write("]\n")?;
        }
        let mut files: Vec<&mut PartialFile> =
            self.csv.iter_mut().chain(self.json.iter_mut()).collect();
        for f in &mut files {
            f.close()?;
        }
        for f in &files {
            std::fs::rename(&f.temporary, &f.path)
                .map_err(|e| format!("{}: {e}", f.path.display()))?;
        }
        Ok(())
    }
}
