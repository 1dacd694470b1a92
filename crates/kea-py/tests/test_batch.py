"""Batches: shapes, bit-for-bit agreement with worlds stepped one by one and across thread
counts, resets, and the Gymnasium environment."""

import numpy as np
import pytest

import kea
from kea.envs import CartPoleEnv, CartPoleVecEnv, cart_pole_world, initial_states


def perturbed_states(world, n, seed):
    return initial_states(world.state(), np.random.default_rng(seed), n)


def test_batch_arrays_have_batch_shapes_and_float64():
    b = kea.Batch(cart_pole_world(), 5, threads=2)
    assert len(b) == 5 and b.body_count == 2 and b.joint_count == 2
    s = b.state()
    assert s.shape == (5, 2, kea.STATE_WIDTH) and s.dtype == np.float64
    pos, vel = b.joint_state()
    assert pos.shape == (5, 2) and vel.shape == (5, 2) and pos.dtype == np.float64


def test_a_batch_equals_its_worlds_stepped_one_by_one_bit_for_bit():
    n, steps = 6, 40
    template = cart_pole_world()
    states = perturbed_states(template, n, 7)
    speeds = np.random.default_rng(8).uniform(-3, 3, (steps, n))
    forces = np.random.default_rng(9).normal(0, 2, (steps, n, 2, 3))
    results = []
    for threads in (1, 2):
        batch = kea.Batch(template, n, threads=threads)
        batch.set_state(states)
        motors = np.zeros((n, 2))
        for k in range(steps):
            motors[:, 0] = speeds[k]
            batch.set_motors(motors)
            batch.apply_forces(forces[k])
            batch.step(0.01, 2)
        results.append(batch.state())
    assert np.array_equal(results[0], results[1])
    for i in range(n):
        w = template.copy()
        w.set_state(states[i])
        for k in range(steps):
            w.set_motor(0, speeds[k, i])
            for body in range(2):
                w.add_force(body, forces[k, i, body])
            w.step(0.01, 2)
        assert np.array_equal(w.state(), results[0][i]), f"world {i}"


def test_reset_puts_chosen_worlds_back():
    batch = kea.Batch(cart_pole_world(), 3)
    start = batch.state()
    motors = np.zeros((3, 2))
    motors[:, 0] = 2.0
    batch.set_motors(motors)
    batch.step(0.01, 20)
    moved = batch.state()
    batch.reset([0, 2])
    after = batch.state()
    assert np.array_equal(after[[0, 2]], start[[0, 2]])
    assert np.array_equal(after[1], moved[1])
    with pytest.raises(IndexError, match="indices"):
        batch.reset([3])


def test_a_closed_loop_reads_and_drives_what_each_world_holds():
    """A learning loop's set-step-read: what the loop reads must be what each world holds
    (as a copy taken out shows it), at every step; motors set before a copy is taken out
    or before a reset act as they would on a world of its own."""
    n, steps = 4, 6
    template = cart_pole_world()
    speeds = np.random.default_rng(3).uniform(-3, 3, (steps, n))
    batch = kea.Batch(template, n, threads=2)
    alone = [template.copy() for _ in range(n)]
    motors = np.zeros((n, 2))
    for k in range(steps):
        motors[:, 0] = speeds[k]
        batch.set_motors(motors)
        batch.step(0.01, 2)
        states, (pos, vel) = batch.state(), batch.joint_state()
        for i, w in enumerate(alone):
            w.set_motor(0, speeds[k, i])
            w.step(0.01, 2)
            assert np.array_equal(states[i], w.state()), (k, i)
            assert np.array_equal(batch.world(i).state(), w.state()), (k, i)
        # Forces change no state before the step: the read-outs still hold.
        batch.apply_forces(np.zeros((n, 2, 3)))
        assert np.array_equal(batch.state(), states)
        assert np.array_equal(batch.joint_state()[0], pos)
    # Setting the states changes what the next read sees.
    moved = batch.state()
    moved[:, 0, 0] += 0.25
    batch.set_state(moved)
    after = batch.state()
    assert np.allclose(after, moved, rtol=0, atol=1e-6)  # to the build's precision
    assert all(np.array_equal(after[i], batch.world(i).state()) for i in range(n))
    for i, w in enumerate(alone):
        w.set_state(moved[i])
    # A copy taken out after set_motors carries the motors.
    motors[:, 0] = 2.5
    batch.set_motors(motors)
    out = batch.world(1)
    alone[1].set_motor(0, 2.5)
    out.step(0.01, 3)
    alone[1].step(0.01, 3)
    assert np.array_equal(out.state(), alone[1].state())
    # A reset after set_motors puts the worlds back to the batch's world, motors and all.
    motors[:, 0] = -1.5
    batch.set_motors(motors)
    batch.reset()
    batch.step(0.01, 4)
    fresh = template.copy()
    fresh.step(0.01, 4)
    assert np.array_equal(batch.state()[2], fresh.state())


def test_batch_refuses_bad_arrays_by_name():
    batch = kea.Batch(cart_pole_world(), 2)
    with pytest.raises(ValueError, match="forces"):
        batch.apply_forces(np.zeros((2, 3, 3)))
    with pytest.raises(ValueError, match="forces"):
        batch.apply_forces(np.full((2, 2, 3), np.nan))
    with pytest.raises(ValueError, match="velocities"):
        batch.set_motors(np.ones((2, 2)))  # joint 1 (the hinge) has no motor
    with pytest.raises(ValueError, match="state"):
        batch.set_state(np.zeros((2, 2, 13)))
    with pytest.raises(ValueError, match="n"):
        kea.Batch(cart_pole_world(), 0)


def test_the_cart_pole_passes_the_gymnasium_checker():
    from gymnasium.utils.env_checker import check_env

    check_env(CartPoleEnv(), skip_render_check=True)


def test_the_vector_env_balances_for_a_while_and_resets_itself():
    env = CartPoleVecEnv(8, threads=2)
    obs, _ = env.reset(seed=3)
    assert obs.shape == (8, 4) and obs.dtype == np.float32
    assert np.all(np.abs(obs) <= 0.05 + 1e-6)
    episodes = 0
    for _ in range(300):
        # A hand-tuned balancing servo: move the cart under the pole.
        action = np.clip(-(8.0 * obs[:, 1] + 1.5 * obs[:, 3]) * -1.0 + 0.1 * obs[:, 0], -1, 1)
        obs, reward, terminated, truncated, _ = env.step(action[:, None])
        episodes += int(terminated.sum() + truncated.sum())
        assert obs.shape == (8, 4) and reward.shape == (8,)
    assert np.all(np.isfinite(obs))
    # Random actions end episodes within a few hundred steps; the env restarts them.
    env.reset(seed=4)
    rng = np.random.default_rng(0)
    ended = 0
    for _ in range(200):
        _, _, terminated, truncated, _ = env.step(rng.uniform(-1, 1, (8, 1)))
        ended += int(terminated.sum() + truncated.sum())
    assert ended > 0


def test_a_closed_loop_reads_states_from_its_steps_on_the_bits_of_each_world():
    # After a state() that follows a step, each step reads every world's states while its
    # worker holds the world; state() answers from them until anything else changes a world.
    n = 4
    batch = kea.Batch(cart_pole_world(), n)
    alone = [cart_pole_world() for _ in range(n)]
    motors = np.zeros((n, 2))
    for k in range(12):
        motors[:, 0] = np.linspace(-2.0, 2.0, n) * np.cos(0.3 * k)
        batch.set_motors(motors)
        batch.step(0.01, 2)
        read = batch.state()
        for i, w in enumerate(alone):
            w.set_motor(0, motors[i, 0])
            w.step(0.01, 2)
            assert np.array_equal(read[i], w.state()), f"world {i}, step {k}"
    moved = read.copy()
    moved[:, 0, 0] += 0.5
    batch.set_state(moved)
    assert np.allclose(batch.state(), moved, rtol=0, atol=1e-6)
    batch.reset([0])
    assert np.array_equal(batch.state()[0], cart_pole_world().state())
