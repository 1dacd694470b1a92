//! Hybrid routing: which path solves each island.
//!
//! By structure first: an island of contacts only (a pile, a box on the floor, balls in a box)
//! goes to the iterative path, whose contact solver is built for exactly that, unless it is
//! small and its contacts join bodies of very different masses (a 1 kg box under a 100 kg
//! one): the soft step crushes the light body, a direct solve holds it. A stack (an island of
//! contacts only whose contacts join its bodies without a loop, a column of boxes, and at
//! least `stack_bodies` of them) goes exact too: the soft step's contacts yield under every
//! box they carry, so a column of 40 sags 44 cm and a taller one falls, and a stack's system
//! factorises without fill, so the exact path solves it in time linear in its boxes. An
//! island with joints only goes to the exact solver when small, where pivoting is cheap and
//! its answer is the reference, and is split when big: its joints solved directly (the exact
//! path's sparse factorisation, time linear in the rows of a tree) inside the iterative path's
//! substeps, which follow fast rotation better than one solve a step. An island of joints and
//! contacts (a ragdoll on the ground, a vehicle on rubble) is split too, its contacts going to
//! the contact solver. An island that was iterative or split last step returns to exact only
//! once it is clearly small again (below the thresholds times `hysteresis`), so an island near
//! the threshold does not flip every step. A body can ask for exact solving of its island's
//! joints (vehicles, ragdolls: exact when the island has no contact, split when it has), and
//! the world can force any path.
//!
//! Whatever the mode, an island is then turned away from a path that cannot hold it, and the
//! step counts it as a warning ([`super::SolverStats::rerouted_islands`]): contacts whose
//! dense exact system would pass [`DENSE_EXACT_MAX_ROWS`] (a step would stall), and, forced
//! exact or iterative, a light chain carrying a body `mass_ratio` times heavier (it tears) and
//! an island of joints closing loops (forced iterative: any loop, Gauss–Seidel leaves a
//! four-bar open by 1.8 mm; forced exact: more than four, one linearisation a step leaves a
//! net open by 11 cm), all solved split.

use super::island::Islands;
use super::{ConstraintBlock, SolverBody, SolverContact};
use crate::error::{KeaError, KeaResult};
use crate::math::{Real, Vec3};

/// Which solver handled an island.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum SolverPath {
    /// Not solved (no constraint) this step.
    #[default]
    None,
    /// The exact pivoting solver.
    Exact,
    /// The iterative substepping solver.
    Iterative,
    /// Split: the island's joints solved directly (the exact path's sparse factorisation) inside
    /// the iterative path's substeps, its contacts by the contact solver around them.
    Split,
}

/// How islands are routed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum SolverMode {
    /// Small islands exact, big ones iterative (the default).
    #[default]
    Hybrid,
    /// Every island exact (slow for big islands: rows² to rows³).
    Exact,
    /// Every island iterative.
    Iterative,
    /// Every island with joints split (joints direct inside the substeps, contacts
    /// iterative); islands of contacts only iterative.
    Split,
}

/// Routing settings.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Routing {
    /// The mode. Default hybrid.
    pub mode: SolverMode,
    /// Largest island with joints, in rows (three per contact point), that the hybrid mode sends
    /// to the exact path. Default 64.
    pub max_exact_rows: u32,
    /// Largest island, in bodies, that the hybrid mode sends to the exact path. Default 32.
    pub max_exact_bodies: u32,
    /// An island that was iterative goes back to exact only below `hysteresis ×` the limits,
    /// in (0, 1]. Default 0.75.
    pub hysteresis: Real,
    /// An island of contacts only goes to the exact path when a contact joins two bodies whose
    /// masses differ by more than this ratio, and the island has at most `max_exact_bodies`
    /// bodies and `4 × max_exact_rows` rows; an island of joints only goes to split islands
    /// (direct solves in the substeps) when a joint does. At least 1; default 10; infinity
    /// never.
    pub mass_ratio: Real,
    /// An island of contacts only whose bodies rest on one another (their contacts face along
    /// gravity, within 45°) and whose contacts join them without a loop (a column of boxes: as
    /// many pairs of its bodies in contact as it has bodies less one) goes to
    /// the exact path once it has at least this many bodies, whatever its size: its system
    /// factorises without fill, so its cost is linear in the bodies (a column of 40 boxes
    /// sags 7 mm there at about 0.2 ms a step; the iterative path's sags 44 cm, and columns of
    /// 60 fall). At least 1; default 6; `u32::MAX` never.
    pub stack_bodies: u32,
    /// Largest tree, in coordinates (a ball joint counts three), that the hybrid mode steps in
    /// reduced coordinates: a tree of hinges, prismatic joints and ball joints without
    /// limits hanging from the static world (or a disabled body) by one
    /// joint, touched by nothing else, stepped in its joint coordinates (exact for the tree,
    /// no joint error at all; `kea::articulation`) instead of as bodies held by rows. Its
    /// stops must be hard without restitution, its servos uncapped, its joints unbreakable
    /// and its bodies undamped; anything else, or a contact on a link (unless
    /// [`crate::WorldSettings::reduced_contacts`] takes it into joint space), sends the tree
    /// to the other paths for that step. Default 32; 0 never. The forced modes never reduce.
    pub max_reduced_links: u32,
}

impl Default for Routing {
    fn default() -> Self {
        Self {
            mode: SolverMode::Hybrid,
            max_exact_rows: 64,
            max_exact_bodies: 32,
            hysteresis: 0.75,
            mass_ratio: 10.0,
            stack_bodies: 6,
            max_reduced_links: 32,
        }
    }
}

impl Routing {
    /// Checks the thresholds.
    pub fn validate(&self) -> KeaResult<()> {
        if !(self.hysteresis.is_finite() && self.hysteresis > 0.0 && self.hysteresis <= 1.0) {
            return Err(KeaError::OutOfRange {
                arg: "hysteresis",
                value: format!("{}", self.hysteresis),
                expected: "must be in (0, 1]",
            });
        }
        if self.mass_ratio.is_nan() || self.mass_ratio < 1.0 {
            return Err(KeaError::OutOfRange {
                arg: "mass_ratio",
                value: format!("{}", self.mass_ratio),
                expected: "must be at least 1 (infinity: never)",
            });
        }
        if self.stack_bodies == 0 {
            return Err(KeaError::OutOfRange {
                arg: "stack_bodies",
                value: "0".into(),
                expected: "must be at least 1 (u32::MAX: never)",
            });
        }
        Ok(())
    }
}

/// What one island was and how it was solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct IslandReport {
    /// The path that solved it.
    pub path: SolverPath,
    /// Bodies in the island.
    pub bodies: u32,
    /// Rows in the island.
    pub rows: u32,
    /// LCP factorisations (exact) or Gauss-Seidel sweeps (iterative).
    pub iterations: u32,
    /// Pivots (exact path only).
    pub pivots: u32,
}

/// Most rows of an island with contacts that the exact path's dense LCP takes, whatever the
/// mode: its factorisations cost rows³ (one of 256 rows takes about 2 ms here, and a hard
/// step may need tens of them), so a bigger island of contacts with loops, or of contacts and
/// joints, goes to the iterative path (split when it holds joints) and the step says so
/// ([`super::SolverStats::rerouted_islands`]). Stacks (contacts only, no loop) are not held to
/// it: their block-sparse system costs time linear in their rows.
pub const DENSE_EXACT_MAX_ROWS: u32 = 256;

/// Constraints of an island compared pairwise for repeated pairs when its loops are counted.
const PAIRS_COMPARED: usize = 64;

/// Most independent joint loops an island forced exact keeps on the exact path (a four-bar
/// holds to 0.4 mm with one linearisation a step; a net does not).
const MOST_LOOPS_IN_ONE_STEP: u32 = 4;

/// The path chosen for an island, and whether it was turned away from the path its mode
/// asked for: the exact path's dense LCP past [`DENSE_EXACT_MAX_ROWS`], or a light chain
/// carrying a body more than [`Routing::mass_ratio`] times heavier forced exact or iterative
/// (solved split).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Choice {
    pub(crate) path: SolverPath,
    pub(crate) rerouted: bool,
}

/// One island as the routing reads it: its blocks and contacts, over the step's arrays.
#[derive(Clone, Copy)]
pub(crate) struct IslandView<'a> {
    pub(crate) islands: &'a Islands,
    pub(crate) k: usize,
    pub(crate) blocks: &'a [ConstraintBlock],
    pub(crate) contacts: &'a [SolverContact],
    pub(crate) bodies: &'a [SolverBody],
}

impl IslandView<'_> {
    /// The island's joint blocks (indices into `blocks`).
    fn joints(&self) -> &[u32] {
        self.islands.blocks(self.k)
    }

    /// The island's contacts (indices into `contacts`).
    fn contact_list(&self) -> &[u32] {
        self.islands.contacts(self.k)
    }

    /// Bodies in the island.
    fn body_count(&self) -> u32 {
        self.islands.island_bodies[self.k]
    }

    /// Rows: its joints' and three per contact point.
    pub(crate) fn rows(&self) -> u32 {
        let contact_rows: u32 = self
            .contact_list()
            .iter()
            .map(|&c| 3 * self.contacts[c as usize].contact.points().len() as u32)
            .sum();
        self.joints()
            .iter()
            .map(|&b| self.blocks[b as usize].row_count)
            .sum::<u32>()
            + contact_rows
    }

    /// Independent loops of a joint-only island's joint graph (pairs joined less bodies, plus
    /// one, the world and every fixed body counted as one body): 0 for a tree, 1 for a
    /// four-bar, 82 for a 10×10 net hung by two corners. A second constraint on a pair already
    /// joined (a redundant joint) is no loop; it is looked for among the first
    /// [`PAIRS_COMPARED`] constraints only (an island with more is a loop of many anyway or a
    /// tree with duplicates, rare).
    fn joint_loops(&self) -> u32 {
        let ground = |x: &Option<u32>| x.is_none_or(|x| self.bodies[x as usize].is_fixed());
        let pair = |b: u32| {
            let [x, y] = self.blocks[b as usize].bodies;
            let key = |x: Option<u32>| {
                if ground(&x) {
                    u32::MAX
                } else {
                    x.unwrap_or(u32::MAX)
                }
            };
            let (x, y) = (key(x), key(y));
            (x.min(y), x.max(y))
        };
        let joints = self.joints();
        let grounded = joints
            .iter()
            .any(|&b| self.blocks[b as usize].bodies.iter().any(ground));
        let compared = joints.len().min(PAIRS_COMPARED);
        let repeats = (1..compared)
            .filter(|&i| joints[..i].iter().any(|&o| pair(o) == pair(joints[i])))
            .count();
        let pairs = (joints.len() - repeats) as u32;
        (pairs + 1).saturating_sub(self.body_count() + u32::from(grounded))
    }

    /// Whether both of `pair` are bodies that move.
    fn moving(&self, pair: &[Option<u32>; 2]) -> bool {
        pair.iter()
            .all(|b| b.is_some_and(|b| !self.bodies[b as usize].is_fixed()))
    }

    /// The ratio of the masses of `a` and `b`, larger over smaller (1 when either cannot
    /// move).
    fn pair_ratio(&self, a: u32, b: u32) -> Real {
        let (ia, ib) = (
            self.bodies[a as usize].inv_mass,
            self.bodies[b as usize].inv_mass,
        );
        if ia > 0.0 && ib > 0.0 {
            (ia / ib).max(ib / ia)
        } else {
            1.0
        }
    }

    /// The largest mass ratio across one of `pairs` (a contact's or a joint's).
    fn mass_ratio(&self, pairs: impl Iterator<Item = [Option<u32>; 2]>) -> Real {
        pairs
            .filter_map(|pair| match pair {
                [Some(a), Some(b)] => Some(self.pair_ratio(a, b)),
                _ => None,
            })
            .fold(1.0, Real::max)
    }

    /// Whether the island's bodies rest on one another (every contact between two of them
    /// faces along gravity, within 45°) and its contacts join them without a loop (as many
    /// pairs of moving bodies in contact as it has bodies less one: an island is connected;
    /// contacts that follow one another on one pair count once), with few contacts in all (at
    /// most three a body for each point a manifold may have).
    fn is_stack(&self, gravity: Vec3) -> bool {
        let up = -gravity.normalize_or_zero();
        // Bodies resting on one another: a row of boxes side by side, whose sliding moves the
        // Coulomb bounds under the pivoting, is left to the contact solver.
        let resting = self.contact_list().iter().all(|&c| {
            let sc = &self.contacts[c as usize];
            !self.moving(&sc.bodies) || sc.contact.normal().dot(up).abs() >= STACK_NORMAL_COS
        });
        if !resting {
            return false;
        }
        // Contacts between two moving bodies, a run of them on one pair (a manifold per
        // corner, or per part of a compound) counted once.
        let mut last = None;
        let joining = self
            .contact_list()
            .iter()
            .map(|&c| self.contacts[c as usize].bodies)
            .filter(|p| self.moving(p))
            .filter(|&p| last.replace(p) != Some(p))
            .count();
        let n = self.body_count() as usize;
        joining + 1 == n
            && self.contact_list().len() <= 3 * n * crate::constraint::MAX_CONTACT_POINTS
    }

    /// Whether one of the island's joints joins a body to one more than `ratio` times heavier
    /// while the light one is held by another joint too: a link of a light chain carrying a
    /// heavy end. (A light body on one joint, a car's wheel on its 50 times heavier chassis,
    /// is not: one linearisation a step holds it.)
    fn carries_heavy_end(&self, ratio: Real) -> bool {
        let joints = self.joints();
        joints.iter().any(|&j| {
            let [Some(a), Some(b)] = self.blocks[j as usize].bodies else {
                return false;
            };
            if self.pair_ratio(a, b) <= ratio {
                return false;
            }
            let light = if self.bodies[a as usize].inv_mass > self.bodies[b as usize].inv_mass {
                a
            } else {
                b
            };
            joints
                .iter()
                .filter(|&&o| self.blocks[o as usize].bodies.contains(&Some(light)))
                .nth(1)
                .is_some()
        })
    }
}

/// The least cosine between gravity and the normal of a contact between two bodies of a stack
/// (45°).
const STACK_NORMAL_COS: Real = 0.7;

/// Chooses the path of an island: [`choose_by_structure`], then turned away from a path that
/// cannot hold the island (see [`Choice`]).
pub(crate) fn choose(routing: &Routing, island: &IslandView<'_>, gravity: Vec3) -> Choice {
    let path = choose_by_structure(routing, island, gravity);
    let joints = !island.joints().is_empty();
    let forced_one_way = matches!(routing.mode, SolverMode::Exact | SolverMode::Iterative);
    // A light chain carrying a heavy end: one linearisation a step tears it by metres,
    // Gauss-Seidel opens it by decimetres and blows up hanging; the direct solves inside the
    // substeps hold it to a fraction of a millimetre.
    if forced_one_way
        && path != SolverPath::Split
        && joints
        && island.carries_heavy_end(routing.mass_ratio)
    {
        return Choice {
            path: SolverPath::Split,
            rerouted: true,
        };
    }
    // Loops: Gauss-Seidel leaves a four-bar open by 1.8 mm and a net by 11 mm, one
    // linearisation a step a net by 11 cm; the direct solves in the substeps, with their
    // compliance for loops, hold both to hundredths of a millimetre.
    if forced_one_way && path != SolverPath::Split && joints && island.contact_list().is_empty() {
        let loops = island.joint_loops();
        let most = match routing.mode {
            SolverMode::Iterative => 0,
            _ => MOST_LOOPS_IN_ONE_STEP,
        };
        if loops > most {
            return Choice {
                path: SolverPath::Split,
                rerouted: true,
            };
        }
    }
    let dense = path == SolverPath::Exact
        && !island.contact_list().is_empty()
        && (joints || !island.is_stack(gravity));
    if dense && island.rows() > DENSE_EXACT_MAX_ROWS {
        let path = if joints {
            SolverPath::Split
        } else {
            SolverPath::Iterative
        };
        return Choice {
            path,
            rerouted: true,
        };
    }
    Choice {
        path,
        rerouted: false,
    }
}

/// Chooses the path of an island by its structure (module docs).
fn choose_by_structure(routing: &Routing, island: &IslandView<'_>, gravity: Vec3) -> SolverPath {
    let joints = island.joints();
    match routing.mode {
        SolverMode::Exact => return SolverPath::Exact,
        SolverMode::Iterative => return SolverPath::Iterative,
        SolverMode::Split => {
            return if joints.is_empty() {
                SolverPath::Iterative
            } else {
                SolverPath::Split
            }
        }
        SolverMode::Hybrid => {}
    }
    let (blocks, contacts, bodies) = (island.blocks, island.contacts, island.bodies);
    let k = island.k;
    let rows = island.rows();
    let n_bodies = island.body_count();
    let mut was_iterative = false;
    let mut prefer_exact = false;
    let mut fast_spin = false;
    let joint_pairs = || joints.iter().map(|&b| blocks[b as usize].bodies);
    let contact_pairs = || {
        island
            .contact_list()
            .iter()
            .map(|&c| contacts[c as usize].bodies)
    };
    for pair in joint_pairs().chain(contact_pairs()) {
        for i in pair.iter().flatten() {
            let body = &bodies[*i as usize];
            if island.islands.body_island[*i as usize] == k as u32 {
                was_iterative |=
                    matches!(body.last_path, SolverPath::Iterative | SolverPath::Split);
                prefer_exact |= body.prefer_exact;
                fast_spin |= body.fast_spin_axis.is_some() && !body.is_fixed();
            }
        }
    }
    let scale = if was_iterative {
        routing.hysteresis
    } else {
        1.0
    };
    let fits = |n: u32, max: u32| n as Real <= max as Real * scale;
    if joints.is_empty() {
        // Contacts only: the contact solver's work, unless masses differ too much for it.
        let small =
            fits(rows, 4 * routing.max_exact_rows) && fits(n_bodies, routing.max_exact_bodies);
        let uneven = small && island.mass_ratio(contact_pairs()) > routing.mass_ratio;
        let stack = n_bodies >= routing.stack_bodies && island.is_stack(gravity);
        return if uneven || stack {
            SolverPath::Exact
        } else {
            SolverPath::Iterative
        };
    }
    if !island.contact_list().is_empty() {
        // Joints among contacts (a ragdoll on the ground, a vehicle on rubble): the joints
        // solved directly inside the substeps, the contacts by the contact solver.
        return SolverPath::Split;
    }
    // Joints only: small or asked for, one exact solve; big, holding a fast-spinning body or
    // joining masses more than `mass_ratio` apart, direct solves in the substeps (a tree
    // costs its rows either way; the substeps' fresh rows follow fast rotation: a 300 rad/s
    // wheel on a turning chassis keeps its axle to 0.2 µrad there, 3 mrad with one
    // linearisation per step; a light chain swinging a 100× heavier end stays closed to
    // 0.01 mm there, and tears by metres with one).
    let uneven = island.mass_ratio(joint_pairs()) > routing.mass_ratio;
    if prefer_exact
        || (!fast_spin
            && !uneven
            && fits(rows, routing.max_exact_rows)
            && fits(n_bodies, routing.max_exact_bodies))
    {
        SolverPath::Exact
    } else {
        SolverPath::Split
    }
}
