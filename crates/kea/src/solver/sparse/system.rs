//! The system a block-sparse LCP solve works on: the matrix's values over its pattern and
//! layout, the right-hand side and the friction links — what pivoting solves and what the held
//! factorisation factorises.

use super::factor::Layout;
use super::pattern::Pattern;

/// A friction row's link: the index of its normal row and μ.
pub(crate) type FrictionLink = Option<(u32, f64)>;

/// The system: `A` (values over `pattern` and `layout`), `b` and the friction links.
pub(crate) struct System<'a> {
    pub pattern: &'a Pattern,
    pub layout: &'a Layout,
    pub a: &'a [f64],
    pub b: &'a [f64],
    pub links: &'a [FrictionLink],
    /// Identifies the values of `a`: a factorisation of the same values with the same held
    /// rows is reused (0: never).
    pub stamp: u64,
}
