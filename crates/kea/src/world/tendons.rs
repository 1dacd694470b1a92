//! Fixed tendons (MuJoCo's `<tendon><fixed>`): a length that is a weighted sum of joint
//! coordinates, `L = Σ cᵢ qᵢ`, with a spring and damper along it and a range it stays in.
//!
//! A tendon acts while each of its joints is live and enabled. On the reduced path (its
//! joints all in one tree; a tendon over joints of two trees, or of a tree and anything
//! else, keeps them off that path) it acts inside the tree's accelerations exactly as in
//! MuJoCo: the spring and damper as joint forces, the range as a soft row of the tree's
//! exact solve (`articulation/tendons.rs`). On the maximal paths it acts through its joints'
//! coordinate rows as a force fixed for the step, from the coordinates and rates the last
//! step left: the spring and damper are MuJoCo's passive force (as explicit as there), the
//! range a one-sided spring and damper with the soft model's stiffness and damping on the
//! tendon's effective mass estimated from its joints' bodies alone (their other joints
//! make the true one heavier, so it is softer than MuJoCo's and never stiffer, and under a
//! load it sinks further into the range).

use super::constraint_entry::{ConstraintEntry, ConstraintKind};
use super::World;
use crate::error::{KeaError, KeaResult};
use crate::handle::{Arena, ConstraintHandle};
use crate::math::{wide, Mat3, Real};
use crate::SoftLimit;

/// One term of a tendon: a joint coordinate and its weight.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TendonTerm {
    /// A hinge, a prismatic joint or a planar joint.
    pub joint: ConstraintHandle,
    /// Which of its coordinates: 0 for a hinge or a slider; 0, 1 (travels) or 2 (turn) for a
    /// planar joint.
    pub coordinate: usize,
    /// Its weight in the length (m or rad per unit of the coordinate; any sign, finite).
    pub coefficient: Real,
}

/// A fixed tendon (module docs): its terms, spring, damper and range.
#[derive(Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FixedTendon {
    /// At least one.
    pub terms: Vec<TendonTerm>,
    /// Spring stiffness along the length, N/m (or N·m/rad), ≥ 0.
    pub stiffness: Real,
    /// Damping along the length, N·s/m, ≥ 0.
    pub damping: Real,
    /// The spring's rest lengths `[low, high]` (equal for one length): no spring force
    /// between them.
    pub spring_length: [Real; 2],
    /// The range `[low, high]` the length stays in, if any.
    pub range: Option<[Real; 2]>,
    /// The range's soft model (MuJoCo's `solreflimit`, `solimplimit`, `margin`).
    pub soft: SoftLimit,
}

impl Clone for FixedTendon {
    fn clone(&self) -> Self {
        Self {
            terms: self.terms.clone(),
            stiffness: self.stiffness,
            damping: self.damping,
            spring_length: self.spring_length,
            range: self.range,
            soft: self.soft,
        }
    }

    /// Reuses this tendon's terms (a world's state copied into another allocates nothing).
    fn clone_from(&mut self, source: &Self) {
        self.terms.clone_from(&source.terms);
        self.stiffness = source.stiffness;
        self.damping = source.damping;
        self.spring_length = source.spring_length;
        self.range = source.range;
        self.soft = source.soft;
    }
}

impl Default for FixedTendon {
    /// No terms, no spring, no damper, no range, MuJoCo's default soft model.
    fn default() -> Self {
        Self {
            terms: Vec::new(),
            stiffness: 0.0,
            damping: 0.0,
            spring_length: [0.0, 0.0],
            range: None,
            soft: SoftLimit::default(),
        }
    }
}

/// A handle to a tendon of a [`World`]. Slots are never reused: a removed tendon's handle
/// stays refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TendonHandle {
    world: u32,
    index: u32,
}

impl TendonHandle {
    /// The tendon's index in its world.
    #[must_use]
    pub fn index(self) -> u32 {
        self.index
    }
}

impl World {
    /// Adds a fixed tendon. Errors name the field and value: no terms, a joint that is not
    /// this world's live hinge, prismatic or planar joint, a coordinate it does not have, a
    /// non-finite coefficient, a negative or non-finite stiffness or damping, spring lengths
    /// or a range out of order or not finite, a bad soft model; nothing changes then.
    pub fn add_tendon(&mut self, tendon: FixedTendon) -> KeaResult<TendonHandle> {
        self.check_tendon(&tendon)?;
        self.tendons.push(Some(tendon));
        self.joint_revision = super::constraint_index::next_joint_revision();
        Ok(TendonHandle {
            world: self.id,
            index: self.tendons.len() as u32 - 1,
        })
    }

    /// Removes a tendon; its joints no longer feel it.
    pub fn remove_tendon(&mut self, h: TendonHandle) -> KeaResult<()> {
        self.tendon(h)?;
        let tendon = self.tendons[h.index as usize].take();
        for term in tendon.iter().flat_map(|t| &t.terms) {
            if let Some(limit) = self.coordinate_limit_mut(term.joint, term.coordinate) {
                limit.set_tendon_force(0.0);
            }
        }
        self.joint_revision = super::constraint_index::next_joint_revision();
        Ok(())
    }

    /// A tendon's definition.
    pub fn tendon(&self, h: TendonHandle) -> KeaResult<&FixedTendon> {
        if h.world != self.id {
            return Err(KeaError::OutOfRange {
                arg: "tendon",
                value: format!("{h:?}"),
                expected: "a tendon of this world",
            });
        }
        self.tendons
            .get(h.index as usize)
            .and_then(Option::as_ref)
            .ok_or_else(|| KeaError::OutOfRange {
                arg: "tendon",
                value: format!("{h:?}"),
                expected: "a tendon not removed",
            })
    }

    /// The tendons live in the world, with their handles.
    pub fn tendons(&self) -> impl Iterator<Item = (TendonHandle, &FixedTendon)> + '_ {
        let world = self.id;
        self.tendons.iter().enumerate().filter_map(move |(i, t)| {
            t.as_ref().map(|t| {
                (
                    TendonHandle {
                        world,
                        index: i as u32,
                    },
                    t,
                )
            })
        })
    }

    /// A tendon's length and its rate after the last step (from its joints' coordinates);
    /// refused if one of its joints is gone.
    pub fn tendon_length(&self, h: TendonHandle) -> KeaResult<(Real, Real)> {
        let t = self.tendon(h)?;
        self.length_of(t).ok_or(KeaError::InvalidState {
            operation: "tendon_length",
            reason: "one of the tendon's joints was destroyed",
        })
    }

    /// The length and rate of `t` from its joints' tracked coordinates; `None` if a joint is
    /// gone.
    fn length_of(&self, t: &FixedTendon) -> Option<(Real, Real)> {
        let mut length = 0.0;
        let mut rate = 0.0;
        for term in &t.terms {
            let limit = self.coordinate_limit(term.joint, term.coordinate)?;
            length += term.coefficient * limit.position();
            rate += term.coefficient * limit.velocity();
        }
        Some((length, rate))
    }

    pub(super) fn check_tendon(&self, t: &FixedTendon) -> KeaResult<()> {
        let bad = |arg: &'static str, value: String, expected: &'static str| {
            Err(KeaError::OutOfRange {
                arg,
                value,
                expected,
            })
        };
        if t.terms.is_empty() {
            return bad("terms", "none".into(), "at least one joint coordinate");
        }
        for (k, term) in t.terms.iter().enumerate() {
            if self.coordinate_limit(term.joint, term.coordinate).is_none() {
                return bad(
                    "terms",
                    format!("term {k}: {:?} coordinate {}", term.joint, term.coordinate),
                    "a live hinge or prismatic joint (coordinate 0) or planar joint (0 to 2) of this world",
                );
            }
            if !term.coefficient.is_finite() {
                return bad(
                    "coefficient",
                    format!("term {k}: {}", term.coefficient),
                    "a finite number",
                );
            }
        }
        for (arg, v) in [("stiffness", t.stiffness), ("damping", t.damping)] {
            if !(v.is_finite() && v >= 0.0) {
                return bad(arg, v.to_string(), "finite and >= 0");
            }
        }
        let ordered = |[lo, hi]: [Real; 2]| lo.is_finite() && hi.is_finite() && lo <= hi;
        if !ordered(t.spring_length) {
            return bad(
                "spring_length",
                format!("{:?}", t.spring_length),
                "finite, low <= high",
            );
        }
        if t.range.is_some_and(|r| !ordered(r)) {
            return bad("range", format!("{:?}", t.range), "finite, low <= high");
        }
        t.soft.validate()
    }

    /// The limit of a joint's coordinate, if the joint is live and has it.
    fn coordinate_limit(&self, joint: ConstraintHandle, k: usize) -> Option<&crate::Limit> {
        coordinate_limit(&self.constraints, joint, k)
    }

    fn coordinate_limit_mut(
        &mut self,
        joint: ConstraintHandle,
        k: usize,
    ) -> Option<&mut crate::Limit> {
        match &mut self.constraints.get_mut(joint).ok()?.kind {
            ConstraintKind::Hinge(j) if k == 0 => Some(&mut j.limit),
            ConstraintKind::Prismatic(j) if k == 0 => Some(&mut j.limit),
            ConstraintKind::Planar(j) => j.limit_mut(k),
            _ => None,
        }
    }

    /// Whether tendon `t`'s joints are all live and enabled: it acts.
    pub(super) fn tendon_acts(&self, t: &FixedTendon) -> bool {
        tendon_acts(&self.constraints, t)
    }

    /// Sets the coordinate force each maximal-path joint feels from its tendons this step
    /// (module docs); tendons the reduced path stepped (`reduced[i]`) are left out.
    pub(super) fn load_tendon_forces(&mut self, dt: Real) {
        if self.tendons.is_empty() {
            return;
        }
        let tendons = std::mem::take(&mut self.tendons);
        for t in tendons.iter().flatten() {
            for term in &t.terms {
                if let Some(limit) = self.coordinate_limit_mut(term.joint, term.coordinate) {
                    limit.set_tendon_force(0.0);
                }
            }
        }
        for (i, t) in tendons.iter().enumerate() {
            let Some(t) = t else { continue };
            let reduced = self.scratch.tendon_reduced.get(i).copied().unwrap_or(false);
            if reduced || !self.tendon_acts(t) {
                continue;
            }
            let Some(f) = self.maximal_tendon_force(t, dt) else {
                continue;
            };
            for term in &t.terms {
                if let Some(limit) = self.coordinate_limit_mut(term.joint, term.coordinate) {
                    let now = limit.tendon_force();
                    limit.set_tendon_force(now + term.coefficient * f);
                }
            }
        }
        self.tendons = tendons;
    }

    /// Tendon `t`'s force along its length on the maximal path this step (module docs).
    fn maximal_tendon_force(&self, t: &FixedTendon, dt: Real) -> Option<Real> {
        let (length, rate) = self.length_of(t)?;
        let [lo, hi] = t.spring_length.map(wide);
        let stretch = crate::articulation::stretch(wide(length), (lo, hi)) as Real;
        let mut f = -t.stiffness * stretch - t.damping * rate;
        if let Some([low, high]) = t.range {
            let s = &t.soft;
            let (b, k) = crate::articulation::reference_gains(s, wide(dt));
            let (b, k) = (b as Real, k as Real);
            let mobility: Real = t
                .terms
                .iter()
                .map(|term| term.coefficient.powi(2) * self.coordinate_mobility(term))
                .sum();
            if mobility > 0.0 {
                for (sign, distance) in [(1.0, length - low), (-1.0, high - length)] {
                    let x = distance - s.margin;
                    if x >= 0.0 {
                        continue;
                    }
                    let d = crate::articulation::impedance(s, wide(x)) as Real;
                    let push = d * (-b * sign * rate - k * d * x) / mobility;
                    f += sign * push.max(0.0);
                }
            }
        }
        Some(f)
    }

    /// A joint coordinate's inverse inertia from its two bodies alone: `uᵀ(I₁⁻¹ + I₂⁻¹)u`
    /// for a turn about `u`, `1/m₁ + 1/m₂` for a travel.
    fn coordinate_mobility(&self, term: &TendonTerm) -> Real {
        let Ok(entry) = self.constraints.get(term.joint) else {
            return 0.0;
        };
        let bodies = entry.bodies.map(|h| {
            h.and_then(|h| self.bodies.get(h).ok())
                .filter(|b| b.enabled && !b.kinematic)
        });
        let turn_axis = match &entry.kind {
            ConstraintKind::Hinge(j) => Some(j.local_axis2),
            ConstraintKind::Planar(j) if term.coordinate == 2 => Some(j.local_normal2),
            _ => None,
        };
        let second = entry.bodies[1]
            .and_then(|h| self.bodies.get(h).ok())
            .map_or(crate::math::Quat::IDENTITY, |b| b.orientation);
        let mut w = 0.0;
        for b in bodies.into_iter().flatten() {
            w += match turn_axis {
                Some(local) => {
                    let u = second * local;
                    let r = Mat3::from_quat(b.orientation);
                    u.dot(r * b.inv_inertia * r.transpose() * u)
                }
                None => b.inv_mass,
            };
        }
        w
    }
}

/// The limit of a joint's coordinate among `constraints`, if the joint is live and has it.
fn coordinate_limit(
    constraints: &Arena<ConstraintEntry, ConstraintHandle>,
    joint: ConstraintHandle,
    k: usize,
) -> Option<&crate::Limit> {
    match &constraints.get(joint).ok()?.kind {
        ConstraintKind::Hinge(j) if k == 0 => Some(j.limit()),
        ConstraintKind::Prismatic(j) if k == 0 => Some(j.limit()),
        ConstraintKind::Planar(j) => j.limit(k),
        _ => None,
    }
}

/// Whether tendon `t`'s joints are all live and enabled in `constraints`: it acts.
pub(super) fn tendon_acts(
    constraints: &Arena<ConstraintEntry, ConstraintHandle>,
    t: &FixedTendon,
) -> bool {
    t.terms.iter().all(|term| {
        constraints.get(term.joint).is_ok_and(|e| e.enabled)
            && coordinate_limit(constraints, term.joint, term.coordinate).is_some()
    })
}
