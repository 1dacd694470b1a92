"""Batch throughput: Kea's ``kea.Batch`` against MuJoCo's ``rollout`` on the same cart-pole,
on the same KUKA iiwa arm loaded by both engines from pybullet_data's URDF, and on Gymnasium's
ant and humanoid loaded by both from Gymnasium's MJCF.

Both models: a 1 kg cart on a slider along x (stops at ±2.4 m) driven by a velocity servo
(±3 m/s, at most 30 N), a 0.1 kg, 1 m pole on a hinge; 0.01 s physics steps, two per
environment step. Two ways of driving each, in the same run:

* closed loop: per environment step, set the actions, step 2 × 0.01 s, read every state
  (what a learning loop does);
* open loop: one call steps 200 physics steps with fixed actions.

The arm: 7 hinges with their damping, no contacts, released from a bent pose; 2 ms physics
steps, five per environment step; closed loop reads the joint positions every environment
step (MuJoCo: its whole state), open loop steps all of them in one call. Both engines load
the same URDF text without its visual and collision elements (no contacts are asked for).

Prints environment steps per second (worlds × env steps / wall time), the median of
``--runs`` runs, for one thread and all cores, and the ratios.

    python crates/kea-py/bench/batch_vs_mujoco.py [--worlds 1024] [--runs 5]
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np

import kea
from kea.envs import DT, MOTOR_FORCE, MOTOR_SPEED, SUBSTEPS, cart_pole_world

MJCF = f"""
<mujoco model="cartpole">
  <option timestep="{DT}" integrator="implicitfast"/>
  <worldbody>
    <body name="cart">
      <joint name="slider" type="slide" axis="1 0 0" limited="true" range="-2.4 2.4"/>
      <geom type="box" size="0.25 0.1 0.15" mass="1" contype="0" conaffinity="0"/>
      <body name="pole">
        <joint name="hinge" type="hinge" axis="0 0 1"/>
        <geom type="capsule" fromto="0 0 0 0 1 0" size="0.03" mass="0.1" contype="0" conaffinity="0"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <velocity joint="slider" kv="100" forcelimited="true" forcerange="-{MOTOR_FORCE} {MOTOR_FORCE}"
              ctrlrange="-{MOTOR_SPEED} {MOTOR_SPEED}"/>
  </actuator>
</mujoco>
"""


def median_rate(run, runs: int) -> float:
    return statistics.median(run() for _ in range(runs))


def kea_rates(worlds: int, threads: int | None, env_steps: int, runs: int):
    world = cart_pole_world()
    # MuJoCo's implicitfast is Kea's Euler (one evaluation a step); Kea's default is RK4.
    world.integrator = "euler"
    batch = kea.Batch(world, worlds, threads)
    motors = np.zeros((worlds, 2))
    rng = np.random.default_rng(0)

    def closed():
        batch.reset()
        start = time.perf_counter()
        for _ in range(env_steps):
            motors[:, 0] = rng.uniform(-MOTOR_SPEED, MOTOR_SPEED, worlds)
            batch.set_motors(motors)
            batch.step(DT, SUBSTEPS)
            batch.state()
        return worlds * env_steps / (time.perf_counter() - start)

    def open_loop():
        batch.reset()
        batch.set_motors(motors)
        start = time.perf_counter()
        batch.step(DT, SUBSTEPS * env_steps)
        batch.state()
        return worlds * env_steps / (time.perf_counter() - start)

    closed()  # warm
    return median_rate(closed, runs), median_rate(open_loop, runs)


def mujoco_rates(worlds: int, threads: int, env_steps: int, runs: int):
    import mujoco
    from mujoco import rollout

    model = mujoco.MjModel.from_xml_string(MJCF)
    datas = [mujoco.MjData(model) for _ in range(threads)]
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    nstate = mujoco.mj_stateSize(model, spec)
    state0 = np.zeros((worlds, nstate))
    mujoco.mj_getState(model, datas[0], state0[0], spec)
    state0[:] = state0[0]
    rng = np.random.default_rng(0)

    def closed():
        state = state0.copy()
        start = time.perf_counter()
        for _ in range(env_steps):
            control = rng.uniform(-MOTOR_SPEED, MOTOR_SPEED, (worlds, 1, 1))
            out, _ = rollout.rollout(model, datas, state, control, nstep=SUBSTEPS, persistent_pool=True)
            state = out[:, -1, :]
        return worlds * env_steps / (time.perf_counter() - start)

    def open_loop():
        control = np.zeros((worlds, 1, 1))
        start = time.perf_counter()
        rollout.rollout(model, datas, state0, control, nstep=SUBSTEPS * env_steps, persistent_pool=True)
        return worlds * env_steps / (time.perf_counter() - start)

    closed()
    return median_rate(closed, runs), median_rate(open_loop, runs)


ARM_Q = [0.4, 0.5, -0.3, -1.1, 0.5, 0.8, 0.2]
ARM_DT = 0.002
ARM_SUBSTEPS = 5


def arm_file() -> str:
    import importlib.util

    spec = importlib.util.find_spec("pybullet_data")
    return os.path.join(list(spec.submodule_search_locations)[0], "kuka_iiwa", "model.urdf")


def arm_text() -> str:
    """The arm's URDF as both engines load it: without its visual and collision elements (no
    contacts are asked for), so neither engine carries meshes it never uses."""
    import re

    text = open(arm_file()).read()
    text = re.sub(r"<visual\b.*?</visual>", "", text, flags=re.S)
    return re.sub(r"<collision\b.*?</collision>", "", text, flags=re.S)


def load_arm_file(text: str, load):
    import tempfile

    with tempfile.NamedTemporaryFile("w", suffix=".urdf", delete=False) as f:
        f.write(text)
    try:
        return load(f.name)
    finally:
        os.unlink(f.name)


def kea_arm_rates(worlds: int, threads: int | None, env_steps: int, runs: int):
    arm = load_arm_file(arm_text(), lambda path: kea.World.from_urdf(path, fixed_base=True))
    arm.set_joint_positions(ARM_Q)
    arm.integrator = "euler"  # MuJoCo steps the URDF it compiles with Euler
    batch = kea.Batch(arm, worlds, threads)

    def closed():
        batch.reset()
        start = time.perf_counter()
        for _ in range(env_steps):
            batch.step(ARM_DT, ARM_SUBSTEPS)
            batch.joint_positions()
        return worlds * env_steps / (time.perf_counter() - start)

    def open_loop():
        batch.reset()
        start = time.perf_counter()
        batch.step(ARM_DT, ARM_SUBSTEPS * env_steps)
        batch.joint_positions()
        return worlds * env_steps / (time.perf_counter() - start)

    closed()
    return median_rate(closed, runs), median_rate(open_loop, runs)


def mujoco_arm_rates(worlds: int, threads: int, env_steps: int, runs: int):
    import re

    import mujoco
    from mujoco import rollout

    # MuJoCo's own extension: take the file's inertias as they are.
    text = re.sub(r"(<robot\b[^>]*>)", r'\1<mujoco><compiler inertiafromgeom="false"/></mujoco>', arm_text(), count=1)
    model = load_arm_file(text, mujoco.MjModel.from_xml_path)
    model.opt.timestep = ARM_DT
    datas = [mujoco.MjData(model) for _ in range(threads)]
    datas[0].qpos[:] = ARM_Q
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state0 = np.zeros((worlds, mujoco.mj_stateSize(model, spec)))
    mujoco.mj_getState(model, datas[0], state0[0], spec)
    state0[:] = state0[0]

    def closed():
        state = state0.copy()
        control = np.zeros((worlds, ARM_SUBSTEPS, model.nu))
        start = time.perf_counter()
        for _ in range(env_steps):
            out, _ = rollout.rollout(model, datas, state, control, nstep=ARM_SUBSTEPS, persistent_pool=True)
            state = out[:, -1, :]
        return worlds * env_steps / (time.perf_counter() - start)

    def open_loop():
        control = np.zeros((worlds, ARM_SUBSTEPS * env_steps, model.nu))
        start = time.perf_counter()
        rollout.rollout(model, datas, state0, control, nstep=ARM_SUBSTEPS * env_steps, persistent_pool=True)
        return worlds * env_steps / (time.perf_counter() - start)

    closed()
    return median_rate(closed, runs), median_rate(open_loop, runs)


ROBOT_FRAME_SKIP = 5


def gymnasium_file(name: str) -> str:
    from kea.robot_envs import gymnasium_asset

    return gymnasium_asset(name)


def kea_robot_rates(asset: str, worlds: int, threads: int | None, env_steps: int, runs: int):
    """Gymnasium's robot from its own MJCF at its file's timestep: closed loop sets random
    controls, steps the frame skip and reads every world's joint positions and velocities."""
    world = kea.World.from_mjcf(gymnasium_file(asset))
    dt = world.timestep
    batch = kea.Batch(world, worlds, threads)
    ranges = np.array(world.control_ranges())
    rng = np.random.default_rng(0)

    def closed():
        batch.reset()
        start = time.perf_counter()
        for _ in range(env_steps):
            batch.set_controls(rng.uniform(ranges[:, 0], ranges[:, 1], (worlds, len(ranges))))
            batch.step(dt, ROBOT_FRAME_SKIP)
            batch.joint_positions()
            batch.joint_velocities()
        return worlds * env_steps / (time.perf_counter() - start)

    def open_loop():
        batch.reset()
        batch.set_controls(np.zeros((worlds, len(ranges))))
        start = time.perf_counter()
        batch.step(dt, ROBOT_FRAME_SKIP * env_steps)
        batch.joint_positions()
        return worlds * env_steps / (time.perf_counter() - start)

    closed()
    return median_rate(closed, runs), median_rate(open_loop, runs)


def mujoco_robot_rates(asset: str, worlds: int, threads: int, env_steps: int, runs: int):
    import mujoco
    from mujoco import rollout

    model = mujoco.MjModel.from_xml_path(gymnasium_file(asset))
    datas = [mujoco.MjData(model) for _ in range(threads)]
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state0 = np.zeros((worlds, mujoco.mj_stateSize(model, spec)))
    mujoco.mj_getState(model, datas[0], state0[0], spec)
    state0[:] = state0[0]
    low, high = model.actuator_ctrlrange[:, 0], model.actuator_ctrlrange[:, 1]
    rng = np.random.default_rng(0)

    def closed():
        state = state0.copy()
        start = time.perf_counter()
        for _ in range(env_steps):
            u = rng.uniform(low, high, (worlds, 1, model.nu)).repeat(ROBOT_FRAME_SKIP, axis=1)
            out, _ = rollout.rollout(model, datas, state, u, nstep=ROBOT_FRAME_SKIP, persistent_pool=True)
            state = out[:, -1, :]
        return worlds * env_steps / (time.perf_counter() - start)

    def open_loop():
        control = np.zeros((worlds, ROBOT_FRAME_SKIP * env_steps, model.nu))
        start = time.perf_counter()
        rollout.rollout(model, datas, state0, control, nstep=ROBOT_FRAME_SKIP * env_steps, persistent_pool=True)
        return worlds * env_steps / (time.perf_counter() - start)

    closed()
    return median_rate(closed, runs), median_rate(open_loop, runs)


def report(title: str, rows: dict, cores: int) -> None:
    print(title)
    print(f"{'engine':<8} {'threads':>7} {'closed loop':>14} {'open loop':>14}   (env steps/s)")
    for (engine, threads), (closed, open_loop) in rows.items():
        print(f"{engine:<8} {threads:>7} {closed:>14,.0f} {open_loop:>14,.0f}")
    for threads in sorted({1, cores}):
        k, m = rows[("kea", threads)], rows[("mujoco", threads)]
        print(f"kea / mujoco on {threads} thread(s): closed loop {k[0] / m[0]:.2f}x, open loop {k[1] / m[1]:.2f}x")
    if cores > 1:
        k1, kn = rows[("kea", 1)], rows[("kea", cores)]
        print(f"kea {cores} threads / 1 thread: closed loop {kn[0] / k1[0]:.2f}x, open loop {kn[1] / k1[1]:.2f}x")
    print()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--worlds", type=int, default=1024)
    parser.add_argument("--env-steps", type=int, default=100)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--robot-env-steps", type=int, default=20, help="ant and humanoid")
    parser.add_argument("--only", choices=["cartpole", "kuka", "ant", "humanoid"], action="append")
    args = parser.parse_args()
    only = set(args.only or ["cartpole", "kuka", "ant", "humanoid"])
    cores = os.cpu_count() or 1
    rows, arm = {}, {}
    robots = {name: {} for name in ("ant", "humanoid") if name in only}
    for threads in sorted({1, cores}):
        if "cartpole" in only:
            rows[("kea", threads)] = kea_rates(args.worlds, threads, args.env_steps, args.runs)
            rows[("mujoco", threads)] = mujoco_rates(args.worlds, threads, args.env_steps, args.runs)
        if "kuka" in only:
            arm[("kea", threads)] = kea_arm_rates(args.worlds, threads, args.env_steps, args.runs)
            arm[("mujoco", threads)] = mujoco_arm_rates(args.worlds, threads, args.env_steps, args.runs)
        for name, table in robots.items():
            steps = args.robot_env_steps
            table[("kea", threads)] = kea_robot_rates(f"{name}.xml", args.worlds, threads, steps, args.runs)
            table[("mujoco", threads)] = mujoco_robot_rates(f"{name}.xml", args.worlds, threads, steps, args.runs)
    if rows:
        report(f"{args.worlds} cart-poles, {args.env_steps} env steps of 2 x {DT} s, median of {args.runs} runs, {cores} cores", rows, cores)
    if arm:
        report(f"{args.worlds} KUKA iiwa arms (URDF), {args.env_steps} env steps of {ARM_SUBSTEPS} x {ARM_DT} s", arm, cores)
    for name, table in robots.items():
        report(
            f"{args.worlds} Gymnasium {name}s (their MJCF), {args.robot_env_steps} env steps of "
            f"{ROBOT_FRAME_SKIP} file steps from the file's pose, random controls (closed loop)",
            table,
            cores,
        )


if __name__ == "__main__":
    main()
