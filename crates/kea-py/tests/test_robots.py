"""Robots from their own files and the queries a learning loop makes: URDF and MJCF models
shipped by pybullet and Gymnasium, joint vectors, ray casts against closed forms, contact and
reaction forces against weights, snapshots and pickle bit for bit, batches equal to worlds
stepped one by one, and numpy inputs of any real dtype and layout.

The robot models come from the installed ``pybullet_data`` and ``gymnasium`` packages; without
them the tests that need them are skipped (CI installs them).
"""

import importlib.util
import math
import os
import pickle

import numpy as np
import pytest

import kea

G = 9.81


def _package_dir(name):
    spec = importlib.util.find_spec(name)
    if spec is None or not spec.submodule_search_locations:
        return None
    return list(spec.submodule_search_locations)[0]


PYBULLET_DATA = _package_dir("pybullet_data")
GYM = _package_dir("gymnasium")
GYM_ASSETS = os.path.join(GYM, "envs", "mujoco", "assets") if GYM else None
needs_pybullet = pytest.mark.skipif(PYBULLET_DATA is None, reason="pybullet_data not installed")
needs_gym_assets = pytest.mark.skipif(
    GYM_ASSETS is None or not os.path.isdir(GYM_ASSETS), reason="gymnasium's assets not installed"
)

KUKA_Q = [0.4, 0.5, -0.3, -1.1, 0.5, 0.8, 0.2]

PENDULUM_URDF = """<robot name="pendulum">
  <link name="base"/>
  <link name="bob">
    <inertial><origin xyz="0 0 -1"/><mass value="2"/>
      <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0 0 -1"/><geometry><sphere radius="0.1"/></geometry></collision>
  </link>
  <joint name="pivot" type="continuous">
    <parent link="base"/><child link="bob"/><origin xyz="0 0 2"/><axis xyz="0 1 0"/>
  </joint>
</robot>"""


def pendulum(tmp_path):
    path = tmp_path / "pendulum.urdf"
    path.write_text(PENDULUM_URDF)
    return kea.World.from_urdf(str(path), fixed_base=True)


@needs_pybullet
def test_kuka_from_urdf_has_its_joints_and_takes_any_real_array():
    w = kea.World.from_urdf(os.path.join(PYBULLET_DATA, "kuka_iiwa", "model.urdf"), fixed_base=True)
    assert w.position_count == 7 and w.velocity_count == 7
    assert w.joint_names == [f"lbr_iiwa_joint_{k}" for k in range(1, 8)]
    assert w.gravity == pytest.approx((0.0, 0.0, -9.81))
    # float32, a list, and a non-contiguous view are all accepted.
    q32 = np.array(KUKA_Q, dtype=np.float32)
    w.set_joint_positions(q32)
    assert w.joint_positions() == pytest.approx(q32, abs=1e-6)
    strided = np.zeros(14)
    strided[::2] = KUKA_Q
    w.set_joint_positions(strided[::2])
    assert w.joint_positions() == pytest.approx(KUKA_Q, abs=1e-6)
    w.set_joint_velocities([0.1] * 7)
    assert w.joint_velocities() == pytest.approx([0.1] * 7, abs=1e-6)
    with pytest.raises(ValueError, match="q"):
        w.set_joint_positions([0.0] * 6)
    with pytest.raises(ValueError, match="q"):
        w.set_joint_positions([math.nan] * 7)


@needs_pybullet
def test_panda_and_r2d2_load_and_report_what_they_skip():
    panda = kea.World.from_urdf(
        os.path.join(PYBULLET_DATA, "franka_panda", "panda.urdf"), fixed_base=True
    )
    assert panda.position_count == 9
    assert any("mimic" in s for s in panda.skipped())
    r2d2 = kea.World.from_urdf(os.path.join(PYBULLET_DATA, "r2d2.urdf"))
    assert r2d2.position_count == 7 + 8  # a free base, then its joints
    r2d2.step(1.0 / 240.0, 10)


@needs_gym_assets
def test_reacher_and_double_pendulum_from_mjcf_read_the_files_coordinates():
    reacher = kea.World.from_mjcf(os.path.join(GYM_ASSETS, "reacher.xml"))
    assert reacher.position_count == 4
    # The target's slides read their `ref` at the file's pose.
    assert reacher.joint_positions() == pytest.approx([0.0, 0.0, 0.1, -0.1], abs=1e-6)
    assert reacher.timestep == pytest.approx(0.01)
    assert reacher.control_ranges() == [(-1.0, 1.0), (-1.0, 1.0)]
    idp = kea.World.from_mjcf(os.path.join(GYM_ASSETS, "inverted_double_pendulum.xml"))
    assert idp.position_count == 3
    assert idp.gravity == pytest.approx((1e-5, 0.0, -9.81))


def test_import_errors_name_file_line_and_element(tmp_path):
    with pytest.raises(OSError, match="nowhere.urdf"):
        kea.World.from_urdf(str(tmp_path / "nowhere.urdf"))
    bad = tmp_path / "bad.urdf"
    bad.write_text('<robot name="r">\n<link name="a"/><link name="b"/>\n'
                   '<joint name="j" type="hinge"><parent link="a"/><child link="b"/></joint>\n</robot>')
    with pytest.raises(ValueError, match=r"bad.urdf:3: <joint \"j\">"):
        kea.World.from_urdf(str(bad))
    with pytest.raises(ValueError, match="no robot"):
        kea.World().joint_positions()


def test_ray_casts_meet_a_ball_where_geometry_says():
    w = kea.World()
    ball = w.add_body(position=(1.0, 2.0, 3.0))
    w.add_collider(ball, "ball", radius=0.5)
    origins = np.array([[1.0, 10.0, 3.0], [-4.0, 2.0, 3.0], [1.0, 2.0, 10.0], [5.0, 5.0, 5.0]], dtype=np.float32)
    directions = np.array([[0.0, -2.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]])
    hit, distance, normal, body = w.cast_rays(origins, directions, 20.0)
    assert hit.tolist() == [True, True, True, False]
    assert distance[:3] == pytest.approx([7.5, 4.5, 6.5], abs=1e-4)
    assert distance[3] == 20.0
    assert normal[0] == pytest.approx([0.0, 1.0, 0.0], abs=1e-4)
    assert normal[1] == pytest.approx([-1.0, 0.0, 0.0], abs=1e-4)
    assert body.tolist() == [ball, ball, ball, -1]
    with pytest.raises(ValueError, match="directions"):
        w.cast_rays(origins, np.zeros((4, 3)))
    with pytest.raises(ValueError, match="origins"):
        w.cast_rays(np.zeros((4, 2)), directions)


def test_a_batch_casts_rays_in_every_world_as_one_world_does():
    w = kea.World()
    ball = w.add_body(position=(0.0, 3.0, 0.0))
    w.add_collider(ball, "ball", radius=0.5)
    batch = kea.Batch(w, 3, threads=2)
    batch.step(1.0 / 60.0, 10)  # the ball falls
    origins = np.tile(np.array([[0.0, 10.0, 0.0], [0.0, -10.0, 0.0]]), (3, 1, 1))
    directions = np.tile(np.array([[0.0, -1.0, 0.0], [0.0, 1.0, 0.0]]), (3, 1, 1))
    hit, distance, normal, body = batch.cast_rays(origins, directions, 50.0)
    assert hit.shape == (3, 2) and normal.shape == (3, 2, 3)
    one = batch.world(1).cast_rays(origins[1], directions[1], 50.0)
    assert np.array_equal(distance[1], one[1])
    y = 3.0 - 0.5 * G * (10 / 60.0) ** 2  # about: semi-implicit Euler runs a little ahead
    assert distance[0, 0] == pytest.approx(10.0 - y - 0.5, abs=0.02)


def test_contact_forces_of_a_resting_box_sum_to_its_weight():
    w = kea.World(gravity=(0.0, -G, 0.0))
    w.add_collider(None, "cuboid", half_extents=(5.0, 0.5, 5.0))
    box = w.add_body(position=(0.0, 1.0, 0.0))
    w.add_collider(box, "cuboid", half_extents=(0.5, 0.5, 0.5), density=200.0)
    w.step(1.0 / 60.0, 120)
    c = w.contact_points()
    assert len(c["normal_force"]) >= 4
    weight = w.mass(box) * G
    assert c["normal_force"].sum() == pytest.approx(weight, rel=0.01)
    assert set(c["body_a"].tolist()) | set(c["body_b"].tolist()) == {box, -1}
    # The normals point up, from the ground to the box (or down, from the box to the ground).
    assert np.abs(c["normal"][:, 1]).min() == pytest.approx(1.0, abs=1e-4)


def test_a_hanging_pendulum_pulls_its_joint_with_its_weight(tmp_path):
    w = pendulum(tmp_path)
    w.step(1e-3, 200)
    reaction = w.joint_reactions()
    assert reaction.shape == (1, 6)
    # The joint holds the 2 kg bob up: m g along +z on the bob, no sideways force.
    assert reaction[0, :3] == pytest.approx([0.0, 0.0, 2.0 * G], abs=1e-3)


def test_snapshots_and_pickles_step_on_the_same_bits(tmp_path):
    w = pendulum(tmp_path)
    w.set_joint_positions([0.7])
    w.step(1e-3, 50)
    copies = [kea.World.restore(w.snapshot()), pickle.loads(pickle.dumps(w))]
    for c in copies:
        assert np.array_equal(c.joint_positions(), w.joint_positions())
        assert c.joint_names == w.joint_names and c.body_names == w.body_names
    w.step(1e-3, 300)
    for c in copies:
        c.step(1e-3, 300)
        assert np.array_equal(c.state(), w.state())
        assert np.array_equal(c.joint_velocities(), w.joint_velocities())
    with pytest.raises(ValueError, match="data"):
        kea.World.restore(b"not a world")


@needs_pybullet
def test_a_batch_of_robots_equals_its_worlds_stepped_one_by_one():
    arm = kea.World.from_urdf(os.path.join(PYBULLET_DATA, "kuka_iiwa", "model.urdf"), fixed_base=True)
    arm.set_joint_positions(KUKA_Q)
    batch = kea.Batch(arm, 4, threads=2)
    batch.step(2e-3, 50)
    one = arm.copy()
    one.step(2e-3, 50)
    states = batch.state()
    for i in range(4):
        assert np.array_equal(states[i], one.state())


def test_arrays_of_any_real_dtype_and_layout_set_a_state():
    w = kea.World()
    for k in range(3):
        w.add_collider(w.add_body(position=(0.0, float(k), 0.0)), "ball", radius=0.1)
    s = w.state()
    w.set_state(s.astype(np.float32))
    w.set_state(np.asfortranarray(s))
    wide = np.zeros((3, 26))
    wide[:, ::2] = s
    w.set_state(wide[:, ::2])  # a strided view
    assert np.array_equal(w.state(), s)
    batch = kea.Batch(w, 2)
    states = batch.state()
    batch.set_state(states.astype(np.float32)[:, :, :])
    batch.apply_forces(np.zeros((2, 3, 3), dtype=np.float32))


@needs_gym_assets
def test_a_robot_batch_reads_and_writes_joint_vectors_and_controls_per_world():
    reacher = kea.World.from_mjcf(os.path.join(GYM_ASSETS, "reacher.xml"))
    batch = kea.Batch(reacher, 3, threads=2)
    q = np.tile(reacher.joint_positions(), (3, 1))
    q[:, 0] = [0.1, 0.2, 0.3]
    batch.set_joint_positions(q.astype(np.float32))
    assert batch.joint_positions()[:, 0] == pytest.approx([0.1, 0.2, 0.3], abs=1e-6)
    # Different torques in each world turn the first joint different ways.
    batch.set_controls(np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 0.0]]))
    batch.step(0.01, 10)
    v = batch.joint_velocities()
    assert v[0, 0] > 0.1 and v[1, 0] < -0.1 and abs(v[2, 0]) < abs(v[0, 0])
    # A step reads the joint vectors while it holds each world; what it read answers only
    # until something else changes a world.
    moved = batch.joint_positions()
    batch.reset([1])
    assert np.array_equal(batch.joint_positions()[1], reacher.joint_positions())
    assert np.array_equal(batch.joint_velocities()[1], reacher.joint_velocities())
    assert np.array_equal(batch.joint_positions()[0], moved[0])
    v[0, 0] = 2.5
    batch.set_joint_velocities(v)
    assert batch.joint_velocities()[0, 0] == pytest.approx(2.5)
    batch.step(0.01, 1)
    assert np.array_equal(batch.joint_positions()[2], batch.world(2).joint_positions())
    # A link's position and a point fixed in it, in every world.
    tips = batch.link_positions("fingertip")
    assert tips.shape == (3, 3)
    one = batch.world(2)
    (p, _) = one.link_pose("fingertip")
    assert tips[2] == pytest.approx(p, abs=1e-9)
    reactions = batch.joint_reactions()
    assert reactions.shape == (3, batch.joint_count, 6)
    with pytest.raises(ValueError, match="controls"):
        batch.set_controls(np.zeros((3, 5)))
    # Controls are checked when set (each world takes them when the next step takes it in):
    # a refused row changes nothing, and a copy taken out carries the last good controls.
    batch.set_controls(np.array([[0.5, -0.5], [0.0, 0.0], [0.0, 0.0]]))
    with pytest.raises(ValueError, match="controls"):
        batch.set_controls(np.array([[np.nan, 0.0], [0.0, 0.0], [0.0, 0.0]]))
    one = batch.world(0)
    batch.step(0.01, 5)
    one.step(0.01, 5)
    assert np.array_equal(batch.joint_positions()[0], one.joint_positions())
    with pytest.raises(ValueError, match="no robot"):
        kea.Batch(kea.World(), 2).joint_positions()


@needs_pybullet
def test_motors_drive_the_arm_and_its_links_are_named():
    arm = kea.World.from_urdf(os.path.join(PYBULLET_DATA, "kuka_iiwa", "model.urdf"), fixed_base=True)
    arm.set_joint_motors(np.full(7, 0.3))
    arm.step(0.002, 100)
    assert arm.joint_velocities() == pytest.approx(np.full(7, 0.3), abs=0.02)
    with pytest.raises(ValueError, match="velocities"):
        arm.set_joint_motors(np.zeros(6))
    (pos, quat) = arm.link_pose("lbr_iiwa_link_7")
    assert len(pos) == 3 and len(quat) == 4
    assert "lbr_iiwa_link_7" in arm.link_names()


@needs_gym_assets
def test_an_mjcf_files_option_sets_the_step_and_integrator_and_follows_mujoco():
    """The file's `timestep` and `integrator` are the world's: `step()` with no `dt` takes the
    file's step, and the inverted double pendulum (RK4 in its file) follows MuJoCo from a random
    start for 0.5 s at that step (VALIDATION #39)."""
    path = os.path.join(GYM_ASSETS, "inverted_double_pendulum.xml")
    w = kea.World.from_mjcf(path)
    assert w.integrator == "rk4"
    assert w.timestep == pytest.approx(0.01)
    with pytest.raises(ValueError, match="integrator"):
        w.integrator = "verlet"
    assert w.integrator == "rk4"
    mujoco = pytest.importorskip("mujoco")
    m = mujoco.MjModel.from_xml_path(path)
    d = mujoco.MjData(m)
    rng = np.random.default_rng(7)
    q0, v0 = rng.uniform(-0.3, 0.3, m.nq), rng.uniform(-1, 1, m.nv)
    d.qpos[:], d.qvel[:] = q0, v0
    w.set_joint_positions(q0)
    w.set_joint_velocities(v0)
    worst = 0.0
    for _ in range(50):
        mujoco.mj_step(m, d)
        w.step()
        worst = max(worst, float(np.max(np.abs(w.joint_positions() - d.qpos))))
    assert worst < 0.01, worst
    w.integrator = "euler"
    assert w.integrator == "euler"


TENDON_ARM = """<mujoco><option timestep="0.002"/>
  <worldbody><body name="a" pos="0 0 1"><joint name="j1" type="hinge" axis="0 1 0"/>
    <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.04"/>
    <body name="b" pos="0.4 0 0"><joint name="j2" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.04"/></body></body></worldbody>
  <tendon>
    <fixed name="held" range="-0.3 0.3"><joint joint="j1" coef="0.5"/><joint joint="j2" coef="1"/></fixed>
    <fixed name="idle"><joint joint="j1"/></fixed>
  </tendon></mujoco>"""


def test_a_robots_tendons_read_their_lengths_in_the_files_units(tmp_path):
    path = tmp_path / "arm.xml"
    path.write_text(TENDON_ARM)
    arm = kea.World.from_mjcf(str(path))
    assert arm.tendon_names() == ["held"]  # the force-free one is only reported
    assert any("idle" in line for line in arm.skipped())
    arm.step(0.002, steps=500)
    q = arm.joint_positions()
    (length, rate), = arm.tendon_lengths()
    assert length == pytest.approx(0.5 * q[0] + q[1], abs=1e-5)
    # Hanging from the horizontal, the arm folds until the range holds it (soft: a little past).
    assert -0.33 < length < 0.33
    assert math.isfinite(rate)


@needs_gym_assets
@pytest.mark.parametrize("model", ["ant.xml", "humanoid.xml"])
def test_legged_robot_batches_step_each_world_on_its_own_bits(model):
    """A batch's worlds hold only their states, and a worker per thread steps them: every
    world must still come out on the bits of the same world stepped alone, with its own
    controls, on one thread and on two, touching the floor, and a world taken out of the
    batch must go on stepping as the lone world does."""
    template = kea.World.from_mjcf(os.path.join(GYM_ASSETS, model))
    n, dt = 5, template.timestep
    rng = np.random.default_rng(7)
    controls = rng.uniform(-0.4, 0.4, size=(12, n, len(template.actuator_names())))
    alone = [template.copy() for _ in range(n)]
    batches = [kea.Batch(template, n, threads=t) for t in (1, 2)]
    for k, u in enumerate(controls):
        for i, w in enumerate(alone):
            w.set_controls(u[i])
            w.step(dt, 5)
        for batch in batches:
            batch.set_controls(u)
            batch.step(dt, 5)
            # Read every step, as a learning loop does.
            states, q, v = batch.state(), batch.joint_positions(), batch.joint_velocities()
            for i, w in enumerate(alone):
                at = (model, batch.threads, k, i)
                assert np.array_equal(states[i], w.state()), at
                assert np.array_equal(q[i], w.joint_positions()), at
                assert np.array_equal(v[i], w.joint_velocities()), at
    assert all(len(w.contact_points()["depth"]) > 0 for w in alone), "they touch the floor"
    out = batches[1].world(3)
    out.step(dt, 20)
    alone[3].step(dt, 20)
    assert np.array_equal(out.state(), alone[3].state())
