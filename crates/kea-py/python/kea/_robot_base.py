"""What Kea's robot tasks share (``kea.robot_envs``, ``kea.locomotion``): where the robots'
files are (the installed ``gymnasium`` and ``pybullet`` packages), a vector task over one
``kea.Batch`` of a robot's world, and its single form (a batch of one)."""

from __future__ import annotations

import importlib.util
import os
from typing import Optional

import gymnasium as gym
import numpy as np

import kea
from kea.envs import AutoresetVecEnv, SingleEnv


def _package_dir(name: str) -> str:
    spec = importlib.util.find_spec(name)
    if spec is None or not spec.submodule_search_locations:
        raise ImportError(f"{name} is not installed: it ships the robot's file")
    return list(spec.submodule_search_locations)[0]


def gymnasium_asset(name: str) -> str:
    """The path of one of Gymnasium's MuJoCo model files."""
    return os.path.join(_package_dir("gymnasium"), "envs", "mujoco", "assets", name)


def pybullet_data_file(name: str) -> str:
    """The path of a file in pybullet's ``pybullet_data``."""
    return os.path.join(_package_dir("pybullet_data"), name)


class _RobotVecEnv(AutoresetVecEnv):
    """What every task shares: a batch of one robot's world, reset and stepped as arrays."""

    max_steps = 1000
    frame_skip = 1

    def __init__(self, world: kea.World, num_envs: int, threads: Optional[int], dt: float):
        self.num_envs = num_envs
        self.dt_physics = dt
        self.batch = kea.Batch(world, num_envs, threads)
        self.init_qpos = world.joint_positions()
        self.init_qvel = world.joint_velocities()
        self.single_observation_space = gym.spaces.Box(
            -np.inf, np.inf, shape=(self.observation_size,), dtype=np.float64
        )
        self.observation_space = gym.vector.utils.batch_space(self.single_observation_space, num_envs)
        self.action_space = gym.vector.utils.batch_space(self.single_action_space, num_envs)
        self._rng = np.random.default_rng()
        self._steps = np.zeros(num_envs, dtype=np.int64)
        self._done = np.zeros(num_envs, dtype=bool)

    @property
    def dt(self) -> float:
        """One environment step, s (Gymnasium's ``dt``)."""
        return self.dt_physics * self.frame_skip

    # What a task defines.
    observation_size = 0
    single_action_space: gym.spaces.Box

    def _initial(self, count: int) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    def _observe(self) -> np.ndarray:
        raise NotImplementedError

    def _apply(self, actions: np.ndarray) -> None:
        raise NotImplementedError

    def _reward(self, actions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    def _start(self, idx: np.ndarray) -> None:
        q = self.batch.joint_positions()
        v = self.batch.joint_velocities()
        q[idx], v[idx] = self._initial(idx.size)
        self.batch.set_joint_positions(q)
        self.batch.set_joint_velocities(v)

    def step(self, actions):
        restart = self._begin_step()
        low, high = self.single_action_space.low, self.single_action_space.high
        raw = np.asarray(actions, dtype=np.float64).reshape(self.num_envs, -1)
        self._apply(np.clip(raw, low, high))
        self.batch.step(self.dt_physics, self.frame_skip)
        obs = self._observe()
        # As Gymnasium's: the robot feels the actions clipped to their range, the control
        # cost is on the actions as given.
        reward, terminated = self._reward(raw)
        return self._end_step(restart, obs, reward, terminated, self.max_steps)


class _Single(SingleEnv):
    """One task (a batch of one), for ``gymnasium.make``."""

    vector_class: type = _RobotVecEnv
