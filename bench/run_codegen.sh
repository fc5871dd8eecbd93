#!/usr/bin/env bash
# Pinocchio's code-generated rnea, crba, aba and derivatives (CppADCodeGen) timed on this machine; see bench/README.md.
#   bash bench/run_codegen.sh
#   ROBOTS="ur5" CALLS=20000 REPS=3 bash bench/run_codegen.sh
# Environment: ROBOTS (default "ur5 panda rand7": fixed-base URDFs in tests/data/robots or its trees/, or
# NAME=PATH.urdf for any other file),
# CALLS (100000), REPS (5), CG_CC (C compiler for the generated code, default gcc),
# CG_CFLAGS_SETS (the flag sets the generated C is compiled with, '|'-separated, default
# "-O3 -march=native|-Ofast": Pinocchio's compileLib uses -Ofast; each function is reported with the faster),
# CG_CFLAGS (one flag set instead of those), CG_ROUNDS (2: the sets run in turn this many times, and each
# function keeps its lowest median, which is generous to Pinocchio on a noisy machine), CXX (for the benchmark
# program, default g++).
# Output: ~/.cache/dynamics-gen-bench/pinocchio_codegen.txt ("robot nv algo median_ns min_ns", the best flag set's
# times per function), every flag set's times with its flags in pinocchio_codegen_by_flags.txt, the full log
# (build times, checks, which flags won) beside it in pinocchio_codegen.log.
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
if [ -n "${CG_CFLAGS:-}" ]; then CG_CFLAGS_SETS=$CG_CFLAGS; fi
IFS='|' read -r -a FLAG_SETS <<< "${CG_CFLAGS_SETS:-"-O3 -march=native|-Ofast"}"
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
#    flag set and robot (codegen/<flags>/<robot>/), cleared when the model, the program or the C compiler and
#    flags change.
ARGS=()
NAMES=()
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
  ARGS+=("$name=$CACHE/models/$name.bin")
  NAMES+=("$name")
done
# The folder name of a flag set: its flags with every run of other characters than letters, digits, '.', '_'
# and '=' turned into one '_' ("-O3 -march=native" -> "_O3_march=native").
slug() { printf '%s' "$1" | tr -cs 'A-Za-z0-9._=' '_'; }

# 4. Run each flag set in turn, CG_ROUNDS times: build lines and checks to the log, each run's results with its
#    flags to pinocchio_codegen_by_flags.txt, and per function the lowest median to pinocchio_codegen.txt.
LOG=$CACHE/pinocchio_codegen.log
BY_FLAGS=$CACHE/pinocchio_codegen_by_flags.txt
{
  echo "# $(nproc) cores, $(lscpu | sed -n 's/^Model name:[[:space:]]*//p' | head -1); Pinocchio $("$VENV/bin/python" -c 'import pinocchio; print(pinocchio.__version__)'), CppADCodeGen 2.4.3, CppAD 20250000.2"
  echo "# generated C: $CG_CC ($("$CG_CC" --version | head -1)) with each of: $(printf '"%s" ' "${FLAG_SETS[@]}"); calls=$CALLS reps=$REPS; ns per call of the generated function (ForwardZero)"
} > "$LOG"
: > "$BY_FLAGS"
for round in $(seq "${CG_ROUNDS:-2}"); do
for flags in "${FLAG_SETS[@]}"; do
  libs=$CACHE/codegen/$(slug "$flags")
  for name in "${NAMES[@]}"; do
    key=$( { cat "$CACHE/models/$name.bin"; echo "$KEY"; "$CG_CC" --version; echo "$CG_CC $flags"; } | sha256sum | cut -c1-16)
    d=$libs/$name
    if [ "$(cat "$d/key" 2>/dev/null)" != "$key" ]; then
      rm -rf "$d"
      mkdir -p "$d"
      echo "$key" > "$d/key"
    fi
  done
  { echo "# flags: $flags (round $round)"; echo "# robot           nv algo                 median_ns     min_ns"; } | tee -a "$LOG"
  set +e
  "$BIN" --calls "$CALLS" --reps "$REPS" --lib-dir "$libs" --cc "$CG_CC" --cflags "$flags" "${ARGS[@]}" > "$CACHE/codegen/run.txt"
  rc=$?
  set -e
  tee -a "$LOG" < "$CACHE/codegen/run.txt"
  [ "$rc" = 0 ] || { echo "pinocchio_codegen_bench failed with \"$flags\" (exit $rc); log: $LOG" >&2; exit "$rc"; }
  grep -v '^#' "$CACHE/codegen/run.txt" | sed "s|\$| $flags|" >> "$BY_FLAGS" || true
done
done
# Per robot and function the lowest median of any run, in the order of the first run's lines.
awk '{ k = $1 " " $3; f = $6; for (i = 7; i <= NF; i++) f = f " " $i
       if (!(k in best)) order[n++] = k
       if (!(k in best) || $4 + 0 < best[k]) { best[k] = $4 + 0; row[k] = sprintf("%-18s %2s %-20s %10s %10s", $1, $2, $3, $4, $5); won[k] = f } }
     END { for (i = 0; i < n; i++) { print row[order[i]] > out; print "# best " order[i] ": " won[order[i]] } }' \
  out="$CACHE/pinocchio_codegen.txt" "$BY_FLAGS" | tee -a "$LOG"
echo "# written: $CACHE/pinocchio_codegen.txt, $BY_FLAGS (log: $LOG)"
