//! Big islands and the two solver paths: a column of 20 boxes and a 10×10×5 block of boxes
//! (500 bodies, one island), with contacts from the simple analytic box–box code below, timed
//! per step under the exact path, the iterative path and the hybrid default.
//!
//! Run: `cargo run --release --example big_island [-- --steps N]`

use kea::{
    inertia, BodyDef, BodyHandle, ConstraintHandle, Contact, ContactParams, Real, Routing,
    SolverMode, StepStats, Vec3, World,
};
use std::collections::BTreeMap;
use std::time::Duration;

const HALF: Real = 0.5;
const MARGIN: Real = 0.02;

/// Persistent vertex–face contacts between axis-aligned-ish unit boxes and the ground, kept by
/// (box, other box or ground, corner) so the iterative path can warm-start them.
#[derive(Default)]
struct BoxContacts {
    live: BTreeMap<(u32, u32, u8), ConstraintHandle>,
    seen: BTreeMap<(u32, u32, u8), bool>,
}

impl BoxContacts {
    fn update(&mut self, world: &mut World, boxes: &[BodyHandle], params: ContactParams) {
        self.seen.clear();
        let poses: Vec<_> = boxes
            .iter()
            .map(|&b| {
                let body = world.body(b).unwrap();
                (body.position(), body.orientation())
            })
            .collect();
        // Ground: corners below y = MARGIN.
        for (i, &(p, q)) in poses.iter().enumerate() {
            if p.y > 2.0 {
                continue;
            }
            for (k, c) in corners(p, q).into_iter().enumerate() {
                if c.y < MARGIN {
                    self.touch(
                        world,
                        (i as u32, u32::MAX, k as u8),
                        boxes[i],
                        None,
                        c,
                        Vec3::Y,
                        -c.y,
                        params,
                    );
                }
            }
        }
        // Box pairs: corners of box i inside (or just outside) box j, against j's nearest face.
        for i in 0..poses.len() {
            for j in 0..poses.len() {
                let (pi, qi) = poses[i];
                let (pj, qj) = poses[j];
                if i == j || (pi - pj).length_squared() > 3.0 {
                    continue;
                }
                // One side of each pair is enough: the upper box's corners against the lower
                // box (or, side by side, the higher index against the lower).
                let dy = pi.y - pj.y;
                if dy < -0.25 || (dy.abs() <= 0.25 && i < j) {
                    continue;
                }
                // The face of j that faces i: along the largest component of their separation.
                let d = qj.inverse() * (pi - pj);
                let axis = if d.x.abs() >= d.y.abs() && d.x.abs() >= d.z.abs() {
                    Vec3::X * d.x.signum()
                } else if d.y.abs() >= d.z.abs() {
                    Vec3::Y * d.y.signum()
                } else {
                    Vec3::Z * d.z.signum()
                };
                // Diagonal neighbours only touch along an edge: no face contact.
                if (d - axis * d.dot(axis)).abs().max_element() > 0.9 {
                    continue;
                }
                for (k, c) in corners(pi, qi).into_iter().enumerate() {
                    let local = qj.inverse() * (c - pj);
                    let pen = HALF - local.dot(axis);
                    // Corners near the face and over it (not beside it) touch it.
                    let across = local - axis * local.dot(axis);
                    if !(-MARGIN..HALF).contains(&pen) || across.abs().max_element() > HALF + 0.01 {
                        continue;
                    }
                    let n = qj * axis;
                    let key = (i as u32, j as u32, k as u8);
                    self.touch(world, key, boxes[i], Some(boxes[j]), c, n, pen, params);
                }
            }
        }
        // Forget contacts not seen this step.
        let stale: Vec<_> = self
            .live
            .keys()
            .filter(|k| !self.seen.contains_key(k))
            .copied()
            .collect();
        for k in stale {
            world
                .destroy_constraint(self.live.remove(&k).unwrap())
                .unwrap();
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn touch(
        &mut self,
        world: &mut World,
        key: (u32, u32, u8),
        a: BodyHandle,
        b: Option<BodyHandle>,
        point: Vec3,
        normal: Vec3,
        penetration: Real,
        params: ContactParams,
    ) {
        self.seen.insert(key, true);
        match self.live.get(&key) {
            Some(&h) => {
                let c = world.contact_mut(h).unwrap();
                c.set_position(point).unwrap();
                c.set_normal(normal).unwrap();
                c.set_penetration(penetration).unwrap();
            }
            None => {
                let mut c = Contact::new(point, normal, penetration).unwrap();
                c.set_params(params).unwrap();
                self.live
                    .insert(key, world.create_contact(a, b, c).unwrap());
            }
        }
    }
}

fn corners(p: Vec3, q: kea::Quat) -> [Vec3; 8] {
    let mut out = [Vec3::ZERO; 8];
    for (k, o) in out.iter_mut().enumerate() {
        let s = Vec3::new(
            if k & 1 == 0 { -HALF } else { HALF },
            if k & 2 == 0 { -HALF } else { HALF },
            if k & 4 == 0 { -HALF } else { HALF },
        );
        *o = p + q * s;
    }
    out
}

/// Runs a scene; returns (ms per step in the solver, the last step's stats, top drift).
fn run(positions: &[Vec3], mode: SolverMode, steps: usize) -> (f64, StepStats, Real) {
    let n = positions.len();
    let mut world = World::new(kea::WorldDef {
        max_bodies: n,
        max_constraints: 24 * n,
        settings: kea::WorldSettings {
            routing: Routing {
                mode,
                ..Default::default()
            },
            ..Default::default()
        },
        ..Default::default()
    })
    .unwrap();
    let boxes: Vec<_> = positions
        .iter()
        .map(|&p| {
            world
                .create_body(&BodyDef {
                    position: p,
                    inertia: inertia::solid_box(1.0, Vec3::splat(HALF)).unwrap(),
                    ..Default::default()
                })
                .unwrap()
        })
        .collect();
    let top = *boxes
        .iter()
        .max_by(|a, b| {
            let (pa, pb) = (
                world.body(**a).unwrap().position(),
                world.body(**b).unwrap().position(),
            );
            pa.y.total_cmp(&pb.y)
        })
        .unwrap();
    let top0 = world.body(top).unwrap().position();
    let mut contacts = BoxContacts::default();
    let mut total = Duration::ZERO;
    let mut last = StepStats::default();
    for _ in 0..steps {
        contacts.update(&mut world, &boxes, ContactParams::default());
        last = world.step(1.0 / 60.0).unwrap();
        total += last.time_total;
    }
    let p = world.body(top).unwrap().position();
    let drift = ((p - top0) * Vec3::new(1.0, 0.0, 1.0)).length();
    (total.as_secs_f64() * 1000.0 / steps as f64, last, drift)
}

fn report(name: &str, positions: &[Vec3], modes: &[SolverMode], steps: usize) {
    for &mode in modes {
        let (ms, s, drift) = run(positions, mode, steps);
        println!(
            "{name:<16} {:<9} {ms:8.2} ms/step  rows {:5}  islands exact {} iterative {}  \
             (gather {:.2} ms, exact {:.2} ms, iterative {:.2} ms)  top drift {:.1} mm",
            format!("{mode:?}"),
            s.rows,
            s.solver.exact_islands,
            s.solver.iterative_islands,
            s.time_gather.as_secs_f64() * 1e3,
            s.solver.time_solve_exact.as_secs_f64() * 1e3,
            s.solver.time_solve_iterative.as_secs_f64() * 1e3,
            drift * 1e3,
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let steps = args
        .iter()
        .position(|a| a == "--steps")
        .and_then(|i| args.get(i + 1))
        .and_then(|s| s.parse().ok())
        .unwrap_or(120);
    println!(
        "big_island: {steps} steps at 60 Hz, solver time per step (contact generation not counted)"
    );
    let column: Vec<Vec3> = (0..20)
        .map(|i| Vec3::new(0.0, HALF + i as Real, 0.0))
        .collect();
    report(
        "column of 20",
        &column,
        &[SolverMode::Exact, SolverMode::Iterative, SolverMode::Hybrid],
        steps,
    );
    let mut block = Vec::new();
    for y in 0..5 {
        for x in 0..10 {
            for z in 0..10 {
                block.push(Vec3::new(x as Real, HALF + y as Real, z as Real));
            }
        }
    }
    report(
        "block 10x10x5",
        &block,
        &[SolverMode::Iterative, SolverMode::Hybrid],
        steps,
    );
    // Touching neighbours make the block one island of ~6,000 support rows plus side
    // contacts: far beyond what a dense pivoting solve can do in real time.
    let rows = 500 * 4 * 3;
    println!(
        "block 10x10x5    Exact     not run: one island of over {rows} rows needs a {:.0} MB matrix and \
         ~{:.0} GFLOP per factorisation (the reason the hybrid default sends it to the iterative path)",
        (rows * rows * 8) as f64 / 1e6,
        (rows as f64).powi(3) / 3.0 / 1e9
    );
}
