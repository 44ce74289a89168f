#!/usr/bin/env bash
# The real-photo dev set of issue 32: the folders datasets/wheelchair/ and datasets/roboflow/ of
# the public GitHub repository lexra/wheelchair (real photos with YOLO boxes; class 1: a person
# in a wheelchair, the box drawn around person and chair; class 0: a person without one), turned
# into two COCO box files over the same images:
#   OUT/wheelchair.json  people in wheelchairs to find, people without as crowd regions
#   OUT/standing.json    the reverse
# so `eval --type bbox` scores each group while detections of the other are neither rewarded nor
# punished. Only those two folders are read: the repository's other folders are an independent
# held-out test. The repository states no licence: its images and labels are for measuring only,
# never committed and never trained on.
#
# usage: scripts/real-photos.sh SRC OUT
#   SRC: a checkout of lexra/wheelchair, or its bare git directory (e.g. what the tool library's
#        fetch brings); OUT: the folder to write (default out/real-dev)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
wp="$root/build/release/wheelpose"
[[ $# -ge 1 ]] || { sed -n '2,16p' "$0"; exit 2; }
src=$1
out=${2:-out/real-dev}
folders=(datasets/wheelchair datasets/roboflow)
[[ -x "$wp" ]] || { echo "real-photos: $wp is missing: cmake --build --preset release" >&2; exit 1; }
if [[ -f "$out/wheelchair.json" && -f "$out/standing.json" ]]; then
  echo "real-photos: $out is complete" >&2
  exit 0
fi
scratch="$out.partial"
rm -rf "$scratch"
mkdir -p "$scratch/files"
if [[ -d "$src/${folders[0]}" ]]; then
  for f in "${folders[@]}"; do
    [[ -d "$src/$f" ]] || { echo "real-photos: $src/$f: no such folder" >&2; exit 2; }
    cp "$src/$f"/* "$scratch/files/"
  done
elif git --git-dir="$src" rev-parse --verify -q HEAD >/dev/null 2>&1; then
  git --git-dir="$src" archive HEAD "${folders[@]}" | tar -x -C "$scratch/files" --strip-components=2
else
  echo "real-photos: $src: neither a checkout with ${folders[0]} nor a git directory" >&2
  exit 2
fi
mkdir -p "$scratch/images" "$scratch/labels"
find "$scratch/files" -maxdepth 1 -name '*.txt' -exec mv -t "$scratch/labels" {} +
find "$scratch/files" -maxdepth 1 -type f -exec mv -t "$scratch/images" {} +
rmdir "$scratch/files"
source_note="lexra/wheelchair (GitHub, no licence stated; measuring only): ${folders[*]}"
"$wp" -q coco import-yolo --images "$scratch/images" --labels "$scratch/labels" \
  --classes 1=person,0=crowd --description "$source_note; people in wheelchairs" \
  --out "$scratch/wheelchair.json"
"$wp" -q coco import-yolo --images "$scratch/images" --labels "$scratch/labels" \
  --classes 0=person,1=crowd --description "$source_note; people without wheelchairs" \
  --out "$scratch/standing.json"
rm -rf "$out"
mv "$scratch" "$out"
for set in wheelchair standing; do
  echo "real-photos: $out/$set.json: $(jq '.images | length' "$out/$set.json") images," \
    "$(jq '[.annotations[] | select(.iscrowd == 0)] | length' "$out/$set.json") people" >&2
done
