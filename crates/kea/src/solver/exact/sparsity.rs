//! Which system an island takes: dense (the dense LCP with Coulomb bounds iterated around
//! it) or block-sparse (the cached analysis, block Cholesky and pivoting), from the structure
//! of the blocks gathered.

use super::ExactWorkspace;

/// Islands of up to this many rows take the dense system whatever they hold (see
/// [`ExactWorkspace::dense_system`]).
const DENSE_MAX_ROWS: usize = 16;

/// Most blocks on one body in an island of contacts that takes the block-sparse system (see
/// [`ExactWorkspace::blocks_form_forest`]): a box in a column with a contact per corner has
/// eight; a body with dozens of contact manifolds couples them all, densely, and goes to the
/// dense path and its work budget.
const STACK_MAX_BLOCKS_PER_BODY: usize = 12;

impl ExactWorkspace {
    /// Whether the gathered island takes the dense system: islands with contacts (but those of
    /// contacts only whose blocks form a forest, a stack) or joint friction (see
    /// [`super::dense`]), and islands small enough that the block-sparse analysis, layout and
    /// held factor cost more than the dense `n³/6` they save.
    pub(super) fn dense_system(&mut self) -> bool {
        if self.rows.len() <= DENSE_MAX_ROWS {
            return true;
        }
        if self.with_contacts {
            // Contacts only (no joint rows before them), joined without a loop.
            let contacts_only = self.contact_rows_from == Some(0);
            return !(contacts_only && self.blocks_form_forest());
        }
        self.sys.links.iter().any(Option::is_some)
    }

    /// Whether the gathered blocks join the island's bodies without a loop (each block that
    /// joins two bodies links two trees; blocks that follow one another on one pair count
    /// once, their couplings stay within the pair), and no body holds more than
    /// [`STACK_MAX_BLOCKS_PER_BODY`] of them: then the factor has no fill and small dense
    /// parts (the blocks on one body all couple).
    fn blocks_form_forest(&mut self) -> bool {
        let n = self.island_bodies.len();
        let degree = &mut self.forest;
        degree.clear();
        degree.resize(n, 0);
        for key in &self.block_key {
            for &b in key.iter().filter(|&&b| b != u32::MAX) {
                degree[b as usize] += 1;
                if degree[b as usize] as usize > STACK_MAX_BLOCKS_PER_BODY {
                    return false;
                }
            }
        }
        let parent = &mut self.forest;
        parent.clear();
        parent.extend(0..n as u32);
        let find = |parent: &mut Vec<u32>, mut x: u32| {
            while parent[x as usize] != x {
                let up = parent[parent[x as usize] as usize];
                parent[x as usize] = up;
                x = up;
            }
            x
        };
        let mut last = None;
        for key in &self.block_key {
            if key[0] == u32::MAX || key[1] == u32::MAX || last.replace(key) == Some(key) {
                // On one body, or another block on the pair just linked.
                continue;
            }
            let (a, b) = (find(parent, key[0]), find(parent, key[1]));
            if a == b {
                return false;
            }
            parent[a as usize] = b;
        }
        true
    }
}
