"""Kea: rigid-body dynamics with an exact constraint solver, in Python.

``kea.World`` is one world, built in code or from a scene file; ``kea.Batch`` is N copies
of one world stepped in parallel on all cores with the GIL released, read and written as
(N, ...) numpy arrays. ``kea.envs`` holds Gymnasium environments built on batches.

A body's state row has 13 numbers: position (3), quaternion x y z w (4), linear velocity
(3), angular velocity (3). Errors are Python exceptions naming the argument: ``ValueError``
for bad input, ``IndexError`` for a body, collider or joint that does not exist.
"""

from ._kea import DOUBLE_PRECISION, STATE_WIDTH, Batch, World, __version__

__all__ = ["Batch", "World", "STATE_WIDTH", "DOUBLE_PRECISION", "__version__"]
