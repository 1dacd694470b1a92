"""Gymnasium tasks on robots from their own files: Gymnasium's Reacher and
InvertedDoublePendulum from their MJCF and a KUKA reaching task from its URDF, in single and
vector forms on ``kea.Batch``, checked by Gymnasium's ``env_checker`` and against MuJoCo's own
environments where the same state and actions give the same observations."""

import importlib.util

import numpy as np
import pytest

gym = pytest.importorskip("gymnasium")
from gymnasium.utils.env_checker import check_env  # noqa: E402

if importlib.util.find_spec("pybullet_data") is None:
    pytest.skip("pybullet_data (the KUKA's URDF) is not installed", allow_module_level=True)

import kea.robot_envs as tasks  # noqa: E402

SINGLE = [
    tasks.ReacherEnv,
    tasks.InvertedDoublePendulumEnv,
    tasks.KukaReachEnv,
    tasks.HopperEnv,
    tasks.Walker2dEnv,
    tasks.HalfCheetahEnv,
    tasks.AntEnv,
    tasks.HumanoidEnv,
]
VECTOR = [tasks.ReacherVecEnv, tasks.InvertedDoublePendulumVecEnv, tasks.KukaReachVecEnv]

# Gymnasium's own tasks and how many environment steps from a shared state are compared: the
# walkers' first steps stand or push on the ground; the cheetah falls for two steps and lands
# in the third, where the engines' impacts part (MuJoCo's regulariser uses its bodies' mean
# inverse weights at the model's pose, Kea's the contacts' present Delassus diagonal).
# The relative tolerance: the cheetah's random torques (gear 120) drive its joints at up to
# 7 rad/s in one step and onto its soft stops, whose regulariser MuJoCo takes at the model's
# pose and Kea at the present one (2.5% measured on one rate). The cheetah is compared until
# it lands (a reset can start it in the ground): its impacts part the same way, by 15%.
# The walker's feet grip with MuJoCo's friction, the larger of the two geoms' (1.9 on a 0.7
# floor): its pushes part by 2% on a rate, as the cheetah's stops do.
# The ant and the humanoid are compared while neither engine touches the ground: a contact's
# force in MuJoCo's ``cfrc_ext`` is its last Runge-Kutta stage's, in Kea the step's mean, so
# the first impact reads differently in the observation (and the ant's random kicks, gear
# 150, part the engines' hops from there). Before it, their joint stops' regularisers differ
# as the cheetah's do: the humanoid's hips (a 30-degree range) are on their stops within a few
# steps of random torques, and their rates part by up to 0.05 rad/s over 0.15 s.
LOCOMOTION = [
    (tasks.HopperEnv, "Hopper-v5", 5, 0.0, 0.02, False),
    (tasks.Walker2dEnv, "Walker2d-v5", 3, 0.03, 0.02, False),
    (tasks.HalfCheetahEnv, "HalfCheetah-v5", 2, 0.03, 0.02, True),
    (tasks.AntEnv, "Ant-v5", 3, 0.03, 0.02, True),
    (tasks.HumanoidEnv, "Humanoid-v5", 10, 0.03, 0.05, True),
]


def _touching(ours) -> bool:
    return bool(np.abs(ours._vec.batch.link_states()["contact_force"]).sum() > 0)


@pytest.mark.parametrize("env_class", SINGLE)
def test_single_tasks_pass_the_gymnasium_checker(env_class):
    env = env_class()
    check_env(env, skip_render_check=True)


@pytest.mark.parametrize("env_class", SINGLE)
def test_single_and_vector_forms_agree(env_class):
    single = env_class()
    vec = env_class.vector_class(3, threads=2)
    obs, _ = vec.reset(seed=5)
    assert obs.shape == (3,) + single.observation_space.shape
    actions = np.stack([single.action_space.sample() * 0.0 for _ in range(3)])
    for _ in range(5):
        obs, reward, terminated, truncated, _ = vec.step(actions)
        assert obs.shape == (3,) + single.observation_space.shape and reward.shape == (3,)
        assert np.isfinite(obs).all()


def test_the_reachers_spaces_match_gymnasiums():
    ours = tasks.ReacherEnv()
    assert ours.observation_space.shape == (10,)
    assert ours.action_space.shape == (2,) and ours.action_space.low.tolist() == [-1.0, -1.0]
    pendulum = tasks.InvertedDoublePendulumEnv()
    assert pendulum.observation_space.shape == (9,) and pendulum.action_space.shape == (1,)


def test_the_double_pendulum_follows_mujocos_from_the_same_state():
    pytest.importorskip("mujoco")
    try:
        theirs = gym.make("InvertedDoublePendulum-v5").unwrapped
    except Exception as e:  # rendering dependencies missing: nothing to compare with
        pytest.skip(f"Gymnasium's MuJoCo environment cannot be made: {e}")
    ours = tasks.InvertedDoublePendulumEnv()
    theirs.reset(seed=3)
    ours.reset(seed=3)
    ours._vec.batch.set_joint_positions(theirs.data.qpos[None])
    ours._vec.batch.set_joint_velocities(theirs.data.qvel[None])
    for _ in range(5):
        a = np.array([0.2], dtype=np.float32)
        expected, r_expected, *_ = theirs.step(a)
        got, r_got, *_ = ours.step(a)
        # Angles and rates within a few hundredths after 0.25 s of the file's RK4 at 0.01 s.
        assert got[:8] == pytest.approx(expected[:8], abs=0.05)
        assert r_got == pytest.approx(r_expected, abs=0.05)


@pytest.mark.parametrize("ours_class, gym_id, steps, rel, tol, until_landing", LOCOMOTION)
def test_locomotion_tasks_match_gymnasiums_from_the_same_state(
    ours_class, gym_id, steps, rel, tol, until_landing
):
    pytest.importorskip("mujoco")
    try:
        theirs = gym.make(gym_id).unwrapped
    except Exception as e:  # rendering dependencies missing: nothing to compare with
        pytest.skip(f"Gymnasium's MuJoCo environment cannot be made: {e}")
    ours = ours_class()
    assert ours.observation_space.shape == theirs.observation_space.shape
    assert ours.action_space.shape == theirs.action_space.shape
    assert np.array_equal(ours.action_space.low, theirs.action_space.low)
    assert np.array_equal(ours.action_space.high, theirs.action_space.high)
    assert ours._vec.dt == pytest.approx(theirs.dt, rel=1e-6)
    rng = np.random.default_rng(7)
    compared = 0
    for seed in range(3):
        theirs.reset(seed=seed)
        ours.reset(seed=seed)
        ours._vec.batch.set_joint_positions(theirs.data.qpos[None])
        ours._vec.batch.set_joint_velocities(theirs.data.qvel[None])
        for _ in range(steps):
            low, high = ours.action_space.low, ours.action_space.high
            a = rng.uniform(low, high).astype(np.float32)
            expected, r_expected, t_expected, *_ = theirs.step(a)
            got, r_got, t_got, *_ = ours.step(a)
            if until_landing and (theirs.data.ncon > 0 or _touching(ours)):
                break
            compared += 1
            assert got == pytest.approx(expected, rel=rel, abs=tol), f"{gym_id}, seed {seed}"
            assert r_got == pytest.approx(r_expected, abs=0.02), f"{gym_id}, seed {seed}"
            assert t_got == t_expected
    assert compared >= 3, f"{gym_id}: {compared} steps compared"


def test_locomotion_tasks_end_when_unhealthy_and_reset_with_gymnasiums_noise():
    hopper = tasks.HopperEnv()
    obs, _ = hopper.reset(seed=1)
    # Uniform noise of ±5e-3 about the file's pose (x left out of the observation).
    assert np.abs(obs[:5] - hopper._vec.init_qpos[1:]).max() <= 5e-3
    # Fallen: the torso below 0.7 m ends the episode, with no healthy reward.
    q = hopper._vec.batch.joint_positions()
    q[0, 1] = 0.5
    hopper._vec.batch.set_joint_positions(q)
    _, reward, terminated, _, _ = hopper.step(np.zeros(3, dtype=np.float32))
    assert terminated and reward < 0.5
    cheetah = tasks.HalfCheetahEnv()
    for _ in range(10):
        _, _, terminated, _, _ = cheetah.step(cheetah.action_space.sample())
        assert not terminated  # the cheetah never ends early


def test_kuka_reaching_moves_the_hand_towards_a_target_with_a_simple_controller():
    env = tasks.KukaReachEnv()
    obs, _ = env.reset(seed=2)
    hand = obs[14:17].copy()
    # Every joint driven at +0.5 rad/s for 0.4 s: the motors hold their speed against gravity
    # and the joints turn 0.2 rad, which swings the hand by several centimetres.
    q0 = obs[:7].copy()
    for _ in range(20):
        obs, *_ = env.step(np.full(7, 0.5, dtype=np.float32))
    assert obs[7:14] == pytest.approx(np.full(7, 0.5), abs=0.05), "the motors hold their speed"
    assert obs[:7] - q0 == pytest.approx(np.full(7, 0.2), abs=0.02)
    assert np.linalg.norm(obs[14:17] - hand) > 0.05


def test_the_floating_base_tasks_end_off_their_height_range_and_reset_about_the_file_pose():
    for env, size, z_off, noise in [
        (tasks.AntEnv(), 105, 1.5, 0.1),
        (tasks.HumanoidEnv(), 348, 0.8, 1e-2),
    ]:
        obs, _ = env.reset(seed=2)
        assert obs.shape == (size,)
        q = env._vec.batch.joint_positions()
        init = env._vec.init_qpos
        # Uniform noise about the file's pose, the free joint's quaternion normalised.
        assert np.abs(q[0, 7:] - init[7:]).max() <= noise + 1e-9
        assert np.abs(q[0, :3] - init[:3]).max() <= noise + 1e-9
        assert np.linalg.norm(q[0, 3:7]) == pytest.approx(1.0)
        # Off the healthy height range: the episode ends, with no healthy reward.
        q[0, 2] = z_off
        env._vec.batch.set_joint_positions(q)
        _, reward, terminated, _, _ = env.step(np.zeros(env.action_space.shape, dtype=np.float32))
        assert terminated and reward < env._vec.healthy_reward / 2


def test_link_states_weigh_and_carry_the_humanoid():
    import kea

    world = kea.World.from_mjcf(tasks.gymnasium_asset("humanoid.xml"))
    world.step(world.timestep, steps=2000)
    s = world.link_states()
    names = world.link_names()
    assert s["mass"].shape == (len(names),) and s["inertia"].shape == (len(names), 3, 3)
    # Lying on the floor after 6 s: the contacts on its links carry its weight (42.116 kg,
    # MuJoCo's sum of this file's body masses; the links its joints are chained through
    # weigh 0.1 g each).
    total = s["mass"].sum()
    assert total == pytest.approx(42.116, rel=1e-4)
    assert s["contact_force"][1:].sum(axis=0)[2] == pytest.approx(total * 9.81, rel=0.05)
    forces = world.actuator_forces(np.full(17, 0.4))
    assert forces.shape == (23,) and np.all(forces[:6] == 0.0) and np.all(forces[6:] > 0.0)
