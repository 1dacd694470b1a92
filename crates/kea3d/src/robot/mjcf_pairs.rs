//! MuJoCo's rule for the friction of a contact between two geoms, as materials of the world's
//! table: a contact has the larger of the two geoms' `condim` and the larger of their sliding
//! frictions (MuJoCo's default when neither has a `priority`), and `condim = 1` makes it
//! frictionless. Kea's own combine rule (the geometric mean) would give a body geom with
//! MuJoCo's default friction 1 on a floor of 0.5 a friction of 0.71 where MuJoCo has 1, and
//! friction to contacts MuJoCo makes frictionless (the humanoid's limbs on each other).
//!
//! Each distinct (friction, condim) of a file's geoms becomes one material, and every pair of
//! them a pair entry with the combined friction; pairs with materials from elsewhere (a floor
//! the user added) keep Kea's combine rule.

use super::spec::GeomSpec;
use crate::PhysicsWorld;
use kea::{ContactType, FrictionModel, Real};
use kea_collision::{CollisionResult, MaterialId, Surface};

/// The materials of a file's geoms, by (friction, condim).
#[derive(Debug, Default)]
pub(crate) struct PairMaterials {
    classes: Vec<(Real, u32, MaterialId)>,
}

impl PairMaterials {
    /// Adds a material for each distinct (friction, condim) of `geoms` that carry a `condim`
    /// (MJCF's) and sets the pair entries between all of them.
    pub(crate) fn add<'a>(
        world: &mut PhysicsWorld,
        geoms: impl Iterator<Item = &'a GeomSpec>,
    ) -> CollisionResult<Self> {
        let mut classes: Vec<(Real, u32, MaterialId)> = Vec::new();
        let materials = &mut world.collision_mut().materials;
        for g in geoms {
            let (Some(condim), Some(mu)) = (g.condim, g.friction) else {
                continue;
            };
            if classes.iter().any(|&(m, c, _)| m == mu && c == condim) {
                continue;
            }
            let id = materials.add(Surface {
                friction: mu,
                ..Surface::default()
            })?;
            classes.push((mu, condim, id));
        }
        for (i, &(mu_a, condim_a, a)) in classes.iter().enumerate() {
            for &(mu_b, condim_b, b) in &classes[i..] {
                let mut params = materials.params(a, b)?;
                if condim_a.max(condim_b) == 1 {
                    params.contact_type = ContactType::Frictionless;
                    params.friction = [FrictionModel::Coulomb { mu: 0.0 }; 2];
                } else {
                    params.contact_type = ContactType::Friction2D;
                    params.friction = [FrictionModel::Coulomb { mu: mu_a.max(mu_b) }; 2];
                }
                materials.set_pair(a, b, params)?;
            }
        }
        Ok(Self { classes })
    }

    /// The material of a geom of the file (`None`: it keeps the collider's own surface).
    pub(crate) fn of(&self, g: &GeomSpec) -> Option<MaterialId> {
        let (condim, mu) = (g.condim?, g.friction?);
        self.classes
            .iter()
            .find(|&&(m, c, _)| m == mu && c == condim)
            .map(|&(_, _, id)| id)
    }
}
