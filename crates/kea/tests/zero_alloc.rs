//! The guide's promise, proven: once a world has warmed up, a step whose counts do not grow
//! performs zero heap allocations, even with contacts created and destroyed every step.

mod common;
use common::{box_plane_contacts, clear_contacts, sphere_ground_contact};
use kea::{
    inertia, BodyDef, ContactParams, CustomConstraint, DemMode, DemSettings, Jacobian, Real,
    Routing, Row, RowContext, RowWriter, SolverMode, Vec3, World,
};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct CountingAllocator;
// Per thread: the tests run side by side.
thread_local! {
    static COUNTING: Cell<bool> = const { Cell::new(false) };
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn count_one() {
    if COUNTING.with(|c| c.get()) {
        ALLOCATIONS.with(|n| n.set(n.get() + 1));
    }
}

unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count_one();
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count_one();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[derive(Debug, Clone)]
struct Spring;
impl CustomConstraint for Spring {
    fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        let x = ctx.bodies[0].position.x - 3.0;
        out.push(
            Row::new(Jacobian::new(Vec3::X, Vec3::ZERO), Jacobian::ZERO)
                .with_error(x)
                .with_softness(kea::Softness::from_spring(50.0, 1.0, ctx.dt).unwrap()),
        );
    }
}

#[test]
fn warm_step_allocates_nothing() {
    for mode in [SolverMode::Exact, SolverMode::Iterative, SolverMode::Hybrid] {
        let (allocations, rows) = warm_allocations(mode);
        assert!(
            rows > 240 * 8,
            "{mode:?}: the scene should keep contacts and joints busy ({rows} rows)"
        );
        assert_eq!(
            allocations, 0,
            "{mode:?}: {allocations} heap allocations in 240 warm steps"
        );
    }
    // The counter really counts: one deliberate allocation is seen.
    ALLOCATIONS.with(|n| n.set(0));
    COUNTING.with(|c| c.set(true));
    let probe = std::hint::black_box(vec![1u8; 16]);
    COUNTING.with(|c| c.set(false));
    drop(probe);
    assert_eq!(ALLOCATIONS.with(Cell::get), 1);
}

/// Allocations during 240 warm steps of a busy scene routed to `mode`, and the rows solved.
fn warm_allocations(mode: SolverMode) -> (usize, u32) {
    let mut world = World::with_capacity(16, 64).unwrap();
    world
        .update_settings(|s| {
            s.routing = Routing {
                mode,
                ..Default::default()
            }
        })
        .unwrap();
    // Auto-disable on, so the sleep bookkeeping is counted too.
    world
        .update_settings(|s| {
            s.dem = DemSettings {
                mode: DemMode::PartitionAutoDisable,
                ..Default::default()
            }
        })
        .unwrap();
    let ball = world
        .create_body(&BodyDef {
            position: Vec3::new(0.0, 2.0, 0.0),
            inertia: inertia::solid_sphere(1.0, 0.2).unwrap(),
            ..Default::default()
        })
        .unwrap();
    let half = Vec3::splat(0.3);
    let crate_ = world
        .create_body(&BodyDef {
            position: Vec3::new(2.0, 0.31, 0.0),
            inertia: inertia::solid_box(1.0, half).unwrap(),
            ..Default::default()
        })
        .unwrap();
    let bob = world
        .create_body(&BodyDef {
            position: Vec3::new(-2.0, 1.0, 0.0),
            ..Default::default()
        })
        .unwrap();
    world
        .create_joint(bob, None, kea::JointSpec::ball(Vec3::new(-1.0, 2.0, 0.0)))
        .unwrap();
    world.add_custom_constraint(crate_, None, Spring).unwrap();
    // A hinged rod with a fixed tendon's spring, damper and range on it (the reduced path's
    // joint space under Hybrid, the joint's rows otherwise).
    let rod = world
        .create_body(&BodyDef {
            position: Vec3::new(4.0, 1.5, 0.0),
            linear_velocity: Vec3::new(3.0, 0.0, 0.0),
            ..Default::default()
        })
        .unwrap();
    let hinge = world
        .create_joint(
            rod,
            None,
            kea::JointSpec::hinge(Vec3::new(4.0, 2.0, 0.0), Vec3::Z),
        )
        .unwrap();
    world
        .add_tendon(kea::FixedTendon {
            terms: vec![kea::TendonTerm {
                joint: hinge.raw(),
                coordinate: 0,
                coefficient: 2.0,
            }],
            stiffness: 1.0,
            damping: 0.1,
            range: Some([-0.3, 0.3]),
            ..Default::default()
        })
        .unwrap();
    let params = ContactParams {
        restitution: 0.5,
        ..Default::default()
    };
    let mut contacts = Vec::with_capacity(64);

    let step = |world: &mut World, contacts: &mut Vec<_>| {
        clear_contacts(world, contacts);
        sphere_ground_contact(world, ball, 0.2, 0.05, params, contacts);
        box_plane_contacts(
            world,
            crate_,
            half,
            Vec3::Y,
            0.0,
            0.05,
            params,
            None,
            contacts,
        );
        world
            .body_mut(crate_)
            .unwrap()
            .add_force(Vec3::new(1.0, 0.0, 0.0))
            .unwrap();
        world.step(1.0 / 60.0).unwrap()
    };
    // The island lists are refilled every step too: once warm, that allocates nothing either.
    let mut islands = kea::IslandList::default();
    for _ in 0..120 {
        step(&mut world, &mut contacts);
        world.islands(&mut islands);
    }
    ALLOCATIONS.with(|n| n.set(0));
    COUNTING.with(|c| c.set(true));
    let mut rows = 0;
    for _ in 0..240 {
        let stats = step(&mut world, &mut contacts);
        world.islands(&mut islands);
        rows += stats.rows;
    }
    COUNTING.with(|c| c.set(false));
    let _: Real = world.kinetic_energy();
    (ALLOCATIONS.with(Cell::get), rows)
}

/// A floating tree tumbling in reduced coordinates, as a thrown ant's body and leg: its
/// root's chart is centred again every few steps (the tree built again on its kept model),
/// and no warm step allocates.
#[test]
fn a_tumbling_floating_tree_steps_without_allocating() {
    let mut world = World::new(kea::WorldDef {
        settings: kea::WorldSettings {
            gravity: Vec3::ZERO,
            reduced_free_trees: true,
            ..kea::WorldSettings::default()
        },
        ..kea::WorldDef::default()
    })
    .unwrap();
    let spin = Vec3::new(1.0, 4.0, 2.0);
    let mut parent = None;
    let mut root = None;
    for k in 0..3 {
        let x = Vec3::new(0.6 * k as Real, 1.0, 0.0);
        let b = world
            .create_body(&BodyDef {
                position: x,
                angular_velocity: spin,
                linear_velocity: spin.cross(x - Vec3::new(0.0, 1.0, 0.0)),
                inertia: inertia::solid_box(1.0, Vec3::new(0.3, 0.05, 0.05)).unwrap(),
                ..Default::default()
            })
            .unwrap();
        if let Some(p) = parent {
            let axis = if k == 1 { Vec3::Z } else { Vec3::Y };
            let anchor = x - Vec3::new(0.3, 0.0, 0.0);
            world
                .create_joint(b, Some(p), kea::JointSpec::hinge(anchor, axis))
                .unwrap();
        }
        parent = Some(b);
        root.get_or_insert(b);
    }
    let h = 1.0 / 240.0;
    for _ in 0..60 {
        assert_eq!(world.step(h).unwrap().reduced_trees, 1, "one floating tree");
    }
    let turn0 = world.body(root.unwrap()).unwrap().orientation();
    ALLOCATIONS.with(|n| n.set(0));
    COUNTING.with(|c| c.set(true));
    for _ in 0..240 {
        world.step(h).unwrap();
    }
    COUNTING.with(|c| c.set(false));
    let allocations = ALLOCATIONS.with(Cell::get);
    // Turned by several times the chart's half-radian reach: centred again many times.
    let turned = world
        .body(root.unwrap())
        .unwrap()
        .orientation()
        .angle_between(turn0);
    assert!(turned > 1.0, "the root turned {turned} rad");
    assert_eq!(
        allocations, 0,
        "{allocations} allocations in warm tumbling steps"
    );
}
