#!/bin/bash
# runvariant.sh SRC_COMPARE_DIR OUT_DIR [SED_EXPR]: re-runs the cooperative configs of a
# `hopnav compare` folder with $BIN (default: this checkout's release build), optionally
# editing each config with sed, JOBS at a time (default 1). Pair the results with the
# folder's rover-only runs: tools/paired.py SRC_COMPARE_DIR OUT_DIR.
set -u
src=$1; out=$2; sedexpr=${3:-}
root=$(cd "$(dirname "$0")/.." && pwd)
BIN=${BIN:-$root/target/release/hopnav}; JOBS=${JOBS:-1}
mkdir -p "$out/cfg"
for d in "$src"/*/; do
  [ -f "$d/config.toml" ] && grep -q '^mode = "cooperative"' "$d/config.toml" || continue
  name=$(basename "$d")
  cfg="$out/cfg/$name.toml"
  if [ -n "$sedexpr" ]; then sed "$sedexpr" "$d/config.toml" > "$cfg"; else cp "$d/config.toml" "$cfg"; fi
  sed -i "s#^out_dir = .*#out_dir = \"$out\"#" "$cfg"
  echo "$cfg"
done | xargs -P "$JOBS" -I{} sh -c "cd '$root' && '$BIN' launch {} > {}.log 2>&1"
echo done
