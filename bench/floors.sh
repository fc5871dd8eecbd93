#!/usr/bin/env bash
# What bounds a generated function below 20x the generic reference: the machine code of the
# copy this CPU runs counted, and the time its multiplications and its stores alone would take.
#
#   bash bench/floors.sh SIDE_BY_SIDE_OUTPUT [BENCH_BINARY]
#
# SIDE_BY_SIDE_OUTPUT: what the benchmark binary printed with SIDE_BY_SIDE set (README,
# "Where issue #12's bars stand"; lines `side-by-side LABEL FUNCTION ours reference ratio q1
# q3`). BENCH_BINARY: the binary that printed it (default: the newest
# target/bench-default/release/deps/dynamics-*). For every single-state cell below RATIO (20 by
# default) whose copy is found (`<module>::Robot::<function>_$COPY` of the f64 code; COPY defaults
# to the copy the dispatch runs here: avx512 on an AMD core with AVX-512, avx2 elsewhere, Intel's
# AVX-512 cores included), it disassembles the copy (objdump, Intel syntax) and prints:
#   instr, bytes      instructions and code bytes of the copy
#   mult              multiplication slots: vmul*/vfma*/vfnma*/vfms*/vfnms*, a 512-bit one twice
#                     (Zen 4 has two units, and a zmm operation takes both)
#   stores, spills    stores to memory (any width), of which to the stack ([rsp ...])
#   reloads           moves from the stack into a register (vmov* reg, [rsp ...]; a reload
#                     folded into an arithmetic instruction as its memory operand not counted)
#   lane              instructions that move values between lanes or registers' halves, build
#                     or take apart packs: shuffles, permutes, unpacks, blends, inserts,
#                     extracts, broadcasts and duplicates, and the sign flips and masks
#                     (vxorpd/vandpd and their integer forms) other than zeroing a register
#   memset            bytes zeroed by calls of memset (a result zeroed before its entries are
#                     written; the size from the `mov edx` before the call)
#   floor_mul         mult / 2 cycles, in ns at GHZ (default: the clock `bench/ports.rs`
#                     calibrates now, with a chain of dependent multiply-adds; run this right
#                     after the side-by-side run, as the machine's clock drifts)
#   floor_st          (stores + memset / 32) / STORES per cycle, in ns (default: the rate
#                     `bench/ports.rs` measures for stores into one cache line: 1 a cycle on
#                     Zen 3 and Zen 4, 2 on Intel's Emerald Rapids; the zeroing counted as
#                     32-byte stores)
#   floor_fetch       for a copy larger than a 32 KB instruction cache: bytes / FETCH, the
#                     rate straight-line code runs at from beyond the caches (bytes/ns;
#                     default: the `fetch:` line of `bench/ports.rs`, measured now; about 16
#                     bytes a cycle on the Zen 3). With OC=1 (the default for the AVX2 copies on
#                     an AMD core, where the op cache model below is the Zen 3's), also for a
#                     copy of whose op cache lines some miss at every call (`full`, below): the
#                     bytes of those lines / FETCH. `-` for other copies
#   at20              the reference's median / RATIO: the time the bar allows
#   needs             floor_mul / at20: the share of the multiplication units' peak the bar needs
#   reaches           floor_mul / ours: the share the copy reaches now
#   bound             "fetch", "stores" or "mult": the floors that exceed at20
#   oc_lines          lines of an AMD Zen 3 op cache the copy's code needs, by a model of its
#                     4K operations that fits what was measured: each 64-byte block of code
#                     takes one line per 8 instructions (ceil(n / 8)), 512 lines, 8 in each of
#                     64 sets (the block's address bits 6-11)
#   full              of those 64 sets, how many the copy fills to 8 lines or more by itself,
#                     and after the slash how many it overfills: a call walks through every
#                     line once, so in an overfilled set each line misses at every call (least
#                     recently used), and in a full one as soon as any other code run in the
#                     same loop (the caller's) lands there. Measured on a Zen 3: such a copy
#                     then runs from the decoders at the rate of its bytes, up to 45 % slower
#                     (docs/performance.md, the sixty-fourth session's section)
# A cell whose `needs` is near or above 100 %, or whose floor_st exceeds at20, cannot reach the
# bar with that machine code's operations; one whose `reaches` is far below `needs` has room.
# Counts are exact; the floors ignore everything else (latency, decoding, loads).
set -euo pipefail
SBS=${1:?usage: bash bench/floors.sh SIDE_BY_SIDE_OUTPUT [BENCH_BINARY]}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=${2:-$(ls -t "$ROOT"/target/bench-default/release/deps/dynamics-* 2>/dev/null | grep -v '\.d$' | sed -n 1p)}
[ -x "$BIN" ] || { echo "floors.sh: no benchmark binary (build it as the README says, or pass its path)" >&2; exit 1; }
command -v objdump >/dev/null || { echo "floors.sh: needs objdump (binutils)" >&2; exit 1; }
RATIO=${RATIO:-20}
SYMS=$(mktemp)
TMP=$(mktemp -d)
trap 'rm -rf "$SYMS" "$TMP"' EXIT
if [ -z "${GHZ:-}" ] || [ -z "${FETCH:-}" ] || [ -z "${STORES:-}" ]; then
  rustc -O --edition 2021 "$ROOT/bench/ports.rs" -o "$TMP/ports"
  "$TMP/ports" >"$TMP/ports.txt"
  GHZ=${GHZ:-$(awk '/^clock:/ { print $2; exit }' "$TMP/ports.txt")}
  FETCH=${FETCH:-$(awk '/^fetch:/ { print $2; exit }' "$TMP/ports.txt")}
  # "8 f64 stores (vmovsd), one cache line   <ns> ns   <cycles> cycles": 8 / cycles, rounded
  # to a whole number of stores per cycle.
  STORES=${STORES:-$(awk '/stores \(vmovsd\), one cache line/ { c = $(NF - 1); printf "%d", 8 / c + 0.5; exit }' "$TMP/ports.txt")}
  [ -n "$GHZ" ] && [ -n "$FETCH" ] && [ -n "$STORES" ] ||
    { echo "floors.sh: no clock, fetch or store rate from bench/ports.rs (x86-64 only); set GHZ, FETCH and STORES" >&2; exit 1; }
fi
AMD=0
grep -q '^vendor_id.*AuthenticAMD' /proc/cpuinfo 2>/dev/null && AMD=1
if [ -z "${COPY:-}" ]; then
  COPY=avx2
  [ "$AMD" = 1 ] && grep -q '^flags.* avx512f' /proc/cpuinfo 2>/dev/null && COPY=avx512
fi
if [ -z "${OC:-}" ]; then
  OC=0
  [ "$COPY" = avx2 ] && [ "$AMD" = 1 ] && OC=1
fi
echo "clock: $GHZ GHz; fetch beyond 32 KB$([ "$OC" = 1 ] && echo " or the op cache"): $FETCH bytes/ns; stores: $STORES per cycle; copies: _$COPY; bar: ${RATIO}x; binary: $BIN"
nm -S --demangle "$BIN" | awk '$3 == "T" || $3 == "t"' >"$SYMS"

# The module a side-by-side label's code is in (tests/src/generated.rs).
module_of() {
  for m in "urdf_$1" "tree_$1" "$1"; do
    if grep -q " dynamics_tests::generated::$m::Robot::" "$SYMS"; then
      echo "$m"
      return
    fi
  done
}

printf '%-18s %-30s %6s %6s %5s %6s %6s %7s %5s %6s %9s %8s %11s %6s %6s %6s %7s %8s %7s %s\n' \
  robot function instr bytes mult stores spills reloads lane memset floor_mul floor_st floor_fetch at20 ours needs reaches oc_lines full bound
awk -F'\t' -v r="$RATIO" '$1 == "side-by-side" && $3 !~ /_x[0-9]+$/ && $6 + 0 < r + 0 { print $2, $3, $4, $5 }' "$SBS" |
  while read -r label fn ours reference; do
    m=$(module_of "$label")
    line=$([ -n "$m" ] && grep " dynamics_tests::generated::$m::Robot::${fn}_$COPY\$" "$SYMS" || true)
    if [ -z "$line" ]; then
      printf '%-18s %-30s (no %s_%s symbol: not dispatched, or inlined into the benchmark)\n' "$label" "$fn" "$fn" "$COPY"
      continue
    fi
    read -r start size _ <<<"$line"
    objdump -d --no-show-raw-insn -M intel --start-address=$((16#$start)) \
      --stop-address=$((16#$start + 16#$size)) "$BIN" |
      awk -F'\t' -v label="$label" -v fn="$fn" -v bytes=$((16#$size)) -v ghz="$GHZ" -v fetch="$FETCH" -v spc="$STORES" \
        -v ours="$ours" -v ref="$reference" -v r="$RATIO" -v oc="$OC" '
        NF >= 2 && $1 ~ /^ *[0-9a-f]+:$/ {
          n++
          a = $1
          gsub(/[ :]/, "", a)
          block[int(hex(a) / 64)]++
          split($2, w, " ")
          op = w[1]
          args = substr($2, length(op) + 1)
          if (op ~ /^v(mul|fn?madd|fn?msub)/) mult += (args ~ /zmm/) ? 2 : 1
          # Intel syntax: a store writes its first operand, a memory reference.
          if (args ~ /^ *[A-Z]+ PTR \[/ && op !~ /^(cmp|test|prefetch)/) {
            stores++
            if (args ~ /^ *[A-Z]+ PTR \[rsp/) spills++
          } else if (op ~ /^v?mov/ && args ~ /PTR \[rsp/) reloads++
          if (op ~ /^v(shuf|perm|unpck|blend|pblend|insert|extract|broadcast|pbroadcast|movddup|movlhps|movhlps|movhpd|movlpd)/ ||
              (op ~ /^v(xorp|andp|andnp|pxor|pand|pandn)/ && !(split(args, o, ",") == 3 && o[1] == o[2] && o[2] == o[3])))
            lane++
          if (op == "mov" && args ~ /^ *edx,0x[0-9a-f]+$/) edx = substr(args, index(args, "0x") + 2)
          if (op == "call" && args ~ /memset/) memset += hex(edx)
        }
        function hex(h,   i, v) {
          v = 0
          for (i = 1; i <= length(h); i++) v = 16 * v + index("0123456789abcdef", substr(h, i, 1)) - 1
          return v
        }
        END {
          fm = mult / 2 / ghz
          fs = (stores + memset / 32) / spc / ghz
          at = ref / r
          for (b in block) {
            l = int((block[b] + 7) / 8)
            lines += l
            set[b % 64] += l
          }
          for (k in set) {
            if (set[k] >= 8) full++
            if (set[k] > 8) { over++; missed += set[k] }
          }
          ff = bytes > 32768 ? bytes / fetch : (oc && missed ? bytes * missed / lines / fetch : 0)
          bound = (ff > at ? " fetch" : "") (fs > at ? " stores" : "") (fm > at ? " mult" : "")
          printf "%-18s %-30s %6d %6d %5d %6d %6d %7d %5d %6d %9.1f %8.1f %11s %6.1f %6.1f %5.0f%% %6.0f%% %8d %7s %s\n",
            label, fn, n, bytes, mult, stores, spills, reloads, lane, memset, fm, fs,
            (ff > 0 ? sprintf("%.1f", ff) : "-"), at, ours, 100 * fm / at, 100 * fm / ours,
            lines, full + 0 "/" over + 0, substr(bound, 2)
        }'
  done
