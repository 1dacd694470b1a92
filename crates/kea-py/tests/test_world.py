"""Kea through Python: physics against closed forms, numpy shapes and dtypes, errors that
name their argument, and scene files."""

import math
import pathlib

import numpy as np
import pytest

import kea

SCENES = pathlib.Path(__file__).resolve().parents[3] / "scenes"
G = 9.81


def test_free_fall_follows_semi_implicit_euler():
    w = kea.World()
    b = w.add_body(position=(0.0, 100.0, 0.0))
    w.add_collider(b, "ball", radius=0.5)
    h, n = 1.0 / 60.0, 60
    w.step(h, n)
    # v_n = -g n h, y_n = y0 - g h² n(n+1)/2
    y = 100.0 - G * h * h * n * (n + 1) / 2
    assert w.position(b)[1] == pytest.approx(y, abs=1e-3)
    assert w.linear_velocity(b)[1] == pytest.approx(-G * h * n, abs=1e-3)
    assert w.time == pytest.approx(1.0, abs=1e-5)


def test_density_gives_the_mass_of_a_ball():
    w = kea.World()
    b = w.add_body()
    w.add_collider(b, "ball", radius=0.3, density=500.0)
    assert w.mass(b) == pytest.approx(500.0 * 4.0 / 3.0 * math.pi * 0.3**3, rel=1e-5)


@pytest.mark.parametrize("length", [0.5, 2.0])
def test_hinge_pendulum_has_the_small_angle_period(length):
    w = kea.World()
    theta0 = 0.05
    bob = w.add_body(position=(length * math.sin(theta0), -length * math.cos(theta0), 0.0))
    w.add_collider(bob, "ball", radius=0.01, density=1e4)
    j = w.add_joint("hinge", bob, None, anchor=(0, 0, 0), axis=(0, 0, 1))
    h = 1.0 / 240.0
    crossings, last = [], w.position(bob)[0]
    for i in range(1, 2400):
        w.step(h)
        x = w.position(bob)[0]
        if last < 0.0 <= x:
            crossings.append(i * h)
        last = x
        if len(crossings) == 3:
            break
    period = (crossings[2] - crossings[0]) / 2
    assert period == pytest.approx(2 * math.pi * math.sqrt(length / G), rel=0.01)
    assert abs(w.joint_position(j)) < 2 * theta0 + 1e-3


def test_state_is_a_float64_array_of_13_columns_that_round_trips():
    w = kea.World()
    for i in range(3):
        b = w.add_body(position=(i, 1.0, 0.0))
        w.add_collider(b, "cuboid", half_extents=(0.1, 0.2, 0.3))
    s = w.state()
    assert s.shape == (3, kea.STATE_WIDTH) and s.dtype == np.float64
    assert np.array_equal(s[:, 0], [0.0, 1.0, 2.0])
    assert np.array_equal(s[:, 3:7], np.tile([0.0, 0.0, 0.0, 1.0], (3, 1)))
    s[1, 7:10] = (1.0, 2.0, 3.0)
    w.set_state(s)
    assert w.linear_velocity(1) == (1.0, 2.0, 3.0)
    assert np.array_equal(w.state(), s)


def test_bad_input_raises_value_error_naming_the_argument_and_changes_nothing():
    w = kea.World()
    b = w.add_body()
    before = w.state()
    with pytest.raises(ValueError, match="radius"):
        w.add_collider(b, "ball", radius=-1.0)
    with pytest.raises(ValueError, match="density"):
        w.add_collider(b, "cuboid", half_extents=(1, 1, 1), density=float("nan"))
    with pytest.raises(ValueError, match="kind"):
        w.add_body(kind="wobbly")
    with pytest.raises(ValueError, match="shape"):
        w.add_collider(b, "teapot")
    with pytest.raises(ValueError, match="dt"):
        w.step(-0.1)
    with pytest.raises(ValueError, match="axis"):
        w.add_joint("hinge", b, None, axis=(0, 0, 0))
    with pytest.raises(ValueError, match="state"):
        w.set_state(np.zeros((2, 13)))
    bad = before.copy()
    bad[0, 3:7] = (0.0, 0.0, 0.0, 2.0)
    with pytest.raises(ValueError, match="state"):
        w.set_state(bad)
    with pytest.raises(IndexError, match="body"):
        w.add_force(7, (0, 1, 0))
    with pytest.raises(ValueError, match="position"):
        w.add_body(position=(float("inf"), 0, 0))
    assert np.array_equal(w.state(), before)
    assert w.body_count == 1


def test_a_kinematic_body_moves_at_its_velocity_and_pushes_a_box():
    w = kea.World()
    floor = w.add_body(kind="static")
    w.add_collider(floor, "cuboid", half_extents=(20, 0.5, 20))
    box = w.add_body(position=(1.0, 1.0, 0.0))
    w.add_collider(box, "cuboid", half_extents=(0.5, 0.5, 0.5), density=125.0)
    pusher = w.add_body(kind="kinematic", position=(-1.0, 1.1, 0.0))
    w.add_collider(pusher, "cuboid", half_extents=(0.5, 0.55, 1.0))
    w.set_linear_velocity(pusher, (1.0, 0.0, 0.0))
    w.step(1.0 / 60.0, 180)
    px, bx = w.position(pusher)[0], w.position(box)[0]
    assert px == pytest.approx(2.0, abs=1e-4)
    assert bx - px == pytest.approx(1.0, abs=0.02)


def test_a_scene_file_loads_with_its_names():
    w = kea.World.from_scene(SCENES / "pendulum.json")
    assert w.body_count >= 1 and len(w.body_names) == w.body_count
    assert all(w.body_names)
    y0 = w.state()[:, 1].copy()
    w.step(1.0 / 60.0, 30)
    assert np.all(np.isfinite(w.state()))
    assert not np.array_equal(w.state()[:, 1], y0)
    with pytest.raises(OSError, match="path"):
        kea.World.from_scene(SCENES / "missing.json")
    with pytest.raises(ValueError):
        kea.World.from_scene_json('{"version": 1, "bodies": [{"mass": -1}]}')
