#!/usr/bin/env bash
# Per-process start-up benchmark of the prepared-map cache (issue 32): wall time of whole `m2rc
# eval` and `m2rc compile` processes on the largest map of a suite (its first episode: the gold
# route scored, the gold program compiled), and of the Hard fixture program on house 149 imported
# as a Map2Route map, each with the cache off and on (second use). A benchmark, not a test: it
# prints min / median / max milliseconds and checks nothing.
#
#   cargo build --release -p m2rc
#   scripts/startup-bench.sh SUITE_DIR [RUNS]      (RUNS defaults to 10)
#
# M2RC picks the binary (default target/release/m2rc). Run it on an idle machine: the figures are
# wall clock, and docs/maps.md gives the last ones measured with the machine's load.
set -euo pipefail

suite=${1:?usage: scripts/startup-bench.sh SUITE_DIR [RUNS]}
runs=${2:-10}
here=$(cd "$(dirname "$0")/.." && pwd)
bin=${M2RC:-$here/target/release/m2rc}
[ -x "$bin" ] || { echo "no $bin: run cargo build --release -p m2rc first" >&2; exit 2; }
house="$here/../shared/procthor/fixtures/procthor10k_uniform_hard_val_150_149.json"
program="$here/planner/benches/house149_hard.m2r"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cache="$work/map-cache"

# The largest map of the suite, its first episode and that episode's gold program.
map=$(ls -S "$suite"/maps/*/*.json | head -n 1)
scene=$(basename "$(dirname "$map")")
episode=$(ls "$suite/instructions/$scene/instruction_files/"*.json | sort | head -n 1)
gold="$suite/programs/$scene/$(basename "$episode" .json).m2r"
M2RC_MAP_CACHE=off "$bin" compile --map "$map" --episode "$episode" "$gold" \
    -o "$work/route.json" >/dev/null
"$bin" map import "$house" -o "$work/h149.json" >/dev/null 2>&1

# min / median / max wall milliseconds of RUNS runs of a command.
timed() {
    local ts=() s e
    for _ in $(seq "$runs"); do
        s=$(date +%s%N)
        "$@" >/dev/null 2>&1
        e=$(date +%s%N)
        ts+=($(((e - s) / 1000000)))
    done
    printf '%s\n' "${ts[@]}" | sort -n |
        awk '{a[NR] = $1} END {printf "min %d  median %d  max %d ms\n", a[1], a[int((NR + 1) / 2)], a[NR]}'
}

eval_cmd=("$bin" eval --map "$map" --episode "$episode" --route "$work/route.json")
compile_cmd=("$bin" compile --map "$work/h149.json" "$program")
gold_cmd=("$bin" compile --map "$map" --episode "$episode" "$gold")
n=$(sed -n 's/.*"grid_size": *\([0-9]*\).*/\1/p' "$map" | head -n 1)
echo "binary:  $bin ($(git -C "$here" rev-parse --short HEAD 2>/dev/null || echo unknown))"
echo "load:    $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo unknown)"
echo "eval:    $scene ($n x $n, $(($(stat -c %s "$map") / 1000000)) MB), $(basename "$episode"), its gold route"
echo "compile: $(basename "$program") on house 149 as a Map2Route map"
echo "gold:    compile of that episode's gold program on $scene"

# The entries are written on first use; an identity younger than 3 s is checked by the source's
# full CRC (docs/maps.md), so wait that out before the cached runs.
for cmd in eval compile gold; do
    declare -n c="${cmd}_cmd"
    printf '%-8s cache off     ' "$cmd"
    M2RC_MAP_CACHE=off timed "${c[@]}"
    M2RC_MAP_CACHE="$cache" "${c[@]}" >/dev/null 2>&1
done
sleep 4
for cmd in eval compile gold; do
    declare -n c="${cmd}_cmd"
    printf '%-8s cache on      ' "$cmd"
    M2RC_MAP_CACHE="$cache" timed "${c[@]}"
done
