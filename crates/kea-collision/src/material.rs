//! Materials: every collider has a material id; a table gives the contact parameters of each
//! pair of materials (the guide: restitution is a property of the two materials together), and
//! combine rules fill in pairs that have no entry.
//!
//! Combine rules for a pair with no entry, from the two [`Surface`]s:
//! - friction μ: geometric mean `√(μ₁μ₂)` (a frictionless surface makes the pair frictionless);
//! - restitution: the larger (a bouncy ball bounces on a dull floor); threshold: the larger;
//! - softness: the sum (two springs in series add their compliances); `None` if both are rigid;
//! - slip: the sum; adhesion: the smaller (both surfaces must be sticky).
//!
//! A pair entry may also fix the world direction of its contacts' first friction direction
//! ([`MaterialTable::set_pair_with_direction`]), so that its `slide` moves things along it: a
//! conveyor belt.

use crate::error::{CollisionError, CollisionResult};
use kea::{ContactParams, ContactType, FrictionModel, Real, Vec3};

/// Index of a material in a [`MaterialTable`]. Material 0 always exists.
pub type MaterialId = u32;

/// The surface properties of one material, combined with another's by the rules above.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Surface {
    /// Coulomb friction coefficient, ≥ 0: the kinetic one when `static_friction` is set.
    pub friction: Real,
    /// A static coefficient (≥ `friction`) that holds surfaces at rest on each other until
    /// they slide (`kea::FrictionModel::StaticKinetic`); `None`: one coefficient.
    #[cfg_attr(feature = "serde", serde(default))]
    pub static_friction: Option<Real>,
    /// Coefficient of restitution, ≥ 0.
    pub restitution: Real,
    /// Slowest approach speed that bounces, m/s.
    pub restitution_threshold: Real,
    /// Contact softness ε; `None` uses the world's ε.
    pub softness: Option<Real>,
    /// Slip, m/s per N, both directions.
    pub slip: Real,
    /// Largest adhesive force, N.
    pub adhesion: Real,
}

impl Default for Surface {
    /// μ = 0.5, no bounce (threshold 0.1 m/s), world softness, no slip, no adhesion.
    fn default() -> Self {
        Self {
            friction: 0.5,
            static_friction: None,
            restitution: 0.0,
            restitution_threshold: 0.1,
            softness: None,
            slip: 0.0,
            adhesion: 0.0,
        }
    }
}

impl Surface {
    /// Checks every field, naming the first bad one. (Checking the combined parameters of a
    /// surface with itself would not do: √(μ·μ) hides a negative μ.)
    pub fn validate(&self) -> CollisionResult<()> {
        let fields = [
            ("friction", self.friction),
            ("restitution", self.restitution),
            ("restitution_threshold", self.restitution_threshold),
            ("slip", self.slip),
            ("adhesion", self.adhesion),
            ("softness", self.softness.unwrap_or(0.0)),
            (
                "static_friction",
                self.static_friction.unwrap_or(self.friction),
            ),
        ];
        for (arg, value) in fields {
            if !(value.is_finite() && value >= 0.0) {
                return Err(kea::KeaError::OutOfRange {
                    arg,
                    value: format!("{value}"),
                    expected: "must be finite and ≥ 0",
                }
                .into());
            }
        }
        if let Some(s) = self.static_friction.filter(|&s| s < self.friction) {
            return Err(kea::KeaError::OutOfRange {
                arg: "static_friction",
                value: format!("{s} < friction {}", self.friction),
                expected: "a static coefficient at least the (kinetic) friction",
            }
            .into());
        }
        Ok(())
    }
}

/// Materials and their pair table.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct MaterialTable {
    surfaces: Vec<Surface>,
    /// Explicit pair entries, keyed by (smaller id, larger id), sorted for binary search.
    pairs: Vec<((MaterialId, MaterialId), PairEntry)>,
    /// Counts the changes: contacts keep their parameters until it moves.
    revision: u64,
}

/// One explicit pair entry.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct PairEntry {
    params: ContactParams,
    /// A fixed world friction direction, oriented for the pair's smaller id as body 1.
    direction: Option<Vec3>,
    /// The pair's own contact strategy (most points per manifold), if it has one.
    #[cfg_attr(feature = "serde", serde(default))]
    max_points: Option<usize>,
}

/// What contacts between two materials get: their parameters and, for a conveyor pair, the
/// world direction of their primary friction direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairContact {
    /// The contact parameters, with `slide` oriented for the contact's body 1.
    pub params: ContactParams,
    /// A fixed world direction for the primary friction direction (`None`: the collision layer
    /// picks one). The contact uses its projection on the tangent plane, or its own choice when
    /// the direction is within about 0.6° of the normal.
    pub friction_direction: Option<Vec3>,
    /// The pair's own contact strategy (`None`: the collision world's,
    /// [`crate::CollisionWorld::strategy`]).
    pub strategy: Option<crate::ContactStrategy>,
}

impl Default for MaterialTable {
    fn default() -> Self {
        Self {
            surfaces: vec![Surface::default()],
            pairs: Vec::new(),
            revision: 0,
        }
    }
}

impl MaterialTable {
    /// A table holding only material 0, with the default [`Surface`].
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a material and returns its id.
    pub fn add(&mut self, surface: Surface) -> CollisionResult<MaterialId> {
        surface.validate()?;
        self.surfaces.push(surface);
        self.revision += 1;
        Ok((self.surfaces.len() - 1) as MaterialId)
    }

    /// Replaces a material's surface.
    pub fn set_surface(&mut self, id: MaterialId, surface: Surface) -> CollisionResult<()> {
        self.check(id)?;
        surface.validate()?;
        self.surfaces[id as usize] = surface;
        self.revision += 1;
        Ok(())
    }

    /// Sets the exact contact parameters of a pair of materials (in either order), overriding
    /// the combine rules.
    pub fn set_pair(
        &mut self,
        a: MaterialId,
        b: MaterialId,
        params: ContactParams,
    ) -> CollisionResult<()> {
        self.check(a)?;
        self.check(b)?;
        self.set_pair_with_direction(a, b, params, None)
    }

    /// Sets a pair entry with a fixed world primary friction direction, for conveyor belts:
    /// `params.slide[0]` is then the speed of material `a`'s surface relative to material `b`'s
    /// along `direction` (unit), and `slide[1]` along `normal × direction`, where the normal
    /// points from `b` to `a`. Without a direction this is [`MaterialTable::set_pair`], whose
    /// slide runs along directions the collision layer picks.
    pub fn set_pair_with_direction(
        &mut self,
        a: MaterialId,
        b: MaterialId,
        params: ContactParams,
        direction: Option<Vec3>,
    ) -> CollisionResult<()> {
        self.check(a)?;
        self.check(b)?;
        params.validate()?;
        if let Some(d) = direction {
            if !(d.is_finite() && (d.length() - 1.0).abs() < 1.0e-3) {
                return Err(kea::KeaError::NotUnit {
                    arg: "direction",
                    value: format!("{d}"),
                    length: kea::math::wide(d.length()),
                }
                .into());
            }
        }
        let key = (a.min(b), a.max(b));
        // Stored for the smaller id as body 1.
        let (params, direction) = match direction {
            Some(d) if a > b => reverse(params, d),
            _ => (params, direction),
        };
        match self.pairs.binary_search_by_key(&key, |e| e.0) {
            Ok(i) => {
                let max_points = self.pairs[i].1.max_points;
                self.pairs[i].1 = PairEntry {
                    params,
                    direction,
                    max_points,
                };
            }
            Err(i) => {
                let entry = PairEntry {
                    params,
                    direction,
                    max_points: None,
                };
                self.pairs.insert(i, (key, entry));
            }
        }
        self.revision += 1;
        Ok(())
    }

    /// Gives contacts between materials `a` and `b` their own contact strategy (the guide's
    /// per-pair strategy: one point for bouncing bodies, up to four for resting ones; `None`:
    /// the collision world's again). The pair keeps its parameters (the combined surfaces'
    /// until [`MaterialTable::set_pair`]). Values outside 1–4 are clamped.
    pub fn set_pair_strategy(
        &mut self,
        a: MaterialId,
        b: MaterialId,
        strategy: Option<crate::ContactStrategy>,
    ) -> CollisionResult<()> {
        let params = self.params(a, b)?;
        let key = (a.min(b), a.max(b));
        let max_points = strategy.map(|s| s.max_points.clamp(1, kea::MAX_CONTACT_POINTS));
        match self.pairs.binary_search_by_key(&key, |e| e.0) {
            Ok(i) => self.pairs[i].1.max_points = max_points,
            Err(i) => {
                let entry = PairEntry {
                    params,
                    direction: None,
                    max_points,
                };
                self.pairs.insert(i, (key, entry));
            }
        }
        self.revision += 1;
        Ok(())
    }

    /// What a contact whose body 1 has material `body1` and body 2 material `body2` gets: the
    /// pair's parameters and fixed friction direction, oriented for that order.
    pub fn pair_contact(
        &self,
        body1: MaterialId,
        body2: MaterialId,
    ) -> CollisionResult<PairContact> {
        let params = self.params(body1, body2)?;
        let key = (body1.min(body2), body1.max(body2));
        let (direction, max_points) = match self.pairs.binary_search_by_key(&key, |e| e.0) {
            Ok(i) => (self.pairs[i].1.direction, self.pairs[i].1.max_points),
            Err(_) => (None, None),
        };
        let (params, friction_direction) = match direction {
            Some(d) if body1 > body2 => reverse(params, d),
            _ => (params, direction),
        };
        Ok(PairContact {
            params,
            friction_direction,
            strategy: max_points.map(|max_points| crate::ContactStrategy { max_points }),
        })
    }

    /// The contact parameters for a pair of materials.
    pub fn params(&self, a: MaterialId, b: MaterialId) -> CollisionResult<ContactParams> {
        self.check(a)?;
        self.check(b)?;
        let key = (a.min(b), a.max(b));
        Ok(match self.pairs.binary_search_by_key(&key, |e| e.0) {
            Ok(i) => self.pairs[i].1.params,
            Err(_) => surface_params(&self.surfaces[a as usize], &self.surfaces[b as usize]),
        })
    }

    /// A number that changes whenever the table does.
    #[must_use]
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// Checks that a material id exists.
    pub fn check(&self, id: MaterialId) -> CollisionResult<()> {
        if (id as usize) < self.surfaces.len() {
            Ok(())
        } else {
            Err(CollisionError::UnknownMaterial(id))
        }
    }
}

/// The same conveyor seen with the bodies swapped: `slide[0]` is body 1's speed relative to
/// body 2 along `t₁` and `slide[1]` along `n × t₁`. Swapping the bodies reverses the normal and
/// the relative velocity; taking `t₁ = −d` keeps `slide[0]` and `n × t₁`, so `slide[1]` flips.
fn reverse(mut params: ContactParams, d: Vec3) -> (ContactParams, Option<Vec3>) {
    params.slide[1] = -params.slide[1];
    (params, Some(-d))
}

/// The combine rules of the module documentation.
fn surface_params(a: &Surface, b: &Surface) -> ContactParams {
    let mu = (a.friction * b.friction).sqrt();
    // Static coefficients combine as the kinetic ones do, a surface without one lending its
    // single coefficient; a pair gets static friction when either surface has it.
    let friction = match (a.static_friction, b.static_friction) {
        (None, None) => FrictionModel::Coulomb { mu },
        (sa, sb) => FrictionModel::StaticKinetic {
            static_mu: (sa.unwrap_or(a.friction) * sb.unwrap_or(b.friction))
                .sqrt()
                .max(mu),
            kinetic_mu: mu,
        },
    };
    let softness = match (a.softness, b.softness) {
        (None, None) => None,
        (x, y) => Some(x.unwrap_or(0.0) + y.unwrap_or(0.0)),
    };
    ContactParams {
        contact_type: if mu > 0.0 {
            ContactType::Friction2D
        } else {
            ContactType::Frictionless
        },
        friction: [friction; 2],
        restitution: a.restitution.max(b.restitution),
        restitution_threshold: a.restitution_threshold.max(b.restitution_threshold),
        softness,
        max_adhesive_force: a.adhesion.min(b.adhesion),
        slip: [a.slip + b.slip; 2],
        slide: [0.0; 2],
    }
}

impl MaterialTable {
    /// Becomes a copy of `other`, reusing this one's buffers (`state_copy.rs`).
    pub(crate) fn copy_from(&mut self, other: &Self) {
        self.surfaces.clone_from(&other.surfaces);
        self.pairs.clone_from(&other.pairs);
        self.revision = other.revision;
    }
}
