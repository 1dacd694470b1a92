//! What a learning or robotics loop asks of a world besides its state: batched ray casts
//! (PyBullet's `rayTestBatch`), contact points with their normal forces
//! (`getContactPoints`), and joint reaction forces — on a `kea.World`, and ray casts on every
//! world of a `kea.Batch`.

use crate::convert::{bad, matrix, py, real};
use crate::world::PyWorld;
use kea3d::collision::QueryFilter;
use kea3d::{BodyHandle, PhysicsWorld, Vec3};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// One ray's answer: hit, distance (m), normal, body index (−1: none, or geometry without a
/// numbered body).
pub type RayAnswer = (bool, f64, [f64; 3], i64);

/// Casts each ray `origin + t·direction/|direction|`, `0 ≤ t ≤ max_distance`; a miss reads
/// `(false, max_distance, 0, −1)`. `origins` and `directions` are row-major (rays, 3).
pub fn cast_rays(
    world: &PhysicsWorld,
    bodies: &[BodyHandle],
    origins: &[f64],
    directions: &[f64],
    max_distance: f64,
    out: &mut [RayAnswer],
) -> kea3d::Result<()> {
    for ((o, d), answer) in origins
        .chunks_exact(3)
        .zip(directions.chunks_exact(3))
        .zip(out.iter_mut())
    {
        let origin = Vec3::new(real(o[0]), real(o[1]), real(o[2]));
        let dir = Vec3::new(real(d[0]), real(d[1]), real(d[2])).normalize_or_zero();
        let hit = world.collision().cast_ray(
            world.dynamics(),
            &kea3d::collision::RayCast::new(origin, dir, real(max_distance)),
            QueryFilter::default(),
        )?;
        *answer = match hit {
            None => (false, max_distance, [0.0; 3], -1),
            Some(h) => {
                let body = world.collision().collider(h.collider)?.body;
                let index = body
                    .and_then(|b| bodies.iter().position(|&x| x == b))
                    .map_or(-1, |i| i as i64);
                let n = h.normal;
                (
                    true,
                    f64::from(h.distance),
                    [f64::from(n.x), f64::from(n.y), f64::from(n.z)],
                    index,
                )
            }
        };
    }
    Ok(())
}

/// Checks a (rays, 3) pair of array-likes and that no direction is zero.
pub fn ray_arrays(
    origins: &Bound<'_, PyAny>,
    directions: &Bound<'_, PyAny>,
    max_distance: f64,
) -> PyResult<(usize, Vec<f64>, Vec<f64>)> {
    let (n, o) = matrix("origins", origins, 3)?;
    let (m, d) = matrix("directions", directions, 3)?;
    if n != m {
        return Err(bad(
            "directions",
            format!("{m} rows"),
            &format!("{n} rows, one per origin"),
        ));
    }
    check_rays(&d, max_distance)?;
    Ok((n, o, d))
}

/// No zero direction, and a positive finite reach.
pub fn check_rays(directions: &[f64], max_distance: f64) -> PyResult<()> {
    if let Some(k) = directions
        .chunks_exact(3)
        .position(|v| v.iter().all(|x| *x == 0.0))
    {
        return Err(bad(
            "directions",
            format!("ray {k} = [0, 0, 0]"),
            "non-zero directions",
        ));
    }
    if !(max_distance.is_finite() && max_distance > 0.0) {
        return Err(bad(
            "max_distance",
            max_distance,
            "a positive finite distance, m",
        ));
    }
    Ok(())
}

/// The answers as four arrays: hit (bool), distance, normal (rays, 3), body (int64).
pub fn answers_to_arrays<'py>(
    py_: Python<'py>,
    answers: &[RayAnswer],
    shape: &[usize],
) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
    let hit = PyArray1::from_iter(py_, answers.iter().map(|a| a.0));
    let distance = PyArray1::from_iter(py_, answers.iter().map(|a| a.1));
    let normal = PyArray1::from_iter(py_, answers.iter().flat_map(|a| a.2));
    let body = PyArray1::from_iter(py_, answers.iter().map(|a| a.3));
    let mut with3 = shape.to_vec();
    with3.push(3);
    pyo3::types::PyTuple::new(
        py_,
        [
            hit.reshape(shape.to_vec())?.into_any(),
            distance.reshape(shape.to_vec())?.into_any(),
            normal.reshape(with3)?.into_any(),
            body.reshape(shape.to_vec())?.into_any(),
        ],
    )
}

#[pymethods]
impl PyWorld {
    /// Casts rays from `origins` along `directions` (both (rays, 3), any real dtype; the
    /// directions need not be unit) up to `max_distance` m. Returns `(hit, distance, normal,
    /// body)`: arrays of shape (rays,), (rays,), (rays, 3), (rays,); a miss has distance
    /// `max_distance`, a zero normal and body −1 (as does static geometry without a body).
    #[pyo3(signature = (origins, directions, max_distance = 100.0))]
    fn cast_rays<'py>(
        &self,
        py_: Python<'py>,
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        max_distance: f64,
    ) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        let (n, o, d) = ray_arrays(origins, directions, max_distance)?;
        let mut answers = vec![(false, 0.0, [0.0; 3], -1); n];
        let (inner, bodies) = (&self.inner, &self.bodies);
        py(py_.detach(|| cast_rays(inner, bodies, &o, &d, max_distance, &mut answers)))?;
        answers_to_arrays(py_, &answers, &[n])
    }

    /// The contact points of the last step, as a dict of arrays, one entry per point:
    /// `body_a`, `body_b` (int64; −1 for the static world), `position` (points, 3), `normal`
    /// (points, 3; unit, from body b towards body a), `depth` (m, positive when overlapping)
    /// and `normal_force` (N, what the step's solve pressed the point with).
    fn contact_points<'py>(&self, py_: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let w = self.inner.dynamics();
        let index = |b: Option<BodyHandle>| {
            b.and_then(|b| self.bodies.iter().position(|&x| x == b))
                .map_or(-1, |i| i as i64)
        };
        let (mut a, mut b, mut pos, mut normal, mut depth, mut force) = (
            Vec::new(),
            Vec::new(),
            Vec::new(),
            Vec::new(),
            Vec::new(),
            Vec::new(),
        );
        for (h, contact, bodies) in w.contacts() {
            let lambdas = py(w.constraint_lambdas(h))?;
            let points = contact.points();
            let stride = if points.is_empty() {
                0
            } else {
                lambdas.len() / points.len()
            };
            let n = contact.normal();
            for (k, p) in points.iter().enumerate() {
                a.push(index(bodies[0]));
                b.push(index(bodies[1]));
                pos.extend([p.position.x, p.position.y, p.position.z].map(f64::from));
                normal.extend([n.x, n.y, n.z].map(f64::from));
                depth.push(f64::from(p.penetration));
                force.push(if stride > 0 {
                    f64::from(lambdas[k * stride])
                } else {
                    0.0
                });
            }
        }
        let count = a.len();
        let out = PyDict::new(py_);
        out.set_item("body_a", PyArray1::from_vec(py_, a))?;
        out.set_item("body_b", PyArray1::from_vec(py_, b))?;
        out.set_item(
            "position",
            PyArray1::from_vec(py_, pos).reshape([count, 3])?,
        )?;
        out.set_item(
            "normal",
            PyArray1::from_vec(py_, normal).reshape([count, 3])?,
        )?;
        out.set_item("depth", PyArray1::from_vec(py_, depth))?;
        out.set_item("normal_force", PyArray1::from_vec(py_, force))?;
        Ok(out)
    }

    /// Each joint's reaction in the last step: a (joints, 6) array of the force (N) and torque
    /// (N·m, about its centre of mass) the joint applied to its first body — a robot joint's
    /// child link — in the world frame.
    fn joint_reactions<'py>(&self, py_: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
        let mut out = Vec::with_capacity(self.joints.len() * 6);
        for j in &self.joints {
            let [r, _] = py(self.inner.dynamics().constraint_reaction(j.raw))?;
            out.extend(
                [
                    r.force.x, r.force.y, r.force.z, r.torque.x, r.torque.y, r.torque.z,
                ]
                .map(f64::from),
            );
        }
        PyArray1::from_vec(py_, out).reshape([self.joints.len(), 6])
    }
}
