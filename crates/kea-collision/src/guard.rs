//! The last line of defence around parry: a panic inside a query or a pair's manifold becomes a
//! named error for that call or that pair, never a crash. Inputs are checked before they reach
//! parry (`error.rs`); this catches what the checks did not foresee.

use std::panic::{catch_unwind, AssertUnwindSafe};

/// Runs `f`, turning a panic into its message.
pub(crate) fn guarded<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    // Unwind safety: on a panic the caller discards everything `f` touched (a pair's scratch
    // output, a query's partial result).
    catch_unwind(AssertUnwindSafe(f)).map_err(|payload| {
        payload
            .downcast_ref::<&str>()
            .map(|s| (*s).to_owned())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic without a message".to_owned())
    })
}
