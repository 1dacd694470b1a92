//! A `kea.Batch` of robot worlds (made from `World.from_urdf` / `from_mjcf`): every world's
//! joint vectors, controls, motors and link positions as (N, …) arrays, in parallel.

use crate::batch::PyBatch;
use crate::convert::real;
use kea3d::robot::Robot;
use kea3d::{PhysicsWorld, Real};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

impl PyBatch {
    pub(crate) fn robot(&self) -> PyResult<Robot> {
        self.robot.clone().ok_or_else(|| {
            PyValueError::new_err(
                "this batch holds no robot: make it from World.from_urdf or World.from_mjcf",
            )
        })
    }

    /// Every world's `width` numbers from `read`, as an (N, width) array.
    fn gather<'py, F>(
        &mut self,
        py_: Python<'py>,
        width: usize,
        read: F,
    ) -> PyResult<Bound<'py, PyArray2<f64>>>
    where
        F: Fn(&PhysicsWorld, &mut [Real]) -> kea3d::Result<()> + Sync + Send,
    {
        let n = self.worlds.len();
        // Each world reads into its row as the batch's reals, widened after.
        let mut out: Vec<Real> = vec![0.0; n * width];
        self.visit(py_, &mut out, width, |_, w, row| read(w, &mut row[..width]))?;
        let out: Vec<f64> = out.into_iter().map(f64::from).collect();
        PyArray1::from_vec(py_, out).reshape([n, width])
    }

    /// Applies `write` to every world with its row of an (N, width) array-like.
    fn scatter<F>(
        &mut self,
        py_: Python<'_>,
        arg: &str,
        x: &Bound<'_, PyAny>,
        width: usize,
        write: F,
    ) -> PyResult<()>
    where
        F: Fn(&mut PhysicsWorld, &[Real]) -> kea3d::Result<()> + Sync + Send,
    {
        let (rows, values) = crate::convert::matrix(arg, x, width)?;
        if rows != self.worlds.len() {
            return Err(crate::convert::bad(
                arg,
                format!("{rows} rows"),
                &format!("{} rows, one per world", self.worlds.len()),
            ));
        }
        let values: Vec<Real> = values.into_iter().map(real).collect();
        self.each(py_, |i, w| write(w, &values[i * width..(i + 1) * width]))
    }

    /// Every world's `width` numbers as an (N, width) array: the rows the last step read into
    /// `stepped` while they are fresh, else read from each world by `read`.
    fn rows_or_gather<'py, F>(
        &mut self,
        py_: Python<'py>,
        stepped: &[Real],
        width: usize,
        read: F,
    ) -> PyResult<Bound<'py, PyArray2<f64>>>
    where
        F: Fn(&PhysicsWorld, &mut [Real]) -> kea3d::Result<()> + Sync + Send,
    {
        if !self.observed.fresh {
            return self.gather(py_, width, read);
        }
        let n = self.worlds.len();
        let out: Vec<f64> = stepped
            .chunks(crate::batch::row_stride(width))
            .take(n)
            .flat_map(|row| row[..width].iter().map(|&x| f64::from(x)))
            .collect();
        PyArray1::from_vec(py_, out).reshape([n, width])
    }
}

#[pymethods]
impl PyBatch {
    /// Every world's joint positions, (N, position_count) float64.
    fn joint_positions<'py>(&mut self, py_: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let robot = self.robot()?;
        let stepped = std::mem::take(&mut self.observed.q);
        let read = self.rows_or_gather(py_, &stepped, robot.position_count(), |w, row| {
            robot.joint_positions_into(w, row)
        });
        self.observed.q = stepped;
        read
    }

    /// Every world's joint velocities, (N, velocity_count) float64.
    fn joint_velocities<'py>(&mut self, py_: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let robot = self.robot()?;
        let stepped = std::mem::take(&mut self.observed.v);
        let read = self.rows_or_gather(py_, &stepped, robot.velocity_count(), |w, row| {
            robot.joint_velocities_into(w, row)
        });
        self.observed.v = stepped;
        read
    }

    /// Re-poses every world's robot to its row of `q` (N, position_count).
    fn set_joint_positions(&mut self, py_: Python<'_>, q: &Bound<'_, PyAny>) -> PyResult<()> {
        let robot = self.robot()?;
        self.scatter(py_, "q", q, robot.position_count(), |w, row| {
            robot.set_joint_positions(w, row)
        })
    }

    /// Sets every world's joint velocities to its row of `v` (N, velocity_count).
    fn set_joint_velocities(&mut self, py_: Python<'_>, v: &Bound<'_, PyAny>) -> PyResult<()> {
        let robot = self.robot()?;
        self.scatter(py_, "v", v, robot.velocity_count(), |w, row| {
            robot.set_joint_velocities(w, row)
        })
    }

    /// Feeds every world's actuators its row of `controls` (N, actuators). Checked now;
    /// each world takes its row as the next step takes it in (reads and writes before that
    /// see them too), as MuJoCo's step reads `ctrl`.
    fn set_controls(&mut self, controls: &Bound<'_, PyAny>) -> PyResult<()> {
        let robot = self.robot()?;
        let width = robot.actuators().len();
        let (rows, values) = crate::convert::matrix("controls", controls, width)?;
        if rows != self.worlds.len() {
            return Err(crate::convert::bad(
                "controls",
                format!("{rows} rows"),
                &format!("{} rows, one per world", self.worlds.len()),
            ));
        }
        let values: Vec<Real> = values.into_iter().map(real).collect();
        // Checked whole now (as each world's `set_controls` would), so that applying them
        // in the step cannot fail.
        for (i, row) in values.chunks(width.max(1)).enumerate().take(rows) {
            robot.check_controls(&row[..width]).map_err(|e| {
                crate::convert::bad(
                    "controls",
                    format!("row {i}: {e}"),
                    "controls each actuator takes",
                )
            })?;
        }
        self.defer(Box::new(move |i, w| {
            robot.set_controls(w, &values[i * width..(i + 1) * width])
        }));
        Ok(())
    }

    /// Drives every world's joint coordinates at its row of `velocities` (N, velocity_count)
    /// with motors of at most `max_forces` (one per coordinate; default each joint's effort
    /// limit from its file).
    #[pyo3(signature = (velocities, max_forces = None))]
    fn set_joint_motors(
        &mut self,
        py_: Python<'_>,
        velocities: &Bound<'_, PyAny>,
        max_forces: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let robot = self.robot()?;
        let forces = crate::robot::motor_forces(&robot, max_forces)?;
        self.scatter(
            py_,
            "velocities",
            velocities,
            robot.velocity_count(),
            |w, row| robot.set_joint_motors(w, row, &forces),
        )
    }

    /// Every world's position of a point fixed in a link (its frame origin by default), (N, 3).
    #[pyo3(signature = (name, point = [0.0; 3]))]
    fn link_positions<'py>(
        &mut self,
        py_: Python<'py>,
        name: &str,
        point: [f64; 3],
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let robot = self.robot()?;
        let index = crate::robot::link_index(&robot, name)?;
        let local = crate::convert::vec3(point);
        self.gather(py_, 3, |w, row| {
            let p = robot.link_pose(w, index)?.point(local);
            row.copy_from_slice(&[p.x, p.y, p.z]);
            Ok(())
        })
    }

    /// Every world's joint reactions in the last step, (N, joints, 6): force and torque on each
    /// joint's first body, world frame (as `World.joint_reactions`).
    fn joint_reactions<'py>(
        &mut self,
        py_: Python<'py>,
    ) -> PyResult<Bound<'py, numpy::PyArray3<f64>>> {
        let (n, nj) = (self.worlds.len(), self.joints.len());
        let joints = self.joints.clone();
        let flat = self.gather(py_, nj * 6, |w, row| {
            for (j, out) in joints.iter().zip(row.chunks_exact_mut(6)) {
                let [r, _] = w.dynamics().constraint_reaction(j.raw)?;
                out.copy_from_slice(&[
                    r.force.x, r.force.y, r.force.z, r.torque.x, r.torque.y, r.torque.z,
                ]);
            }
            Ok(())
        })?;
        flat.reshape([n, nj, 6])
    }
}
