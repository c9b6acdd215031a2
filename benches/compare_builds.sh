#!/usr/bin/env bash
# The cost of one filter step in three builds of the same source, measured in one run on this
# machine (docs/speed.md, "One build for every x86-64"):
#   portable   the default build (plain x86-64; the hot kernels' AVX2 + FMA copies chosen at
#              run time, navkf_dynamics::instruction_set), as the wheel and `cargo install`;
#   baseline   the same binary with NAVKF_SIMD=baseline (the plain copies only: an x86-64
#              without AVX2);
#   native     built with RUSTFLAGS="-C target-cpu=native" (into target/native).
# Each round runs step_timing and strapdown_step once per build, interleaved, so that a
# machine that speeds up or slows down affects all three alike; the table gives, per filter,
# the median over rounds of each build's median step, and the ratios to native.
#
#   benches/compare_builds.sh [ROUNDS] [SECONDS]      (defaults 5 rounds of 1 s per filter)
#
# The first run compiles both builds (about 5 minutes on 2 cores).
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-5}
seconds=${2:-1}
examples=(--example step_timing --example strapdown_step)
cargo build --release -q -p navkf-benches "${examples[@]}"
RUSTFLAGS="-C target-cpu=native" CARGO_TARGET_DIR=target/native \
    cargo build --release -q -p navkf-benches "${examples[@]}"

out=$(mktemp)
trap 'rm -f "$out"' EXIT
# One line per measurement: build, model, filter, microseconds.
measure() {
    local build=$1 dir=$2
    shift 2
    env "$@" "$dir/step_timing" all "$seconds" |
        awk -v b="$build" '$2 == "median" { print b, "platform", $1, $3 }'
    env "$@" "$dir/strapdown_step" "$seconds" |
        awk -v b="$build" 'NR > 1 { print b, "strapdown", $1, $4 }'
}
for r in $(seq "$rounds"); do
    measure portable target/release/examples >>"$out"
    measure baseline target/release/examples NAVKF_SIMD=baseline >>"$out"
    measure native target/native/release/examples >>"$out"
    echo "round $r of $rounds done" >&2
done

echo "CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), $(nproc) cores"
echo "rounds: $rounds, ${seconds} s per filter per round; microseconds per predict + update"
python3 - "$out" <<'SUMMARY'
import statistics, sys
runs = {}
for line in open(sys.argv[1]):
    build, model, name, us = line.split()
    runs.setdefault((model, name), {}).setdefault(build, []).append(float(us))
print(f"{'model / filter':28} {'native':>9} {'portable':>9} {'baseline':>9} {'port/nat':>9} {'base/nat':>9}")
for (model, name), by in runs.items():
    nat, por, bas = (statistics.median(by[b]) for b in ("native", "portable", "baseline"))
    print(f"{model + ' / ' + name:28} {nat:9.2f} {por:9.2f} {bas:9.2f} {por / nat:9.3f} {bas / nat:9.3f}")
SUMMARY
