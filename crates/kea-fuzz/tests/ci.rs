//! The fuzz driver's CI run: fixed seeds, a fixed number of operations each, and nothing may go
//! wrong (no panic, escaped or caught; no operation past the bound; no refused call that changed
//! the world; no NaN after accepted input).

use std::time::Duration;

#[test]
fn fixed_seeds_find_nothing() {
    let report = kea_fuzz::run(0..8, 2_500, Duration::from_secs(5));
    assert_eq!(report.operations, 20_000);
    assert!(
        report.refused > 1000,
        "the driver should try bad input too: {report:?}"
    );
    assert!(report.is_clean(), "{report:#?}");
}
