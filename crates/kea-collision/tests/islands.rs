//! The world's islands as body lists (the guide's partitions), as a user meets them through
//! contacts from geometry: each island lists exactly its bodies; a box that lands on a pile
//! merges with it and splits off again when it leaves; a sleeping pile wakes whole when a
//! ball touches it; a clone taken mid-run lists the same islands and steps on to the same bits.

use kea::{
    BodyDef, BodyHandle, DemMode, DemSettings, IslandList, Quat, Real, Vec3, World, WorldDef,
};
use kea_collision::{ColliderDef, CollisionWorld, Shape};
mod common;

const DT: Real = 1.0 / 60.0;

fn world(bodies: usize, sleeping: bool) -> (World, CollisionWorld) {
    let mut w = World::new(WorldDef {
        max_bodies: bodies + 1,
        max_constraints: 16 * bodies + 16,
        settings: kea::WorldSettings {
            gravity: Vec3::new(0.0, -9.81, 0.0),
            ..Default::default()
        },
        ..Default::default()
    })
    .unwrap();
    if sleeping {
        w.update_settings(|s| {
            s.dem = DemSettings {
                mode: DemMode::PartitionAutoDisable,
                ..Default::default()
            }
        })
        .unwrap();
    }
    let mut c = CollisionWorld::new();
    c.add_collider(&w, ColliderDef::new(None, Shape::plane(Vec3::Y).unwrap()))
        .unwrap();
    (w, c)
}

fn add(w: &mut World, c: &mut CollisionWorld, shape: Shape, at: Vec3) -> BodyHandle {
    let mp = shape.mass_properties(500.0).unwrap();
    let b = w
        .create_body(&BodyDef {
            mass: mp.mass,
            inertia: mp.inertia,
            position: at,
            orientation: Quat::IDENTITY,
            ..Default::default()
        })
        .unwrap();
    c.add_collider(w, ColliderDef::new(Some(b), shape)).unwrap();
    b
}

fn unit_box() -> Shape {
    Shape::cuboid(Vec3::splat(0.5)).unwrap()
}

/// A stack of `n` unit boxes standing at `x`, bottom first.
fn stack(w: &mut World, c: &mut CollisionWorld, x: Real, n: usize) -> Vec<BodyHandle> {
    (0..n)
        .map(|i| add(w, c, unit_box(), Vec3::new(x, 0.5 + i as Real, 0.0)))
        .collect()
}

fn islands(w: &World) -> IslandList {
    let mut list = IslandList::default();
    w.islands(&mut list);
    list
}

/// The island holding every body of `group`, which must be exactly that group.
fn island_is(list: &IslandList, group: &[BodyHandle]) -> bool {
    let Some(k) = list.island_of(group[0]) else {
        return false;
    };
    let mut want = group.to_vec();
    want.sort_by_key(|h| h.index());
    list.bodies(k) == want.as_slice()
}

#[test]
fn each_island_lists_exactly_its_bodies() {
    let (mut w, mut c) = world(8, false);
    let a = stack(&mut w, &mut c, 0.0, 2);
    let b = stack(&mut w, &mut c, 5.0, 3);
    let ball = add(
        &mut w,
        &mut c,
        Shape::sphere(0.5).unwrap(),
        Vec3::new(-5.0, 0.5, 0.0),
    );
    // Two boxes apart in the air, held together by a joint only.
    let j1 = add(&mut w, &mut c, unit_box(), Vec3::new(10.0, 5.0, 0.0));
    let j2 = add(&mut w, &mut c, unit_box(), Vec3::new(12.0, 5.0, 0.0));
    w.create_joint(
        j1,
        Some(j2),
        kea::JointSpec::ball(Vec3::new(11.0, 5.0, 0.0)),
    )
    .unwrap();
    for _ in 0..30 {
        common::step(&mut c, &mut w, DT).unwrap();
    }
    let list = islands(&w);
    assert_eq!(list.len(), 4, "{list:?}");
    for group in [&a[..], &b[..], &[ball][..], &[j1, j2][..]] {
        assert!(island_is(&list, group), "{group:?} in {list:?}");
    }
    // Every body once, islands by their lowest body, bodies by slot.
    let all: Vec<u32> = list.iter().flatten().map(|h| h.index()).collect();
    let mut sorted = all.clone();
    sorted.sort_unstable();
    sorted.dedup();
    assert_eq!(sorted.len(), 8);
    let firsts: Vec<u32> = list.iter().map(|i| i[0].index()).collect();
    assert!(firsts.windows(2).all(|p| p[0] < p[1]), "{firsts:?}");
    assert!(list
        .iter()
        .all(|i| i.windows(2).all(|p| p[0].index() < p[1].index())));
    assert!((0..list.len()).all(|k| !list.is_asleep(k)));
}

#[test]
fn a_box_that_lands_on_a_pile_merges_with_it_and_splits_off_when_it_leaves() {
    let (mut w, mut c) = world(3, false);
    let pile = stack(&mut w, &mut c, 0.0, 2);
    let falling = add(&mut w, &mut c, unit_box(), Vec3::new(0.0, 4.0, 0.0));
    common::step(&mut c, &mut w, DT).unwrap();
    let list = islands(&w);
    assert!(island_is(&list, &pile) && island_is(&list, &[falling]));
    // It lands within a second.
    for _ in 0..60 {
        common::step(&mut c, &mut w, DT).unwrap();
    }
    let mut merged = pile.clone();
    merged.push(falling);
    assert!(island_is(&islands(&w), &merged), "{:?}", islands(&w));
    // Thrown up and away, it leaves the pile's island once its contacts end.
    w.body_mut(falling)
        .unwrap()
        .set_linear_velocity(Vec3::new(3.0, 6.0, 0.0))
        .unwrap();
    for _ in 0..20 {
        common::step(&mut c, &mut w, DT).unwrap();
    }
    let list = islands(&w);
    assert!(w.body(falling).unwrap().position().y > 3.0);
    assert!(
        island_is(&list, &pile) && island_is(&list, &[falling]),
        "{list:?}"
    );
}

#[test]
fn a_sleeping_pile_is_one_sleeping_island_and_wakes_whole_when_a_ball_touches_it() {
    let (mut w, mut c) = world(4, true);
    let pile = stack(&mut w, &mut c, 0.0, 3);
    for _ in 0..180 {
        common::step(&mut c, &mut w, DT).unwrap();
    }
    let list = islands(&w);
    let k = list.island_of(pile[0]).unwrap();
    assert!(island_is(&list, &pile) && list.is_asleep(k), "{list:?}");
    assert!(pile.iter().all(|&b| w.body(b).unwrap().is_sleeping()));
    // A ball dropped on top: when it touches, the whole pile wakes and joins its island.
    let ball = add(
        &mut w,
        &mut c,
        Shape::sphere(0.25).unwrap(),
        Vec3::new(0.0, 3.6, 0.0),
    );
    let mut touched = false;
    for _ in 0..60 {
        common::step(&mut c, &mut w, DT).unwrap();
        let list = islands(&w);
        if list.island_of(ball) == list.island_of(pile[0]) {
            touched = true;
            let k = list.island_of(ball).unwrap();
            assert!(!list.is_asleep(k));
            assert!(
                pile.iter().all(|&b| !w.body(b).unwrap().is_sleeping()),
                "the pile wakes whole"
            );
            break;
        }
    }
    assert!(touched, "the ball reached the pile");
}

/// Bits of every body's pose and velocity.
fn state(w: &World, bodies: &[BodyHandle]) -> Vec<u64> {
    let mut out = Vec::new();
    for &h in bodies {
        let b = w.body(h).unwrap();
        let (p, q, v) = (b.position(), b.orientation(), b.linear_velocity());
        for x in [p.x, p.y, p.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z] {
            #[allow(clippy::useless_conversion)]
            out.push(f64::from(x).to_bits());
        }
    }
    out
}

#[test]
fn a_clone_taken_mid_run_lists_the_same_islands_and_steps_to_the_same_bits() {
    let (mut w, mut c) = world(6, true);
    let mut bodies = stack(&mut w, &mut c, 0.0, 3);
    bodies.extend(stack(&mut w, &mut c, 3.0, 2));
    bodies.push(add(&mut w, &mut c, unit_box(), Vec3::new(3.0, 5.0, 0.0)));
    for _ in 0..30 {
        common::step(&mut c, &mut w, DT).unwrap();
    }
    let (mut w2, mut c2) = (w.clone(), c.clone());
    for step in 0..240 {
        common::step(&mut c, &mut w, DT).unwrap();
        common::step(&mut c2, &mut w2, DT).unwrap();
        let (a, b) = (islands(&w), islands(&w2));
        let lists = |l: &IslandList| l.iter().map(<[BodyHandle]>::to_vec).collect::<Vec<_>>();
        assert_eq!(lists(&a), lists(&b), "step {step}");
        assert_eq!(state(&w, &bodies), state(&w2, &bodies), "step {step}");
    }
    // By then everything has landed and gone to sleep: two piles, two sleeping islands.
    let list = islands(&w);
    assert_eq!(list.len(), 2, "{list:?}");
    assert!((0..2).all(|k| list.is_asleep(k)));
}

/// The largest move up or down of any of `bodies` since their heights `before`.
fn largest_move(w: &World, bodies: &[BodyHandle], before: &[Real]) -> Real {
    bodies
        .iter()
        .zip(before)
        .map(|(&b, &y)| (y - w.body(b).unwrap().position().y).abs())
        .fold(0.0, Real::max)
}

#[test]
fn a_contacts_warm_start_survives_sleep_and_wake() {
    // A stack of 8 boxes falls asleep carrying its weight: each contact's force at the end of
    // its last awake step (the next step's warm start) is kept while it sleeps.
    // The iterative path (the exact path, which a stack takes by default, starts from no
    // guess).
    let (mut w, mut c) = world(8, true);
    w.update_settings(|s| s.routing.mode = kea::SolverMode::Iterative)
        .unwrap();
    let pile = stack(&mut w, &mut c, 0.0, 8);
    for _ in 0..240 {
        common::step(&mut c, &mut w, DT).unwrap();
    }
    assert!(pile.iter().all(|&b| w.body(b).unwrap().is_sleeping()));
    let warm = |w: &World| -> Vec<(kea::ConstraintHandle, Vec<kea::PointForce>)> {
        w.contacts()
            .map(|(h, contact, _)| (h, contact.warm_forces().to_vec()))
            .collect()
    };
    let asleep = warm(&w);
    let weight: Real = pile
        .iter()
        .map(|&b| w.body(b).unwrap().mass())
        .sum::<Real>()
        * 9.81;
    let floor: Real = asleep
        .iter()
        .filter(|(h, _)| w.constraint_bodies(*h).unwrap().contains(&None))
        .flat_map(|(_, f)| f.iter().map(|f| f.normal))
        .sum();
    assert!(
        (floor - weight).abs() < 0.05 * weight,
        "the floor's warm start carries the stack: {floor} against {weight} N"
    );
    for _ in 0..30 {
        common::step(&mut c, &mut w, DT).unwrap();
    }
    assert_eq!(
        warm(&w),
        asleep,
        "asleep, the warm starts are kept as they were"
    );
    // Woken, the stack takes up its load from the kept warm start and barely moves; the same
    // stack with its warm starts cleared sags in the first step.
    let mut cold = (w.clone(), c.clone());
    for (h, forces) in &asleep {
        let zero = vec![kea::PointForce::default(); forces.len()];
        cold.0.contact_mut(*h).unwrap().set_forces(&zero);
    }
    let heights: Vec<Real> = pile
        .iter()
        .map(|&b| w.body(b).unwrap().position().y)
        .collect();
    let mut drops = Vec::new();
    for (w, c) in [(&mut w, &mut c), (&mut cold.0, &mut cold.1)] {
        w.wake_body(pile[0]).unwrap();
        common::step(c, w, DT).unwrap();
        assert!(
            pile.iter().all(|&b| !w.body(b).unwrap().is_sleeping()),
            "woken whole"
        );
        drops.push(largest_move(w, &pile, &heights));
    }
    let (warm_drop, cold_drop) = (drops[0], drops[1]);
    println!("warm start: {warm_drop:.2e} m, cold: {cold_drop:.2e} m");
    assert!(
        warm_drop < 0.25 * cold_drop && warm_drop < 1.0e-4,
        "woken from its warm start the stack moves {warm_drop:.2e} m in a step, from a cold \
         start {cold_drop:.2e} m"
    );
}
