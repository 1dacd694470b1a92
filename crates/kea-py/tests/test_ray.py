"""The Ray example: rollouts on two local Ray workers give the same bits as local ones."""

import importlib.util
import pathlib

import pytest

ray = pytest.importorskip("ray")

EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "ray_rollouts.py"


def load_example():
    spec = importlib.util.spec_from_file_location("ray_rollouts", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_ray_rollouts_match_local_ones():
    example = load_example()
    seeds, steps = [0, 1, 2, 3], 30
    try:
        remote = example.run_on_ray(seeds, steps, workers=2)
    finally:
        pass
    local = [example.rollout(s, steps) for s in seeds]
    ray.shutdown()
    assert remote == local
    assert len({digest for _, digest in local}) == len(seeds)
