#!/usr/bin/env bash
# Kea against Rapier the way a speed-minded user builds both: the `bench-lto` profile
# (lto = "thin", codegen-units = 1), Rapier with and without `simd8`, in one table.
# Usage: bash crates/kea-bench/fair.sh [--runs N] [--quick] [FILTER]   (extra arguments go to kea-bench)
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build -q --profile bench-lto -p kea-bench --features simd8
cp target/bench-lto/kea-bench target/bench-lto/kea-bench-simd8
cargo build -q --profile bench-lto -p kea-bench
exec target/bench-lto/kea-bench --rapier-simd8 target/bench-lto/kea-bench-simd8 "$@"
