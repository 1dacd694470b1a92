//! A `kea.World` saved and restored whole, bit for bit: `world.snapshot()` /
//! `kea.World.restore(data)`, and pickle (`pickle.dumps(world)`) through the same bytes.
//!
//! The bytes: a magic line, the length of the world's scene snapshot (little-endian u64), the
//! snapshot's binary form, then the Python side's tables (body, collider and joint numbering,
//! names, the robot) in postcard.

use crate::state::JointEntry;
use crate::world::PyWorld;
use kea3d::collision::ColliderHandle;
use kea3d::robot::Robot;
use kea3d::scene::SceneSnapshot;
use kea3d::{BodyHandle, PhysicsWorld};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyTuple};
use serde::{Deserialize, Serialize};

const MAGIC: &[u8; 8] = b"KEAPYW1\n";

/// The Python side's tables.
#[derive(Serialize, Deserialize)]
struct Tables {
    bodies: Vec<BodyHandle>,
    colliders: Vec<ColliderHandle>,
    joints: Vec<JointEntry>,
    body_names: Vec<String>,
    joint_names: Vec<String>,
    robot: Option<Robot>,
}

fn refused(why: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!("data: not a kea.World snapshot ({why})"))
}

#[pymethods]
impl PyWorld {
    /// The whole world as bytes: restoring them (`World.restore`) and stepping gives the same
    /// bits as stepping this world on.
    fn snapshot<'py>(&self, py_: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let scene = self
            .inner
            .snapshot()
            .and_then(|s| s.to_binary())
            .map_err(|e| PyValueError::new_err(format!("snapshot: {e}")))?;
        let tables = Tables {
            bodies: self.bodies.clone(),
            colliders: self.colliders.clone(),
            joints: self.joints.clone(),
            body_names: self.body_names.clone(),
            joint_names: self.joint_names.clone(),
            robot: self.robot.clone(),
        };
        let tables = postcard::to_stdvec(&tables).map_err(refused)?;
        let mut out = MAGIC.to_vec();
        out.extend_from_slice(&(scene.len() as u64).to_le_bytes());
        out.extend_from_slice(&scene);
        out.extend_from_slice(&tables);
        Ok(PyBytes::new(py_, &out))
    }

    /// The world `data` (from `snapshot()`) was taken of, at that instant.
    #[staticmethod]
    fn restore(data: &[u8]) -> PyResult<Self> {
        let rest = data
            .strip_prefix(MAGIC.as_slice())
            .ok_or_else(|| refused("its first bytes are not KEAPYW1"))?;
        let (len, rest) = rest
            .split_first_chunk::<8>()
            .ok_or_else(|| refused("cut short"))?;
        let len = usize::try_from(u64::from_le_bytes(*len)).map_err(refused)?;
        if rest.len() < len {
            return Err(refused("cut short"));
        }
        let (scene, tables) = rest.split_at(len);
        let snapshot = SceneSnapshot::from_binary(scene)
            .map_err(|e| PyValueError::new_err(format!("data: {e}")))?;
        let inner = PhysicsWorld::restore(snapshot)
            .map_err(|e| PyValueError::new_err(format!("data: {e}")))?;
        let t: Tables = postcard::from_bytes(tables).map_err(refused)?;
        if t.bodies.iter().any(|&b| inner.dynamics().body(b).is_err()) {
            return Err(refused("its body table does not match its world"));
        }
        Ok(PyWorld {
            inner,
            bodies: t.bodies,
            colliders: t.colliders,
            joints: t.joints,
            body_names: t.body_names,
            joint_names: t.joint_names,
            robot: t.robot,
        })
    }

    /// Pickle support: a world pickles as its snapshot.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py_ = slf.py();
        let restore = slf.get_type().getattr("restore")?;
        let data = slf.borrow().snapshot(py_)?;
        PyTuple::new(py_, [restore, PyTuple::new(py_, [data])?.into_any()])
    }
}
