//! Mesh files for collision geometry (STL, binary or ASCII; Wavefront OBJ) and how their names
//! are found: `package://name/rest` and relative paths, against the robot file's folder and
//! the caller's search path.

use super::ImportError;
use kea::{Real, Vec3};
use std::path::{Path, PathBuf};

/// A mesh's vertices and triangles.
pub(crate) struct MeshData {
    pub vertices: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
}

/// The file a mesh name refers to: tried against the robot file's folder, then each folder of
/// the search path; `package://pkg/rest` tries `rest` and `pkg/rest` in each (and the robot
/// file's folder's ancestors, where ROS packages usually sit).
pub(crate) fn resolve(name: &str, file: &Path, search: &[PathBuf]) -> Option<PathBuf> {
    let base = file.parent().unwrap_or(Path::new("."));
    let mut roots: Vec<PathBuf> = vec![base.to_path_buf()];
    roots.extend(base.ancestors().skip(1).take(3).map(Path::to_path_buf));
    roots.extend(search.iter().cloned());
    let candidates: Vec<PathBuf> = if let Some(rest) = name.strip_prefix("package://") {
        let without_pkg = rest.split_once('/').map(|(_, r)| r).unwrap_or(rest);
        vec![PathBuf::from(rest), PathBuf::from(without_pkg)]
    } else if let Some(rest) = name.strip_prefix("file://") {
        vec![PathBuf::from(rest)]
    } else {
        vec![PathBuf::from(name)]
    };
    for c in &candidates {
        if c.is_absolute() && c.is_file() {
            return Some(c.clone());
        }
    }
    roots
        .iter()
        .flat_map(|r| candidates.iter().map(move |c| r.join(c)))
        .find(|p| p.is_file())
}

/// Reads an STL or OBJ file, scaled per axis.
pub(crate) fn load(path: &Path, scale: Vec3) -> Result<MeshData, ImportError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let mut mesh = match ext.as_str() {
        "stl" => load_stl(path)?,
        "obj" => load_obj(path)?,
        other => {
            return Err(ImportError::file(
                path,
                format!("mesh format \"{other}\" is not supported (STL and OBJ are)"),
            ))
        }
    };
    for v in &mut mesh.vertices {
        *v *= scale;
    }
    if mesh.vertices.is_empty() {
        return Err(ImportError::file(path, "the mesh has no vertices"));
    }
    if let Some(v) = mesh.vertices.iter().find(|v| !v.is_finite()) {
        return Err(ImportError::file(
            path,
            format!("a vertex is not finite: {v}"),
        ));
    }
    Ok(mesh)
}

fn load_stl(path: &Path) -> Result<MeshData, ImportError> {
    let bytes = std::fs::read(path).map_err(|e| ImportError::file(path, e.to_string()))?;
    check_stl_size(&bytes).map_err(|reason| ImportError::file(path, reason))?;
    let mesh = stl_io::read_stl(&mut std::io::Cursor::new(&bytes)).map_err(|e| {
        let form = if is_ascii_stl(&bytes) {
            "ASCII"
        } else {
            "binary"
        };
        ImportError::file(path, format!("not a readable {form} STL file: {e}"))
    })?;
    let vertices = mesh
        .vertices
        .iter()
        .map(|v| Vec3::new(v[0] as Real, v[1] as Real, v[2] as Real))
        .collect();
    let triangles = mesh
        .faces
        .iter()
        .map(|f| f.vertices.map(|i| i as u32))
        .collect();
    Ok(MeshData {
        vertices,
        triangles,
    })
}

/// Whether `bytes` start as an ASCII STL file does (`solid`, then a facet).
fn is_ascii_stl(bytes: &[u8]) -> bool {
    let head = &bytes[..bytes.len().min(512)];
    bytes.trim_ascii_start().starts_with(b"solid")
        && head.windows(5).any(|w| w == b"facet" || w == b"endso")
}

/// Why a file cannot be an STL file by its size alone: a binary STL file is an 80-byte
/// header, a triangle count, and 50 bytes per triangle.
fn check_stl_size(bytes: &[u8]) -> Result<(), String> {
    if is_ascii_stl(bytes) {
        return Ok(());
    }
    if bytes.len() < 84 {
        return Err(format!(
            "{} bytes: too short for a binary STL file (an 80-byte header and a triangle count), and not ASCII STL (`solid …`)",
            bytes.len()
        ));
    }
    let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
    if count == 0 {
        return Err("a binary STL file with no triangles".into());
    }
    let needed = 84 + 50 * count;
    if bytes.len() < needed {
        return Err(format!(
            "a binary STL file declaring {count} triangles needs {needed} bytes, this one has {} (cut short, or not STL)",
            bytes.len()
        ));
    }
    Ok(())
}

fn load_obj(path: &Path) -> Result<MeshData, ImportError> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, _) = tobj::load_obj(path, &options)
        .map_err(|e| ImportError::file(path, format!("not a readable OBJ file: {e}")))?;
    let mut mesh = MeshData {
        vertices: Vec::new(),
        triangles: Vec::new(),
    };
    for m in models {
        let base = mesh.vertices.len() as u32;
        mesh.vertices.extend(
            m.mesh
                .positions
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0] as Real, p[1] as Real, p[2] as Real)),
        );
        mesh.triangles.extend(
            m.mesh
                .indices
                .chunks_exact(3)
                .map(|t| [base + t[0], base + t[1], base + t[2]]),
        );
    }
    Ok(mesh)
}
