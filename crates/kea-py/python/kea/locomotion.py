"""Gymnasium's locomotion tasks on Kea, from their own MJCF files, each as a vector
environment over one ``kea.Batch`` and as a single ``gymnasium.Env`` (re-exported and
registered by ``kea.robot_envs``):

* ``HopperVecEnv``, ``Walker2dVecEnv``, ``HalfCheetahVecEnv`` (and their single forms):
  Gymnasium's ``Hopper-v5``, ``Walker2d-v5`` and ``HalfCheetah-v5`` from their own MJCF files,
  stepped in reduced coordinates with their contacts in joint space: the observation is the
  joint positions but the first (x) and the velocities (clipped to ±10 for the hopper and the
  walker), the actions the motors' controls in [-1, 1], the reward the forward speed (x moved
  over the environment step) less ``ctrl_cost_weight·|a|²`` plus 1 while healthy (hopper,
  walker), ending when unhealthy (torso height and angle out of range; the hopper's state past
  ±100), 1000 steps of ``frame_skip`` × the file's step; reset noise as Gymnasium's (uniform
  ±5e-3, or for the cheetah uniform ±0.1 on positions and normal 0.1 on velocities).

* ``AntVecEnv`` and ``HumanoidVecEnv`` (and their single forms): Gymnasium's ``Ant-v5`` and
  ``Humanoid-v5`` from their MJCF files, floating bases in reduced coordinates: the observation
  is the joint positions but x and y, the velocities, and MuJoCo's per-body quantities about
  the robot's centre of mass (``cfrc_ext`` clipped to ±1 for the ant; ``cinert``, ``cvel``,
  ``qfrc_actuator`` and ``cfrc_ext`` for the humanoid), built from ``Batch.link_states`` and
  ``Batch.actuator_forces``; the reward the torso's (ant) or the centre of mass's (humanoid)
  forward speed, plus the healthy reward, less the control and contact costs; ending when the
  torso's height leaves (0.2, 1.0) m or (1.0, 2.0) m. Kea reads these quantities at the step's
  end and a contact's force as its mean over the last physics step (MuJoCo reports the last
  Runge-Kutta stage's state and force, so impacts read differently).

Actions are clipped to their space before they reach the robot; the control cost is on the
actions as given, as Gymnasium's.
"""

from __future__ import annotations

from typing import Optional

import gymnasium as gym
import numpy as np

import kea
from kea._robot_base import _RobotVecEnv, _Single, gymnasium_asset


class _LocomotionVecEnv(_RobotVecEnv):
    """What Gymnasium's planar walkers share (module docs): a task sets the file, the frame
    skip and the weights, and whether it has a healthy range."""

    asset = ""
    frame_skip = 4
    max_steps = 1000
    forward_reward_weight = 1.0
    ctrl_cost_weight = 1e-3
    healthy_reward = 1.0
    # (low, high) of the torso's height and angle; None: never unhealthy.
    healthy_z: Optional[tuple[float, float]] = None
    healthy_angle: tuple[float, float] = (-np.inf, np.inf)
    # Bound on every entry of the state past its first two (the hopper's).
    healthy_state: Optional[float] = None
    clip_velocity: Optional[float] = 10.0
    reset_noise = 5e-3
    normal_velocity_noise = False

    def __init__(self, num_envs: int = 16, threads: Optional[int] = None):
        world = kea.World.from_mjcf(gymnasium_asset(self.asset))
        self.observation_size = world.position_count - 1 + world.velocity_count
        super().__init__(world, num_envs, threads, world.timestep)
        self._x_before = np.zeros(num_envs)

    def _initial(self, count):
        s = self.reset_noise
        nq, nv = self.init_qpos.size, self.init_qvel.size
        q = self.init_qpos + self._rng.uniform(-s, s, size=(count, nq))
        if self.normal_velocity_noise:
            v = self.init_qvel + s * self._rng.standard_normal((count, nv))
        else:
            v = self.init_qvel + self._rng.uniform(-s, s, size=(count, nv))
        return q, v

    def _observe(self):
        q, v = self.batch.joint_positions(), self.batch.joint_velocities()
        if self.clip_velocity is not None:
            v = np.clip(v, -self.clip_velocity, self.clip_velocity)
        return np.concatenate([q[:, 1:], v], axis=1)

    def _apply(self, actions):
        self._x_before = self.batch.joint_positions()[:, 0].copy()
        self.batch.set_controls(actions)

    def _healthy(self) -> np.ndarray:
        q, v = self.batch.joint_positions(), self.batch.joint_velocities()
        healthy = np.ones(self.num_envs, dtype=bool)
        if self.healthy_z is None:
            return healthy
        z, angle = q[:, 1], q[:, 2]
        healthy &= (self.healthy_z[0] < z) & (z < self.healthy_z[1])
        healthy &= (self.healthy_angle[0] < angle) & (angle < self.healthy_angle[1])
        if self.healthy_state is not None:
            state = np.concatenate([q, v], axis=1)[:, 2:]
            healthy &= np.all(np.abs(state) < self.healthy_state, axis=1)
        return healthy

    def _reward(self, actions):
        x_velocity = (self.batch.joint_positions()[:, 0] - self._x_before) / self.dt
        healthy = self._healthy()
        reward = self.forward_reward_weight * x_velocity - self.ctrl_cost_weight * np.square(
            actions
        ).sum(axis=1)
        if self.healthy_z is not None:
            reward = reward + self.healthy_reward * healthy
            return reward, ~healthy
        return reward, np.zeros(self.num_envs, dtype=bool)


class HopperVecEnv(_LocomotionVecEnv):
    """``num_envs`` of Gymnasium's Hopper-v5, from its MJCF file, in one ``kea.Batch``."""

    asset = "hopper.xml"
    single_action_space = gym.spaces.Box(-1.0, 1.0, shape=(3,), dtype=np.float32)
    healthy_z = (0.7, np.inf)
    healthy_angle = (-0.2, 0.2)
    healthy_state = 100.0


class Walker2dVecEnv(_LocomotionVecEnv):
    """``num_envs`` of Gymnasium's Walker2d-v5, from its MJCF file, in one ``kea.Batch``."""

    asset = "walker2d_v5.xml"
    single_action_space = gym.spaces.Box(-1.0, 1.0, shape=(6,), dtype=np.float32)
    healthy_z = (0.8, 2.0)
    healthy_angle = (-1.0, 1.0)


class HalfCheetahVecEnv(_LocomotionVecEnv):
    """``num_envs`` of Gymnasium's HalfCheetah-v5, from its MJCF file, in one ``kea.Batch``."""

    asset = "half_cheetah.xml"
    single_action_space = gym.spaces.Box(-1.0, 1.0, shape=(6,), dtype=np.float32)
    frame_skip = 5
    ctrl_cost_weight = 0.1
    clip_velocity = None
    reset_noise = 0.1
    normal_velocity_noise = True


class _FloatingBaseVecEnv(_RobotVecEnv):
    """What Gymnasium's Ant and Humanoid share (module docs): a free-floating torso whose
    height keeps the episode alive, MuJoCo's per-body quantities about the robot's centre of
    mass (``cfrc_ext``, and for the humanoid ``cinert``, ``cvel`` and ``qfrc_actuator``) built
    from ``Batch.link_states`` and ``Batch.actuator_forces``, at the environment step's end."""

    asset = ""
    frame_skip = 5
    max_steps = 1000
    forward_reward_weight = 1.0
    ctrl_cost_weight = 0.5
    contact_cost_weight = 5e-4
    healthy_reward = 1.0
    healthy_z: tuple[float, float] = (0.2, 1.0)
    reset_noise = 0.1
    # What the observation holds past the coordinates and rates, Gymnasium's order.
    observe_inertia = False
    observe_velocity = False
    observe_actuators = False
    # cfrc_ext in the observation clipped to this range (the Ant's), or whole (None).
    contact_clip: Optional[tuple[float, float]] = (-1.0, 1.0)

    def __init__(self, num_envs: int = 16, threads: Optional[int] = None):
        world = kea.World.from_mjcf(gymnasium_asset(self.asset))
        # MuJoCo's bodies: the file's links but the world and the links a body's several
        # joints are chained through (named "body/joint").
        self._bodies = np.array(
            [i for i, n in enumerate(world.link_names()) if i > 0 and "/" not in n]
        )
        ranges = np.array(world.control_ranges(), dtype=np.float32)
        self.single_action_space = gym.spaces.Box(ranges[:, 0], ranges[:, 1], dtype=np.float32)
        nb, nv = self._bodies.size, world.velocity_count
        self.observation_size = (
            world.position_count - 2
            + nv
            + 10 * nb * self.observe_inertia
            + 6 * nb * self.observe_velocity
            + (nv - 6) * self.observe_actuators
            + 6 * nb
        )
        super().__init__(world, num_envs, threads, world.timestep)
        self._actions = np.zeros((num_envs, ranges.shape[0]))
        self._before = np.zeros((num_envs, 2))

    def _initial(self, count):
        s = self.reset_noise
        nq, nv = self.init_qpos.size, self.init_qvel.size
        q = self.init_qpos + self._rng.uniform(-s, s, size=(count, nq))
        # Gymnasium's noise lands on the free joint's quaternion too; MuJoCo normalises it.
        q[:, 3:7] /= np.linalg.norm(q[:, 3:7], axis=1, keepdims=True)
        v = self.init_qvel + self._noise_velocity(count, nv)
        return q, v

    def _noise_velocity(self, count: int, nv: int) -> np.ndarray:
        return self.reset_noise * self._rng.standard_normal((count, nv))

    def _about_mass_centre(self):
        """Each body's MuJoCo quantities about the robot's centre of mass: cinert (N, B, 10),
        cvel (N, B, 6), cfrc_ext (N, B, 6), and that centre (N, 3)."""
        s = self.batch.link_states()
        b = self._bodies
        m, com = s["mass"][:, b], s["center_of_mass"][:, b]
        centre = (m[..., None] * com).sum(axis=1) / m.sum(axis=1)[:, None]
        d = com - centre[:, None]
        inertia = s["inertia"][:, b] + m[..., None, None] * (
            np.einsum("...i,...i", d, d)[..., None, None] * np.eye(3)
            - d[..., :, None] * d[..., None, :]
        )
        cinert = np.concatenate(
            [
                inertia[..., [0, 1, 2, 0, 0, 1], [0, 1, 2, 1, 2, 2]],
                m[..., None] * d,
                m[..., None],
            ],
            axis=-1,
        )
        w = s["angular_velocity"][:, b]
        cvel = np.concatenate([w, s["linear_velocity"][:, b] + np.cross(w, -d)], axis=-1)
        f = s["contact_force"][:, b]
        cfrc = np.concatenate([s["contact_torque"][:, b] + np.cross(d, f), f], axis=-1)
        return cinert, cvel, cfrc, centre

    def _observe(self):
        q, v = self.batch.joint_positions(), self.batch.joint_velocities()
        cinert, cvel, cfrc, _ = self._about_mass_centre()
        parts = [q[:, 2:], v]
        if self.observe_inertia:
            parts.append(cinert.reshape(self.num_envs, -1))
        if self.observe_velocity:
            parts.append(cvel.reshape(self.num_envs, -1))
        if self.observe_actuators:
            parts.append(self.batch.actuator_forces(self._actions)[:, 6:])
        if self.contact_clip is not None:
            cfrc = np.clip(cfrc, *self.contact_clip)
        parts.append(cfrc.reshape(self.num_envs, -1))
        return np.concatenate(parts, axis=1)

    def _forward_position(self) -> np.ndarray:
        return self.batch.joint_positions()[:, :2]

    def _apply(self, actions):
        self._actions = actions
        self._before = self._forward_position().copy()
        self.batch.set_controls(actions)

    def _contact_cost(self, cfrc: np.ndarray) -> np.ndarray:
        if self.contact_clip is not None:
            cfrc = np.clip(cfrc, *self.contact_clip)
        return self.contact_cost_weight * np.square(cfrc).sum(axis=(1, 2))

    def _healthy(self, q, v):
        z = q[:, 2]
        healthy = np.isfinite(np.concatenate([q, v], axis=1)).all(axis=1)
        return healthy & (self.healthy_z[0] <= z) & (z <= self.healthy_z[1])

    def _reward(self, actions):
        q, v = self.batch.joint_positions(), self.batch.joint_velocities()
        x_velocity = (self._forward_position()[:, 0] - self._before[:, 0]) / self.dt
        healthy = self._healthy(q, v)
        _, _, cfrc, _ = self._about_mass_centre()
        reward = (
            self.forward_reward_weight * x_velocity
            + self.healthy_reward * healthy
            - self.ctrl_cost_weight * np.square(actions).sum(axis=1)
            - self._contact_cost(cfrc)
        )
        return reward, ~healthy


class AntVecEnv(_FloatingBaseVecEnv):
    """``num_envs`` of Gymnasium's Ant-v5, from its MJCF file, in one ``kea.Batch``."""

    asset = "ant.xml"


class HumanoidVecEnv(_FloatingBaseVecEnv):
    """``num_envs`` of Gymnasium's Humanoid-v5, from its MJCF file, in one ``kea.Batch``."""

    asset = "humanoid.xml"
    forward_reward_weight = 1.25
    ctrl_cost_weight = 0.1
    contact_cost_weight = 5e-7
    healthy_reward = 5.0
    healthy_z = (1.0, 2.0)
    reset_noise = 1e-2
    observe_inertia = True
    observe_velocity = True
    observe_actuators = True
    contact_clip = None

    def _noise_velocity(self, count: int, nv: int) -> np.ndarray:
        return self._rng.uniform(-self.reset_noise, self.reset_noise, size=(count, nv))

    def _forward_position(self) -> np.ndarray:
        # The robot's centre of mass (Gymnasium's ``mass_center``).
        return self._about_mass_centre()[3][:, :2]

    def _contact_cost(self, cfrc: np.ndarray) -> np.ndarray:
        return np.minimum(self.contact_cost_weight * np.square(cfrc).sum(axis=(1, 2)), 10.0)

    def _healthy(self, q, v):
        # Strictly inside (1, 2) m; the finite check is the Ant's alone.
        z = q[:, 2]
        return (self.healthy_z[0] < z) & (z < self.healthy_z[1])


class HopperEnv(_Single):
    """Gymnasium's Hopper-v5 on Kea, from its own MJCF."""

    vector_class = HopperVecEnv


class Walker2dEnv(_Single):
    """Gymnasium's Walker2d-v5 on Kea, from its own MJCF."""

    vector_class = Walker2dVecEnv


class HalfCheetahEnv(_Single):
    """Gymnasium's HalfCheetah-v5 on Kea, from its own MJCF."""

    vector_class = HalfCheetahVecEnv


class AntEnv(_Single):
    """Gymnasium's Ant-v5 on Kea, from its own MJCF."""

    vector_class = AntVecEnv


class HumanoidEnv(_Single):
    """Gymnasium's Humanoid-v5 on Kea, from its own MJCF."""

    vector_class = HumanoidVecEnv
