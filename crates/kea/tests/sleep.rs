//! The guide's DEM: resting islands are disabled automatically and wake when touched or pushed;
//! NoPartition solves everything as one problem with the same answer.

mod common;
use common::{box_plane_contacts, clear_contacts, F64};
use kea::{inertia, BodyDef, Contact, ContactParams, DemMode, DemSettings, Real, Vec3, World};

const HALF: Vec3 = Vec3::splat(0.25);
const H: Real = 1.0 / 60.0;

fn resting_box_world(mode: DemMode) -> (World, kea::BodyHandle) {
    let mut world = World::with_capacity(8, 64).unwrap();
    world
        .update_settings(|s| {
            s.dem = DemSettings {
                mode,
                ..Default::default()
            }
        })
        .unwrap();
    let b = world
        .create_body(&BodyDef {
            position: Vec3::new(0.0, HALF.y + 0.01, 0.0),
            inertia: inertia::solid_box(1.0, HALF).unwrap(),
            ..Default::default()
        })
        .unwrap();
    (world, b)
}

fn ground(world: &mut World, b: kea::BodyHandle, contacts: &mut Vec<kea::ConstraintHandle>) {
    box_plane_contacts(
        world,
        b,
        HALF,
        Vec3::Y,
        0.0,
        0.02,
        ContactParams::default(),
        None,
        contacts,
    );
}

#[test]
fn a_resting_box_falls_asleep_and_stays_put() {
    let (mut world, b) = resting_box_world(DemMode::PartitionAutoDisable);
    let mut contacts = Vec::new();
    let mut asleep_at = None;
    for i in 0..120 {
        clear_contacts(&mut world, &mut contacts);
        ground(&mut world, b, &mut contacts);
        let stats = world.step(H).unwrap();
        if asleep_at.is_none() && world.body(b).unwrap().is_sleeping() {
            asleep_at = Some(i);
            assert_eq!(stats.sleeping_bodies, 1);
        }
    }
    let at = asleep_at.expect("never slept") as Real * H;
    assert!(at > 0.5 && at < 1.5, "slept at {at} s");
    let p = world.body(b).unwrap().position();
    for _ in 0..60 {
        clear_contacts(&mut world, &mut contacts);
        ground(&mut world, b, &mut contacts);
        let stats = world.step(H).unwrap();
        assert_eq!(stats.bodies, 0, "a sleeping body is not simulated");
    }
    assert_eq!(world.body(b).unwrap().position(), p);
}

#[test]
fn default_mode_never_sleeps() {
    let (mut world, b) = resting_box_world(DemMode::PartitionNoAutoDisable);
    let mut contacts = Vec::new();
    for _ in 0..120 {
        clear_contacts(&mut world, &mut contacts);
        ground(&mut world, b, &mut contacts);
        world.step(H).unwrap();
    }
    assert!(!world.body(b).unwrap().is_sleeping());
}

#[test]
fn a_push_or_a_touch_wakes_the_island() {
    let (mut world, b) = resting_box_world(DemMode::PartitionAutoDisable);
    let mut contacts = Vec::new();
    for _ in 0..90 {
        clear_contacts(&mut world, &mut contacts);
        ground(&mut world, b, &mut contacts);
        world.step(H).unwrap();
    }
    assert!(world.body(b).unwrap().is_sleeping());
    // A force below the threshold does not wake it.
    world
        .body_mut(b)
        .unwrap()
        .add_force(Vec3::new(1e-4, 0.0, 0.0))
        .unwrap();
    world.step(H).unwrap();
    assert!(world.body(b).unwrap().is_sleeping());
    // A contact with an awake body does.
    let ball = world
        .create_body(&BodyDef {
            position: Vec3::new(0.0, 2.0 * HALF.y + 0.1, 0.0),
            linear_velocity: Vec3::new(0.0, -1.0, 0.0),
            ..Default::default()
        })
        .unwrap();
    let c = Contact::new(Vec3::new(0.0, 2.0 * HALF.y, 0.0), Vec3::Y, 0.0).unwrap();
    let touch = world.create_contact(ball, Some(b), c).unwrap();
    let stats = world.step(H).unwrap();
    assert!(!world.body(b).unwrap().is_sleeping());
    assert_eq!(stats.bodies, 2);
    world.destroy_constraint(touch).unwrap();
    // A force above the threshold wakes a sleeper too.
    let (mut world, b) = resting_box_world(DemMode::PartitionAutoDisable);
    let mut contacts = Vec::new();
    for _ in 0..90 {
        clear_contacts(&mut world, &mut contacts);
        ground(&mut world, b, &mut contacts);
        world.step(H).unwrap();
    }
    world
        .body_mut(b)
        .unwrap()
        .add_force(Vec3::new(5.0, 0.0, 0.0))
        .unwrap();
    clear_contacts(&mut world, &mut contacts);
    ground(&mut world, b, &mut contacts);
    world.step(H).unwrap();
    assert!(!world.body(b).unwrap().is_sleeping());
    assert!(world.body(b).unwrap().linear_velocity().x > 0.0);
}

#[test]
fn no_partition_gives_the_same_answer_in_one_island() {
    let run = |mode: DemMode| {
        let mut world = World::with_capacity(8, 8).unwrap();
        // The maximal paths (a tree of ball joints on the world would step in reduced coordinates).
        world
            .update_settings(|s| s.routing.max_reduced_links = 0)
            .unwrap();
        world
            .update_settings(|s| {
                s.dem = DemSettings {
                    mode,
                    ..Default::default()
                }
            })
            .unwrap();
        let mut bodies = Vec::new();
        for i in 0..3 {
            let b = world
                .create_body(&BodyDef {
                    position: Vec3::new(i as Real * 3.0 + 1.0, 0.0, 0.0),
                    ..Default::default()
                })
                .unwrap();
            world
                .create_joint(
                    b,
                    None,
                    kea::JointSpec::ball(Vec3::new(i as Real * 3.0, 0.0, 0.0)),
                )
                .unwrap();
            bodies.push(b);
        }
        let mut islands = 0;
        for _ in 0..100 {
            islands = world.step(H).unwrap().solver.islands;
        }
        (
            islands,
            bodies
                .iter()
                .map(|&b| world.body(b).unwrap().position())
                .collect::<Vec<_>>(),
        )
    };
    let (i1, p1) = run(DemMode::PartitionNoAutoDisable);
    let (i2, p2) = run(DemMode::NoPartition);
    assert_eq!((i1, i2), (3, 1));
    for (a, b) in p1.iter().zip(&p2) {
        assert!(
            (*a - *b).length() < if F64 { 1e-9 } else { 1e-4 },
            "{a} vs {b}"
        );
    }
}

#[test]
fn sleeping_islands_cost_no_body_and_wake_alone() {
    // Two boxes resting apart: two islands. Once both sleep a step simulates nothing; a force
    // under the wake threshold wakes nothing and is cleared; a push wakes its own island only;
    // a body destroyed while asleep leaves the other's island as it was.
    let (mut world, a) = resting_box_world(DemMode::PartitionAutoDisable);
    let b = world
        .create_body(&BodyDef {
            position: Vec3::new(3.0, HALF.y + 0.01, 0.0),
            inertia: inertia::solid_box(1.0, HALF).unwrap(),
            ..Default::default()
        })
        .unwrap();
    let mut contacts = Vec::new();
    let mut step = |world: &mut World, bodies: &[kea::BodyHandle]| {
        clear_contacts(world, &mut contacts);
        for &x in bodies {
            ground(world, x, &mut contacts);
        }
        world.step(H).unwrap()
    };
    let mut stats = step(&mut world, &[a, b]);
    for _ in 0..240 {
        if stats.sleeping_bodies == 2 {
            break;
        }
        stats = step(&mut world, &[a, b]);
    }
    assert_eq!(stats.sleeping_bodies, 2, "both boxes fall asleep");
    let stats = step(&mut world, &[a, b]);
    assert_eq!(
        (stats.bodies, stats.constraints),
        (0, 0),
        "nothing simulated"
    );
    world
        .body_mut(b)
        .unwrap()
        .add_force(Vec3::new(0.0, 0.0, 1.0e-4))
        .unwrap();
    let stats = step(&mut world, &[a, b]);
    assert_eq!(stats.bodies, 0, "a force under the threshold wakes nothing");
    assert_eq!(
        world.body(b).unwrap().force(),
        Vec3::ZERO,
        "and the step clears it"
    );
    world
        .body_mut(b)
        .unwrap()
        .add_force(Vec3::new(5.0, 0.0, 0.0))
        .unwrap();
    let stats = step(&mut world, &[a, b]);
    assert_eq!(
        (stats.bodies, stats.sleeping_bodies),
        (1, 1),
        "the push wakes b alone"
    );
    assert!(!world.body(b).unwrap().is_sleeping() && world.body(a).unwrap().is_sleeping());
    assert!(
        world.body(b).unwrap().linear_velocity().x > 0.0,
        "and moves it"
    );
    assert_eq!(world.body(b).unwrap().force(), Vec3::ZERO);
    step(&mut world, &[b]); // a's contacts go before a does
    world.destroy_body(a).unwrap();
    let stats = step(&mut world, &[b]);
    assert_eq!((stats.bodies, stats.sleeping_bodies), (1, 0));
}

#[test]
fn a_touch_wakes_a_whole_sleeping_island_beside_one_that_never_sleeps() {
    // Two boxes on the ground joined by a fixed joint (one island) fall asleep while a
    // pendulum swings elsewhere and never does. Every step then has something awake but
    // nothing reaching the pair: they stay asleep. A ball landing on one box wakes both —
    // the other only through the joint.
    {
        let (mut world, a) = resting_box_world(DemMode::PartitionAutoDisable);
        let b = world
            .create_body(&BodyDef {
                position: Vec3::new(0.6, HALF.y + 0.01, 0.0),
                inertia: inertia::solid_box(1.0, HALF).unwrap(),
                ..Default::default()
            })
            .unwrap();
        let anchor = Vec3::new(0.3, HALF.y + 0.01, 0.0);
        world
            .create_joint(a, Some(b), kea::JointSpec::fixed(anchor))
            .unwrap();
        let bob = world
            .create_body(&BodyDef {
                position: Vec3::new(5.0, 2.0, 0.0),
                ..Default::default()
            })
            .unwrap();
        world
            .create_joint(bob, None, kea::JointSpec::ball(Vec3::new(5.0, 3.0, 1.0)))
            .unwrap();
        let mut contacts = Vec::new();
        let mut step = |world: &mut World, extra: Option<kea::BodyHandle>| {
            clear_contacts(world, &mut contacts);
            ground(world, a, &mut contacts);
            ground(world, b, &mut contacts);
            if let Some(ball) = extra {
                let c = Contact::new(Vec3::new(0.6, 2.0 * HALF.y, 0.0), Vec3::Y, 0.0).unwrap();
                contacts.push(world.create_contact(ball, Some(b), c).unwrap());
            }
            world.step(H).unwrap()
        };
        let asleep = |world: &World| [a, b].map(|x| world.body(x).unwrap().is_sleeping());
        for _ in 0..300 {
            step(&mut world, None);
            if asleep(&world) == [true, true] {
                break;
            }
        }
        assert_eq!(asleep(&world), [true, true], "the pair falls asleep");
        for _ in 0..30 {
            step(&mut world, None);
            assert_eq!(
                asleep(&world),
                [true, true],
                "nothing awake reaches the pair"
            );
            assert!(
                !world.body(bob).unwrap().is_sleeping(),
                "the pendulum swings on"
            );
        }
        let ball = world
            .create_body(&BodyDef {
                position: Vec3::new(0.6, 2.0 * HALF.y + 0.1, 0.0),
                linear_velocity: Vec3::new(0.0, -1.0, 0.0),
                ..Default::default()
            })
            .unwrap();
        step(&mut world, Some(ball));
        assert_eq!(
            asleep(&world),
            [false, false],
            "the touched box and, through the joint, the other"
        );
    }
}
