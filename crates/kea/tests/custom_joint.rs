//! A joint written entirely by the user from rows (the guide: "You Can Add Your Own Joint
//! Types"): a distance joint (rigid rod) and its one-sided variant (a rope).

use kea::{BodyDef, CustomConstraint, Jacobian, Real, Row, RowContext, RowWriter, Vec3, World};

/// Keeps |a₁ − a₂| = length between body 1's centre and a world point.
#[derive(Debug, Clone)]
struct Distance {
    anchor: Vec3,
    length: Real,
    rope: bool,
}

impl CustomConstraint for Distance {
    fn name(&self) -> &'static str {
        "distance joint"
    }
    fn write_rows(&self, ctx: &RowContext, out: &mut RowWriter<'_>) {
        let p = ctx.bodies[0].position;
        let d = p - self.anchor;
        let len = d.length();
        let u = d / len;
        let mut row =
            Row::new(Jacobian::new(u, Vec3::ZERO), Jacobian::ZERO).with_error(len - self.length);
        if self.rope {
            // A rope only pulls: λ (force along u on body 1) ≤ 0.
            row = row.with_bounds(Real::NEG_INFINITY, 0.0);
        }
        out.push(row);
    }
}

#[test]
fn custom_distance_joint_holds_its_length() {
    let mut world = World::with_capacity(4, 4).unwrap();
    let b = world
        .create_body(&BodyDef {
            position: Vec3::new(2.0, 0.0, 0.0),
            ..Default::default()
        })
        .unwrap();
    let j = world
        .add_custom_constraint(
            b,
            None,
            Distance {
                anchor: Vec3::ZERO,
                length: 2.0,
                rope: false,
            },
        )
        .unwrap();
    assert_eq!(world.constraint_kind(j).unwrap(), "distance joint");
    let mut max_err: Real = 0.0;
    for _ in 0..600 {
        world.step(1.0 / 60.0).unwrap();
        max_err = max_err.max((world.body(b).unwrap().position().length() - 2.0).abs());
    }
    // A velocity-level row on a curved path drifts (v h)²/(2L) per step, removed at rate γ:
    // at the bottom of this swing (v ≈ 6.3 m/s) that is about (0.105)²/4/0.2 ≈ 14 mm.
    let v = (2.0 * 9.81 * 2.0 as Real).sqrt();
    let bound = (v / 60.0).powi(2) / (2.0 * 2.0) / 0.2 * 1.2;
    assert!(max_err < bound, "rod length error {max_err} > {bound}");
    assert_eq!(world.constraint_lambdas(j).unwrap().len(), 1);
}

#[test]
fn rope_goes_slack_when_pushed_in() {
    let mut world = World::with_capacity(4, 4).unwrap();
    world.update_settings(|s| s.gravity = Vec3::ZERO).unwrap();
    let b = world
        .create_body(&BodyDef {
            position: Vec3::new(1.0, 0.0, 0.0),
            linear_velocity: Vec3::new(-1.0, 0.0, 0.0),
            ..Default::default()
        })
        .unwrap();
    world
        .add_custom_constraint(
            b,
            None,
            Distance {
                anchor: Vec3::ZERO,
                length: 2.0,
                rope: true,
            },
        )
        .unwrap();
    world.step(0.1).unwrap();
    // Moving inward, the rope is slack: the velocity is untouched.
    assert!((world.body(b).unwrap().linear_velocity().x + 1.0).abs() < 1e-6);
}
