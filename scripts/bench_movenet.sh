#!/usr/bin/env bash
# MoveNet inference side by side in one run: our LibTorch path (bench/learn_bench.cpp) and the
# real TF.js runtime (wasm backend, tests/tfjs_reference) on the same network inputs, with the
# same thread count. Prints one Markdown table: ms per image for each model and input size.
# The C++ figure includes letterboxing/cropping and decoding; TF.js's is the graph run alone.
# Needs a release build and scripts/setup.sh (models, npm packages).
# usage: scripts/bench_movenet.sh [THREADS (default 2)] [RUNS (default 20)]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
threads="${1:-2}"
runs="${2:-20}"
bench="$root/build/release/bench/bench_learn"
[[ -x "$bench" ]] || { echo "bench_movenet: $bench is missing: cmake --build --preset release" >&2; exit 1; }
[[ -d "$root/tests/tfjs_reference/node_modules" ]] ||
  { echo "bench_movenet: TF.js packages missing: run scripts/setup.sh" >&2; exit 1; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

"$bench" --write-tfjs-inputs "$work/inputs"
(cd "$root/tests/tfjs_reference" &&
  node reference.mjs --models "$root/models" --inputs "$work/inputs/manifest.json" \
    --out "$work/tfjs.json" --backend wasm --threads "$threads" --time-runs "$runs") >&2
WHEELPOSE_BENCH_THREADS="$threads" "$bench" --benchmark_format=json \
  --benchmark_min_time=2 >"$work/ours.json"

echo "| model | input | LibTorch ms | TF.js wasm ms | speed-up |"
echo "|---|---|---:|---:|---:|"
jq -r --slurpfile ours "$work/ours.json" '
  .entries[] as $e
  | ($e.file | rtrimstr(".png") | sub("_(?<s>[^_]+)$"; "/\(.s)")) as $name
  | ($ours[0].benchmarks[] | select((.name | split("/real_time")[0]) == $name) | .real_time) as $cpp
  | "| \($e.model) | \($e.input_shape[2])×\($e.input_shape[1]) | \($cpp * 100 | round / 100) | \($e.ms_per_run * 100 | round / 100) | \($e.ms_per_run / $cpp * 10 | round / 10)× |"
' "$work/tfjs.json"
echo
echo "threads: $threads; TF.js: median of $runs runs; LibTorch: Google Benchmark mean, $(nproc) cores present"
