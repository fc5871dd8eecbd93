#!/usr/bin/env bash
# Batch functions against single calls, per state, as a user crate gets the code (std, the
# default release profile; NATIVE=1 adds -C target-cpu=native): the UR5 and the Panda
# generated into bench/batch/src/generated/, then bench/batch's harness (8 single calls
# against one *_batch::<8> call on the same 8 states, medians of 7 interleaved runs).
#   bash bench/batch.sh
#   NATIVE=1 bash bench/batch.sh
#   BY_REF=1 bash bench/batch.sh      # results to black_box by reference (see bench/README.md)
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/.." && pwd)
OUT=$HERE/batch/src/generated
mkdir -p "$OUT"
F=inverse_dynamics,forward_dynamics,mass_matrix,gravity,coriolis,inverse_dynamics_batch,forward_dynamics_batch,mass_matrix_batch,gravity_batch
(cd "$ROOT" && cargo build -q --release -p dynamics-gen)
GEN=$ROOT/target/release/dynamics-gen
"$GEN" generate "$ROOT/tests/data/robots/ur5.urdf" --functions $F --name Ur5 -o "$OUT/ur5.rs.new"
"$GEN" generate "$ROOT/tests/data/robots/panda.urdf" --functions $F --name Panda -o "$OUT/panda.rs.new"
# Rewritten only on change, so that an unchanged generator rebuilds nothing.
for m in ur5 panda; do
  if cmp -s "$OUT/$m.rs.new" "$OUT/$m.rs"; then rm "$OUT/$m.rs.new"; else mv "$OUT/$m.rs.new" "$OUT/$m.rs"; fi
done
for m in ur5 panda; do
  echo "mod $m { include!(concat!(env!(\"CARGO_MANIFEST_DIR\"), \"/src/generated/$m.rs\")); }"
done > "$OUT/robots.rs"
if [ "${NATIVE:-0}" = 1 ]; then export RUSTFLAGS="${RUSTFLAGS:-} -C target-cpu=native"; fi
echo "# $(lscpu | sed -n 's/^Model name:[[:space:]]*//p' | head -1); RUSTFLAGS='${RUSTFLAGS:-}'; B = 8 and 4"
echo "# robot function B single_ns/state batch_ns/state gain"
FEATURES=()
if [ "${BY_REF:-0}" = 1 ]; then FEATURES=(--features by-ref); echo "# results to black_box by reference"; fi
cd "$HERE/batch" && cargo build -q --release "${FEATURES[@]}" && ./target/release/batch-bench
