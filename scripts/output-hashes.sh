#!/usr/bin/env bash
# Hashes of what wheelpose writes for a fixed set of small runs, for refactors that must not
# change a byte (issue 23): generate (wall and room scenes, HDRI, standing people), render (the
# example scenes at several sample counts, adaptive on and off, 1 and 2 threads), body exports
# (static, posed by a clip, rigged glb and FBX, empty chair, contact sheet), a keypoint CSV import,
# stats and eval. Run it with the binary before and after a change and diff the two lists.
#
# usage: scripts/output-hashes.sh [WHEELPOSE_BINARY] [OUT_DIR]   (defaults: build/release/wheelpose,
#        a temporary folder); prints "<sha256>  <file>" lines sorted by file, and a digest line.
# Needs the shared data (../shared beside the checkout, or $WHEELPOSE_SHARED_DIR). About 1 minute
# on 2 cores.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
wp="$(realpath "${1:-$root/build/release/wheelpose}")"
out="${2:-$(mktemp -d)}"
shared="${WHEELPOSE_SHARED_DIR:-$root/../shared}"
[[ -d $shared/assets ]] || shared=/work/shared
rm -rf "$out" && mkdir -p "$out"
cd "$out"
assets=(--assets "$shared/assets")
quiet() { "$wp" -q "$@" >/dev/null; }

quiet generate --out gen --frames 12 --seed 7
quiet generate --out stand --frames 6 --seed 9 --config "$root/configs/boost-standing.yaml" \
  --clips-from "$root/configs/boost-test-clips.json"
printf 'image:\n  spp: 8\n  light_samples: 2\nrandomizers:\n  Environment:\n    room_probability: 1.0\n    hdri_probability: 0.5\n' >rooms.yaml
quiet generate --out rooms --frames 6 --seed 3 --config rooms.yaml
for scene in sphere_on_floor textured_room; do
  quiet render "$root/data/scenes/$scene.json" --out "render/$scene-a" --spp 16 --light-samples 4 --threads 2
  quiet render "$root/data/scenes/$scene.json" --out "render/$scene-b" --spp 8 --light-samples 8 \
    --threads 1 --adaptive-contrast -1
  quiet render "$root/data/scenes/$scene.json" --out "render/$scene-c" --spp 32 --light-samples 2 \
    --threads 2 --adaptive-contrast 0.1
done

quiet motion library --out lib --seed 3 --exports json,glb,bvh,fbx
clip=lib/basketball_chest_pass.json
mkdir -p body
for s in 1 2 3 11; do quiet body export --seed "$s" "${assets[@]}" --out "body/p$s.glb"; done
quiet body export --seed 4 "${assets[@]}" --params mobility_aid=cane wear=clothes/male_casualsuit01 \
  --clip "$clip" --frame 40 --out body/clip.glb
quiet body export --seed 5 "${assets[@]}" --params wheelchair=none mobility_aid=walker --out body/standing.glb
for ext in glb fbx; do
  quiet body export --rigged --seed 4 "${assets[@]}" --params mobility_aid=cane wear=clothes/shoes01 \
    --clip "$clip" --out "body/rigged.$ext"
done
quiet body export --empty-wheelchair --seed 2 --params wheelchair=sport --out body/chair.glb
quiet body sample --out body/sample --count 4 --seed 8 "${assets[@]}"

# The library clip's positions as a wide keypoint CSV, read back through the CSV importer.
jq -r '(.skeleton.joints | map(. as $j | ["\($j)_x", "\($j)_y", "\($j)_z"]) | flatten
        | "# fps: 30\nframe," + join(",")),
       (.positions | to_entries[] | "\(.key)," + (.value | flatten | map(tostring) | join(",")))' \
  "$clip" >keypoints.csv
quiet motion convert keypoints.csv --out csv --exports json,bvh

quiet stats gen/annotations.json --out stats --label gen --reference \
  "$shared/data/coco-sample/person_keypoints_sample.json"
# Detections: the ground truth with fixed offsets, scored against it with a baseline.
for k in 1 2; do
  jq --argjson k "$k" '[.annotations[] | {image_id, category_id: 1, bbox, score: (.id % 7 / 7),
      keypoints: (.keypoints | to_entries | map(if .key % 3 == 2 then 1 else .value + $k * (.key % 5) end))}]' \
    gen/annotations.json >"dt$k.json"
done
quiet eval --gt gen/annotations.json --dt dt1.json --baseline dt2.json --type both --out eval

find . -type f ! -name '*.log' ! -name rooms.yaml ! -name hashes.txt -print0 | sort -z | xargs -0 sha256sum >hashes.txt
cat hashes.txt
echo "digest $(awk '{print $1}' hashes.txt | sha256sum | cut -c1-16) over $(wc -l <hashes.txt) files"
