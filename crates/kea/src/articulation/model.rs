//! A tree's model and its drives, apart: the model/data split of the articulated path.
//!
//! A tree's links are three things. Their geometry and inertia (parent, joint kind, axis,
//! anchor, mass, centre, inertia) and what follows from them (parents, ancestry, motion
//! subspaces, charts) stay as they are while the tree keeps its joints: that is the
//! [`TreeModel`], held behind an `Arc` so that many trees of the same model — a batch's
//! worlds, a world and its clone, a worker and the worlds it steps — hold one copy, which
//! stays in the cache while a worker steps world after world. Their drives (armature,
//! damping, stops, motor, friction, springs, servos: [`LinkDrive`]) are each tree's own: a
//! world writes them from its joints at every step, and each world of a batch drives its
//! robot its own way. Their origins (each link's frame in its parent's at `q = 0`) are each
//! tree's own too: a world measures them where its bodies are when it builds the tree (a
//! floating root's place and the centre of its turn's chart, each joint's turn), so a
//! batch's robots, reset to different poses, and a floating robot built again as its chart
//! is centred again, still share one model.
//!
//! Sharing changes no number: a tree shares a model only when its geometry is the same,
//! bit for bit. A shared model that must change is copied first (`Arc::make_mut`), which
//! allocates; that happens only when a tree is built again with other geometry, never in a
//! warm step of a kept tree.

use super::{ball_charts, TreeLink};
use crate::solver::sparse::joint_space::Ancestry;
use glam::DVec3;
use std::sync::{Arc, LazyLock};

/// What stays constant while a tree keeps its joints: its links' geometry and inertia
/// (their drives and origins zeroed: a tree reads those from its own [`LinkDrive`]s and
/// origins), and what the recursions read from them.
#[derive(Debug, Clone, PartialEq, Default)]
pub(super) struct TreeModel {
    pub(super) links: Vec<TreeLink>,
    /// Each link's parent and joint motion subspace (its link's coordinates): the
    /// factorisations and recursions walk them compactly.
    pub(super) parents: Vec<Option<usize>>,
    /// Each link's ancestors, flat, for the joint-space factor's loops.
    pub(super) ancestry: Ancestry,
    pub(super) motion: Vec<[DVec3; 2]>,
    /// The first link of each ball joint's (or floating root's) three hinges
    /// (`ball_charts.rs`).
    pub(super) charts: Vec<usize>,
}

/// The model of a tree with no link, shared by every empty tree: making one allocates
/// nothing (a world takes a kept tree out of its list with `mem::take` while it builds it).
static EMPTY: LazyLock<Arc<TreeModel>> = LazyLock::new(|| Arc::new(TreeModel::default()));

impl TreeModel {
    /// The shared model of an empty tree.
    pub(super) fn empty() -> Arc<TreeModel> {
        Arc::clone(&EMPTY)
    }

    /// Whether `links`' geometry is this model's, bit for bit (their drives and origins
    /// aside), charts included (a chart's last two links sit at their parents' frames).
    pub(super) fn has_geometry_of(&self, links: &[TreeLink]) -> bool {
        self.links.len() == links.len()
            && self
                .links
                .iter()
                .zip(links)
                .all(|(m, l)| *m == l.geometry())
            && ball_charts::charts(links).eq(self.charts.iter().copied())
    }

    /// Becomes the model of `links` (each one's parent before it), reusing its buffers.
    pub(super) fn refill(&mut self, links: &[TreeLink]) {
        self.links.clear();
        self.links.extend(links.iter().map(TreeLink::geometry));
        self.parents.clear();
        self.parents.extend(self.links.iter().map(|l| l.parent));
        self.ancestry.refill(&self.parents);
        self.charts.clear();
        self.charts.extend(ball_charts::charts(links));
        self.motion.clear();
        self.motion
            .extend(self.links.iter().map(TreeLink::subspace));
    }
}

/// A link's joint dynamics, stops and drives: what a world writes from the joint at every
/// step (see [`TreeLink`] for each field's meaning).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LinkDrive {
    pub(crate) armature: f64,
    pub(crate) damping: f64,
    pub(crate) limits: Option<(f64, f64)>,
    pub(crate) motor: Option<(f64, f64)>,
    pub(crate) friction: f64,
    pub(crate) soft_limit: Option<crate::SoftLimit>,
    pub(crate) servo: Option<(f64, f64, f64, f64)>,
    pub(crate) spring: Option<(f64, f64)>,
    pub(crate) stop_recovery_speed: f64,
}

impl TreeLink {
    /// Its drives.
    pub(super) fn drive(&self) -> LinkDrive {
        LinkDrive {
            armature: self.armature,
            damping: self.damping,
            limits: self.limits,
            motor: self.motor,
            friction: self.friction,
            soft_limit: self.soft_limit,
            servo: self.servo,
            spring: self.spring,
            stop_recovery_speed: self.stop_recovery_speed,
        }
    }

    /// Its geometry and inertia, with the drives and origin of [`TreeLink::default`] (none,
    /// and the parent's frame).
    pub(super) fn geometry(&self) -> TreeLink {
        let none = TreeLink::default();
        TreeLink {
            origin: none.origin,
            armature: none.armature,
            damping: none.damping,
            limits: none.limits,
            motor: none.motor,
            friction: none.friction,
            soft_limit: none.soft_limit,
            servo: none.servo,
            spring: none.spring,
            stop_recovery_speed: none.stop_recovery_speed,
            ..*self
        }
    }
}

/// Models a world's trees were built with lately, for the next tree built with the same
/// geometry to share (a batch's worker builds each world's arm once: every world then holds
/// the same model). A few are kept, the oldest replaced first.
#[derive(Debug, Clone, Default)]
pub(crate) struct SharedModels {
    models: Vec<Arc<TreeModel>>,
    next: usize,
}

/// Models kept for sharing.
const SHARED_MODELS: usize = 4;

impl SharedModels {
    /// Gives `tree` a kept model of its geometry if there is one, or keeps its model for the
    /// trees built after it.
    pub(crate) fn share(&mut self, tree: &mut super::ArticulatedTree) {
        // A tree built again on its kept model (a floating root's chart centred again) finds
        // it by address, with no comparison.
        if tree.is_empty() || self.models.iter().any(|m| Arc::ptr_eq(m, &tree.model)) {
            return;
        }
        if let Some(m) = self.models.iter().find(|m| ***m == *tree.model) {
            tree.model = Arc::clone(m);
            return;
        }
        let model = Arc::clone(&tree.model);
        if self.models.len() < SHARED_MODELS {
            self.models.push(model);
        } else {
            self.models[self.next] = model;
            self.next = (self.next + 1) % SHARED_MODELS;
        }
    }
}
