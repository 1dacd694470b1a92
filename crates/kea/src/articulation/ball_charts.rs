//! Turns of three coordinates stepped as MuJoCo steps a ball or free joint's turn under its
//! Euler integrator (and `implicitfast`, which is Kea's Euler). The world gives a ball joint
//! (and a floating root's turn) three hinges in a row — about x, then the turned y, then the
//! twice-turned z, through one point, the first two on massless links: a chart
//! `R(a, b, c) = Rx(a) Ry(b) Rz(c)` whose rates are not the body's angular velocity
//! `ω = J(q) q̇` away from the chart's centre. Adding `h q̇⁺` to the angles is a first-order
//! step as good as MuJoCo's, but not MuJoCo's, which moves `ω` by `h ω̇` and turns by its
//! exponential, `R⁺ = R exp(h ω⁺)`; the two part by `O(h)` over a second (1e-2 rad for a
//! tumbling box with a limb at 1 ms). So after an Euler step each chart is put where MuJoCo's
//! step would leave it: `ω⁺ = J q̇⁺ + h J̇ q̇` (the same `ω̇ = J q̈ + J̇ q̇`, `q̈` the step's,
//! constraints included), `R⁺ = R(q) exp(h ω⁺)`, its angles read back from `R⁺`, and its rates
//! `J(q⁺)⁻¹ ω⁺`. Kea's implicit step keeps its chart's own discretisation: its velocity
//! derivative is taken in chart rates, so this correction does not make it MuJoCo's (a tumbling
//! box: 6.6e-3 rad from MuJoCo's `implicit` over 1 s at 1 ms, 1.8e-2 with it).

use super::{ArticulatedTree, TreeJointKind, TreeLink};
use glam::{DMat3, DQuat, DVec3, EulerRot};

/// `J(q) q̇`: the angular velocity in the last link's axes of the chart at `q` turning at `qd`.
fn body_rates([_, b, c]: [f64; 3], [da, db, dc]: [f64; 3]) -> DVec3 {
    let (first, second) = columns(b, c);
    first * da + second * db + DVec3::Z * dc
}

/// `J`'s first two columns at `(·, b, c)` (the third is z): `Rz(c)ᵀ Ry(b)ᵀ x`, `Rz(c)ᵀ y`.
fn columns(b: f64, c: f64) -> (DVec3, DVec3) {
    let unturn_z = DQuat::from_rotation_z(-c);
    (
        unturn_z * (DQuat::from_rotation_y(-b) * DVec3::X),
        unturn_z * DVec3::Y,
    )
}

/// `J̇(q, q̇) q̇`, at constant rates.
fn rates_turning([_, b, c]: [f64; 3], [da, db, dc]: [f64; 3]) -> DVec3 {
    let (first, second) = columns(b, c);
    // `Rz(c)ᵀ (y × Ry(b)ᵀ x)`, a turn of a cross product, is the cross of the turned pair.
    -DVec3::Z.cross(first * da + second * db) * dc - second.cross(first) * (db * da)
}

/// `J(q)⁻¹ ω` (the chart is regular for `|b| < π/2`).
fn chart_rates([_, b, c]: [f64; 3], w: DVec3) -> [f64; 3] {
    let (first, second) = columns(b, c);
    let j = DMat3::from_cols(first, second, DVec3::Z);
    let r = j.inverse() * w;
    [r.x, r.y, r.z]
}

/// Whether links `k..k + 3` are such a chart: hinges about x, y and z through one point, each
/// the child of the one before at its frame, the first two massless (only the world makes
/// massless links: a tree made by [`ArticulatedTree::new`] has none).
fn is_chart(links: &[TreeLink], k: usize) -> bool {
    let Some(three) = links.get(k..k + 3) else {
        return false;
    };
    let hinge = |l: &TreeLink, axis: DVec3| l.kind == TreeJointKind::Hinge && l.axis == axis;
    let at_parent = |l: &TreeLink, parent: usize| {
        l.parent == Some(parent) && l.origin == (DVec3::ZERO, DQuat::IDENTITY)
    };
    hinge(&three[0], DVec3::X)
        && hinge(&three[1], DVec3::Y)
        && hinge(&three[2], DVec3::Z)
        && three[0].mass == 0.0
        && three[1].mass == 0.0
        && at_parent(&three[1], k)
        && at_parent(&three[2], k + 1)
        && three[1].anchor == three[0].anchor
        && three[2].anchor == three[0].anchor
}

/// The first link of every chart in `links`, in order.
pub(super) fn charts(links: &[TreeLink]) -> impl Iterator<Item = usize> + '_ {
    let mut k = 0;
    std::iter::from_fn(move || {
        while k < links.len() {
            let at = k;
            if is_chart(links, at) {
                k += 3;
                return Some(at);
            }
            k += 1;
        }
        None
    })
}

impl ArticulatedTree {
    /// Puts each chart where MuJoCo's Euler step would leave it (module docs), from the
    /// step's start (`q_start`, `rate0`) and its end rates `qd`; `q`, `qd` are the end.
    pub(super) fn turn_charts_as_mujoco(&self, q: &mut [f64], qd: &mut [f64], h: f64) {
        for &k in &self.model.charts {
            let r = k..k + 3;
            let q0: [f64; 3] = self.q_start[r.clone()].try_into().expect("three");
            let v0: [f64; 3] = self.rate0[r.clone()].try_into().expect("three");
            let v1: [f64; 3] = qd[r.clone()].try_into().expect("three");
            let w = body_rates(q0, v1) + rates_turning(q0, v0) * h;
            let [a, b, c] = q0;
            let turn = DQuat::from_euler(EulerRot::XYZ, a, b, c) * DQuat::from_scaled_axis(w * h);
            let (a, b, c) = turn.normalize().to_euler(EulerRot::XYZ);
            // Angles near the old ones (a turn read back by half-turns otherwise).
            let near = |x: f64, old: f64| {
                old + (x - old + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                    - std::f64::consts::PI
            };
            let end = [near(a, q[k]), near(b, q[k + 1]), near(c, q[k + 2])];
            // At the chart's singular turn (b = ±π/2: x and z aligned) its rates are not
            // defined: the chart's own step stands (the world re-centres the chart next).
            if end[1].cos().abs() < 1e-6 {
                continue;
            }
            let rates = chart_rates(end, w);
            if !(end.iter().chain(&rates).all(|x| x.is_finite())) {
                continue;
            }
            q[r.clone()].copy_from_slice(&end);
            qd[r].copy_from_slice(&rates);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `J q̇` and `J̇ q̇` against the turn's own derivatives by central differences.
    #[test]
    fn the_charts_rates_are_the_turns_derivatives() {
        let q = [0.3, -0.4, 0.2];
        let v = [0.7, -1.1, 0.5];
        let at = |t: f64| {
            let [a, b, c] = [q[0] + v[0] * t, q[1] + v[1] * t, q[2] + v[2] * t];
            DQuat::from_euler(EulerRot::XYZ, a, b, c)
        };
        let e = 1e-5;
        // ω in body axes: R(t)ᵀ Ṙ(t), from the quaternion's derivative 2 R⁻¹ dR/dt.
        let w_at = |t: f64| {
            let d = (at(t + e) - at(t - e)) * (0.5 / e);
            let w = at(t).conjugate() * d * 2.0;
            DVec3::new(w.x, w.y, w.z)
        };
        let qt = |t: f64| [q[0] + v[0] * t, q[1] + v[1] * t, q[2] + v[2] * t];
        assert!((body_rates(q, v) - w_at(0.0)).length() < 1e-8);
        let dw = (body_rates(qt(e), v) - body_rates(qt(-e), v)) / (2.0 * e);
        assert!((rates_turning(q, v) - dw).length() < 1e-7);
        let back = chart_rates(q, body_rates(q, v));
        for (x, y) in back.iter().zip(v) {
            assert!((x - y).abs() < 1e-12);
        }
    }
}
