#!/usr/bin/env bash
# The training-set size ablation of the model-boosting experiment (the paper's Figure 9 idea):
# fine-tune the same model with the same settings as a finished `scripts/boost.sh OUT` run on
# smaller random subsets of its training set, score each run's best weights on the same held-out
# test set, and write OUT/ablation.md (boost.sh --ablate runs this and puts it in its report).
# Every step resumes: re-running redoes only what is missing.
#
# usage: scripts/ablate.sh [OUT (default out/boost)]
# Environment: ABLATION_SIZES (training images, default "1000 2500"; the full set is OUT/run).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
wp="$root/build/release/wheelpose"
out=${1:-out/boost}
sizes=${ABLATION_SIZES:-1000 2500}
log() { echo "ablate: $*" >&2; }
for f in run/options.json run/done finetuned.json test/annotations.json; do
  [[ -e "$out/$f" ]] || { echo "ablate: $out/$f is missing: run scripts/boost.sh $out first" >&2; exit 1; }
done

# The main run's settings, so that only the training set's size differs.
# shellcheck source=lib/boost-run.sh
source "$root/scripts/lib/boost-run.sh"
main_run_args
opt() { jq -r "$1" "$out/run/options.json"; }
full_size=$(jq '.images | length' "$out/train/annotations.json")

for n in $sizes; do
  if ((n >= full_size)); then
    echo "ablate: size $n is not below the training set's $full_size images" >&2
    exit 1
  fi
  subset="$out/train/subset-$n.json"  # beside annotations.json, so images/ resolves
  run="$out/run-$n"
  [[ -f "$subset" ]] || "$wp" -q coco sample "$out/train/annotations.json" --n "$n" --seed 1 \
    --out "$subset"
  if [[ ! -f "$run/done" ]]; then
    resume=""
    [[ -f "$run/checkpoint.pt" ]] && resume="--resume"
    log "fine-tuning on $n of $full_size training images"
    start=$(date +%s)
    "$wp" train --train "$subset" --out "$run" "${train_args[@]}" $resume
    echo "train_$n $(($(date +%s) - start))" >>"$out/times.txt"
    touch "$run/done"
  fi
  if [[ ! -f "$out/finetuned-$n.json" ]]; then
    "$wp" -q predict --model "$run/best.pt" --coco "$out/test/annotations.json" \
      --images "$out/test/images" --out "$out/finetuned-$n.json"
  fi
done

# One row per training-set size: test-set AP of that run's best weights, in points.
row() { ap_row "$1" "$out/test/annotations.json" "$2" "$3"; }  # row LABEL DETECTIONS STEP
{
  echo "## Ablation: training-set size"
  echo
  echo "The same fine-tuning ($(opt .steps) steps × $(opt .batch) images, seed $(opt .seed)) on"
  echo "random subsets of the training set (\`coco sample --seed 1\`), each run's best weights"
  echo "(by validation keypoint AP) scored on the same held-out test set. Images counted with"
  echo "and without people, as generated."
  echo
  echo "| Training images | best step | KP AP | KP AP50 | KP AR | Box AP | Box AP50 |"
  echo "|---|---|---|---|---|---|---|"
  row "0 (pretrained)" "$out/baseline.json" "–"
  for n in $sizes; do row "$n" "$out/finetuned-$n.json" "$(jq .step "$out/run-$n/best.json")"; done
  row "$full_size" "$out/finetuned.json" "$(jq .step "$out/run/best.json")"
} >"$out/ablation.md.tmp"
mv "$out/ablation.md.tmp" "$out/ablation.md"
log "wrote $out/ablation.md"
