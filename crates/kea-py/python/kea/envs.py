"""Gymnasium environments built from Kea joints and motors, on ``kea.Batch``.

``CartPoleEnv`` is one cart-pole (``gymnasium.Env``); ``CartPoleVecEnv`` is N of them in one
``kea.Batch``, stepped on all cores (``gymnasium.vector.VectorEnv``, autoreset next step).

The model: a 1 kg cart on a prismatic joint along x with hard stops at ±2.4 m, driven by the
joint's motor (the action, in [-1, 1], sets its speed to ±3 m/s with at most 30 N); a 0.1 kg
pole of length 1 m on a hinge about z at the cart's centre. Observation: cart position, pole
angle (rad, 0 upright), cart velocity, pole angular velocity (float32). Reward 1 per step; the
episode ends when the pole tilts past 0.2 rad or the cart reaches a stop, and is cut at 500
steps. Each step is 0.02 s (two Kea steps of 0.01 s).
"""

from __future__ import annotations

from typing import Any, Optional

import gymnasium as gym
import numpy as np

import kea

POLE_LENGTH = 1.0
CART_MASS = 1.0
POLE_MASS = 0.1
MOTOR_SPEED = 3.0
MOTOR_FORCE = 30.0
RAIL = 2.4
TILT_LIMIT = 0.2
DT = 0.01
SUBSTEPS = 2
MAX_STEPS = 500
CART, POLE = 0, 1


def cart_pole_world() -> kea.World:
    """The cart-pole as a Kea world: bodies 0 (cart) and 1 (pole), joints 0 (slider, with a
    motor) and 1 (hinge)."""
    w = kea.World()
    cart = w.add_body(mass=CART_MASS)
    w.add_collider(cart, "cuboid", half_extents=(0.25, 0.1, 0.15))
    pole = w.add_body(mass=POLE_MASS)
    w.add_collider(pole, "capsule", a=(0.0, 0.0, 0.0), b=(0.0, POLE_LENGTH, 0.0), radius=0.03)
    w.add_joint(
        "prismatic", cart, None, axis=(1.0, 0.0, 0.0), limits=(-RAIL, RAIL), motor=(0.0, MOTOR_FORCE)
    )
    w.add_joint("hinge", pole, cart, anchor=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0))
    return w


def initial_states(template: np.ndarray, rng: np.random.Generator, n: int) -> np.ndarray:
    """``n`` states of the cart-pole with x, θ, ẋ, θ̇ each drawn from U(-0.05, 0.05)."""
    x, theta, xdot, thetadot = rng.uniform(-0.05, 0.05, size=(4, n))
    state = np.repeat(template[None], n, axis=0)
    half = 0.5 * POLE_LENGTH
    state[:, CART, 0] = x
    state[:, CART, 7] = xdot
    state[:, POLE, 0] = x
    state[:, POLE, 3:7] = 0.0
    state[:, POLE, 5] = np.sin(theta / 2)
    state[:, POLE, 6] = np.cos(theta / 2)
    # The pole's centre of mass turns about the pivot: v = ẋ x̂ + θ̇ ẑ × R(θ)(0, l/2, 0).
    state[:, POLE, 7] = xdot - thetadot * half * np.cos(theta)
    state[:, POLE, 8] = -thetadot * half * np.sin(theta)
    state[:, POLE, 12] = thetadot
    return state


def observe(state: np.ndarray) -> np.ndarray:
    """Observations (N, 4) from batch states (N, 2, 13)."""
    theta = 2.0 * np.arctan2(state[:, POLE, 5], state[:, POLE, 6])
    obs = np.stack([state[:, CART, 0], theta, state[:, CART, 7], state[:, POLE, 12]], axis=1)
    return obs.astype(np.float32)


def _spaces():
    high = np.array([4.8, np.pi, 100.0, 100.0], dtype=np.float32)
    observation = gym.spaces.Box(-high, high, dtype=np.float32)
    action = gym.spaces.Box(-1.0, 1.0, shape=(1,), dtype=np.float32)
    return observation, action


class AutoresetVecEnv(gym.vector.VectorEnv):
    """The next-step autoreset both Kea vector environments share: an environment that ended
    restarts at the next ``step``, which reports reward 0 and neither ending for it. A subclass
    sets ``num_envs``, ``batch``, ``_rng``, ``_steps`` and ``_done``, and defines
    ``_start(idx)`` (give the environments ``idx``, just reset to the batch's template, their
    random start) and ``_observe()``."""

    metadata = {"autoreset_mode": gym.vector.AutoresetMode.NEXT_STEP}

    def _start(self, idx: np.ndarray) -> None:
        raise NotImplementedError

    def _restart(self, which: np.ndarray) -> None:
        idx = np.flatnonzero(which)
        if idx.size == 0:
            return
        self.batch.reset(idx.tolist())
        self._start(idx)
        self._steps[idx] = 0

    def _observe(self) -> np.ndarray:
        raise NotImplementedError

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        if seed is not None:
            self._rng = np.random.default_rng(seed)
        self._restart(np.ones(self.num_envs, dtype=bool))
        self._done[:] = False
        return self._observe(), {}

    def _begin_step(self) -> np.ndarray:
        """Restarts the environments that ended; returns which."""
        restart = self._done.copy()
        self._restart(restart)
        return restart

    def _end_step(self, restart, obs, reward, terminated, max_steps):
        """Counts the step and returns Gymnasium's tuple for it."""
        self._steps += 1
        truncated = (self._steps >= max_steps) & ~terminated
        reward = np.where(restart, 0.0, reward)
        terminated[restart] = False
        truncated[restart] = False
        self._done = terminated | truncated
        return obs, reward, terminated, truncated, {}


class CartPoleVecEnv(AutoresetVecEnv):
    """``num_envs`` cart-poles in one ``kea.Batch``, stepped on ``threads`` threads."""

    def __init__(self, num_envs: int = 16, threads: Optional[int] = None):
        self.num_envs = num_envs
        self.batch = kea.Batch(cart_pole_world(), num_envs, threads)
        self._template = self.batch.world(0).state()
        self.single_observation_space, self.single_action_space = _spaces()
        self.observation_space = gym.vector.utils.batch_space(self.single_observation_space, num_envs)
        self.action_space = gym.vector.utils.batch_space(self.single_action_space, num_envs)
        self._rng = np.random.default_rng()
        self._steps = np.zeros(num_envs, dtype=np.int64)
        self._done = np.zeros(num_envs, dtype=bool)
        self._motors = np.zeros((num_envs, 2))

    def _start(self, idx: np.ndarray) -> None:
        state = self.batch.state()
        state[idx] = initial_states(self._template, self._rng, idx.size)
        self.batch.set_state(state)

    def _observe(self) -> np.ndarray:
        return observe(self.batch.state())

    def step(self, actions):
        restart = self._begin_step()
        a = np.clip(np.asarray(actions, dtype=np.float64).reshape(self.num_envs), -1.0, 1.0)
        self._motors[:, 0] = a * MOTOR_SPEED
        self.batch.set_motors(self._motors)
        self.batch.step(DT, SUBSTEPS)
        obs = self._observe()
        terminated = (np.abs(obs[:, 1]) > TILT_LIMIT) | (np.abs(obs[:, 0]) >= RAIL - 1e-3)
        return self._end_step(restart, obs, np.ones(self.num_envs), terminated, MAX_STEPS)


class SingleEnv(gym.Env):
    """One environment of a Kea vector environment (a batch of one): ``vector_class`` is the
    vector environment; its spaces are the single environment's."""

    metadata = {"render_modes": []}
    vector_class: type = AutoresetVecEnv

    def __init__(self):
        self._vec = self.vector_class(1, threads=1)
        self.observation_space = self._vec.single_observation_space
        self.action_space = self._vec.single_action_space

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict[str, Any]] = None):
        super().reset(seed=seed)
        if seed is not None or not hasattr(self, "_seeded"):
            self._vec._rng = self.np_random
            self._seeded = True
        self._vec._restart(np.ones(1, dtype=bool))
        self._vec._done[:] = False
        return self._vec._observe()[0], {}

    def step(self, action):
        self._vec._done[:] = False
        obs, reward, terminated, truncated, info = self._vec.step(np.asarray(action).reshape(1, -1))
        return obs[0], float(reward[0]), bool(terminated[0]), bool(truncated[0]), info


class CartPoleEnv(SingleEnv):
    """One Kea cart-pole (a batch of one)."""

    vector_class = CartPoleVecEnv


gym.register(id="kea/CartPole-v0", entry_point="kea.envs:CartPoleEnv")
