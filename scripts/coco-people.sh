#!/usr/bin/env bash
# Real people with keypoints, rebuilt from public GitHub copies of COCO val2017, keeping only the
# images whose Flickr licence lets us use them: Attribution (4), Attribution-ShareAlike (5),
# No known copyright restrictions (7) and United States Government Work (8). Images under any
# other licence (1, 2, 3, 6) are never copied. Nothing here is committed: the sets are built
# into OUT.
#
# Each set is a folder as `wheelpose generate` writes one (annotations.json beside images/), so
# `wheelpose realism OUT/test`, `train --train OUT/rehearsal/annotations.json` and `predict
# --coco OUT/test/annotations.json --images OUT/test/images` find the images.
#   OUT/test/annotations.json   the real-people test: single-person images with the official
#                               person-keypoint ground truth (COCO annotations, CC BY 4.0)
#   OUT/test/seated.json        the test images whose captions say sit, sits, sitting, seated or
#                               sat in at least two of their five (same images/ folder)
#   OUT/rehearsal/annotations.json
#                               the rehearsal set for training: the multi-person images with
#                               YOLO-pose labels (read with `coco import-yolo`, kept in labels/).
#                               Those labels hold only people with keypoints, so the people
#                               the pretrained model finds that no label covers are added as
#                               crowd regions (iscrowd 1), which training ignores.
#   OUT/CREDITS.md              every image with its licence and Flickr address
#
# Sources (each a checkout or the bare git directory the tool library's fetch brings):
#   IMAGES    minto5z/coco_yolo: coco/images/val2017/ (1,045 single-person images) and
#             coco/images/train2017/ (despite its name, more val2017 images), and
#             coco/annotations/instances_val2017.json (the official ground truth of the 1,045)
#   LABELS    Jar-17/yolov7_for_baseball: labels/val2017/ (YOLO-pose labels of val2017)
#   CAPTIONS  ruizewang/evaluate: annotations/captions_val2017.json (every val2017 image's
#             licence and size, and five captions each)
#
# usage: scripts/coco-people.sh IMAGES LABELS CAPTIONS [OUT]   (OUT default out/coco-people)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
wp="$root/build/release/wheelpose"
[[ $# -ge 3 ]] || { sed -n '2,33p' "$0"; exit 2; }
images_src=$1 labels_src=$2 captions_src=$3 out=${4:-out/coco-people}
[[ -x "$wp" ]] || { echo "coco-people: $wp is missing: cmake --build --preset release" >&2; exit 1; }
command -v jq >/dev/null || { echo "coco-people: jq is missing (scripts/setup.sh)" >&2; exit 1; }
if [[ -f "$out/test/annotations.json" && -f "$out/test/seated.json" &&
      -f "$out/rehearsal/annotations.json" ]]; then
  echo "coco-people: $out is complete" >&2
  exit 0
fi

# Copies PATHS (files or folders) of a checkout or git directory SRC into DEST, keeping paths.
extract() {
  local src=$1 dest=$2
  shift 2
  mkdir -p "$dest"
  if [[ -e "$src/$1" ]]; then
    for p in "$@"; do
      [[ -e "$src/$p" ]] || { echo "coco-people: $src/$p: missing" >&2; exit 2; }
      mkdir -p "$dest/$(dirname "$p")"
      cp -r "$src/$p" "$dest/$(dirname "$p")/"
    done
  elif git --git-dir="$src" rev-parse --verify -q HEAD >/dev/null 2>&1; then
    for p in "$@"; do
      mkdir -p "$dest/$(dirname "$p")"
      # By the path's own object, so blobs elsewhere that a partial mirror lacks are not read.
      case "$(git --git-dir="$src" cat-file -t "HEAD:$p" 2>/dev/null)" in
        blob) git --git-dir="$src" cat-file blob "HEAD:$p" >"$dest/$p" ;;
        tree) git --git-dir="$src" archive --prefix="$p/" "HEAD:$p" | tar -x -C "$dest" ;;
        *) echo "coco-people: $src: no $p in its HEAD" >&2; exit 2 ;;
      esac
    done
  else
    echo "coco-people: $src: neither a checkout with $1 nor a git directory" >&2
    exit 2
  fi
}

scratch="$out.partial"
rm -rf "$scratch"
mkdir -p "$scratch/src" "$scratch/test/images" "$scratch/rehearsal/images" \
  "$scratch/rehearsal/labels"
extract "$captions_src" "$scratch/src" annotations/captions_val2017.json
extract "$images_src" "$scratch/src" coco/annotations/instances_val2017.json
extract "$labels_src" "$scratch/src" labels/val2017
extract "$images_src" "$scratch/src" coco/images/val2017 coco/images/train2017
captions="$scratch/src/annotations/captions_val2017.json"
official="$scratch/src/coco/annotations/instances_val2017.json"

# The licences we may use, and every allowed image's record (licence, size, address).
jq '[.images[] | select(.license == 4 or .license == 5 or .license == 7 or .license == 8)]
    | map({key: .file_name, value: .}) | from_entries' "$captions" >"$scratch/allowed.json"

# The real-people test: the official ground truth cut to the allowed images.
jq --slurpfile allowed "$scratch/allowed.json" '
  ($allowed[0]) as $ok
  | .images |= map(select($ok[.file_name] != null))
  | (.images | map(.id) | map({key: tostring, value: true}) | from_entries) as $ids
  | .annotations |= map(select($ids[.image_id | tostring] == true))
  | .licenses |= map(select(.id == 4 or .id == 5 or .id == 7 or .id == 8))
  | .info = {description: "COCO val2017 single-person images under Flickr licences 4, 5, 7, 8 with the official person keypoints (COCO annotations CC BY 4.0); rebuilt by scripts/coco-people.sh"}
  ' "$official" >"$scratch/test/annotations.json"
jq -r '.images[].file_name' "$scratch/test/annotations.json" | while read -r name; do
  mv "$scratch/src/coco/images/val2017/$name" "$scratch/test/images/"
done

# Seated: at least two of an image's captions say so.
jq --slurpfile caps "$captions" '
  ($caps[0].annotations | map(select(.caption | test("\\b(sit|sits|sitting|seated|sat)\\b"; "i")))
   | group_by(.image_id) | map(select(length >= 2) | {key: (.[0].image_id | tostring), value: true})
   | from_entries) as $seated
  | .images |= map(select($seated[.id | tostring] == true))
  | (.images | map(.id) | map({key: tostring, value: true}) | from_entries) as $ids
  | .annotations |= map(select($ids[.image_id | tostring] == true))
  | .info.description += "; seated subset: two or more of five captions say sit/sitting/seated"
  ' "$scratch/test/annotations.json" >"$scratch/test/seated.json"

# The rehearsal set: allowed multi-person images that have a YOLO-pose label file.
jq -r 'keys[]' "$scratch/allowed.json" | while read -r name; do
  stem=${name%.jpg}
  image="$scratch/src/coco/images/train2017/$name"
  label="$scratch/src/labels/val2017/$stem.txt"
  if [[ -f "$image" && -f "$label" ]]; then
    mv "$image" "$scratch/rehearsal/images/"
    mv "$label" "$scratch/rehearsal/labels/"
  fi
done
"$wp" -q coco import-yolo --images "$scratch/rehearsal/images" \
  --labels "$scratch/rehearsal/labels" --classes 0=person \
  --description "COCO val2017 multi-person images under Flickr licences 4, 5, 7, 8; YOLO-pose labels from Jar-17/yolov7_for_baseball (people with keypoints only), unlabelled people found by the pretrained model as crowd regions; rebuilt by scripts/coco-people.sh" \
  --out "$scratch/rehearsal/labelled.json"
# The people the labels leave out become crowd regions, which training ignores (no target, no
# background loss): the pretrained model's people scoring at least 0.3 whose box overlaps no
# labelled person's by IoU 0.3 or more, clipped to the image.
"$wp" -q predict --coco "$scratch/rehearsal/labelled.json" --images "$scratch/rehearsal/images" \
  --out "$scratch/rehearsal/pretrained.json"
jq --slurpfile dt "$scratch/rehearsal/pretrained.json" '
  def iou(a; b):
    ([a[0], b[0]] | max) as $x0 | ([a[1], b[1]] | max) as $y0
    | ([a[0] + a[2], b[0] + b[2]] | min) as $x1 | ([a[1] + a[3], b[1] + b[3]] | min) as $y1
    | ([$x1 - $x0, 0] | max) * ([$y1 - $y0, 0] | max) as $inter
    | $inter / (a[2] * a[3] + b[2] * b[3] - $inter);
  (.images | map({key: (.id | tostring), value: [.width, .height]}) | from_entries) as $size
  | (.annotations | group_by(.image_id)
     | map({key: (.[0].image_id | tostring), value: map(.bbox)}) | from_entries) as $labelled
  | [$dt[0][] | select(.score >= 0.3) | . as $d
     | select(all(($labelled[$d.image_id | tostring] // [])[]; iou($d.bbox; .) < 0.3))
     | $size[$d.image_id | tostring] as [$w, $h]
     | ([$d.bbox[0], 0] | max) as $x0 | ([$d.bbox[1], 0] | max) as $y0
     | ([$d.bbox[0] + $d.bbox[2], $w] | min) as $x1 | ([$d.bbox[1] + $d.bbox[3], $h] | min) as $y1
     | select($x1 > $x0 and $y1 > $y0)
     | {image_id: $d.image_id, bbox: [$x0, $y0, $x1 - $x0, $y1 - $y0]}] as $regions
  | ([.annotations[].id] | max // 0) as $last
  | .annotations += [$regions | to_entries[] | {
      id: ($last + 1 + .key), image_id: .value.image_id, category_id: 1, iscrowd: 1,
      bbox: .value.bbox, area: (.value.bbox[2] * .value.bbox[3]), num_keypoints: 0,
      keypoints: [range(51) | 0]}]
  ' "$scratch/rehearsal/labelled.json" >"$scratch/rehearsal/annotations.json"
rm "$scratch/rehearsal/labelled.json" "$scratch/rehearsal/pretrained.json"

# Credits: every image kept, its licence and where it came from.
{
  echo "# Real-people images (COCO val2017, Flickr)"
  echo
  echo "COCO annotations: CC BY 4.0 (the COCO Consortium). Images: their Flickr owners, under"
  echo "the licence named per image. Built by scripts/coco-people.sh; not redistributed."
  echo
  echo "| file | licence | Flickr |"
  echo "|---|---|---|"
  jq -r --slurpfile caps "$captions" '
    ($caps[0].licenses | map({key: (.id | tostring), value: .name}) | from_entries) as $names
    | to_entries[] | "| \(.key) | \($names[.value.license | tostring]) | \(.value.flickr_url) |"' \
    "$scratch/allowed.json" | while IFS= read -r row; do
    name=${row#| }
    name=${name%% |*}
    if [[ -f "$scratch/test/images/$name" || -f "$scratch/rehearsal/images/$name" ]]; then
      echo "$row"
    fi
  done
} >"$scratch/CREDITS.md"

rm -rf "$scratch/src" "$scratch/allowed.json"
"$wp" -q coco validate "$scratch/test/annotations.json" --images "$scratch/test/images" >/dev/null
rm -rf "$out"
mv "$scratch" "$out"
for set in test/annotations test/seated rehearsal/annotations; do
  echo "coco-people: $out/$set.json: $(jq '.images | length' "$out/$set.json") images," \
    "$(jq '[.annotations[] | select(.iscrowd == 0 and .num_keypoints > 0)] | length' \
      "$out/$set.json") people with keypoints," \
    "$(jq '[.annotations[] | select(.iscrowd == 1)] | length' "$out/$set.json") crowd regions" >&2
done
