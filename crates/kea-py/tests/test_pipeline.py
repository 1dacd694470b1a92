"""One scene, every way in: Python's `kea.World.from_scene` ends on the same bits as `kea run`
and the Rust API. The fingerprints are the ones the Rust test
`crates/kea-cli/tests/pipeline.rs` checks all three of against, in the same file."""

import pathlib

import pytest

import kea

ROOT = pathlib.Path(__file__).resolve().parents[3]
GOLDEN = ROOT / "crates" / "kea-cli" / "tests" / "golden" / "pipeline_f32.txt"
STEPS = 60
DT = 1.0 / 60.0


def fingerprint(state):
    """FNV-1a over the bits of each body's position, orientation and velocity (the first ten
    numbers of its state row), bodies in scene order, as the Rust test computes it."""
    h = 0xCBF29CE484222325
    for row in state[:, :10]:
        for x in row:
            for byte in x.astype("<f8").tobytes():
                h ^= byte
                h = (h * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def golden():
    lines = GOLDEN.read_text().split("\n")
    return {name: int(value, 16) for name, value in (line.split() for line in lines if line)}


@pytest.mark.parametrize("name", sorted(golden()))
def test_a_scene_ends_on_the_same_bits_as_kea_run_and_rust(name):
    w = kea.World.from_scene(ROOT / "scenes" / name)
    w.step(DT, STEPS)
    assert fingerprint(w.state()) == golden()[name], name
