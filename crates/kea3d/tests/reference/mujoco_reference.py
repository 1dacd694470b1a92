"""Reference trajectories from MuJoCo for Kea's robot tests.

    python mujoco_reference.py paths
        prints JSON with the folders of the installed models (pybullet_data, Gymnasium's
        MuJoCo assets, dm_control's suite)
    python mujoco_reference.py swing MODEL DT STEPS EVERY Q0 [V0]
        loads MODEL (URDF or MJCF) in MuJoCo, sets joint positions Q0 (and velocities V0,
        comma-separated, in MuJoCo's qpos/qvel order), turns contacts off, steps STEPS times
        of DT (`file`: the file's own timestep) and prints JSON {"t": [...], "q": [[...], ...]}
        every EVERY steps
    python mujoco_reference.py pybullet_swing URDF DT STEPS EVERY Q0
        the same swing in PyBullet (fixed base, the file's inertias, its default link damping
        turned off, motors off), for reporting beside MuJoCo
    python mujoco_reference.py drop MODEL DT STEPS INDEX
        drops an MJCF model from its file pose and prints qpos[INDEX] (the torso's height) at
        the end

A URDF is given to MuJoCo without its visual and collision geometry (MuJoCo's URDF reader
cannot resolve `package://` meshes; a swing with contacts off does not need them) and with
its links' own inertias (no inertia from geometry), and without `mimic` couplings, which
Kea does not read (it reports them as skipped).
"""
import importlib.util
import json
import os
import re
import sys
import tempfile


def paths():
    out = {}
    spec = importlib.util.find_spec("pybullet_data")
    if spec and spec.submodule_search_locations:
        out["pybullet_data"] = list(spec.submodule_search_locations)[0]
    spec = importlib.util.find_spec("gymnasium")
    if spec and spec.submodule_search_locations:
        out["gymnasium_assets"] = os.path.join(
            list(spec.submodule_search_locations)[0], "envs", "mujoco", "assets")
    spec = importlib.util.find_spec("dm_control")
    if spec and spec.submodule_search_locations:
        out["dm_control_suite"] = os.path.join(list(spec.submodule_search_locations)[0], "suite")
    return out


def load(model_path):
    import mujoco
    if model_path.endswith(".urdf"):
        text = open(model_path).read()
        text = re.sub(r"<visual\b.*?</visual>", "", text, flags=re.S)
        text = re.sub(r"<collision\b.*?</collision>", "", text, flags=re.S)
        # Kea has no mimic coupling (it would tie three bodies in one row): both engines
        # run the file without it.
        text = re.sub(r"<mimic\b[^>]*/>", "", text)
        text = re.sub(r"(<robot\b[^>]*>)",
                      r'\1<mujoco><compiler inertiafromgeom="false" fusestatic="true" '
                      r'discardvisual="true"/></mujoco>', text, count=1)
        with tempfile.NamedTemporaryFile("w", suffix=".urdf", delete=False) as f:
            f.write(text)
            name = f.name
        try:
            return mujoco.MjModel.from_xml_path(name)
        finally:
            os.unlink(name)
    return mujoco.MjModel.from_xml_path(model_path)


def numbers(text):
    return [float(x) for x in text.split(",")] if text else []


def swing(model_path, dt, steps, every, q0, v0):
    import mujoco
    m = load(model_path)
    if dt != "file":
        m.opt.timestep = float(dt)
    dt = m.opt.timestep
    m.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    if os.environ.get("KEA_REF_INTEGRATOR"):
        m.opt.integrator = getattr(mujoco.mjtIntegrator, "mjINT_" + os.environ["KEA_REF_INTEGRATOR"])
    d = mujoco.MjData(m)
    d.qpos[:] = q0
    if v0:
        d.qvel[:] = v0
    mujoco.mj_forward(m, d)
    t, q = [0.0], [d.qpos.tolist()]
    for k in range(1, steps + 1):
        mujoco.mj_step(m, d)
        if k % every == 0:
            t.append(k * dt)
            q.append(d.qpos.tolist())
    return {"t": t, "q": q, "nq": m.nq}


def pybullet_swing(urdf, dt, steps, every, q0):
    import pybullet as p
    client = p.connect(p.DIRECT)
    try:
        p.setGravity(0, 0, -9.81, physicsClientId=client)
        p.setTimeStep(dt, physicsClientId=client)
        robot = p.loadURDF(urdf, useFixedBase=True, flags=p.URDF_USE_INERTIA_FROM_FILE,
                           physicsClientId=client)
        movable = [j for j in range(p.getNumJoints(robot, physicsClientId=client))
                   if p.getJointInfo(robot, j, physicsClientId=client)[2] != p.JOINT_FIXED]
        for link in [-1] + list(range(p.getNumJoints(robot, physicsClientId=client))):
            p.changeDynamics(robot, link, linearDamping=0, angularDamping=0, physicsClientId=client)
        for j, q in zip(movable, q0):
            p.resetJointState(robot, j, q, physicsClientId=client)
        p.setJointMotorControlArray(robot, movable, p.VELOCITY_CONTROL, forces=[0.0] * len(movable),
                                    physicsClientId=client)
        read = lambda: [s[0] for s in p.getJointStates(robot, movable, physicsClientId=client)]
        t, q = [0.0], [read()]
        for k in range(1, steps + 1):
            p.stepSimulation(physicsClientId=client)
            if k % every == 0:
                t.append(k * dt)
                q.append(read())
        return {"t": t, "q": q}
    finally:
        p.disconnect(client)


def drop(model_path, dt, steps, index):
    import mujoco
    m = load(model_path)
    m.opt.timestep = dt
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    for _ in range(steps):
        mujoco.mj_step(m, d)
    return {"height": float(d.qpos[index]), "speed": float(abs(d.qvel).max())}


def collapse(model_path, steps, index):
    """Passive from the file's pose at the file's step: coordinate `index` after every step."""
    import mujoco
    m = load(model_path)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    heights = []
    for _ in range(steps):
        mujoco.mj_step(m, d)
        heights.append(float(d.qpos[index]))
    return {"heights": heights, "timestep": float(m.opt.timestep), "speed": float(abs(d.qvel).max())}


def main(argv):
    if argv[0] == "paths":
        out = paths()
    elif argv[0] == "swing":
        out = swing(argv[1], argv[2] if argv[2] == "file" else float(argv[2]), int(argv[3]), int(argv[4]), numbers(argv[5]),
                    numbers(argv[6]) if len(argv) > 6 else [])
    elif argv[0] == "pybullet_swing":
        out = pybullet_swing(argv[1], float(argv[2]), int(argv[3]), int(argv[4]), numbers(argv[5]))
    elif argv[0] == "collapse":
        out = collapse(argv[1], int(argv[2]), int(argv[3]))
    elif argv[0] == "drop":
        out = drop(argv[1], float(argv[2]), int(argv[3]), int(argv[4]))
    else:
        raise SystemExit(__doc__)
    json.dump(out, sys.stdout)


if __name__ == "__main__":
    main(sys.argv[1:])
