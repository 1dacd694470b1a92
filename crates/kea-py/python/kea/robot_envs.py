"""Gymnasium tasks on robots loaded from their own files, each as a vector environment over
one ``kea.Batch`` (stepped on all cores; ``gymnasium.vector.VectorEnv``, autoreset next step)
and as a single ``gymnasium.Env`` (a batch of one, so both give the same numbers):

* ``ReacherVecEnv`` / ``ReacherEnv``: Gymnasium's ``Reacher-v5`` built from its own MJCF file
  (``gymnasium/envs/mujoco/assets/reacher.xml``): the same 10-number observation, 2 torques in
  [-1, 1] as actions, reward ``-|fingertip - target| - |a|²``, 50 steps of 2 × 0.01 s.
* ``InvertedDoublePendulumVecEnv`` / ``InvertedDoublePendulumEnv``: ``InvertedDoublePendulum-v5``
  from its MJCF: the same 9-number observation (cart position, sines and cosines of the poles'
  angles, clipped velocities, the cart's constraint force), one force in [-1, 1], reward
  ``10 - distance and velocity penalties``, ending when the tip falls below 1 m; 1000 steps of
  5 × 0.01 s (each Kea step split in 2).
* ``KukaReachVecEnv`` / ``KukaReachEnv``: the KUKA iiwa of ``pybullet_data`` (its URDF) reaching
  for a target: actions are the 7 joint motors' speeds (in [-1, 1] × 1 rad/s, at most each
  joint's effort limit), the observation joint positions and velocities, the hand's position and
  the target's (20 numbers), reward ``-|hand - target| - 0.01 |a|²``, 200 steps of 10 × 2 ms.

* The locomotion tasks (``HopperEnv``, ``Walker2dEnv``, ``HalfCheetahEnv``, ``AntEnv``,
  ``HumanoidEnv`` and their vector forms) live in ``kea.locomotion`` and are re-exported here.

Actions are clipped to their space before they reach the robot; the control cost is on the
actions as given, as Gymnasium's. The robot files come from the installed ``gymnasium`` and
``pybullet`` packages.
"""

from __future__ import annotations

from typing import Optional

import gymnasium as gym
import numpy as np

import kea
from kea._robot_base import _RobotVecEnv, _Single, gymnasium_asset, pybullet_data_file
from kea.locomotion import (  # noqa: F401 (re-exported)
    AntEnv,
    AntVecEnv,
    HalfCheetahEnv,
    HalfCheetahVecEnv,
    HopperEnv,
    HopperVecEnv,
    HumanoidEnv,
    HumanoidVecEnv,
    Walker2dEnv,
    Walker2dVecEnv,
)


class ReacherVecEnv(_RobotVecEnv):
    """``num_envs`` of Gymnasium's Reacher, from its MJCF file, in one ``kea.Batch``."""

    observation_size = 10
    single_action_space = gym.spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)
    max_steps = 50
    frame_skip = 2

    def __init__(self, num_envs: int = 16, threads: Optional[int] = None):
        world = kea.World.from_mjcf(gymnasium_asset("reacher.xml"))
        super().__init__(world, num_envs, threads, world.timestep)

    def _initial(self, count):
        q = self.init_qpos + self._rng.uniform(-0.1, 0.1, size=(count, 4))
        goals = np.empty((count, 2))
        for k in range(count):
            while True:
                g = self._rng.uniform(-0.2, 0.2, size=2)
                if np.linalg.norm(g) < 0.2:
                    break
            goals[k] = g
        q[:, 2:] = goals
        v = self.init_qvel + self._rng.uniform(-0.005, 0.005, size=(count, 4))
        v[:, 2:] = 0.0
        return q, v

    def _gap(self):
        return self.batch.link_positions("fingertip") - self.batch.link_positions("target")

    def _observe(self):
        q, v = self.batch.joint_positions(), self.batch.joint_velocities()
        return np.concatenate(
            [np.cos(q[:, :2]), np.sin(q[:, :2]), q[:, 2:], v[:, :2], self._gap()[:, :2]], axis=1
        )

    def _apply(self, actions):
        self.batch.set_controls(actions)

    def _reward(self, actions):
        reward = -np.linalg.norm(self._gap(), axis=1) - np.square(actions).sum(axis=1)
        return reward, np.zeros(self.num_envs, dtype=bool)


class InvertedDoublePendulumVecEnv(_RobotVecEnv):
    """``num_envs`` of Gymnasium's InvertedDoublePendulum, from its MJCF, in one ``kea.Batch``."""

    observation_size = 9
    single_action_space = gym.spaces.Box(-1.0, 1.0, shape=(1,), dtype=np.float32)
    max_steps = 1000
    frame_skip = 5
    gear = 500.0
    damping = 0.05

    def __init__(self, num_envs: int = 16, threads: Optional[int] = None):
        world = kea.World.from_mjcf(gymnasium_asset("inverted_double_pendulum.xml"))
        # The file asks for RK4 at 0.01 s; four Euler substeps of 2.5 ms follow it within a
        # few hundredths over an episode's first steps (the tree steps in reduced coordinates,
        # so they cost little).
        world.set_substeps(4)
        super().__init__(world, num_envs, threads, world.timestep)
        self._force = np.zeros(num_envs)

    def _initial(self, count):
        q = self.init_qpos + self._rng.uniform(-0.1, 0.1, size=(count, 3))
        v = self.init_qvel + self._rng.standard_normal((count, 3)) * 0.1
        return q, v

    def _constraint_force(self):
        # The slider's stop force along x (MuJoCo's qfrc_constraint[0]): the joint's reaction
        # on the cart along the rail, less the motor's force and the joint's damping.
        along = self.batch.joint_reactions()[:, 0, 0]
        return along - self._force + self.damping * self.batch.joint_velocities()[:, 0]

    def _observe(self):
        q, v = self.batch.joint_positions(), self.batch.joint_velocities()
        return np.concatenate(
            [
                q[:, :1],
                np.sin(q[:, 1:]),
                np.cos(q[:, 1:]),
                np.clip(v, -10.0, 10.0),
                np.clip(self._constraint_force(), -10.0, 10.0)[:, None],
            ],
            axis=1,
        )

    def _apply(self, actions):
        self._force = self.gear * actions[:, 0]
        self.batch.set_controls(actions)

    def _reward(self, actions):
        tip = self.batch.link_positions("pole2", (0.0, 0.0, 0.6))
        x, y = tip[:, 0], tip[:, 2]
        v = self.batch.joint_velocities()
        terminated = y <= 1.0
        penalty = 0.01 * x**2 + (y - 2.0) ** 2 + 1e-3 * v[:, 1] ** 2 + 5e-3 * v[:, 2] ** 2
        return np.where(terminated, 0.0, 10.0) - penalty, terminated


class KukaReachVecEnv(_RobotVecEnv):
    """``num_envs`` KUKA iiwa arms (from pybullet_data's URDF) reaching for targets."""

    observation_size = 20
    single_action_space = gym.spaces.Box(-1.0, 1.0, shape=(7,), dtype=np.float32)
    max_steps = 200
    frame_skip = 10
    speed = 1.0  # rad/s at action 1
    hand = "lbr_iiwa_link_7"

    def __init__(self, num_envs: int = 16, threads: Optional[int] = None):
        world = kea.World.from_urdf(pybullet_data_file("kuka_iiwa/model.urdf"), fixed_base=True)
        super().__init__(world, num_envs, threads, 0.002)
        self.targets = np.zeros((num_envs, 3))

    def _initial(self, count):
        q = self._rng.uniform(-0.3, 0.3, size=(count, 7))
        return q, np.zeros((count, 7))

    def _restart(self, which):
        idx = np.flatnonzero(which)
        super()._restart(which)
        self.targets[idx] = self._rng.uniform([0.3, -0.4, 0.3], [0.7, 0.4, 0.9], size=(idx.size, 3))

    def _observe(self):
        return np.concatenate(
            [
                self.batch.joint_positions(),
                self.batch.joint_velocities(),
                self.batch.link_positions(self.hand),
                self.targets,
            ],
            axis=1,
        )

    def _apply(self, actions):
        self.batch.set_joint_motors(actions * self.speed)

    def _reward(self, actions):
        gap = np.linalg.norm(self.batch.link_positions(self.hand) - self.targets, axis=1)
        return -gap - 0.01 * np.square(actions).sum(axis=1), np.zeros(self.num_envs, dtype=bool)


class ReacherEnv(_Single):
    """Gymnasium's Reacher on Kea, from its own MJCF."""

    vector_class = ReacherVecEnv


class InvertedDoublePendulumEnv(_Single):
    """Gymnasium's InvertedDoublePendulum on Kea, from its own MJCF."""

    vector_class = InvertedDoublePendulumVecEnv


class KukaReachEnv(_Single):
    """The KUKA iiwa reaching for a target, from pybullet_data's URDF."""

    vector_class = KukaReachVecEnv


gym.register(id="kea/Reacher-v0", entry_point="kea.robot_envs:ReacherEnv")
gym.register(id="kea/InvertedDoublePendulum-v0", entry_point="kea.robot_envs:InvertedDoublePendulumEnv")
gym.register(id="kea/KukaReach-v0", entry_point="kea.robot_envs:KukaReachEnv")
gym.register(id="kea/Hopper-v0", entry_point="kea.robot_envs:HopperEnv")
gym.register(id="kea/Walker2d-v0", entry_point="kea.robot_envs:Walker2dEnv")
gym.register(id="kea/HalfCheetah-v0", entry_point="kea.robot_envs:HalfCheetahEnv")
gym.register(id="kea/Ant-v0", entry_point="kea.robot_envs:AntEnv")
gym.register(id="kea/Humanoid-v0", entry_point="kea.robot_envs:HumanoidEnv")
