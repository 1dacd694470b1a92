"""Rollouts of the Kea cart-pole across Ray workers: the way to scale Kea past one machine.

Each task builds a ``CartPoleVecEnv`` (a ``kea.Batch`` on its worker's cores), resets it with
its seed, and runs a seeded random policy; it returns the total reward and a digest of the
final observations. Because Kea is bit-for-bit deterministic, a task gives the same answer
on any worker as in this process.

    python crates/kea-py/examples/ray_rollouts.py --seeds 8 --steps 200

Here ``ray.init()`` starts a local Ray. On a cluster, start Ray there (``ray start --head``
on one machine, ``ray start --address=HEAD:6379`` on the others) and run this with
``RAY_ADDRESS=HEAD:6379`` (or ``--address``): the same code then spreads the seeds over the
cluster's machines.
"""

from __future__ import annotations

import argparse
import hashlib
import os

import numpy as np


def rollout(seed: int, steps: int, envs: int = 16, threads: int = 1) -> tuple[float, str]:
    """Total reward and a digest of the final observations of one seeded rollout."""
    from kea.envs import CartPoleVecEnv

    env = CartPoleVecEnv(envs, threads=threads)
    obs, _ = env.reset(seed=seed)
    policy = np.random.default_rng(seed + 1_000_003)
    total = 0.0
    for _ in range(steps):
        actions = policy.uniform(-1.0, 1.0, size=(envs, 1))
        obs, reward, _, _, _ = env.step(actions)
        total += float(reward.sum())
    return total, hashlib.sha256(obs.tobytes()).hexdigest()


def run_on_ray(seeds: list[int], steps: int, address: str | None = None, workers: int | None = None):
    """The rollouts of ``seeds`` as Ray tasks, one per seed, in seed order."""
    import ray

    if not ray.is_initialized():
        ray.init(address=address, num_cpus=workers, include_dashboard=False, log_to_driver=False)
    remote = ray.remote(num_cpus=1)(rollout)
    return ray.get([remote.remote(s, steps) for s in seeds])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=8)
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--address", default=os.environ.get("RAY_ADDRESS"))
    args = parser.parse_args()
    seeds = list(range(args.seeds))
    remote = run_on_ray(seeds, args.steps, args.address)
    local = [rollout(s, args.steps) for s in seeds]
    for s, (r, l) in enumerate(zip(remote, local)):
        print(f"seed {s}: reward {r[0]:.0f} on Ray, {l[0]:.0f} here; same final state: {r[1] == l[1]}")
    assert remote == local, "Ray workers and this process disagree"
    print("Ray and local rollouts agree bit for bit")


if __name__ == "__main__":
    main()
