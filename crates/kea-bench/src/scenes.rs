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
    /// A capsule along the body's y axis: half length of the segment, radius.
    CapsuleY(f32, f32),
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

/// A joint: body `b` to body `a` (or the world) at a world point.
#[derive(Debug, Clone, Copy)]
pub struct Joint {
    pub a: Option<usize>,
    pub b: usize,
    pub anchor: [f32; 3],
    pub kind: JointKind,
}

/// How a joint bends.
#[derive(Debug, Clone, Copy)]
pub enum JointKind {
    /// A ball joint, free.
    Ball,
    /// A ball joint whose body `b` may swing up to `cone` rad away from `axis` (a world unit
    /// vector along the limb at the start) and twist up to ±`twist` rad about it. Rapier has no
    /// cone: it gets the two swing angles each limited to ±`cone`.
    LimitedBall {
        axis: [f32; 3],
        cone: f32,
        twist: f32,
    },
    /// A hinge about world `axis`, its angle in `[lower, upper]` rad.
    Hinge {
        axis: [f32; 3],
        lower: f32,
        upper: f32,
    },
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
    pub joints: Vec<Joint>,
    /// Bodies may sleep (the sleeping scene); otherwise sleeping is off in both engines.
    pub sleep: bool,
    /// Steps run before timing (the sleeping scene settles and falls asleep).
    pub settle: usize,
    /// Steps timed per run.
    pub steps: usize,
    pub quality: Quality,
    /// Kea solves every island exactly (the exact path's own figure); else default routing.
    pub kea_exact: bool,
}

impl Scene {
    /// Bodies on the ground, no joints, awake, timed from the first step, judged by how far
    /// they moved (the piles).
    /// Jointed bodies among `statics`, awake, judged by how far their joints open.
    fn jointed(
        name: String,
        (bodies, joints): (Vec<Body>, Vec<Joint>),
        statics: Vec<Static>,
        steps: usize,
    ) -> Self {
        Self {
            name,
            bodies,
            statics,
            joints,
            sleep: false,
            settle: 0,
            steps,
            quality: Quality::JointGap,
            kea_exact: false,
        }
    }

    fn on_ground(name: String, bodies: Vec<Body>, steps: usize) -> Self {
        Self {
            name,
            bodies,
            statics: vec![Static::Ground],
            joints: Vec::new(),
            sleep: false,
            settle: 0,
            steps,
            quality: Quality::Displacement,
            kea_exact: false,
        }
    }
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
    Scene::on_ground(
        format!("pyramid, base {base} ({} boxes)", bodies.len()),
        bodies,
        steps,
    )
}

/// The same pyramid with sleeping on, timed once it is asleep.
pub fn sleeping_pyramid(base: usize, steps: usize) -> Scene {
    let mut s = pyramid(base, steps);
    s.name = format!("sleeping pyramid, base {base}");
    s.sleep = true;
    s.settle = 300;
    s
}

/// The sleeping pyramid beside something that never sleeps: a ball on a 1.5 m ball joint,
/// released level, swinging well clear of it. What a sleeping pile costs while the rest of
/// the world moves (its quality figure is the pendulum's swing, not the pile's).
pub fn sleeping_pyramid_beside_a_pendulum(base: usize, steps: usize) -> Scene {
    let mut s = sleeping_pyramid(base, steps);
    s.name = format!("sleeping pyramid, base {base}, beside a pendulum");
    let pivot = [base as f32 * 0.5 + 5.0, 3.0, 0.0];
    s.bodies.push(Body {
        shape: Shape::Ball(0.25),
        position: [pivot[0] + 1.5, pivot[1], pivot[2]],
        density: 1.0,
    });
    s.joints.push(Joint {
        a: None,
        b: s.bodies.len() - 1,
        anchor: pivot,
        kind: JointKind::Ball,
    });
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
        kea_exact: false,
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
    Scene::on_ground(format!("column of {n} boxes"), bodies, steps)
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
        .map(|i| Joint {
            a: i.checked_sub(1),
            b: i,
            anchor: [i as f32 * length, height, 0.0],
            kind: JointKind::Ball,
        })
        .collect();
    Scene::jointed(
        format!("{links}-link chain, released horizontal"),
        (bodies, joints),
        Vec::new(),
        steps,
    )
}

/// A chain of `links` capsules hanging straight down from a pin at rest (3 rows a joint, so
/// 333 links make a 999-row island), with Kea forced onto the exact path: what one exact
/// solve of a big articulated island costs.
pub fn hanging_chain(links: usize, steps: usize) -> Scene {
    let mut s = chain(links, steps);
    let (length, top) = (0.5, links as f32 * 0.5 + 1.0);
    for (i, b) in s.bodies.iter_mut().enumerate() {
        b.shape = match b.shape {
            Shape::CapsuleX(h, r) => Shape::CapsuleY(h, r),
            other => other,
        };
        b.position = [0.0, top - (i as f32 + 0.5) * length, 0.0];
    }
    for (i, j) in s.joints.iter_mut().enumerate() {
        j.anchor = [0.0, top - i as f32 * length, 0.0];
    }
    s.name = format!("{links}-link chain hanging, Kea exact");
    s.kea_exact = true;
    s
}

/// A ragdoll's parts: name, centre (figure frame, pelvis at the origin), capsule half length
/// and radius, and whether the capsule lies along x (else along y). Kea's `ragdoll` scene group
/// has the same figure.
const RAGDOLL_PARTS: [(&str, [f32; 3], f32, f32, bool); 11] = [
    ("pelvis", [0.0, 0.0, 0.0], 0.08, 0.1, true),
    ("torso", [0.0, 0.35, 0.0], 0.12, 0.13, false),
    ("head", [0.0, 0.8, 0.0], 0.03, 0.1, false),
    ("left upper arm", [0.27, 0.4, 0.0], 0.1, 0.05, false),
    ("left lower arm", [0.27, 0.105, 0.0], 0.1, 0.045, false),
    ("right upper arm", [-0.27, 0.4, 0.0], 0.1, 0.05, false),
    ("right lower arm", [-0.27, 0.105, 0.0], 0.1, 0.045, false),
    ("left upper leg", [0.1, -0.28, 0.0], 0.14, 0.07, false),
    ("left lower leg", [0.1, -0.7, 0.0], 0.15, 0.06, false),
    ("right upper leg", [-0.1, -0.28, 0.0], 0.14, 0.07, false),
    ("right lower leg", [-0.1, -0.7, 0.0], 0.15, 0.06, false),
];

/// The ragdoll's joints: child part, parent part, anchor, and (cone, twist) for a ball joint
/// or (lower, upper) for a hinge about x.
const RAGDOLL_JOINTS: [(usize, usize, [f32; 3], bool, f32, f32); 10] = [
    (1, 0, [0.0, 0.1, 0.0], true, 0.4, 0.3),
    (2, 1, [0.0, 0.66, 0.0], true, 0.5, 0.5),
    (3, 1, [0.27, 0.55, 0.0], true, 1.4, 0.6),
    (5, 1, [-0.27, 0.55, 0.0], true, 1.4, 0.6),
    (4, 3, [0.27, 0.25, 0.0], false, -2.5, 0.05),
    (6, 5, [-0.27, 0.25, 0.0], false, -2.5, 0.05),
    (7, 0, [0.1, -0.07, 0.0], true, 1.0, 0.3),
    (9, 0, [-0.1, -0.07, 0.0], true, 1.0, 0.3),
    (8, 7, [0.1, -0.49, 0.0], false, -0.05, 2.4),
    (10, 9, [-0.1, -0.49, 0.0], false, -0.05, 2.4),
];

/// `count` ragdolls (11 capsules, 7 limited ball joints and 4 hinges each, density 1,000) dropped
/// in a row over four steps, at staggered heights so that they land apart in time and on one
/// another.
pub fn ragdolls(count: usize, steps: usize) -> Scene {
    let mut bodies = Vec::new();
    let mut joints = Vec::new();
    for r in 0..count {
        let origin = [
            -1.5 + 1.0 * (r % 4) as f32,
            2.5 + 0.6 * r as f32,
            -0.6 + 0.4 * (r / 4) as f32,
        ];
        let at = |p: [f32; 3]| [origin[0] + p[0], origin[1] + p[1], origin[2] + p[2]];
        let first = bodies.len();
        for (_, centre, half, radius, lying) in RAGDOLL_PARTS {
            bodies.push(Body {
                shape: if lying {
                    Shape::CapsuleX(half, radius)
                } else {
                    Shape::CapsuleY(half, radius)
                },
                position: at(centre),
                density: 1000.0,
            });
        }
        for (child, parent, anchor, ball, p, q) in RAGDOLL_JOINTS {
            let kind = if ball {
                // Along the limb: from the anchor to the child's centre.
                let c = RAGDOLL_PARTS[child].1;
                let d = [c[0] - anchor[0], c[1] - anchor[1], c[2] - anchor[2]];
                let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                JointKind::LimitedBall {
                    axis: [d[0] / n, d[1] / n, d[2] / n],
                    cone: p,
                    twist: q,
                }
            } else {
                JointKind::Hinge {
                    axis: [1.0, 0.0, 0.0],
                    lower: p,
                    upper: q,
                }
            };
            joints.push(Joint {
                a: Some(first + parent),
                b: first + child,
                anchor: at(anchor),
                kind,
            });
        }
    }
    let step = |i: usize| Static::Cuboid {
        half: [0.5, 0.15 * (i + 1) as f32, 1.5],
        position: [-1.0 + i as f32, 0.15 * (i + 1) as f32, 0.0],
    };
    Scene::jointed(
        format!("{count} ragdolls on steps"),
        (bodies, joints),
        vec![Static::Ground, step(0), step(1), step(2), step(3)],
        steps,
    )
}

/// A `side` × `side` net of balls joined to their right and lower neighbours by ball joints,
/// hanging from the world by its two top corners, released flat (horizontal): joints that
/// close loops (a grid), Rapier's time beside Kea's (reported, not a target).
pub fn ball_net(side: usize, steps: usize) -> Scene {
    let spacing = 0.25;
    let radius = 0.08;
    let height = 3.0;
    let volume = 4.0 / 3.0 * std::f32::consts::PI * radius * radius * radius;
    let at = |i: usize, j: usize| [i as f32 * spacing, height, j as f32 * spacing];
    let bodies: Vec<Body> = (0..side * side)
        .map(|k| Body {
            shape: Shape::Ball(radius),
            position: at(k % side, k / side),
            density: 1.0 / volume,
        })
        .collect();
    let mut joints = Vec::new();
    let mid = |p: [f32; 3], q: [f32; 3]| [0.5 * (p[0] + q[0]), p[1], 0.5 * (p[2] + q[2])];
    for j in 0..side {
        for i in 0..side {
            let k = j * side + i;
            if i + 1 < side {
                joints.push(Joint {
                    a: Some(k),
                    b: k + 1,
                    anchor: mid(at(i, j), at(i + 1, j)),
                    kind: JointKind::Ball,
                });
            }
            if j + 1 < side {
                joints.push(Joint {
                    a: Some(k),
                    b: k + side,
                    anchor: mid(at(i, j), at(i, j + 1)),
                    kind: JointKind::Ball,
                });
            }
        }
    }
    for corner in [0, side - 1] {
        joints.push(Joint {
            a: None,
            b: corner,
            anchor: at(corner, 0),
            kind: JointKind::Ball,
        });
    }
    Scene::jointed(
        format!("{side}x{side} ball-joint net (loops), hanging by two corners"),
        (bodies, joints),
        Vec::new(),
        steps,
    )
}

/// The largest amount by which any hinge of `scene` is past a stop, rad, from each body's
/// orientation at the start and now (unit quaternions `[x, y, z, w]`): the turn of body `b`
/// relative to body `a` since the start, about the hinge's axis (fixed in `a`), against the
/// hinge's `[lower, upper]`. The same measure for both engines.
pub fn hinge_overrun(scene: &Scene, start: &[[f64; 4]], now: &[[f64; 4]]) -> f64 {
    let world = [0.0, 0.0, 0.0, 1.0];
    let pick = |q: &[[f64; 4]], i: Option<usize>| i.map_or(world, |i| q[i]);
    let mut worst: f64 = 0.0;
    for j in &scene.joints {
        let JointKind::Hinge { axis, lower, upper } = j.kind else {
            continue;
        };
        let (a0, b0) = (pick(start, j.a), start[j.b]);
        let (a, b) = (pick(now, j.a), now[j.b]);
        // The turn since the start in a's frame: a⁻¹ b b0⁻¹ a0.
        let d = mul(mul(mul(conj(a), b), conj(b0)), a0);
        let n = rotate(conj(a0), axis.map(f64::from));
        let along = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
        let mut angle = 2.0 * along.atan2(d[3]);
        if angle > std::f64::consts::PI {
            angle -= 2.0 * std::f64::consts::PI;
        } else if angle < -std::f64::consts::PI {
            angle += 2.0 * std::f64::consts::PI;
        }
        worst = worst
            .max(f64::from(lower) - angle)
            .max(angle - f64::from(upper));
    }
    worst
}

fn mul(p: [f64; 4], q: [f64; 4]) -> [f64; 4] {
    let [px, py, pz, pw] = p;
    let [qx, qy, qz, qw] = q;
    [
        pw * qx + px * qw + py * qz - pz * qy,
        pw * qy - px * qz + py * qw + pz * qx,
        pw * qz + px * qy - py * qx + pz * qw,
        pw * qw - px * qx - py * qy - pz * qz,
    ]
}

fn conj(q: [f64; 4]) -> [f64; 4] {
    [-q[0], -q[1], -q[2], q[3]]
}

fn rotate(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
    let r = mul(mul(q, [v[0], v[1], v[2], 0.0]), conj(q));
    [r[0], r[1], r[2]]
}

/// Whether the scene has hinges (its limits' overrun is reported).
pub fn has_hinges(scene: &Scene) -> bool {
    scene
        .joints
        .iter()
        .any(|j| matches!(j.kind, JointKind::Hinge { .. }))
}
