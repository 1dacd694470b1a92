//! Fixed tendons (`World::add_tendon`): a spring and a damper along a weighted sum of joint
//! coordinates against their closed forms, a range the length stays in, on the reduced path
//! (one tree) and on the maximal paths (forced, or two trees coupled by a tendon), in f32 and
//! f64; bad tendons refused by name; clones stepping on the same bits.

use kea::{
    BodyDef, BodyHandle, ConstraintHandle, FixedTendon, JointSpec, Mat3, Real, Routing, SolverMode,
    TendonTerm, Vec3, World,
};

const G: Real = 9.81;
const PI: Real = kea::PI_REAL;

fn world(gravity: Real, mode: SolverMode) -> World {
    let mut w = World::with_capacity(16, 32).unwrap();
    w.update_settings(|s| {
        s.gravity = Vec3::new(0.0, -gravity, 0.0);
        s.routing = Routing {
            mode,
            ..Routing::default()
        };
    })
    .unwrap();
    w
}

const MODES: [SolverMode; 3] = [SolverMode::Hybrid, SolverMode::Exact, SolverMode::Iterative];

/// A rod of mass `m`, length `l` along −y from `top`, hinged there about z to `parent`,
/// turning at `spin` rad/s (its centre moving with it).
fn rod(
    w: &mut World,
    top: Vec3,
    (m, l): (Real, Real),
    parent: Option<BodyHandle>,
    spin: Real,
) -> (BodyHandle, ConstraintHandle) {
    let i = m * l * l / 12.0;
    let b = w
        .create_body(&BodyDef {
            mass: m,
            inertia: Mat3::from_diagonal(Vec3::new(i, i, i)),
            position: top - Vec3::new(0.0, 0.5 * l, 0.0),
            linear_velocity: Vec3::new(spin * 0.5 * l, 0.0, 0.0),
            angular_velocity: Vec3::new(0.0, 0.0, spin),
            ..BodyDef::default()
        })
        .unwrap();
    let j = w
        .create_joint(b, parent, JointSpec::hinge(top, Vec3::Z))
        .unwrap();
    (b, j.raw())
}

fn term(joint: ConstraintHandle, coefficient: Real) -> TendonTerm {
    TendonTerm {
        joint,
        coordinate: 0,
        coefficient,
    }
}

/// The times the tendon's length crosses zero upwards over `seconds`.
fn upward_crossings(w: &mut World, t: kea::TendonHandle, h: Real, seconds: Real) -> Vec<Real> {
    let (mut time, mut last, mut out) = (0.0, w.tendon_length(t).unwrap().0, Vec::new());
    for _ in 0..(seconds / h).round() as usize {
        w.step(h).unwrap();
        time += h;
        let now = w.tendon_length(t).unwrap().0;
        if last < 0.0 && now >= 0.0 {
            out.push(time - h * now / (now - last));
        }
        last = now;
    }
    out
}

#[test]
fn a_tendon_spring_on_a_wheel_oscillates_at_its_closed_form_frequency_on_every_path() {
    // A rod spinning about its pivot without gravity, a tendon L = c·q with stiffness k:
    // I q̈ = −c² k q, so Ω = c √(k / I) and the length's amplitude is c ω₀ / Ω.
    let (m, l, c, k, spin): (Real, Real, Real, Real, Real) = (2.0, 1.0, 2.0, 3.0, 0.4);
    let inertia = m * l * l / 3.0;
    let omega = c * (k / inertia).sqrt();
    for mode in MODES {
        let mut w = world(0.0, mode);
        let (_, j) = rod(&mut w, Vec3::ZERO, (m, l), None, spin);
        let t = w
            .add_tendon(FixedTendon {
                terms: vec![term(j, c)],
                stiffness: k,
                ..FixedTendon::default()
            })
            .unwrap();
        let h = 1e-3;
        let mut largest: Real = 0.0;
        let mut crossings = Vec::new();
        let (mut time, mut last) = (0.0, 0.0);
        for _ in 0..6000 {
            let stats = w.step(h).unwrap();
            let reduced = u32::from(mode == SolverMode::Hybrid);
            assert_eq!(
                stats.reduced_trees, reduced,
                "{mode:?}: one tree, reduced when free to"
            );
            time += h;
            let now = w.tendon_length(t).unwrap().0;
            largest = largest.max(now.abs());
            if last < 0.0 && now >= 0.0 {
                crossings.push(time - h * now / (now - last));
            }
            last = now;
        }
        let period = 2.0 * PI / omega;
        let measured =
            (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as Real;
        assert!(
            (measured - period).abs() < 5e-3 * period,
            "{mode:?}: period {measured} s, closed form {period} s"
        );
        let amplitude = c * spin / omega;
        // The iterative path holds the step's force over its substeps (between explicit and
        // symplectic Euler): it gains about 0.4% a second here.
        let tolerance = if mode == SolverMode::Iterative {
            0.03
        } else {
            0.002
        };
        assert!(
            (largest - amplitude).abs() < tolerance * amplitude,
            "{mode:?}: amplitude {largest}, closed form {amplitude}"
        );
    }
}

#[test]
fn a_tendon_damper_slows_a_wheel_exponentially_on_every_path() {
    // I ω̇ = −b c² ω: ω(t) = ω₀ exp(−b c² t / I).
    let (m, l, c, b, spin): (Real, Real, Real, Real, Real) = (2.0, 1.0, 1.5, 0.2, 3.0);
    let inertia = m * l * l / 3.0;
    for mode in MODES {
        let mut w = world(0.0, mode);
        let (body, j) = rod(&mut w, Vec3::ZERO, (m, l), None, spin);
        let t = w
            .add_tendon(FixedTendon {
                terms: vec![term(j, c)],
                damping: b,
                ..FixedTendon::default()
            })
            .unwrap();
        for _ in 0..1000 {
            w.step(1e-3).unwrap();
        }
        let expected = spin * (-b * c * c * 1.0 / inertia).exp();
        let now = w.body(body).unwrap().angular_velocity().z;
        assert!(
            (now - expected).abs() < 0.01 * expected,
            "{mode:?}: ω {now} after 1 s, closed form {expected}"
        );
        let rate = w.tendon_length(t).unwrap().1;
        assert!(
            (rate - c * now).abs() < 0.01 * c * expected,
            "{mode:?}: the tendon's rate {rate} is c ω = {}",
            c * now
        );
    }
}

#[test]
fn two_pendulums_coupled_by_a_tendon_spring_swing_in_their_antisymmetric_mode() {
    // Two rods on their own hinges, L = q₁ − q₂ with stiffness k: started ±ω₀, they swing
    // against each other at ω² = (m g l/2 + 2k) / I_pivot. Two trees under one tendon go
    // to the maximal path, where the tendon acts through the joints' rows.
    let (m, l, k, spin): (Real, Real, Real, Real) = (1.0, 1.0, 2.0, 0.1);
    let pivot = m * l * l / 3.0;
    let omega = ((m * G * 0.5 * l + 2.0 * k) / pivot).sqrt();
    for mode in MODES {
        let mut w = world(G, mode);
        let (_, j1) = rod(&mut w, Vec3::ZERO, (m, l), None, spin);
        let (_, j2) = rod(&mut w, Vec3::new(2.0, 0.0, 0.0), (m, l), None, -spin);
        let t = w
            .add_tendon(FixedTendon {
                terms: vec![term(j1, 1.0), term(j2, -1.0)],
                stiffness: k,
                ..FixedTendon::default()
            })
            .unwrap();
        let crossings = upward_crossings(&mut w, t, 1e-3, 6.0);
        let n = crossings.len() - 1;
        let measured = (crossings[n] - crossings[0]) / n as Real;
        let period = 2.0 * PI / omega;
        assert!(
            (measured - period).abs() < 5e-3 * period,
            "{mode:?}: period {measured} s, closed form {period} s"
        );
        assert_eq!(w.step(1e-3).unwrap().reduced_trees, 0, "{mode:?}");
    }
}

#[test]
fn a_tendon_range_holds_a_double_pendulum_on_every_path() {
    // A double pendulum released from the horizontal: its elbow swings past 1 rad free; a
    // tendon L = q₂ (the elbow, relative) with range [−0.2, 0.2] keeps it there, soft as
    // MuJoCo's model is (a few hundredths over under the swing's load).
    let dims = (1.0, 1.0);
    let free = |tendon: bool, mode: SolverMode| -> Real {
        let mut w = world(G, mode);
        let (b1, _) = rod(&mut w, Vec3::ZERO, dims, None, 0.0);
        let (_, j2) = rod(&mut w, Vec3::new(0.0, -1.0, 0.0), dims, Some(b1), 0.0);
        // Turned to the horizontal: the whole chain about the world's pivot.
        let t = tendon.then(|| {
            w.add_tendon(FixedTendon {
                terms: vec![term(j2, 1.0)],
                range: Some([-0.2, 0.2]),
                ..FixedTendon::default()
            })
            .unwrap()
        });
        let mut largest: Real = 0.0;
        // Started by a push on the lower rod's end rather than a turn (angles start at 0).
        w.body_mut(b1)
            .unwrap()
            .set_angular_velocity(Vec3::new(0.0, 0.0, 4.0))
            .unwrap();
        w.body_mut(b1)
            .unwrap()
            .set_linear_velocity(Vec3::new(2.0, 0.0, 0.0))
            .unwrap();
        for _ in 0..2000 {
            let stats = w.step(1e-3).unwrap();
            let reduced = u32::from(mode == SolverMode::Hybrid);
            assert_eq!(stats.reduced_trees, reduced, "{mode:?}");
            let elbow = match t {
                Some(t) => w.tendon_length(t).unwrap().0,
                None => kea::JointHandle::<kea::Hinge>::from_raw(j2)
                    .angle(&w)
                    .unwrap(),
            };
            largest = largest.max(elbow.abs());
        }
        largest
    };
    for mode in MODES {
        let unheld = free(false, mode);
        assert!(unheld > 0.5, "{mode:?}: the elbow swings {unheld} rad free");
        let held = free(true, mode);
        let allowed = if mode == SolverMode::Hybrid {
            0.03
        } else {
            0.1
        };
        assert!(
            held < 0.2 + allowed,
            "{mode:?}: the elbow reached {held} rad against a range of ±0.2"
        );
        assert!(held > 0.15, "{mode:?}: the elbow reached {held} rad");
    }
}

#[test]
fn bad_tendons_are_refused_by_name_and_change_nothing() {
    let mut w = world(G, SolverMode::Hybrid);
    let (b1, j) = rod(&mut w, Vec3::ZERO, (1.0, 1.0), None, 0.0);
    let ball = w
        .create_joint(b1, None, JointSpec::ball(Vec3::new(0.0, -1.0, 0.0)))
        .unwrap()
        .raw();
    let ok = FixedTendon {
        terms: vec![term(j, 1.0)],
        ..FixedTendon::default()
    };
    let cases: Vec<(&str, FixedTendon)> = vec![
        (
            "terms",
            FixedTendon {
                terms: vec![],
                ..ok.clone()
            },
        ),
        (
            "terms",
            FixedTendon {
                terms: vec![term(ball, 1.0)],
                ..ok.clone()
            },
        ),
        (
            "terms",
            FixedTendon {
                terms: vec![TendonTerm {
                    coordinate: 1,
                    ..term(j, 1.0)
                }],
                ..ok.clone()
            },
        ),
        (
            "coefficient",
            FixedTendon {
                terms: vec![term(j, Real::NAN)],
                ..ok.clone()
            },
        ),
        (
            "stiffness",
            FixedTendon {
                stiffness: -1.0,
                ..ok.clone()
            },
        ),
        (
            "damping",
            FixedTendon {
                damping: Real::INFINITY,
                ..ok.clone()
            },
        ),
        (
            "spring_length",
            FixedTendon {
                spring_length: [1.0, 0.0],
                ..ok.clone()
            },
        ),
        (
            "range",
            FixedTendon {
                range: Some([0.1, Real::NAN]),
                ..ok.clone()
            },
        ),
        (
            "range",
            FixedTendon {
                range: Some([0.3, -0.3]),
                ..ok.clone()
            },
        ),
        (
            "solref",
            FixedTendon {
                soft: kea::SoftLimit {
                    solref: [Real::NAN, 1.0],
                    ..kea::SoftLimit::default()
                },
                ..ok.clone()
            },
        ),
    ];
    for (arg, bad) in cases {
        let e = w.add_tendon(bad.clone()).unwrap_err().to_string();
        assert!(e.contains(arg), "{bad:?}: {e} should name `{arg}`");
        assert_eq!(w.tendons().count(), 0);
    }
    let t = w.add_tendon(ok).unwrap();
    w.remove_tendon(t).unwrap();
    assert!(w.tendon(t).unwrap_err().to_string().contains("tendon"));
    assert!(w.remove_tendon(t).is_err());
    let other = World::with_capacity(4, 4).unwrap();
    assert!(other.tendon(t).is_err());
}

#[test]
fn a_clone_with_tendons_steps_on_the_same_bits() {
    for mode in MODES {
        let mut w = world(G, mode);
        let (b1, j1) = rod(&mut w, Vec3::ZERO, (1.0, 1.0), None, 3.0);
        let (b2, j2) = rod(&mut w, Vec3::new(0.0, -1.0, 0.0), (1.0, 1.0), Some(b1), 0.0);
        w.add_tendon(FixedTendon {
            terms: vec![term(j1, 0.5), term(j2, -1.0)],
            stiffness: 4.0,
            damping: 0.3,
            spring_length: [-0.1, 0.1],
            range: Some([-0.3, 0.3]),
            ..FixedTendon::default()
        })
        .unwrap();
        for _ in 0..100 {
            w.step(1e-3).unwrap();
        }
        let mut copy = w.clone();
        for _ in 0..300 {
            w.step(1e-3).unwrap();
            copy.step(1e-3).unwrap();
        }
        for b in [b1, b2] {
            let (x, y) = (w.body(b).unwrap(), copy.body(b).unwrap());
            assert_eq!(x.position().to_array(), y.position().to_array(), "{mode:?}");
            assert_eq!(
                x.angular_velocity().to_array(),
                y.angular_velocity().to_array(),
                "{mode:?}"
            );
        }
    }
}
