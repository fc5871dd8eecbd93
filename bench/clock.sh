# Sourced by bench/run.sh and bench/unseen.sh (after CACHE and HERE are set): `clock LABEL` prints
# "# clock, LABEL: … GHz (…)", the core's clock by bench/ports.rs' multiply-add chains (a
# quarter of a second). On a shared host the clock moves between runs, and the ratios with it (the
# generic reference slows more than the generated code when it falls), so each table says
# what it was. x86-64 only; elsewhere, or if rustc cannot build it, nothing is printed.
clock() {
  [ "$(uname -m)" = x86_64 ] || return 0
  local ports=$CACHE/ports
  if [ ! -x "$ports" ] || [ "$HERE/ports.rs" -nt "$ports" ]; then
    rustc -O --edition 2021 "$HERE/ports.rs" -o "$ports.tmp" 2>/dev/null && mv "$ports.tmp" "$ports" || return 0
  fi
  local line
  line=$("$ports" --clock) || return 0
  echo "# clock, $1: ${line#clock: }"
}
