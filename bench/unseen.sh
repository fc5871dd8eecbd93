#!/usr/bin/env bash
# Arms the tests never saw, against Pinocchio, back to back on this machine:
#   - the xArm7 (UFactory; example-robot-data 6.0.0), general geometry: its URDF writes 1.5708
#     for pi/2 (3.7e-6 rad off), so its joint frames are not axis-aligned;
#   - the same file with --snap-angles 4e-6 (its 1.5708s read as pi/2; a different robot by
#     up to 4e-6 rad);
#   - Baxter's left arm (Rethink; example-robot-data), shoulder to wrist, 7 joints, axis-aligned.
# Pinocchio 4.1.0's C++ benchmark (bench/pinocchio_bench.cpp, -O3 -march=native, 1,024 random
# states) on the files as written, then our generated code (bench/unseen/, compiled with
# -C target-cpu=native; NATIVE=0 for the default target), then the ratios; CODEGEN=1 adds
# Pinocchio's code-generated functions (bench/run_codegen.sh) as a second ratio.
#   bash bench/unseen.sh
#   NATIVE=0 CODEGEN=1 bash bench/unseen.sh
#   Our results go to black_box by reference, as bench/run.sh's do (`keep` in
#   tests/benches/dynamics.rs) and as Pinocchio's stay in its Data; BY_VALUE=1 ...: by value, so
#   that each call's result is copied out of the return slot once more (what a caller pays who
#   copies the returned vector at once: the copy's wide loads read across the callee's 8-byte
#   stores, and store-to-load forwarding fails; before 2026-12-05 this was the default).
#   ROUNDS=3 (default): Pinocchio's benchmark and ours run alternately this many times, and each
#   side keeps its lowest median per function (as run_codegen.sh does for the code generation):
#   on a shared machine a neighbour's burst then slows one round, not one side's whole figure.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/.." && pwd)
CACHE=${XDG_CACHE_HOME:-$HOME/.cache}/dynamics-gen-bench
# shellcheck source=bench/clock.sh
. "$HERE/clock.sh"
VENV=$CACHE/venv
WORK=$CACHE/unseen
mkdir -p "$WORK" "$CACHE/models" "$HERE/unseen/src/generated"

# 1. The venv and Pinocchio's benchmark binary, as bench/run.sh builds them; example-robot-data.
SKIP_CARGO=1 ROBOTS=ur5 CALLS=1000 REPS=1 bash "$HERE/run.sh" >/dev/null
"$VENV/bin/python" -m pip install -q --disable-pip-version-check -r "$HERE/requirements-unseen.txt"
ERD=$("$VENV/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/cmeel.prefix/share/example-robot-data/robots
cp "$ERD/xarm_description/urdf/xarm7.urdf" "$WORK/xarm7.urdf"
# Baxter's left arm: the joints from the base to `left_wrist`, the links they connect
# (visuals and collisions dropped; the mesh paths are not needed).
"$VENV/bin/python" - "$ERD/baxter_description/urdf/baxter.urdf" "$WORK/baxter_left_arm.urdf" <<'PY'
import sys, xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
by_child = {j.find("child").get("link"): j for j in root.findall("joint")}
chain, link = [], "left_wrist"
while link in by_child:
    chain.append(by_child[link])
    link = by_child[link].find("parent").get("link")
links = {link} | {j.find("child").get("link") for j in chain}
arm = ET.Element("robot", {"name": "baxter_left_arm"})
for l in root.findall("link"):
    if l.get("name") in links:
        for tag in ("visual", "collision"):
            for v in l.findall(tag):
                l.remove(v)
        arm.append(l)
for j in reversed(chain):
    arm.append(j)
ET.ElementTree(arm).write(sys.argv[2])
PY

# 2. Generated code.
F=inverse_dynamics,coriolis,mass_matrix,gravity,forward_dynamics,inverse_dynamics_derivatives,forward_dynamics_with_derivatives,mass_matrix_inverse,gravity_derivative
OUT=$HERE/unseen/src/generated
(cd "$ROOT" && cargo build -q --release -p dynamics-gen)
GEN=$ROOT/target/release/dynamics-gen
"$GEN" generate "$WORK/xarm7.urdf" --no-runtime-trait --functions $F --name Xarm7 -o "$OUT/xarm7.rs" 2>/dev/null
"$GEN" generate "$WORK/xarm7.urdf" --snap-angles 4e-6 --no-runtime-trait --functions $F --name Xarm7Snapped -o "$OUT/xarm7_snapped.rs" 2>/dev/null
"$GEN" generate "$WORK/baxter_left_arm.urdf" --no-runtime-trait --functions $F --name BaxterLeftArm -o "$OUT/baxter_left_arm.rs" 2>/dev/null
{
  for m in xarm7 xarm7_snapped baxter_left_arm; do
    echo "#[allow(dead_code)] mod $m { include!(concat!(env!(\"CARGO_MANIFEST_DIR\"), \"/src/generated/$m.rs\")); }"
  done
} > "$OUT/arms.rs"

# 3. Pinocchio and ours, alternately, ROUNDS times.
for r in xarm7 baxter_left_arm; do
  "$VENV/bin/python" -c 'import sys, pinocchio as pin
pin.buildModelFromUrdf(sys.argv[1]).saveToBinary(sys.argv[2])' "$WORK/$r.urdf" "$CACHE/models/$r.bin"
done
ROUNDS=${ROUNDS:-3}
echo "# $(nproc) cores, $(lscpu | sed -n 's/^Model name:[[:space:]]*//p' | head -1); Pinocchio 4.1.0; $ROUNDS rounds"
# CODEGEN=1: Pinocchio's code-generated functions too (bench/run_codegen.sh; a long first run;
# its own CG_ROUNDS, best of each).
: > "$WORK/pinocchio.txt"
if [ "${CODEGEN:-0}" = 1 ]; then
  ROBOTS="xarm7=$WORK/xarm7.urdf baxter_left_arm=$WORK/baxter_left_arm.urdf" CALLS=20000 \
    bash "$HERE/run_codegen.sh" >/dev/null
  tee -a "$WORK/pinocchio.txt" < "$CACHE/pinocchio_codegen.txt"
fi
if [ "${NATIVE:-1}" = 1 ]; then export RUSTFLAGS="${RUSTFLAGS:-} -C target-cpu=native"; fi
FEATURES=(--features by-ref)
if [ "${BY_VALUE:-0}" = 1 ]; then FEATURES=(); fi
echo "# ours: RUSTFLAGS='${RUSTFLAGS:-}', results to black_box $([ ${#FEATURES[@]} = 0 ] && echo by value || echo by reference)"
(cd "$HERE/unseen" && cargo build -q --release "${FEATURES[@]}")
: > "$WORK/ours.txt"
for round in $(seq "$ROUNDS"); do
  echo "# round $round of $ROUNDS"
  clock "round $round"
  "$CACHE/pinocchio_bench" --calls 20000 --reps 5 xarm7="$CACHE/models/xarm7.bin" \
    baxter_left_arm="$CACHE/models/baxter_left_arm.bin" | tee -a "$WORK/pinocchio.txt"
  (cd "$HERE/unseen" && cargo run -q --release "${FEATURES[@]}") | tee -a "$WORK/ours.txt"
done
clock "at the end"

# 4. Side by side (xarm7_snapped against Pinocchio on the file as written).
"$VENV/bin/python" - "$WORK/pinocchio.txt" "$WORK/ours.txt" <<'PY'
import sys
algo = {"inverse_dynamics": "rnea", "coriolis": "nle", "mass_matrix": "crba", "gravity": "gravity", "forward_dynamics": "aba",
        "inverse_dynamics_derivatives": "rnea_derivatives", "forward_dynamics_with_derivatives": "aba_derivatives",
        "mass_matrix_inverse": "minverse", "gravity_derivative": "gravity_derivatives"}
pin = {}
for line in open(sys.argv[1]):
    robot, _nv, a, med, _mn = line.split()
    pin[(robot, a)] = min(float(med), pin.get((robot, a), float("inf")))
# Each side's lowest median over the rounds, in the order of the first round.
ours = {}
for line in open(sys.argv[2]):
    robot, f, ns = line.split()
    ours[(robot, f)] = min(float(ns), ours.get((robot, f), float("inf")))
cg = any(a.startswith("cg_") for _, a in pin)
print(f"\n{'robot':<16} {'ours':<34} {'ours_ns':>8} {'pinocchio':<19} {'pin_ns':>8} {'ratio':>6}"
      + (f" {'codegen_ns':>10} {'ratio':>6}" if cg else ""))
for (robot, f), ns in ours.items():
    r = robot.replace("_snapped", "")
    p = pin.get((r, algo[f]))
    row = f"{robot:<16} {f:<34} {ns:8.1f} {algo[f]:<19} {p:8.1f} {p / ns:5.1f}x"
    c = pin.get((r, "cg_" + algo[f]))
    if c is not None:
        row += f" {c:10.1f} {c / ns:5.1f}x"
    print(row)
PY
