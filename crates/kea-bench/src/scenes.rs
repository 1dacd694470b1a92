//! The benchmark scenes, described once and built the same way in both engines.

/// A shape, in its body's frame (centred on it).
#[derive(Debug, Clone, Copy)]
pub enum Shape {
    /// Half extents.
    Cuboid([f32; 3]),
    /// Radius.
    Ball(f32),
    /// A capsule along the body's x axis: half length of the segment, radius.
    CapsuleX(f32, f32),
}

/// A dynamic body: one shape of uniform density.
#[derive(Debug, Clone, Copy)]
pub struct Body {
    pub shape: Shape,
    pub position: [f32; 3],
    pub density: f32,
}

/// Static geometry.
#[derive(Debug, Clone, Copy)]
pub enum Static {
    /// The ground: the plane y = 0, facing up.
    Ground,
    /// A box.
    Cuboid { half: [f32; 3], position: [f32; 3] },
}

/// A ball joint: body `a` (or the world) to body `b` at a world point.
#[derive(Debug, Clone, Copy)]
pub struct BallJoint {
    pub a: Option<usize>,
    pub b: usize,
    pub anchor: [f32; 3],
}

/// What a scene's quality column reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quality {
    /// Largest displacement of any body from its start (stacks that should stand).
    Displacement,
    /// Final kinetic energy (balls settling).
    Energy,
    /// Largest joint gap seen (chains).
    JointGap,
}

/// One benchmark scene.
#[derive(Debug, Clone)]
pub struct Scene {
    pub name: String,
    pub bodies: Vec<Body>,
    pub statics: Vec<Static>,
    pub joints: Vec<BallJoint>,
    /// Bodies may sleep (the sleeping scene); otherwise sleeping is off in both engines.
    pub sleep: bool,
    /// Steps run before timing (the sleeping scene settles and falls asleep).
    pub settle: usize,
    /// Steps timed per run.
    pub steps: usize,
    pub quality: Quality,
}

/// A pyramid of unit cubes in the x-y plane: `base` boxes at the bottom, each row half a box
/// in, touching (as Kea's `pyramid` scene and Rapier's stress tests build them).
pub fn pyramid(base: usize, steps: usize) -> Scene {
    let mut bodies = Vec::new();
    for layer in 0..base {
        let n = base - layer;
        for i in 0..n {
            let x = i as f32 - (n as f32 - 1.0) * 0.5;
            bodies.push(Body {
                shape: Shape::Cuboid([0.5; 3]),
                position: [x, 0.5 + layer as f32, 0.0],
                density: 1.0,
            });
        }
    }
    Scene {
        name: format!("pyramid, base {base} ({} boxes)", bodies.len()),
        bodies,
        statics: vec![Static::Ground],
        joints: Vec::new(),
        sleep: false,
        settle: 0,
        steps,
        quality: Quality::Displacement,
    }
}

/// The same pyramid with sleeping on, timed once it is asleep.
pub fn sleeping_pyramid(base: usize, steps: usize) -> Scene {
    let mut s = pyramid(base, steps);
    s.name = format!("sleeping pyramid, base {base}");
    s.sleep = true;
    s.settle = 300;
    s
}

/// `count` balls of radius 0.5 in a lattice above a 10 m × 10 m box with 4 walls, falling in:
/// each layer shifted a little so that they do not stack in columns.
pub fn balls(count: usize, steps: usize) -> Scene {
    let mut bodies = Vec::new();
    let per_layer = 64;
    for i in 0..count {
        let layer = i / per_layer;
        let k = i % per_layer;
        let shift = 0.13 * (layer % 4) as f32;
        bodies.push(Body {
            shape: Shape::Ball(0.5),
            position: [
                -4.0 + (k % 8) as f32 * 1.1 + shift,
                1.0 + layer as f32 * 1.1,
                -4.0 + (k / 8) as f32 * 1.1 + shift,
            ],
            density: 1.0,
        });
    }
    let wall = |half: [f32; 3], position: [f32; 3]| Static::Cuboid { half, position };
    Scene {
        name: format!("{count} balls into a walled box"),
        bodies,
        statics: vec![
            Static::Ground,
            wall([0.5, 10.0, 6.0], [-5.5, 10.0, 0.0]),
            wall([0.5, 10.0, 6.0], [5.5, 10.0, 0.0]),
            wall([6.0, 10.0, 0.5], [0.0, 10.0, -5.5]),
            wall([6.0, 10.0, 0.5], [0.0, 10.0, 5.5]),
        ],
        joints: Vec::new(),
        sleep: false,
        settle: 0,
        steps,
        quality: Quality::Energy,
    }
}

/// A column of `n` unit cubes on the ground.
pub fn column(n: usize, steps: usize) -> Scene {
    let bodies = (0..n)
        .map(|i| Body {
            shape: Shape::Cuboid([0.5; 3]),
            position: [0.0, 0.5 + i as f32, 0.0],
            density: 1.0,
        })
        .collect();
    Scene {
        name: format!("column of {n} boxes"),
        bodies,
        statics: vec![Static::Ground],
        joints: Vec::new(),
        sleep: false,
        settle: 0,
        steps,
        quality: Quality::Displacement,
    }
}

/// A column of `n` unit cubes alternating 100 kg and 1 kg, heavy at the bottom.
pub fn heavy_light(n: usize, steps: usize) -> Scene {
    let mut s = column(n, steps);
    for (i, b) in s.bodies.iter_mut().enumerate() {
        b.density = if i % 2 == 0 { 100.0 } else { 1.0 };
    }
    s.name = format!("{n} boxes alternating 100 kg / 1 kg");
    s
}

/// A chain of `links` capsules (0.5 m long, 1 kg) on ball joints, pinned at one end and
/// released horizontal.
pub fn chain(links: usize, steps: usize) -> Scene {
    let length = 0.5;
    let radius = 0.05;
    let height = links as f32 * length + 1.0;
    let volume = std::f32::consts::PI * radius * radius * (length + 4.0 / 3.0 * radius);
    let bodies: Vec<Body> = (0..links)
        .map(|i| Body {
            shape: Shape::CapsuleX(0.5 * length, radius),
            position: [(i as f32 + 0.5) * length, height, 0.0],
            density: 1.0 / volume,
        })
        .collect();
    let joints = (0..links)
        .map(|i| BallJoint {
            a: i.checked_sub(1),
            b: i,
            anchor: [i as f32 * length, height, 0.0],
        })
        .collect();
    Scene {
        name: format!("{links}-link chain, released horizontal"),
        bodies,
        statics: Vec::new(),
        joints,
        sleep: false,
        settle: 0,
        steps,
        quality: Quality::JointGap,
    }
}
