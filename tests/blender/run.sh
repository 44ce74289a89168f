#!/usr/bin/env bash
# CTest `blender_import` (label `blender`): exports seated clips with `wheelpose motion` as fbx,
# glb and bvh, converts every fbx with FBX2glTF (npm fbx2gltf, built on the Autodesk FBX SDK: the
# reader Unity and Autodesk tools use) to <clip>.sdk.glb sampled at 60 fps, then imports every
# file into Debian's Blender (headless) with check_imports.py. Then a dressed person with a cane,
# rigged and animated by one of those clips (`body export --rigged`) as glb and as binary FBX, and
# the FBX as FBX2glTF reads it, are imported and checked against the same person's static exports
# at two frames with check_rigged_person.py.
# Usage: run.sh WHEELPOSE_BINARY SHARED_DIR
# Exits 77 (CTest: skipped) when blender is not installed, except under CI, where that fails; the
# same for FBX2glTF (`npm ci` in tests/blender, which scripts/setup.sh runs).
set -euo pipefail
wheelpose=$1
shared=$2
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

if ! command -v blender >/dev/null 2>&1; then
  if [ -n "${CI:-}" ]; then
    echo "blender_import: blender is not installed (scripts/setup.sh installs it)"
    exit 1
  fi
  echo "blender_import skipped: blender is not installed (apt-get install blender, or scripts/setup.sh)"
  exit 77
fi

out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
# The 59 library clips at 30 fps (seed 3) and a 120 fps CMU BVH of 994 frames (8.275 s).
"$wheelpose" -q motion library --out "$out" --seed 3 --exports json,glb,bvh,fbx
"$wheelpose" -q motion convert "$shared/data/bvh/131_01.bvh" --out "$out" \
  --exports json,glb,bvh,fbx
fbx2gltf="$here/node_modules/fbx2gltf/bin/Linux/FBX2glTF"
if [ -f "$fbx2gltf" ]; then
  # The npm package ships the binary without its execute bit.
  [ -x "$fbx2gltf" ] || chmod +x "$fbx2gltf"
  for fbx in "$out"/*.fbx; do
    "$fbx2gltf" --binary --anim-framerate bake60 --input "$fbx" --output "${fbx%.fbx}.sdk" \
      >"$out/fbx2gltf.log" 2>&1 || { cat "$out/fbx2gltf.log"; echo "FBX2glTF failed on $fbx"; exit 1; }
  done
elif [ -n "${CI:-}" ]; then
  echo "blender_import: FBX2glTF is missing (run npm ci in tests/blender; scripts/setup.sh does)"
  exit 1
else
  echo "blender_import: FBX SDK check skipped: FBX2glTF is missing (npm ci in tests/blender)"
fi
status=0
blender -b --factory-startup --python "$here/check_imports.py" -- "$out" || status=1

person=(--seed 4 --assets "$shared/assets" --params wheelchair=manual mobility_aid=cane
        wear=clothes/male_casualsuit01 wear=clothes/shoes01 wear=hair/short02)
clip="$out/basketball_chest_pass.json"
"$wheelpose" -q body export --rigged "${person[@]}" --clip "$clip" --out "$out/person.glb"
"$wheelpose" -q body export --rigged "${person[@]}" --clip "$clip" --out "$out/person.fbx"
rigged=("$out/person.glb" "$out/person.fbx")
if [ -f "$fbx2gltf" ]; then
  "$fbx2gltf" --binary --anim-framerate bake60 --input "$out/person.fbx" \
    --output "$out/person.sdk" >"$out/fbx2gltf.log" 2>&1 ||
    { cat "$out/fbx2gltf.log"; echo "FBX2glTF failed on person.fbx"; exit 1; }
fi
# Frame 40 of a 30 fps clip is a whole frame (32) of Blender's default 24 fps scene.
for frame in 0 40; do
  "$wheelpose" -q body export "${person[@]}" --clip "$clip" --frame "$frame" \
    --out "$out/person_$frame.glb"
done
statics=("$out/person_0.glb" 0 "$out/person_40.glb" 40)
for file in "${rigged[@]}"; do
  blender -b --factory-startup --python "$here/check_rigged_person.py" -- "$file" "$clip" \
    "${statics[@]}" || status=1
done
if [ -f "$out/person.sdk.glb" ]; then
  blender -b --factory-startup --python "$here/check_rigged_person.py" -- "$out/person.sdk.glb" \
    "$clip" "${statics[@]}" --baked60 || status=1
fi
exit $status
