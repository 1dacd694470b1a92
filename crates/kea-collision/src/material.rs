//! Materials: every collider has a material id; a table gives the contact parameters of each
//! pair of materials (the guide: restitution is a property of the two materials together), and
//! combine rules fill in pairs that have no entry.
//!
//! Combine rules for a pair with no entry, from the two [`Surface`]s:
//! - friction μ: geometric mean `√(μ₁μ₂)` (a frictionless surface makes the pair frictionless);
//! - restitution: the larger (a bouncy ball bounces on a dull floor); threshold: the larger;
//! - softness: the sum (two springs in series add their compliances); `None` if both are rigid;
//! - slip: the sum; adhesion: the smaller (both surfaces must be sticky).

use crate::error::{CollisionError, CollisionResult};
use kea::{ContactParams, ContactType, FrictionModel, Real};

/// Index of a material in a [`MaterialTable`]. Material 0 always exists.
pub type MaterialId = u32;

/// The surface properties of one material, combined with another's by the rules above.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    /// Coulomb friction coefficient, ≥ 0.
    pub friction: Real,
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
        Ok(())
    }
}

/// Materials and their pair table.
#[derive(Debug, Clone)]
pub struct MaterialTable {
    surfaces: Vec<Surface>,
    /// Explicit pair entries, keyed by (smaller id, larger id), sorted for binary search.
    pairs: Vec<((MaterialId, MaterialId), ContactParams)>,
}

impl Default for MaterialTable {
    fn default() -> Self {
        Self {
            surfaces: vec![Surface::default()],
            pairs: Vec::new(),
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
        Ok((self.surfaces.len() - 1) as MaterialId)
    }

    /// Replaces a material's surface.
    pub fn set_surface(&mut self, id: MaterialId, surface: Surface) -> CollisionResult<()> {
        self.check(id)?;
        surface.validate()?;
        self.surfaces[id as usize] = surface;
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
        params.validate()?;
        let key = (a.min(b), a.max(b));
        match self.pairs.binary_search_by_key(&key, |e| e.0) {
            Ok(i) => self.pairs[i].1 = params,
            Err(i) => self.pairs.insert(i, (key, params)),
        }
        Ok(())
    }

    /// The contact parameters for a pair of materials.
    pub fn params(&self, a: MaterialId, b: MaterialId) -> CollisionResult<ContactParams> {
        self.check(a)?;
        self.check(b)?;
        let key = (a.min(b), a.max(b));
        Ok(match self.pairs.binary_search_by_key(&key, |e| e.0) {
            Ok(i) => self.pairs[i].1,
            Err(_) => surface_params(&self.surfaces[a as usize], &self.surfaces[b as usize]),
        })
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

/// The combine rules of the module documentation.
fn surface_params(a: &Surface, b: &Surface) -> ContactParams {
    let mu = (a.friction * b.friction).sqrt();
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
        friction: [FrictionModel::Coulomb { mu }; 2],
        restitution: a.restitution.max(b.restitution),
        restitution_threshold: a.restitution_threshold.max(b.restitution_threshold),
        softness,
        max_adhesive_force: a.adhesion.min(b.adhesion),
        slip: [a.slip + b.slip; 2],
        slide: [0.0; 2],
    }
}
