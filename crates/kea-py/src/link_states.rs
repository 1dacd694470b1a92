//! A robot's links' dynamic state and its actuators' joint-space forces, for one world
//! (`World.link_states`, `World.actuator_forces`) and for every world of a batch (the same
//! names on `Batch`, with a leading world axis): what Gymnasium's Ant and Humanoid observe.

use crate::batch::PyBatch;
use crate::convert::{bad, py, real, vector};
use crate::world::PyWorld;
use kea3d::robot::{LinkState, Robot};
use kea3d::{PhysicsWorld, Real};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Numbers a link's state takes: mass, centre of mass (3), inertia (9), angular and linear
/// velocity (3 each), contact force and torque (3 each).
const WIDTH: usize = 25;

/// The names and widths of a link's numbers in the dictionary, in their order.
const FIELDS: [(&str, usize); 7] = [
    ("mass", 1),
    ("center_of_mass", 3),
    ("inertia", 9),
    ("angular_velocity", 3),
    ("linear_velocity", 3),
    ("contact_force", 3),
    ("contact_torque", 3),
];

fn flatten(s: &LinkState, out: &mut [f64]) {
    let i = s.inertia.to_cols_array(); // symmetric: rows and columns alike
    let v = [
        s.center_of_mass,
        s.angular_velocity,
        s.linear_velocity,
        s.contact_force,
        s.contact_torque,
    ];
    out[0] = f64::from(s.mass);
    for (k, x) in i.iter().enumerate() {
        out[4 + k] = f64::from(*x);
    }
    for (slot, x) in [(1, v[0]), (13, v[1]), (16, v[2]), (19, v[3]), (22, v[4])] {
        out[slot..slot + 3].copy_from_slice(&[x.x, x.y, x.z].map(f64::from));
    }
}

/// One world's link states as `WIDTH` numbers a link.
fn read(
    robot: &Robot,
    world: &PhysicsWorld,
    scratch: &mut Vec<LinkState>,
    row: &mut [f64],
) -> kea3d::Result<()> {
    robot.link_states(world, scratch)?;
    for (s, out) in scratch.iter().zip(row.chunks_exact_mut(WIDTH)) {
        flatten(s, out);
    }
    Ok(())
}

/// The dictionary of arrays over `flat` (`lead` × links × `WIDTH`), each field shaped
/// `lead + [links] + its own`.
fn dictionary<'py>(
    py_: Python<'py>,
    lead: &[usize],
    links: usize,
    flat: &[f64],
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py_);
    let rows = flat.len() / WIDTH.max(1);
    let mut offset = 0;
    for (name, width) in FIELDS {
        let mut values = Vec::with_capacity(rows * width);
        for r in 0..rows {
            values.extend_from_slice(&flat[r * WIDTH + offset..r * WIDTH + offset + width]);
        }
        let mut shape: Vec<usize> = lead.to_vec();
        shape.push(links);
        match width {
            1 => {}
            9 => shape.extend([3, 3]),
            w => shape.push(w),
        }
        d.set_item(name, PyArray1::from_vec(py_, values).reshape(shape)?)?;
        offset += width;
    }
    Ok(d)
}

#[pymethods]
impl PyWorld {
    /// Each of the robot's links' state (`link_names` order), world frame, as a dictionary of
    /// arrays: ``mass`` (L,), ``center_of_mass`` (L, 3), ``inertia`` (L, 3, 3) about the centre
    /// of mass, ``angular_velocity`` and ``linear_velocity`` (of the centre of mass) (L, 3),
    /// and the contacts' mean ``contact_force`` and ``contact_torque`` (about the centre of
    /// mass) on its geometry over the last step (L, 3). Each link has its own mass
    /// properties, also where links welded together share one body.
    fn link_states<'py>(&self, py_: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let robot = self.robot()?;
        let links = robot.links().len();
        let mut flat = vec![0.0; links * WIDTH];
        py(read(robot, &self.inner, &mut Vec::new(), &mut flat))?;
        dictionary(py_, &[], links, &flat)
    }

    /// The joint-space forces the file's actuators apply for `controls` at the present state
    /// (the layout of `joint_velocities`; MuJoCo's ``qfrc_actuator``): a motor ``gear·u``, a
    /// servo its spring and damper, controls clamped to their ranges and forces to theirs.
    fn actuator_forces<'py>(
        &mut self,
        py_: Python<'py>,
        controls: &Bound<'_, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let robot = self.robot()?;
        let u: Vec<Real> = vector("controls", controls, None)?
            .into_iter()
            .map(real)
            .collect();
        let f = py(robot.actuator_forces(&self.inner, &u))?;
        Ok(PyArray1::from_iter(py_, f.into_iter().map(f64::from)))
    }
}

#[pymethods]
impl PyBatch {
    /// Every world's `World.link_states`, each array with a leading world axis (N, L, …).
    fn link_states<'py>(&mut self, py_: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let robot = self.robot()?;
        let (n, links) = (self.worlds.len(), robot.links().len());
        let mut flat = vec![0.0; n * links * WIDTH];
        self.visit(py_, &mut flat, links * WIDTH, |_, w, row| {
            read(&robot, w, &mut Vec::new(), &mut row[..links * WIDTH])
        })?;
        dictionary(py_, &[n], links, &flat)
    }

    /// Every world's `World.actuator_forces` for its row of `controls` (N, actuators), as an
    /// (N, velocity_count) array.
    fn actuator_forces<'py>(
        &mut self,
        py_: Python<'py>,
        controls: &Bound<'_, PyAny>,
    ) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
        let robot = self.robot()?;
        let width = robot.actuators().len();
        let (rows, values) = crate::convert::matrix("controls", controls, width)?;
        let n = self.worlds.len();
        if rows != n {
            return Err(bad(
                "controls",
                format!("{rows} rows"),
                &format!("{n} rows, one per world"),
            ));
        }
        let nv = robot.velocity_count();
        let mut out = vec![0.0; n * nv];
        self.visit(py_, &mut out, nv, |i, w, row| {
            let u: Vec<Real> = values[i * width..(i + 1) * width]
                .iter()
                .map(|&x| real(x))
                .collect();
            let f = robot.actuator_forces(w, &u)?;
            for (o, x) in row.iter_mut().zip(f) {
                *o = f64::from(x);
            }
            Ok(())
        })?;
        PyArray1::from_vec(py_, out).reshape([n, nv])
    }
}
