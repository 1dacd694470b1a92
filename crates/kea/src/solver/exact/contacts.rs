//! Islands with contacts on the exact path: each contact writes its rows (a normal and its
//! friction rows per point) beside a copy of the island's joint rows, the whole is solved as one
//! system, and the forces go back to the joints and to each contact point (which keeps them as
//! the next step's warm start).

use super::super::integrate::BodyScratch;
use super::super::{reserve, ConstraintBlock, Reaction, SolverBody, SolverContact, SolverStats};
use super::{ExactWorkspace, IslandInputs};
use crate::constraint::{
    Contact, PointForce, Row, RowBody, RowContext, RowWriter, Spring, MAX_CONTACT_POINTS,
};
use crate::math::Real;
use crate::solver::StepArrays;
use crate::solver::EXACT_CONTACT_STIFFENING;

/// An island's joint rows and its contacts' rows as one system: the blocks (joints first, in
/// island order, then contacts), their rows, warm-start guesses, forces and reactions.
#[derive(Debug, Default, Clone)]
pub(crate) struct MixedIsland {
    rows: Vec<Row>,
    blocks: Vec<ConstraintBlock>,
    order: Vec<u32>,
    lambda: Vec<Real>,
    guess: Vec<Real>,
    reactions: Vec<[Reaction; 2]>,
}

impl MixedIsland {
    /// Reserves room for islands of `n` rows.
    pub(crate) fn reserve(&mut self, n: usize) {
        reserve(&mut self.rows, n);
        reserve(&mut self.blocks, n);
        reserve(&mut self.order, n);
        reserve(&mut self.lambda, n);
        reserve(&mut self.guess, n);
        reserve(&mut self.reactions, n);
    }

    /// Bytes held.
    pub(crate) fn bytes(&self) -> usize {
        self.rows.capacity() * std::mem::size_of::<Row>()
            + self.blocks.capacity() * std::mem::size_of::<ConstraintBlock>()
            + self.order.capacity() * 4
            + (self.lambda.capacity() + self.guess.capacity()) * std::mem::size_of::<Real>()
            + self.reactions.capacity() * std::mem::size_of::<[Reaction; 2]>()
    }

    /// Copies the island's joint blocks, their rows and their last forces.
    fn gather_joints(
        &mut self,
        island_blocks: &[u32],
        blocks: &[ConstraintBlock],
        rows: &[Row],
        lambda: &[Real],
    ) {
        self.rows.clear();
        self.blocks.clear();
        self.guess.clear();
        for &k in island_blocks {
            let blk = blocks[k as usize];
            let range = blk.first_row as usize..(blk.first_row + blk.row_count) as usize;
            self.blocks.push(ConstraintBlock {
                first_row: self.rows.len() as u32,
                ..blk
            });
            self.rows.extend_from_slice(&rows[range.clone()]);
            self.guess.extend_from_slice(&lambda[range]);
        }
    }

    /// Writes each contact's rows, warm started from its points' last forces.
    fn add_contacts(
        &mut self,
        island_contacts: &[u32],
        contacts: &[SolverContact],
        ctx: impl Fn(&SolverContact) -> RowContext,
    ) {
        for &c in island_contacts {
            let sc = &contacts[c as usize];
            let first = self.rows.len();
            sc.contact
                .write_rows(&ctx(sc), &mut RowWriter::new(&mut self.rows));
            warm_contact_rows(&sc.contact, &self.rows[first..], &mut self.guess);
            self.blocks.push(ConstraintBlock {
                bodies: sc.bodies,
                first_row: first as u32,
                row_count: (self.rows.len() - first) as u32,
            });
        }
        self.order.clear();
        self.order.extend(0..self.blocks.len() as u32);
        self.lambda.clear();
        self.lambda.extend_from_slice(&self.guess);
        self.reactions.clear();
        self.reactions
            .resize(self.blocks.len(), [Reaction::default(); 2]);
    }

    /// The joints' forces and reactions back in the step's arrays, and each contact's point
    /// forces.
    fn write_back(
        &self,
        (island_blocks, island_contacts): (&[u32], &[u32]),
        blocks: &[ConstraintBlock],
        out: (&mut [Real], &mut [[Reaction; 2]]),
        contacts: &mut [SolverContact],
    ) {
        let (lambda, reactions) = out;
        for (i, &k) in island_blocks.iter().enumerate() {
            let blk = &blocks[k as usize];
            let from = self.blocks[i].first_row as usize;
            let n = blk.row_count as usize;
            lambda[blk.first_row as usize..blk.first_row as usize + n]
                .copy_from_slice(&self.lambda[from..from + n]);
            reactions[k as usize] = self.reactions[i];
        }
        for (i, &c) in island_contacts.iter().enumerate() {
            let blk = &self.blocks[island_blocks.len() + i];
            let range = blk.first_row as usize..(blk.first_row + blk.row_count) as usize;
            let (rows, lambda) = (&self.rows[range.clone()], &self.lambda[range]);
            store_point_forces(&mut contacts[c as usize].contact, rows, lambda);
        }
    }
}

impl ExactWorkspace {
    /// Solves an island of joint blocks and contacts: the contacts write their rows (three
    /// per point) next to a copy of the joints' rows, the whole is solved as one LCP, and the
    /// forces go back to the joints' λ and reactions and to each contact point. Returns false,
    /// having written nothing, for a stack its pivoting did not settle.
    pub(crate) fn solve_island_with_contacts(
        &mut self,
        (island_blocks, island_contacts): (&[u32], &[u32]),
        step: &mut StepArrays<'_>,
        scratch: &mut BodyScratch,
        stats: &mut SolverStats,
    ) -> bool {
        let (blocks, rows, bodies, params) = (step.blocks, step.rows, &*step.bodies, step.params);
        let input = IslandInputs {
            blocks,
            rows,
            bodies,
            params,
        };
        if island_contacts.is_empty() {
            let out = (&mut *step.lambda, &mut *step.reactions);
            return self.solve_island(island_blocks, input, scratch, out, stats);
        }
        let mut mixed = std::mem::take(&mut self.mixed);
        mixed.gather_joints(island_blocks, blocks, rows, step.lambda);
        // A pile's contacts run stiff (see EXACT_CONTACT_STIFFENING); beside joints they keep
        // the world's spring, the balance the joints' own softness was set against.
        let contact_spring = if island_blocks.is_empty() {
            exact_contact_spring(params.contact_spring)
        } else {
            params.contact_spring
        };
        let ctx = |sc: &SolverContact| RowContext {
            bodies: sc.bodies.map(|b| row_body(b, bodies, scratch)),
            dt: params.dt,
            epsilon: params.epsilon,
            gamma: params.gamma,
            contact_spring,
        };
        mixed.add_contacts(island_contacts, step.contacts, ctx);
        self.with_contacts = true;
        self.contact_rows_from = mixed.blocks.get(island_blocks.len()).map(|b| b.first_row);
        let MixedIsland {
            rows: mrows,
            blocks: mblocks,
            order,
            lambda: mlambda,
            reactions: mreactions,
            ..
        } = &mut mixed;
        let input = IslandInputs {
            blocks: mblocks,
            rows: mrows,
            bodies,
            params,
        };
        let solved = self.solve_island(order, input, scratch, (mlambda, mreactions), stats);
        self.with_contacts = false;
        self.contact_rows_from = None;
        if solved {
            let island = (island_blocks, island_contacts);
            let out = (&mut *step.lambda, &mut *step.reactions);
            mixed.write_back(island, blocks, out, step.contacts);
        }
        self.mixed = mixed;
        solved
    }
}

/// The row-writing view of solver body `b` (`None`: the static world).
pub(crate) fn row_body(b: Option<u32>, bodies: &[SolverBody], scratch: &BodyScratch) -> RowBody {
    let Some(b) = b else {
        return RowBody::STATIC;
    };
    let body = &bodies[b as usize];
    RowBody {
        position: body.position,
        orientation: body.orientation,
        linear_velocity: body.linear_velocity,
        angular_velocity: body.angular_velocity,
        free_linear_velocity: scratch.free_linear[b as usize],
        free_angular_velocity: scratch.free_angular[b as usize],
        dynamic: !body.is_fixed(),
        fast_spin_axis: body.fast_spin_axis.map(|a| body.orientation * a),
    }
}

/// Each point's force from the λ of the rows a contact wrote (normal, then its friction rows),
/// and the primary direction they used.
fn store_point_forces(contact: &mut Contact, rows: &[Row], lambda: &[Real]) {
    let per_point = rows.len() / contact.points().len().max(1);
    let mut forces = [PointForce::default(); MAX_CONTACT_POINTS];
    for (j, f) in forces.iter_mut().enumerate().take(contact.points().len()) {
        let base = j * per_point;
        f.normal = lambda[base];
        for k in 1..per_point {
            f.friction += rows[base + k].jacobian[0].linear * lambda[base + k];
        }
    }
    contact.set_forces(&forces[..contact.points().len()]);
    if per_point >= 2 {
        contact.remember_direction(rows[1].jacobian[0].linear);
    }
}

/// The spring of the exact path's contacts for the world's contact spring.
pub(crate) fn exact_contact_spring(spring: Spring) -> Spring {
    Spring::new(
        spring.hertz * EXACT_CONTACT_STIFFENING,
        spring.damping_ratio,
    )
}

/// Each contact row's force of the last step, from the contact's warm forces: the normal force
/// for a normal row, the friction force along the row's direction for a friction row.
fn warm_contact_rows(contact: &Contact, rows: &[Row], guess: &mut Vec<Real>) {
    let warm = contact.warm_forces();
    let per_point = rows.len() / warm.len().max(1);
    for (i, row) in rows.iter().enumerate() {
        let f = warm.get(i / per_point.max(1)).copied().unwrap_or_default();
        guess.push(if i % per_point.max(1) == 0 {
            f.normal
        } else {
            f.friction.dot(row.jacobian[0].linear)
        });
    }
}
