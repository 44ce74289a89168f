#!/bin/sh
# Accept reviewed renderer output as the new golden references: copies every
# <name>.actual.png written by a failing golden test (src/render/golden_test.cpp) over
# tests/golden/render/<name>.png. Look at the images first; then commit the references.
# Usage: scripts/promote_golden.sh [FAILURE_DIR]   (default: $TMPDIR or /tmp, /wheelpose_golden_render)
set -eu
src="${1:-${TMPDIR:-/tmp}/wheelpose_golden_render}"
dest="$(cd "$(dirname "$0")/.." && pwd)/tests/golden/render"
if [ ! -d "$src" ]; then
  echo "error: $src does not exist (run the golden tests first)" >&2
  exit 2
fi
mkdir -p "$dest"
count=0
for actual in "$src"/*.actual.png; do
  [ -e "$actual" ] || continue
  name="$(basename "$actual" .actual.png)"
  cp "$actual" "$dest/$name.png"
  echo "promoted $name -> $dest/$name.png"
  count=$((count + 1))
done
if [ "$count" -eq 0 ]; then
  echo "error: no *.actual.png in $src" >&2
  exit 2
fi
rm -f "$src"/*.actual.png "$src"/*.expected.png "$src"/*.diff.png
