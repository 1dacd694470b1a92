//! `kea.Batch`: N copies of one world stepped on all cores with the GIL released, their
//! states, actions and observations as (N, …) numpy arrays that each world reads or writes
//! in place.
//!
//! The model/data split: the batch's world is its model, and one hot worker world per
//! thread, made from it, holds the definitions (masses, inertias, joints' frames and stops,
//! colliders) and the step's scratch (the solver's workspace, the narrow phase's workers,
//! each kept tree's factor and recursions). Each of the N worlds is held as a compact record
//! of what its steps change (`kea3d::HeldWorld`: its bodies' and joints' motion, its
//! contacts, kept trees' coordinates, the clock). To step, read or write a world, a worker
//! takes it in (`PhysicsWorld::enter`: the record's motion copied into the worker's bodies
//! and joints, the rest of its buffers traded), does it, and gives it back
//! (`PhysicsWorld::leave`). A world's memory and the memory a step brings in are its record
//! alone; definitions and scratch, sized once per thread, stay in that thread's cache.

use crate::convert::{any_block, bad, block, matrix, py_err, real};
use crate::queries;
use crate::state::{self, JointEntry, STATE_WIDTH};
use crate::world::PyWorld;
use kea3d::{BodyHandle, HeldWorld, PhysicsWorld};
use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use rayon::prelude::*;
use std::sync::{Mutex, TryLockError};

/// A batch of worlds made from one: stepped in parallel, read and written as arrays.
///
/// Stepping a batch gives the same bits as stepping each world on its own, for any number of
/// threads: each world is stepped by one thread, and worlds share nothing.
#[pyclass(name = "Batch", module = "kea")]
pub struct PyBatch {
    /// The model: every world's definitions, and the world a reset goes back to.
    pub(crate) template: PhysicsWorld,
    /// The model's state, held: what a reset copies into a world.
    start: HeldWorld,
    /// Each world, held beside the model (`HeldWorld`).
    pub(crate) worlds: Vec<HeldWorld>,
    /// The workers that step, read and write the worlds, one per thread of the pool, by
    /// thread index (its definitions and scratch stay in that core's cache). A thread whose
    /// worker is busy — it picked up another run while it waits inside a step — uses a
    /// worker of its own making rather than wait for itself.
    workers: Vec<Mutex<PhysicsWorld>>,
    /// The robot every world holds, when the batch was made from a robot's world.
    pub(crate) robot: Option<kea3d::robot::Robot>,
    bodies: Vec<BodyHandle>,
    pub(crate) joints: Vec<JointEntry>,
    pub(crate) pool: rayon::ThreadPool,
    /// A robot batch's joint positions and velocities, read by each worker as it finishes a
    /// world's step, while the world is still in its cache.
    pub(crate) observed: Observed,
    /// Actions set since the last step (motors, controls), in order: applied to each world
    /// in the step's own visit, after the worker takes it in and before it steps, as
    /// MuJoCo's `ctrl` is read by its step; any other visit applies them first.
    pending: Vec<Write>,
}

/// A write to every world (by index), owned, kept until the batch next visits its worlds.
pub(crate) type Write = Box<dyn Fn(usize, &mut PhysicsWorld) -> kea3d::Result<()> + Send + Sync>;

/// Every world's joint positions and velocities (MuJoCo's `qpos` and `qvel`) as its last
/// step left them, read in the step by the worker that held the world: a closed loop reads
/// them after every step, and a second pass over every world would bring each back from
/// memory. `fresh` until anything but a step changes a world.
#[derive(Default)]
pub(crate) struct Observed {
    pub(crate) q: Vec<kea3d::Real>,
    pub(crate) v: Vec<kea3d::Real>,
    pub(crate) fresh: bool,
    /// Every world's body states (`Batch.state`'s rows), read in the step when the last
    /// step was followed by a `state()` (a closed loop that reads them after every step);
    /// valid while `fresh`, if the last step read them.
    pub(crate) states: Vec<f64>,
    pub(crate) states_read: bool,
    pub(crate) states_valid: bool,
}

impl PyBatch {
    /// Runs `f` on every world with its index, on the pool, without the GIL, to change it;
    /// the first error comes back naming its world.
    pub(crate) fn each<F>(&mut self, py_: Python<'_>, f: F) -> PyResult<()>
    where
        F: Fn(usize, &mut PhysicsWorld) -> kea3d::Result<()> + Sync + Send,
    {
        self.observed.fresh = false;
        let mut none = vec![(); self.worlds.len()];
        self.visit(py_, &mut none, 1, |i, w, _| f(i, w))
    }

    /// Runs `f` on every world with its index and its `width` entries of `out` (which has
    /// `width` per world), on the pool, without the GIL: each world taken into its thread's
    /// worker, `f` run on it there, and given back. The first error comes back naming its
    /// world. A reader leaves the world as it was; a writer must call `each`, which marks
    /// the step's rows stale.
    pub(crate) fn visit<T, F>(
        &mut self,
        py_: Python<'_>,
        out: &mut [T],
        width: usize,
        f: F,
    ) -> PyResult<()>
    where
        T: Send,
        F: Fn(usize, &mut PhysicsWorld, &mut [T]) -> kea3d::Result<()> + Sync + Send,
    {
        self.apply_pending(py_)?;
        self.visit_now(py_, out, width, f)
    }

    /// Keeps `write` for every world until the batch next visits them: the step applies it
    /// in its own visit (an action costs no pass of its own over the worlds). The caller
    /// has checked its input, so that it cannot fail on any world.
    pub(crate) fn defer(&mut self, write: Write) {
        self.observed.fresh = false;
        self.pending.push(write);
    }

    /// Applies the pending actions to every world now.
    fn apply_pending(&mut self, py_: Python<'_>) -> PyResult<()> {
        if self.pending.is_empty() {
            return Ok(());
        }
        let pending = std::mem::take(&mut self.pending);
        let mut none = vec![(); self.worlds.len()];
        let applied = self.visit_now(py_, &mut none, 1, |i, w, _| {
            pending.iter().try_for_each(|write| write(i, w))
        });
        if applied.is_err() {
            // As after a failed step: the worlds not reached take them later (setting a
            // motor or a control twice is setting it once).
            self.pending = pending;
        }
        applied
    }

    fn visit_now<T, F>(
        &mut self,
        py_: Python<'_>,
        out: &mut [T],
        width: usize,
        f: F,
    ) -> PyResult<()>
    where
        T: Send,
        F: Fn(usize, &mut PhysicsWorld, &mut [T]) -> kea3d::Result<()> + Sync + Send,
    {
        let width = width.max(1);
        let (pool, worlds, workers) = (&self.pool, &mut self.worlds, &self.workers);
        let template = &self.template;
        let result = py_.detach(|| {
            pool.install(|| {
                worlds
                    .par_chunks_mut(RUN)
                    .zip(out.par_chunks_mut(RUN * width))
                    .enumerate()
                    .try_for_each(|(c, (run, rows))| {
                        with_worker(workers, template, |worker| {
                            for (k, (held, row)) in
                                run.iter_mut().zip(rows.chunks_mut(width)).enumerate()
                            {
                                worker.enter(held);
                                let done = f(c * RUN + k, worker, row);
                                worker.leave(held, template);
                                done.map_err(|e| (c * RUN + k, e))?;
                            }
                            Ok(())
                        })
                    })
            })
        });
        result.map_err(|(i, e)| world_error(py_, i, e))
    }

    fn check_rows(&self, arg: &str, shape: &[usize], width: &[usize]) -> PyResult<()> {
        let mut want = vec![self.worlds.len()];
        want.extend_from_slice(width);
        if shape != want.as_slice() {
            return Err(bad(
                arg,
                format!("an array of shape {shape:?}"),
                &format!("shape {want:?}"),
            ));
        }
        Ok(())
    }
}

#[pymethods]
impl PyBatch {
    /// `n` copies of `world`, stepped on `threads` threads (default: all cores).
    #[new]
    #[pyo3(signature = (world, n, threads = None))]
    fn new(world: &PyWorld, n: usize, threads: Option<usize>) -> PyResult<Self> {
        if n == 0 || n > 1 << 20 {
            return Err(bad("n", n, "1 to 1048576 worlds"));
        }
        let mut builder = rayon::ThreadPoolBuilder::new();
        if let Some(t) = threads {
            if t == 0 || t > 1024 {
                return Err(bad("threads", t, "1 to 1024, or None for all cores"));
            }
            builder = builder.num_threads(t);
        }
        let pool = builder
            .build()
            .map_err(|e| PyRuntimeError::new_err(format!("threads: {e}")))?;
        // Nobody reads a batch world's stage times: skip the clock (same bits either way).
        let mut template = world.inner.clone();
        template.set_step_timing(false);
        let start = template.held();
        let workers = (0..pool.current_num_threads())
            .map(|_| Mutex::new(template.clone()))
            .collect();
        Ok(Self {
            worlds: vec![start.clone(); n],
            start,
            workers,
            template,
            bodies: world.bodies.clone(),
            joints: world.joints.clone(),
            robot: world.robot.clone(),
            pool,
            observed: Observed::default(),
            pending: Vec::new(),
        })
    }

    /// Steps every world `steps` times by `dt` seconds, in parallel, without the GIL.
    #[pyo3(signature = (dt = 1.0 / 60.0, steps = 1))]
    fn step(&mut self, py_: Python<'_>, dt: f64, steps: usize) -> PyResult<()> {
        let dt = real(dt);
        let n = self.worlds.len();
        let robot = self.robot.as_ref();
        let (nq, nv) = robot.map_or((0, 0), |r| (r.position_count(), r.velocity_count()));
        let (nq, nv) = (row_stride(nq), row_stride(nv));
        let observed = &mut self.observed;
        observed.fresh = false;
        observed.q.resize(n * nq, 0.0);
        observed.v.resize(n * nv, 0.0);
        let nb = self.bodies.len();
        let want_states = std::mem::take(&mut observed.states_read) && nb > 0;
        let ns = row_stride(if want_states { nb * STATE_WIDTH } else { 0 });
        observed.states.resize(n * ns, 0.0);
        let bodies = self.bodies.as_slice();
        let (pool, worlds, workers) = (&self.pool, &mut self.worlds, &self.workers);
        let template = &self.template;
        let pending = std::mem::take(&mut self.pending);
        let actions = pending.as_slice();
        let result = py_.detach(|| {
            pool.install(|| {
                worlds
                    .par_chunks_mut(RUN)
                    .zip(observed.q.par_chunks_mut(RUN * nq))
                    .zip(observed.v.par_chunks_mut(RUN * nv))
                    .zip(observed.states.par_chunks_mut(RUN * ns))
                    .enumerate()
                    .try_for_each(|(c, (((run, q), v), states))| {
                        let rows = Rows {
                            robot: robot.map(|r| (r, q, v)),
                            states: want_states.then_some((bodies, states)),
                        };
                        with_worker(workers, template, |worker| {
                            let first = c * RUN;
                            step_run(worker, template, run, first, actions, rows, dt, steps)
                        })
                        .map_err(|(k, e)| (c * RUN + k, e))
                    })
            })
        });
        observed.fresh = result.is_ok();
        observed.states_valid = want_states;
        if result.is_err() {
            // The worlds the failed step did not reach have not taken the actions: they stay
            // pending (setting a motor or a control twice is setting it once).
            self.pending = pending;
        }
        result.map_err(|(i, e)| world_error(py_, i, e))
    }

    /// Puts the chosen worlds (all if None) back to the batch's starting world.
    #[pyo3(signature = (indices = None))]
    fn reset(&mut self, py_: Python<'_>, indices: Option<Vec<usize>>) -> PyResult<()> {
        let n = self.worlds.len();
        let indices = indices.unwrap_or_else(|| (0..n).collect());
        if let Some(&i) = indices.iter().find(|&&i| i >= n) {
            return Err(crate::convert::no_such("indices", i, n));
        }
        self.apply_pending(py_)?;
        self.observed.fresh = false;
        for i in indices {
            // The model's state into the world's own buffers: no allocation.
            self.worlds[i].copy_from(&self.start);
        }
        Ok(())
    }

    /// Every world's body states, as one (N, bodies, 13) float64 array that each world fills
    /// in place, in parallel.
    fn state<'py>(&mut self, py_: Python<'py>) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let (n, nb) = (self.worlds.len(), self.bodies.len());
        let array = PyArray3::<f64>::zeros(py_, [n, nb, STATE_WIDTH], false);
        // The next step reads them for the read that follows it.
        self.observed.states_read = true;
        {
            let mut rw = array.readwrite();
            let out = rw
                .as_slice_mut()
                .map_err(|e| bad("state", e, "a contiguous array"))?;
            let stepped = &self.observed;
            if stepped.fresh && stepped.states_valid && self.pending.is_empty() {
                out.copy_from_slice(&stepped.states[..out.len()]);
            } else {
                let bodies = self.bodies.clone();
                self.visit(py_, out, nb * STATE_WIDTH, |_, w, rows| {
                    state::read_bodies(w, &bodies, rows)
                })?;
            }
        }
        Ok(array)
    }

    /// Sets every world's bodies from an (N, bodies, 13) array; a world with a bad row is
    /// refused by number, and nothing changes in it.
    fn set_state(&mut self, py_: Python<'_>, state: &Bound<'_, PyAny>) -> PyResult<()> {
        let shape = [self.worlds.len(), self.bodies.len(), STATE_WIDTH];
        let src = block("state", state, shape)?;
        let width = self.bodies.len() * STATE_WIDTH;
        let bodies = self.bodies.clone();
        self.each(py_, |i, w| {
            state::write_bodies(w, &bodies, &src[i * width..(i + 1) * width])
        })
    }

    /// Adds forces (N, bodies, 3) at the bodies' centres of mass for the next step, N.
    fn apply_forces(&mut self, py_: Python<'_>, forces: &Bound<'_, PyAny>) -> PyResult<()> {
        let nb = self.bodies.len();
        let src = block("forces", forces, [self.worlds.len(), nb, 3])?;
        let bodies = self.bodies.clone();
        self.each(py_, |i, w| {
            for (b, &h) in bodies.iter().enumerate() {
                let f = &src[(i * nb + b) * 3..][..3];
                w.add_force(h, [real(f[0]), real(f[1]), real(f[2])])?;
            }
            Ok(())
        })
    }

    /// Sets the motor speeds (N, joints) of the joints that have motors; columns of joints
    /// without a motor must be 0. Checked now; each world takes them as the next step takes
    /// it in (reads and writes before that see them too).
    fn set_motors(&mut self, velocities: &Bound<'_, PyAny>) -> PyResult<()> {
        let nj = self.joints.len();
        let (rows, src) = matrix("velocities", velocities, nj)?;
        self.check_rows("velocities", &[rows, nj], &[nj])?;
        let joints = self.joints.clone();
        let motorised: Vec<bool> = joints
            .iter()
            .map(|&j| {
                state::limit(&self.template, j)
                    .ok()
                    .flatten()
                    .is_some_and(|l| l.motor().is_some())
            })
            .collect();
        for (k, x) in src.iter().enumerate() {
            if !real(*x).is_finite() || (!motorised[k % nj.max(1)] && *x != 0.0) {
                return Err(bad(
                    "velocities",
                    format!("{x} in column {}", k % nj.max(1)),
                    "finite speeds, and 0 for joints without a motor",
                ));
            }
        }
        self.defer(Box::new(move |i, w| {
            for (k, &j) in joints.iter().enumerate() {
                if motorised[k] {
                    state::drive(w, j, src[i * nj + k])?;
                }
            }
            Ok(())
        }));
        Ok(())
    }

    /// Every world's joint coordinates and rates: two (N, joints) float64 arrays.
    #[allow(clippy::type_complexity)]
    fn joint_state<'py>(
        &mut self,
        py_: Python<'py>,
    ) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>)> {
        let (n, nj) = (self.worlds.len(), self.joints.len());
        // Each world's row: its positions, then its velocities.
        let mut rows = vec![0.0; n * 2 * nj];
        let joints = self.joints.clone();
        self.visit(py_, &mut rows, 2 * nj, |_, w, row| {
            let (p, v) = row.split_at_mut(nj);
            state::read_joints(w, &joints, p, &mut v[..nj])
        })?;
        let (mut pos, mut vel) = (Vec::with_capacity(n * nj), Vec::with_capacity(n * nj));
        for row in rows.chunks(2 * nj.max(1)).take(n) {
            pos.extend_from_slice(&row[..nj]);
            vel.extend_from_slice(&row[nj..2 * nj]);
        }
        Ok((
            PyArray1::from_vec(py_, pos).reshape([n, nj])?,
            PyArray1::from_vec(py_, vel).reshape([n, nj])?,
        ))
    }

    /// Casts rays in every world: `origins` and `directions` of shape (N, rays, 3), any real
    /// dtype. Returns `(hit, distance, normal, body)` of shapes (N, rays), (N, rays),
    /// (N, rays, 3), (N, rays), as `World.cast_rays` does for one world, in parallel.
    #[pyo3(signature = (origins, directions, max_distance = 100.0))]
    fn cast_rays<'py>(
        &mut self,
        py_: Python<'py>,
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        max_distance: f64,
    ) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        let n = self.worlds.len();
        let (shape, o) = any_block("origins", origins)?;
        let rays = shape[1];
        if shape != [n, rays, 3] {
            return Err(bad(
                "origins",
                format!("an array of shape {shape:?}"),
                &format!("shape ({n}, rays, 3)"),
            ));
        }
        let d = block("directions", directions, [n, rays, 3])?;
        queries::check_rays(&d, max_distance)?;
        let mut answers = vec![(false, 0.0, [0.0; 3], -1); n * rays];
        let bodies = self.bodies.clone();
        let width = rays * 3;
        self.visit(py_, &mut answers, rays, |i, w, out| {
            queries::cast_rays(
                w,
                &bodies,
                &o[i * width..(i + 1) * width],
                &d[i * width..(i + 1) * width],
                max_distance,
                &mut out[..rays],
            )
        })?;
        queries::answers_to_arrays(py_, &answers, &[n, rays])
    }

    /// A copy of world `index` as a `kea.World`.
    fn world(&mut self, py_: Python<'_>, index: usize) -> PyResult<PyWorld> {
        self.apply_pending(py_)?;
        let n = self.worlds.len();
        let held = self
            .worlds
            .get_mut(index)
            .ok_or_else(|| crate::convert::no_such("index", index, n))?;
        // A world that steps on its own: the model with this one's state.
        let mut whole = self.template.clone();
        whole.enter(held);
        let copy = whole.clone();
        whole.leave(held, &self.template);
        let mut out = PyWorld::from_physics(copy);
        out.bodies.clone_from(&self.bodies);
        out.joints.clone_from(&self.joints);
        out.robot.clone_from(&self.robot);
        Ok(out)
    }

    /// Threads stepping the batch.
    #[getter]
    fn threads(&self) -> usize {
        self.pool.current_num_threads()
    }

    /// Bodies per world.
    #[getter]
    fn body_count(&self) -> usize {
        self.bodies.len()
    }

    /// Joints per world.
    #[getter]
    fn joint_count(&self) -> usize {
        self.joints.len()
    }

    fn __len__(&self) -> usize {
        self.worlds.len()
    }
}

/// How far apart the step's rows of `width` numbers lie in [`Observed`]: at least one, so
/// that the rows split into runs as the worlds do even when a robot has no coordinates.
pub(crate) fn row_stride(width: usize) -> usize {
    width.max(1)
}

/// A run's rows of the robot's joint positions and velocities ([`row_stride`] apart), which
/// its worker reads as it finishes each world.
struct Rows<'a> {
    robot: Option<(
        &'a kea3d::robot::Robot,
        &'a mut [kea3d::Real],
        &'a mut [kea3d::Real],
    )>,
    /// The batch's bodies and the run's rows of their states, when the step reads them.
    states: Option<(&'a [BodyHandle], &'a mut [f64])>,
}

/// Worlds in runs of `RUN`, each world's worker asking for the next one's memory while it
/// steps this one.
const RUN: usize = 16;

/// Runs `f` with this thread's worker; a thread whose worker is busy (it picked up another
/// run while it waits inside one) uses a worker of its own making rather than wait for
/// itself.
fn with_worker<R>(
    workers: &[Mutex<PhysicsWorld>],
    template: &PhysicsWorld,
    f: impl FnOnce(&mut PhysicsWorld) -> R,
) -> R {
    let thread = rayon::current_thread_index().unwrap_or(0);
    match workers[thread % workers.len()].try_lock() {
        Ok(mut worker) => f(&mut worker),
        Err(TryLockError::Poisoned(p)) => f(&mut p.into_inner()),
        Err(TryLockError::WouldBlock) => f(&mut template.clone()),
    }
}

/// Steps each world of `run` (world `first` on) `steps` times by `dt` in `worker`, which
/// takes it in, applies the `pending` actions, steps, reads the world's `rows` while it
/// holds it, and gives it back with whatever the step did (as stepping it in place); the
/// first error comes back with the world's place in the run.
#[allow(clippy::too_many_arguments)]
fn step_run(
    worker: &mut PhysicsWorld,
    model: &PhysicsWorld,
    run: &mut [HeldWorld],
    first: usize,
    pending: &[Write],
    mut rows: Rows<'_>,
    dt: kea3d::Real,
    steps: usize,
) -> Result<(), (usize, kea3d::Error)> {
    for k in 0..run.len() {
        if let Some(next) = run.get(k + 1) {
            next.prefetch();
        }
        worker.enter(&mut run[k]);
        let mut stepped = pending
            .iter()
            .try_for_each(|write| write(first + k, worker));
        if stepped.is_ok() {
            stepped = crate::world::step_many(worker, dt, steps);
        }
        if let (Ok(()), Some((robot, q, v))) = (&stepped, rows.robot.as_mut()) {
            let (nq, nv) = (robot.position_count(), robot.velocity_count());
            let (q, v) = (&mut q[k * row_stride(nq)..], &mut v[k * row_stride(nv)..]);
            stepped = robot.joint_state_into(worker, &mut q[..nq], &mut v[..nv]);
        }
        if let (Ok(()), Some((bodies, states))) = (&stepped, rows.states.as_mut()) {
            let width = bodies.len() * STATE_WIDTH;
            stepped = state::read_bodies(worker, bodies, &mut states[k * width..][..width]);
        }
        worker.leave(&mut run[k], model);
        stepped.map_err(|e| (k, e))?;
    }
    Ok(())
}

/// An error of world `i`, as the exception it maps to, naming the world.
fn world_error(py_: Python<'_>, i: usize, e: kea3d::Error) -> PyErr {
    let err = py_err(e);
    let msg = format!("world {i}: {}", err.value(py_));
    PyErr::from_type(err.get_type(py_), msg)
}
