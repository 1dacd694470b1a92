"""Type stubs of the compiled module ``kea._kea``."""

from os import PathLike
from typing import Any, Dict, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

STATE_WIDTH: int
DOUBLE_PRECISION: bool
__version__: str

Vec3 = Sequence[float]
Quat = Sequence[float]
# Any real array-like: a list, or a numpy array of any real dtype and any layout.
ArrayLike = npt.ArrayLike
RayHits = Tuple[
    npt.NDArray[np.bool_], npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.int64]
]

class World:
    """A world: bodies, colliders and joints, stepped together."""

    def __init__(self, gravity: Tuple[float, float, float] = (0.0, -9.81, 0.0)) -> None: ...
    @staticmethod
    def from_scene(path: Union[str, PathLike[str]]) -> "World": ...
    @staticmethod
    def from_scene_json(text: str) -> "World": ...
    def copy(self) -> "World": ...
    def add_body(
        self,
        kind: str = "dynamic",
        position: Vec3 = ...,
        rotation: Quat = ...,
        linear_velocity: Vec3 = ...,
        angular_velocity: Vec3 = ...,
        mass: Optional[float] = None,
        linear_damping: float = 0.0,
        angular_damping: float = 0.0,
    ) -> int: ...
    def add_collider(
        self,
        body: Optional[int],
        shape: str,
        *,
        half_extents: Optional[Vec3] = None,
        radius: Optional[float] = None,
        half_height: Optional[float] = None,
        normal: Optional[Vec3] = None,
        a: Optional[Vec3] = None,
        b: Optional[Vec3] = None,
        translation: Vec3 = ...,
        rotation: Quat = ...,
        density: float = 1000.0,
        mass: Optional[float] = None,
        friction: Optional[float] = None,
        restitution: Optional[float] = None,
    ) -> int: ...
    def add_joint(
        self,
        kind: str,
        body1: int,
        body2: Optional[int] = None,
        *,
        anchor: Vec3 = ...,
        axis: Vec3 = ...,
        axis2: Optional[Vec3] = None,
        limits: Optional[Tuple[float, float]] = None,
        motor: Optional[Tuple[float, float]] = None,
    ) -> int: ...
    def step(self, dt: Optional[float] = None, steps: int = 1) -> None: ...
    def state(self) -> npt.NDArray[np.float64]: ...
    def set_state(self, state: ArrayLike) -> None: ...
    def position(self, body: int) -> Tuple[float, float, float]: ...
    def rotation(self, body: int) -> Tuple[float, float, float, float]: ...
    def linear_velocity(self, body: int) -> Tuple[float, float, float]: ...
    def angular_velocity(self, body: int) -> Tuple[float, float, float]: ...
    def mass(self, body: int) -> float: ...
    def set_linear_velocity(self, body: int, velocity: Vec3) -> None: ...
    def add_force(self, body: int, force: Vec3) -> None: ...
    def add_torque(self, body: int, torque: Vec3) -> None: ...
    def set_kinematic_target(self, body: int, position: Vec3, rotation: Quat) -> None: ...
    def joint_position(self, joint: int) -> float: ...
    def joint_velocity(self, joint: int) -> float: ...
    def set_motor(self, joint: int, velocity: float) -> None: ...
    @property
    def gravity(self) -> Tuple[float, float, float]: ...
    @property
    def time(self) -> float: ...
    @property
    def body_count(self) -> int: ...
    @property
    def joint_count(self) -> int: ...
    @property
    def body_names(self) -> list[str]: ...
    @property
    def joint_names(self) -> list[str]: ...
    # Robots from their own files (URDF, MJCF) and their joint vectors.
    @staticmethod
    def from_urdf(
        path: Union[str, PathLike[str]],
        fixed_base: bool = False,
        *,
        base_position: Vec3 = ...,
        base_rotation: Quat = ...,
        mesh_search_path: Optional[Sequence[Union[str, PathLike[str]]]] = None,
        self_collision: bool = False,
        meshes_as_trimesh: bool = False,
        gravity: Vec3 = ...,
    ) -> "World":
        """A world holding a URDF robot, gravity along -z; errors name file, line, element."""
    @staticmethod
    def from_mjcf(
        path: Union[str, PathLike[str]],
        *,
        mesh_search_path: Optional[Sequence[Union[str, PathLike[str]]]] = None,
        self_collision: bool = True,
        meshes_as_trimesh: bool = False,
    ) -> "World":
        """A world holding an MJCF model, with its gravity, timestep and actuators."""
    def joint_positions(self) -> npt.NDArray[np.float64]:
        """Joint positions in the file's order (MuJoCo's qpos layout)."""
    def joint_velocities(self) -> npt.NDArray[np.float64]:
        """Joint velocities in the file's order (MuJoCo's qvel layout)."""
    def set_joint_positions(self, q: ArrayLike) -> None:
        """Re-poses the robot by forward kinematics, keeping velocities."""
    def set_joint_velocities(self, v: ArrayLike) -> None:
        """Sets the bodies' velocities to these joint velocities."""
    def set_joint_forces(self, forces: ArrayLike) -> None:
        """A force or torque along each joint coordinate, until changed."""
    def set_controls(self, controls: ArrayLike) -> None:
        """One control per actuator of the file (MuJoCo's ctrl), clamped to its range."""
    @property
    def position_count(self) -> int: ...
    @property
    def velocity_count(self) -> int: ...
    @property
    def timestep(self) -> Optional[float]: ...
    @property
    def integrator(self) -> str: ...
    @integrator.setter
    def integrator(self, name: str) -> None: ...
    def link_names(self) -> list[str]: ...
    def actuator_names(self) -> list[str]: ...
    def control_ranges(self) -> list[Tuple[float, float]]: ...
    def link_pose(self, name: str) -> Tuple[Tuple[float, float, float], Tuple[float, float, float, float]]: ...
    def skipped(self) -> list[str]: ...
    # Queries.
    def cast_rays(self, origins: ArrayLike, directions: ArrayLike, max_distance: float = 100.0) -> RayHits:
        """(hit, distance, normal, body) per ray; a miss: max_distance, zero normal, body -1."""
    def contact_points(self) -> Dict[str, npt.NDArray[Any]]:
        """body_a, body_b, position, normal, depth, normal_force: one entry per point."""
    def joint_reactions(self) -> npt.NDArray[np.float64]:
        """(joints, 6): force and torque each joint applied to its first body, world frame."""
    # Snapshots and pickle.
    def snapshot(self) -> bytes: ...
    @staticmethod
    def restore(data: bytes) -> "World": ...
    def __reduce__(self) -> Tuple[Any, Tuple[bytes]]: ...

class Batch:
    """N copies of one world, stepped in parallel with the GIL released."""

    def __init__(self, world: World, n: int, threads: Optional[int] = None) -> None: ...
    def step(self, dt: float = 1.0 / 60.0, steps: int = 1) -> None: ...
    def reset(self, indices: Optional[Sequence[int]] = None) -> None: ...
    def state(self) -> npt.NDArray[np.float64]: ...
    def set_state(self, state: ArrayLike) -> None: ...
    def apply_forces(self, forces: ArrayLike) -> None: ...
    def set_motors(self, velocities: ArrayLike) -> None: ...
    def cast_rays(self, origins: ArrayLike, directions: ArrayLike, max_distance: float = 100.0) -> RayHits:
        """Rays in every world: (N, rays, 3) in, (N, rays) and (N, rays, 3) out."""
    def joint_state(self) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
    def world(self, index: int) -> World: ...
    @property
    def threads(self) -> int: ...
    @property
    def body_count(self) -> int: ...
    @property
    def joint_count(self) -> int: ...
    def __len__(self) -> int: ...
