#!/usr/bin/env bash
# Regenerates tests/fixtures/movenet/{manifest,tfjs_reference}.json: the C++ test writes the
# network inputs it builds (as PNGs), TF.js (wasm backend) runs the three MoveNet models on them.
# Needs a release build (cmake --build --preset release) and scripts/setup.sh (models, npm).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
inputs="$(mktemp -d)"
trap 'rm -rf "$inputs"' EXIT
WHEELPOSE_WRITE_TFJS_INPUTS="$inputs" "$root/build/release/src/learn/learn_test" \
  --gtest_filter=ReferenceInputs.Write
(cd "$root/tests/tfjs_reference" &&
  node reference.mjs --models "$root/models" --inputs "$inputs/manifest.json" \
    --out "$inputs/tfjs_reference.json" --backend wasm --threads "${THREADS:-2}" \
    --time-runs "${TIME_RUNS:-10}")
cp "$inputs/manifest.json" "$inputs/tfjs_reference.json" "$root/tests/fixtures/movenet/"
echo "make_fixture: wrote tests/fixtures/movenet/manifest.json and tfjs_reference.json"
