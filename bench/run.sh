#!/usr/bin/env bash
# One-command speed comparison: Pinocchio's C++ algorithms, then `cargo bench -p dynamics-tests
# --bench dynamics`, back to back, then a side-by-side table.  See bench/README.md.
#   bash bench/run.sh
#   ROBOTS="ur5" CALLS=20000 REPS=3 CRITERION_ARGS="--warm-up-time 0.2 --measurement-time 0.5" bash bench/run.sh
# Environment: ROBOTS (default "ur5 panda rand7 double_pendulum talos_upper_body solo12+ff g1_29dof+ff";
# NAME+ff puts the URDF on a free-flyer base), CALLS (100000), REPS (5),
# CRITERION_ARGS (extra criterion options), SKIP_CARGO=1 (Pinocchio only), CARGO_TARGET_DIR, CODEGEN=1 (also
# Pinocchio's code-generated rnea, crba, aba and derivatives, bench/run_codegen.sh, fixed-base robots), NATIVE (1, the default:
# our code compiled for this CPU with RUSTFLAGS="-C target-cpu=native", as Pinocchio is with -march=native,
# into target/bench-native; 0: for the toolchain's default target CPU, into target/bench-default),
# CALLGRIND=1 (with NATIVE=0: also instructions per call of both sides under valgrind's callgrind, which
# decodes AVX2 and FMA but not AVX-512: ours runs its AVX2 copy there, and Pinocchio is compiled a second time
# for x86-64-v3, AVX2 and FMA, to match), SIDE_BY_SIDE (rounds of the side-by-side timing of ours against the
# reference, default 21; 0: off), PIN_ROUNDS (rounds of Pinocchio and ours interleaved, table 3b; default 7,
# 0: off; with CODEGEN=1 its rounds also run Pinocchio's code-generated functions, table 3c).
# First run: a venv with pin==4.1.0 under ~/.cache/dynamics-gen-bench and a compile of a few minutes.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/.." && pwd)
CACHE=${XDG_CACHE_HOME:-$HOME/.cache}/dynamics-gen-bench
# shellcheck source=bench/clock.sh
. "$HERE/clock.sh"
VENV=$CACHE/venv
BIN=$CACHE/pinocchio_bench
ROBOTS=${ROBOTS:-"ur5 panda rand7 double_pendulum talos_upper_body solo12+ff g1_29dof+ff"}
CALLS=${CALLS:-100000}
# Pinocchio's algorithms, by its benchmark's names, that tables 3b and 5 run on both sides.
ALGOS="rnea nle crba gravity aba rnea_derivatives aba_derivatives minverse gravity_derivatives"
REPS=${REPS:-5}
mkdir -p "$CACHE/models"
if [ "${CALLGRIND:-0}" = 1 ]; then
  [ "${NATIVE:-1}" = 0 ] || { echo "CALLGRIND=1 needs NATIVE=0 (valgrind does not decode this CPU's AVX-512)" >&2; exit 1; }
  command -v valgrind >/dev/null || { echo "CALLGRIND=1 needs valgrind" >&2; exit 1; }
fi

# 1. Pinocchio: venv, models (URDF -> binary via the Python package), native build, timing.
[ -x "$VENV/bin/python" ] || python3 -m venv "$VENV"
if ! cmp -s "$HERE/requirements.txt" "$CACHE/requirements.installed"; then
  "$VENV/bin/python" -m pip install -q --disable-pip-version-check -r "$HERE/requirements.txt"
  cp "$HERE/requirements.txt" "$CACHE/requirements.installed"
fi
P=$("$VENV/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/cmeel.prefix
if [ ! -x "$BIN" ] || [ "$HERE/pinocchio_bench.cpp" -nt "$BIN" ]; then
  echo "compiling bench/pinocchio_bench.cpp (a few minutes) ..." >&2
  ${CXX:-g++} -std=c++17 -O3 -march=native -DNDEBUG -Wno-deprecated-declarations -Wno-stringop-overread \
    -I"$P/include" -I"$P/include/eigen3" -DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30 \
    -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_FUSION_INVOKE_MAX_ARITY=12 "$HERE/pinocchio_bench.cpp" -o "$BIN.tmp" \
    -L"$P/lib" -Wl,-rpath,"$P/lib" -lboost_serialization \
    || { echo "compiling bench/pinocchio_bench.cpp failed (exit $?)" >&2; exit 1; }
  mv "$BIN.tmp" "$BIN"
fi
ARGS=()
NAMES=()
FFS=()
for r in $ROBOTS; do
  # NAME+ff: the URDF on a free-flyer base; URDFs in tests/data/robots or its trees/.
  name=${r%+ff}; ff=0; [ "$name" != "$r" ] && ff=1
  u=$ROOT/tests/data/robots/$name.urdf
  [ -f "$u" ] || u=$ROOT/tests/data/robots/trees/$name.urdf
  [ -f "$u" ] || { echo "no URDF for $name in tests/data/robots or tests/data/robots/trees" >&2; exit 1; }
  "$VENV/bin/python" -c 'import sys, pinocchio as pin
m = pin.buildModelFromUrdf(sys.argv[1], pin.JointModelFreeFlyer()) if sys.argv[3] == "1" else pin.buildModelFromUrdf(sys.argv[1])
m.saveToBinary(sys.argv[2])' "$u" "$CACHE/models/$name.bin" "$ff"
  ARGS+=("$name=$CACHE/models/$name.bin")
  NAMES+=("$name")
  FFS+=("$ff")
done
echo "# $(nproc) cores, $(lscpu | sed -n 's/^Model name:[[:space:]]*//p' | head -1); Pinocchio 4.1.0, calls=$CALLS reps=$REPS"
clock "before Pinocchio"
echo "# robot           nv algo     median_ns     min_ns"
"$BIN" --calls "$CALLS" --reps "$REPS" "${ARGS[@]}" | tee "$CACHE/pinocchio.txt"
# 1b. With CODEGEN=1: Pinocchio's code-generated rnea, crba, aba and derivatives too (bench/run_codegen.sh; fixed-base
# robots only; its first run is long, see bench/README.md), in the same table.
if [ "${CODEGEN:-0}" = 1 ]; then
  CG_ROBOTS=$(for r in $ROBOTS; do [ "${r%+ff}" = "$r" ] && echo "$r"; done | tr '\n' ' ')
  ROBOTS="$CG_ROBOTS" CALLS="$CALLS" REPS="$REPS" bash "$HERE/run_codegen.sh" >/dev/null
  tee -a "$CACHE/pinocchio.txt" < "$CACHE/pinocchio_codegen.txt"
fi
[ "${SKIP_CARGO:-0}" = 1 ] && exit 0

# 2. Our generated code, right after (criterion filter: the same robots).
START=$(date +%s)
FILTER="^($(echo "${NAMES[@]}" | tr ' ' '|'))/"
# Both sides for this CPU by default (Pinocchio: -march=native); a target directory of its own,
# so that the changed RUSTFLAGS do not rebuild the workspace's usual one.
if [ "${NATIVE:-1}" = 1 ]; then
  export RUSTFLAGS="${RUSTFLAGS:-} -C target-cpu=native"
  export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$ROOT/target/bench-native}
else
  export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$ROOT/target/bench-default}
fi
# Absolute: cargo reads a relative one from where it runs (the workspace), but the benchmark
# binary runs in its package's directory and criterion writes its results under it.
case $CARGO_TARGET_DIR in
  /*) ;;
  *) mkdir -p "$ROOT/$CARGO_TARGET_DIR" && CARGO_TARGET_DIR=$(cd "$ROOT/$CARGO_TARGET_DIR" && pwd) ;;
esac
export CARGO_TARGET_DIR
echo "# ours: RUSTFLAGS='${RUSTFLAGS:-}', CARGO_TARGET_DIR=$CARGO_TARGET_DIR"
# SAMPLE=1: build the test crate with its `sample-robots` feature (the 20 cases of SAMPLE in
# tests/build.rs, every robot this kit times among them): a third of the build time.
FEATURES=()
[ "${SAMPLE:-0}" = 1 ] && FEATURES=(--features sample-robots)
# SIDE_BY_SIDE (rounds, default 21; 0: off): the benchmark also times each generated function
# and its reference in alternating blocks of about a millisecond (`side_by_side` in
# tests/benches/dynamics.rs), for table 4b's second ratio.
export SIDE_BY_SIDE=${SIDE_BY_SIDE:-21}
SIDE_BY_SIDE_ROBOTS=$(for r in $ROBOTS; do printf '%s ' "${r%+ff}"; done)
export SIDE_BY_SIDE_ROBOTS
(cd "$ROOT" && cargo bench -p dynamics-tests "${FEATURES[@]}" --bench dynamics -- ${CRITERION_ARGS:-} "$FILTER") |
  tee "$CACHE/cargo_bench.txt"
clock "after ours"

# 3. Side by side: criterion medians of this run only (estimates.json newer than START).
CRIT=$CARGO_TARGET_DIR/criterion
"$VENV/bin/python" - "$CACHE/pinocchio.txt" "$CRIT" "$START" <<'EOF'
import json, os, sys
pin_file, crit, start = sys.argv[1], sys.argv[2], float(sys.argv[3])
ours = {"rnea": "inverse_dynamics", "nle": "coriolis", "crba": "mass_matrix", "gravity": "gravity", "aba": "forward_dynamics",
        "rnea_derivatives": "inverse_dynamics_derivatives", "aba_derivatives": "forward_dynamics_with_derivatives",
        "minverse": "mass_matrix_inverse", "gravity_derivatives": "gravity_derivative",
        "cg_rnea": "inverse_dynamics", "cg_crba": "mass_matrix", "cg_aba": "forward_dynamics",
        "cg_rnea_derivatives": "inverse_dynamics_derivatives",
        "cg_aba_derivatives": "forward_dynamics_with_derivatives", "cg_minverse": "mass_matrix_inverse"}
print(f"\n{'robot':<16} {'pinocchio':<19} {'pin_ns':>8} {'ours':<33} {'ours_ns':>8} {'ratio':>6}")
for line in open(pin_file):
    robot, _nv, algo, med, _mn = line.split()
    est = os.path.join(crit, robot, "generated_" + ours[algo], "new", "estimates.json")
    ns = None
    if os.path.exists(est) and os.path.getmtime(est) >= start:
        ns = json.load(open(est))["median"]["point_estimate"]
    cell = f"{ns:8.1f} {float(med) / ns:5.1f}x" if ns else f"{'-':>8} {'-':>6}"
    print(f"{robot:<16} {algo:<19} {float(med):8.1f} {ours[algo]:<33} {cell}")
EOF
# 3b. Pinocchio and ours interleaved: PIN_ROUNDS rounds (default 7; 0: off), each Pinocchio's benchmark
# (--reps 1) on one robot and then ours on the same robot and algorithms, `tests/examples/calls.rs
# --time 1` (a warm-up round, then CALLS calls timed), one process per algorithm; the median and
# quartiles of the rounds' ratios. Table 3 compares Pinocchio's run with criterion's minutes later.
# With CODEGEN=1, each round of a fixed-base robot also runs Pinocchio's code-generated functions
# (step 1b's libraries, every flag set of CG_CFLAGS_SETS, the fastest per round), table 3c.
if [ "${PIN_ROUNDS:-7}" -gt 0 ]; then
  IFS='|' read -r -a CG_SETS <<< "${CG_CFLAGS_SETS:-"-O3 -march=native|-Ofast"}"
  CG_CC=$(command -v "${CG_CC:-gcc}" || true)
  (cd "$ROOT" && cargo build -q --release -p dynamics-tests "${FEATURES[@]}" --example calls)
  EX=$CARGO_TARGET_DIR/release/examples/calls
  : > "$CACHE/interleaved.txt"
  for i in "${!NAMES[@]}"; do
    name=${NAMES[$i]}; model=${ARGS[$i]}
    for round in $(seq "${PIN_ROUNDS:-7}"); do
      "$BIN" --calls "$CALLS" --reps 1 "$model" | sed "s/^/pin $round /" >> "$CACHE/interleaved.txt"
      if [ "${CODEGEN:-0}" = 1 ] && [ "${FFS[$i]}" = 0 ]; then
        for flags in "${CG_SETS[@]}"; do
          "$CACHE/pinocchio_codegen_bench" --calls "$CALLS" --reps 1 \
            --lib-dir "$CACHE/codegen/$(printf '%s' "$flags" | tr -cs 'A-Za-z0-9._=' '_')" \
            --cc "$CG_CC" --cflags "$flags" "$model" | grep -v '^#' | sed "s/^/cg $round /" >> "$CACHE/interleaved.txt"
        done
      fi
      for algo in $ALGOS; do
        { "$EX" "$name" "$algo" "$CALLS" --time 1 2>/dev/null || true; } | sed "s/^/ours $round /" >> "$CACHE/interleaved.txt"
      done
    done
  done
  "$VENV/bin/python" - "$CACHE/interleaved.txt" <<'EOF'
import sys
pin, cg, ours = {}, {}, {}
for line in open(sys.argv[1]):
    f = line.split()
    if f[0] == "pin" and len(f) == 7:
        pin[(f[2], f[4], f[1])] = float(f[5])
    elif f[0] == "cg" and len(f) == 7 and f[4].startswith("cg_"):
        # The fastest flag set of the round.
        k = (f[2], f[4][3:], f[1])
        cg[k] = min(float(f[5]), cg.get(k, float("inf")))
    elif f[0] == "ours" and len(f) == 5:
        ours[(f[2], f[3], f[1])] = float(f[4])
med = lambda v: sorted(v)[len(v) // 2]
def table(theirs, title, name):
    rows, pairs = [], []
    for (b, a, _r) in theirs:
        if (b, a) not in pairs:
            pairs.append((b, a))
    for robot, algo in pairs:
        rounds = [r for (b, a, r) in theirs if (b, a) == (robot, algo) and (b, a, r) in ours]
        if not rounds:
            continue
        ratios = sorted(theirs[(robot, algo, r)] / ours[(robot, algo, r)] for r in rounds)
        p, o, n = med([theirs[(robot, algo, r)] for r in rounds]), med([ours[(robot, algo, r)] for r in rounds]), len(ratios)
        rows.append(f"{robot:<16} {algo:<19} {p:8.1f} {o:8.1f} {med(ratios):6.1f}x {ratios[n // 4]:5.1f}-{ratios[(3 * n) // 4]:.1f}x {n:6d}")
    if rows:
        print(f"\n{'robot':<16} {title:<19} {name:>8} {'ours_ns':>8} {'ratio':>7} {'quartiles':>11} rounds")
        print("\n".join(rows))
table(pin, "interleaved", "pin_ns")
# 3c. Pinocchio's code generation (CODEGEN=1), the same rounds.
table(cg, "codegen, interleaved", "cg_ns")
EOF
fi

# 4. The batch functions against single calls (below). 4b. The generic reference implementation
# (dynamics-reference: heap, loops over joints) against the generated code, this run: every function criterion timed on both sides (on the arms, all
# that have a counterpart: `bench_every!` in tests/benches/dynamics.rs; the derivatives' reference
# is central differences of the reference, as the tests compare them).
# Beside criterion's ratio, the side-by-side one (SIDE_BY_SIDE rounds of alternating blocks): its
# median over the rounds and the rounds' quartiles. (Tables 4, 4b and 4c in one script.)
"$VENV/bin/python" - "$CRIT" "$START" "$CACHE/cargo_bench.txt" $ROBOTS <<'EOF'
import json, os, sys
crit, start, robots = sys.argv[1], float(sys.argv[2]), [r.split("+")[0] for r in sys.argv[4:]]
side = {}
for line in open(sys.argv[3]):
    f = line.rstrip("\n").split("\t")
    if f[0] == "side-by-side" and len(f) == 8:
        side[(f[1], f[2])] = [float(x) for x in f[3:]]
def median(robot, name):
    est = os.path.join(crit, robot, name, "new", "estimates.json")
    if os.path.exists(est) and os.path.getmtime(est) >= start:
        return json.load(open(est))["median"]["point_estimate"]
# 4. The batch functions: 8 states in one `*_batch` call against 8 single-state calls, this run
# (criterion's two rows, and the side-by-side gain: median and quartiles of the rounds).
rows = []
for robot in robots:
    for f in ["inverse_dynamics", "forward_dynamics", "mass_matrix", "gravity"]:
        single, batch = median(robot, f"generated_{f}_x8_single"), median(robot, f"generated_{f}_x8_batch")
        if single and batch:
            s = side.get((robot, f + "_x8"))
            cell = f"{s[1] / 8:9.1f} {s[0] / 8:9.1f} {s[2]:6.2f}x {s[3]:4.2f}-{s[4]:.2f}x" if s else ""
            rows.append(f"{robot:<16} {f:<18} {single / 8:9.1f} {batch / 8:9.1f} {single / batch:6.2f}x  {cell}")
if rows:
    print(f"\n{'':<35} {'criterion':^27}  {'side by side (median, quartiles of rounds)':^40}")
    print(f"{'robot':<16} {'function (8 states)':<18} {'single/st':>9} {'batch/st':>9} {'gain':>7}  "
          f"{'single/st':>9} {'batch/st':>9} {'gain':>7} {'quartiles':>11}")
    print("\n".join(rows))
# 4b.
rows = []
for robot in robots:
    d = os.path.join(crit, robot)
    names = sorted(n[len("reference_"):] for n in os.listdir(d) if n.startswith("reference_")) if os.path.isdir(d) else []
    for f in names:
        ref, gen = median(robot, "reference_" + f), median(robot, "generated_" + f)
        if ref and gen:
            s = side.get((robot, f))
            cell = (f"{s[1]:10.1f} {s[0]:9.1f} {s[2]:6.1f}x {s[3]:5.1f}-{s[4]:.1f}x" if s else "")
            rows.append(f"{robot:<16} {f:<34} {ref:10.1f} {gen:9.1f} {ref / gen:6.1f}x  {cell}")
if rows:
    print(f"\n{'':<51} {'criterion':^27}  {'side by side (median, quartiles of rounds)':^40}")
    print(f"{'robot':<16} {'function':<34} {'reference':>10} {'ours':>9} {'ratio':>7}  "
          f"{'reference':>10} {'ours':>9} {'ratio':>7} {'quartiles':>11}")
    print("\n".join(rows))
# 4c. f32 beside f64, generated code only (`bench_f32!`): the same robot generated with scalar f32
# on the same states rounded to f32, and for the UR5 its f32 `no_std` code (no CPU dispatch: the
# portable copy).
rows = []
for robot in robots:
    for f in ["inverse_dynamics", "coriolis", "gravity", "mass_matrix", "forward_dynamics",
              "end_effector_pose", "jacobian_space"]:
        f64, f32 = median(robot, "generated_" + f), median(robot, "generated_f32_" + f)
        if f64 and f32:
            ns = median(robot, "generated_f32_no_std_" + f)
            cell = f"{ns:10.1f}" if ns else f"{'-':>10}"
            rows.append(f"{robot:<16} {f:<20} {f64:8.1f} {f32:8.1f} {f64 / f32:6.2f}x {cell}")
if rows:
    print(f"\n{'robot':<16} {'function':<20} {'f64':>8} {'f32':>8} {'f64/f32':>7} {'f32 no_std':>10}")
    print("\n".join(rows))
EOF

# 4d. With NATIVE=0: the size of each benchmarked function's AVX-512 and AVX2 copies (functions of
# their own in the benchmark binary; with NATIVE=1 the code is inlined into criterion's closures), against
# the CPU's level-1 instruction cache: straight-line code larger than it runs at the rate it can be fetched
# from level 2 (docs/performance.md, "The trees' largest functions are bound by instruction fetch").
BENCH_BIN=$(ls -t "$CARGO_TARGET_DIR"/release/deps/dynamics-* 2>/dev/null | grep -v '\.d$' | head -1 || true)
if [ "${NATIVE:-1}" = 0 ] && [ -n "$BENCH_BIN" ]; then
  L1I=$(getconf LEVEL1_ICACHE_SIZE 2>/dev/null || echo 0)
  nm -S -C --defined-only "$BENCH_BIN" > "$CACHE/symbols.txt"
  "$VENV/bin/python" - "$CACHE/symbols.txt" "$ROOT/tests/benches/dynamics.rs" "${L1I:-0}" $ROBOTS <<'EOF'
import re, sys
symbols, bench = open(sys.argv[1]), open(sys.argv[2]).read()
l1i, robots = int(sys.argv[3]), [r.split("+")[0] for r in sys.argv[4:]]
module = dict(re.findall(r'bench_robot!\(\s*c,\s*"([^"]+)",\s*(\w+),', bench))
size = {}
for line in symbols:
    parts = line.split(maxsplit=3)
    if len(parts) == 4 and parts[3].startswith("dynamics_tests::generated::"):
        size[parts[3].strip()] = int(parts[1], 16)
def copy(m, f, suffix):
    hits = [n for k, n in size.items() if k.endswith(f"::{f}_{suffix}") and f"::generated::{m}::" in k]
    return max(hits) if hits else None
cell = lambda b: (f"{b:8d}" + ("*" if l1i and b > l1i else " ")) if b else f"{'-':>8} "
rows = []
for robot in robots:
    m = module.get(robot)
    for f in ["inverse_dynamics", "coriolis", "gravity", "mass_matrix", "forward_dynamics"]:
        a512, a2 = (copy(m, f, s) if m else None for s in ("avx512", "avx2"))
        if a512 or a2:
            rows.append(f"{robot:<16} {f:<18} {cell(a512)} {cell(a2)}")
if rows:
    print(f"\n{'robot':<16} {'function':<18} {'AVX-512':>9} {'AVX2':>9}  bytes of machine code; * above L1i ({l1i} bytes)")
    print("\n".join(rows))
EOF
fi

# 5. With CALLGRIND=1: instructions per call, both sides running AVX2 and FMA code (valgrind reports
# AVX2 and FMA but not AVX-512, so the default build of ours runs its AVX2 copy; Pinocchio is built for
# x86-64-v3). Each program runs at 1,024 and 2,048 calls; the difference of the counts over 1,024 is the
# cost of a call, with start-up and set-up cancelled (every state is called once in the difference).
if [ "${CALLGRIND:-0}" = 1 ]; then
  PBIN=$CACHE/pinocchio_bench_x86-64-v3
  if [ ! -x "$PBIN" ] || [ "$HERE/pinocchio_bench.cpp" -nt "$PBIN" ]; then
    echo "compiling bench/pinocchio_bench.cpp for x86-64-v3 (a few minutes) ..." >&2
    ${CXX:-g++} -std=c++17 -O3 -march=x86-64-v3 -DNDEBUG -Wno-deprecated-declarations -Wno-stringop-overread \
      -I"$P/include" -I"$P/include/eigen3" -DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30 \
      -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_FUSION_INVOKE_MAX_ARITY=12 "$HERE/pinocchio_bench.cpp" -o "$PBIN.tmp" \
      -L"$P/lib" -Wl,-rpath,"$P/lib" -lboost_serialization
    mv "$PBIN.tmp" "$PBIN"
  fi
  (cd "$ROOT" && cargo build -q --release -p dynamics-tests "${FEATURES[@]}" --example calls)
  EX=$CARGO_TARGET_DIR/release/examples/calls
  instr() { valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" 2>&1 >/dev/null | sed -n 's/.*Collected : //p'; }
  per_call() { # program args with the call count last or as --calls
    local a b; a=$(instr "$@" 1024) || return 1; b=$(instr "$@" 2048) || return 1
    [ -n "$a" ] && [ -n "$b" ] && echo $(( (b - a) / 1024 ))
  }
  echo
  printf '%-16s %-20s %12s %12s %7s\n' robot "algorithm (AVX2)" pin_instr ours_instr ratio
  for i in "${!NAMES[@]}"; do
    name=${NAMES[$i]}; model=${ARGS[$i]}
    for algo in $ALGOS; do
      pin=$(per_call "$PBIN" --count "$algo" "$model" --calls) || pin=
      ours=$(per_call "$EX" "$name" "$algo") || ours=
      [ -n "$pin" ] && [ -n "$ours" ] || continue
      printf '%-16s %-20s %12d %12d %6.1fx\n' "$name" "$algo" "$pin" "$ours" "$(awk "BEGIN { print $pin / $ours }")"
    done
  done
fi
clock "at the end"
