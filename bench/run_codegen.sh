#!/usr/bin/env bash
# Pinocchio's code-generated rnea, crba, aba and derivatives (CppADCodeGen) timed on this machine; see bench/README.md.
#   bash bench/run_codegen.sh
#   ROBOTS="ur5" CALLS=20000 REPS=3 bash bench/run_codegen.sh
# Environment: ROBOTS (default "ur5 panda rand7": fixed-base URDFs in tests/data/robots or its trees/, or
# NAME=PATH.urdf for any other file),
# CALLS (100000), REPS (5), CG_CC (C compiler for the generated code, default gcc),
# CG_CFLAGS (its flags, default "-O3 -march=native"), CXX (for the benchmark program, default g++).
# Output: ~/.cache/dynamics-gen-bench/pinocchio_codegen.txt ("robot nv algo median_ns min_ns"), the full log
# (build times, checks) beside it in pinocchio_codegen.log.
# First run: the venv of bench/run.sh plus two header-only packages, one g++ run of the benchmark program
# (the slow part: Pinocchio instantiated on CppAD's code-generation scalar), then per robot three traces and
# three gcc runs on the generated C. All cached; see bench/README.md for the cost.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/.." && pwd)
CACHE=${XDG_CACHE_HOME:-$HOME/.cache}/dynamics-gen-bench
VENV=$CACHE/venv
BIN=$CACHE/pinocchio_codegen_bench
ROBOTS=${ROBOTS:-"ur5 panda rand7"}
CALLS=${CALLS:-100000}
REPS=${REPS:-5}
CG_CC=$(command -v "${CG_CC:-gcc}") || { echo "no C compiler ${CG_CC:-gcc}" >&2; exit 1; }
CG_CFLAGS=${CG_CFLAGS:-"-O3 -march=native"}
CXX=${CXX:-g++}
mkdir -p "$CACHE/models" "$CACHE/codegen"

# 1. venv: pin (requirements.txt, as bench/run.sh) and CppAD + CppADCodeGen (requirements-codegen.txt).
[ -x "$VENV/bin/python" ] || python3 -m venv "$VENV"
for req in requirements.txt requirements-codegen.txt; do
  stamp=$CACHE/${req%.txt}.installed
  if ! cmp -s "$HERE/$req" "$stamp"; then
    "$VENV/bin/python" -m pip install -q --disable-pip-version-check -r "$HERE/$req"
    cp "$HERE/$req" "$stamp"
  fi
done
P=$("$VENV/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/cmeel.prefix

# 2. The benchmark program: rebuilt when its source, the compiler or the flags change.
CXXFLAGS=(-std=c++17 -O3 -march=native -DNDEBUG -Wno-deprecated-declarations -Wno-stringop-overread
  -I"$P/include" -I"$P/include/eigen3" -DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30
  -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_FUSION_INVOKE_MAX_ARITY=12)
LIBS=(-L"$P/lib" -Wl,-rpath,"$P/lib" -lboost_serialization -lcppad_lib -ldl)
KEY=$( { cat "$HERE/pinocchio_codegen_bench.cpp" "$HERE/requirements.txt" "$HERE/requirements-codegen.txt"
         "$CXX" --version; echo "${CXXFLAGS[*]} ${LIBS[*]}"; } | sha256sum | cut -c1-16)
if [ ! -x "$BIN" ] || [ "$(cat "$BIN.key" 2>/dev/null)" != "$KEY" ]; then
  echo "compiling bench/pinocchio_codegen_bench.cpp (about 10 minutes and several GB of memory) ..." >&2
  TIME=(); [ -x /usr/bin/time ] && TIME=(/usr/bin/time -f "g++: %e s wall, max RSS %M KB" -o "$CACHE/pinocchio_codegen_build.txt")
  "${TIME[@]}" "$CXX" "${CXXFLAGS[@]}" "$HERE/pinocchio_codegen_bench.cpp" -o "$BIN.tmp" "${LIBS[@]}" \
    || { echo "compiling bench/pinocchio_codegen_bench.cpp failed" >&2; exit 1; }
  [ -f "$CACHE/pinocchio_codegen_build.txt" ] && cat "$CACHE/pinocchio_codegen_build.txt" >&2
  mv "$BIN.tmp" "$BIN"
  echo "$KEY" > "$BIN.key"
fi

# 3. Models (URDF -> binary via the Python package) and the cache of generated libraries, one folder per
#    robot, cleared when the model, the program or the C compiler and flags change.
ARGS=()
for entry in $ROBOTS; do
  # NAME (a URDF in tests/data/robots or its trees/) or NAME=PATH.urdf (any URDF, e.g. bench/unseen.sh's).
  name=${entry%%=*}
  if [ "$name" != "$entry" ]; then
    u=${entry#*=}
  else
    u=$ROOT/tests/data/robots/$name.urdf
    [ -f "$u" ] || u=$ROOT/tests/data/robots/trees/$name.urdf
  fi
  [ -f "$u" ] || { echo "no URDF for $name (tests/data/robots, its trees/, or NAME=PATH)" >&2; exit 1; }
  "$VENV/bin/python" -c 'import sys, pinocchio as pin
pin.buildModelFromUrdf(sys.argv[1]).saveToBinary(sys.argv[2])' "$u" "$CACHE/models/$name.bin"
  key=$( { cat "$CACHE/models/$name.bin"; echo "$KEY"; "$CG_CC" --version; echo "$CG_CC $CG_CFLAGS"; } | sha256sum | cut -c1-16)
  d=$CACHE/codegen/$name
  if [ "$(cat "$d/key" 2>/dev/null)" != "$key" ]; then
    rm -rf "$d"
    mkdir -p "$d"
    echo "$key" > "$d/key"
  fi
  ARGS+=("$name=$CACHE/models/$name.bin")
done

# 4. Run: build lines and checks to the log, results to pinocchio_codegen.txt.
LOG=$CACHE/pinocchio_codegen.log
{
  echo "# $(nproc) cores, $(lscpu | sed -n 's/^Model name:[[:space:]]*//p' | head -1); Pinocchio $("$VENV/bin/python" -c 'import pinocchio; print(pinocchio.__version__)'), CppADCodeGen 2.4.3, CppAD 20250000.2"
  echo "# generated C: $CG_CC $CG_CFLAGS ($("$CG_CC" --version | head -1)); calls=$CALLS reps=$REPS; ns per call of the generated function (ForwardZero)"
  echo "# robot           nv algo                 median_ns     min_ns"
} | tee "$LOG"
set +e
"$BIN" --calls "$CALLS" --reps "$REPS" --lib-dir "$CACHE/codegen" --cc "$CG_CC" --cflags "$CG_CFLAGS" "${ARGS[@]}" | tee -a "$LOG"
rc=${PIPESTATUS[0]}
set -e
grep -v '^#' "$LOG" > "$CACHE/pinocchio_codegen.txt" || true
[ "$rc" = 0 ] || { echo "pinocchio_codegen_bench failed (exit $rc); log: $LOG" >&2; exit "$rc"; }
echo "# written: $CACHE/pinocchio_codegen.txt (log: $LOG)"
