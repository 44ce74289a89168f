#!/usr/bin/env bash
# CTest `gltf_validator`: every kind of glb wheelpose writes — seated clips (`motion library`), a
# static dressed person with a mobility aid, the same person rigged and animated by a clip
# (`body export --rigged`), a person standing without a wheelchair, an empty wheelchair — is
# checked by the Khronos glTF validator (npm gltf-validator, installed by `npm ci` in
# tests/blender, which scripts/setup.sh runs); any error fails the test.
# Usage: validate.sh WHEELPOSE_BINARY SHARED_DIR
# Exits 77 (CTest: skipped) when node or the validator is missing, except under CI.
set -euo pipefail
wheelpose=$1
shared=$2
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

if ! command -v node >/dev/null 2>&1 || [ ! -d "$here/node_modules/gltf-validator" ]; then
  if [ -n "${CI:-}" ]; then
    echo "gltf_validator: node or npm gltf-validator is missing (npm ci in tests/blender)"
    exit 1
  fi
  echo "gltf_validator skipped: npm gltf-validator is missing (npm ci in tests/blender, or scripts/setup.sh)"
  exit 77
fi

out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
"$wheelpose" -q motion library --out "$out" --seed 3 --exports json,glb
person=(--seed 4 --assets "$shared/assets" --params mobility_aid=crutches
        wear=clothes/female_casualsuit01 wear=clothes/shoes01 wear=hair/bob01)
clip="$out/basketball_chest_pass.json"
"$wheelpose" -q body export "${person[@]}" --clip "$clip" --frame 10 --out "$out/person.glb"
"$wheelpose" -q body export --rigged "${person[@]}" --clip "$clip" --out "$out/person_rigged.glb"
"$wheelpose" -q body export --rigged --seed 6 --assets "$shared/assets" \
  --params wheelchair=none mobility_aid=walker --clip "$clip" --out "$out/standing_rigged.glb"
"$wheelpose" -q body export --empty-wheelchair --seed 2 --out "$out/chair.glb"
node "$here/validate_glb.js" "$out"/*.glb
