#!/usr/bin/env bash
# Fine-tuning that keeps ordinary people: the model-boosting run of a finished
# `scripts/boost.sh OUT` repeated with generated standing people mixed into its training set
# (configs/boost-standing-train.yaml: the training clips, clothes and chairs, everyone standing),
# scored on the same wheelchair test set and the same standing set. Writes OUT/standing-mix.md
# (boost.sh --mix-standing runs this and puts it in its report). Every step resumes.
#
# usage: scripts/standing-mix.sh [OUT (default out/boost)]
# Environment: STANDING_TRAIN_FRAMES (default 1000), STANDING_WEIGHT (each standing image's
# sampling weight against 1 for a wheelchair image; default 1.5, about 23 % of 5,000 + 1,000).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
wp="$root/build/release/wheelpose"
out=${1:-out/boost}
frames=${STANDING_TRAIN_FRAMES:-1000}
weight=${STANDING_WEIGHT:-1.5}
log() { echo "standing-mix: $*" >&2; }
for f in run/options.json run/done finetuned.json test/annotations.json \
  standing/annotations.json standing-finetuned.json standing-baseline.json; do
  [[ -e "$out/$f" ]] || { echo "standing-mix: $out/$f is missing: run scripts/boost.sh $out first" >&2; exit 1; }
done
# shellcheck source=lib/boost-run.sh
source "$root/scripts/lib/boost-run.sh"
main_run_args

# The main run's training clips (boost.sh --ranking narrows them into OUT/train-clips.json).
train_clips="$root/configs/boost-train-clips.json"
[[ -f "$out/train-clips.json" ]] && train_clips="$out/train-clips.json"
set_dir="$out/standing-train"
if [[ ! -f "$set_dir/annotations.json" ]]; then
  log "generating $frames frames of standing people for training (seed 505)"
  resume=""
  [[ -d "$set_dir" ]] && resume="--resume"
  start=$(date +%s)
  "$wp" -q generate --out "$set_dir" --frames "$frames" --seed 505 \
    --config "$root/configs/boost-standing-train.yaml" --clips-from "$train_clips" $resume
  echo "generate_standing_train $(($(date +%s) - start))" >>"$out/times.txt"
fi
# Held out by clip: the standing people scored afterwards play clips this set never does.
shared=$(jq -n --slurpfile a "$set_dir/annotations.json" --slurpfile b "$out/standing/annotations.json" \
  '[$a[0].annotations[].motion_id] as $x | [$b[0].annotations[].motion_id | select(. as $m | $x | index($m))] | length')
if [[ $shared != 0 ]]; then
  echo "standing-mix: $shared standing test people play clips of the standing training set" >&2
  exit 1
fi

run="$out/run-standing-mix"
if [[ ! -f "$run/done" ]]; then
  resume=""
  [[ -f "$run/checkpoint.pt" ]] && resume="--resume"
  log "fine-tuning with standing people mixed in (weight $weight)"
  start=$(date +%s)
  # shellcheck disable=SC2086
  "$wp" train --train "$out/train/annotations.json" --train "$set_dir/annotations.json:$weight" \
    --out "$run" "${train_args[@]}" ${EXTRA_TRAIN_ARGS:-} $resume
  echo "train_standing_mix $(($(date +%s) - start))" >>"$out/times.txt"
  touch "$run/done"
fi
for set in test standing; do
  scored="$out/$set-finetuned-standing-mix.json"
  [[ -f $scored ]] || "$wp" -q predict --model "$run/best.pt" --coco "$out/$set/annotations.json" \
    --images "$out/$set/images" --out "$scored"
done

people() { jq '[.annotations[]] | length' "$1"; }
share=$(jq -n --argjson a "$(jq '.images | length' "$out/train/annotations.json")" \
  --argjson b "$(jq '.images | length' "$set_dir/annotations.json")" --argjson w "$weight" \
  '$b * $w / ($a + $b * $w) * 100 | round')
{
  echo "## Keeping ordinary people: standing people mixed into training"
  echo
  echo "The same fine-tuning with $(jq '.images | length' "$set_dir/annotations.json") generated"
  echo "frames of $(people "$set_dir/annotations.json") standing people (seed 505, the training clips,"
  echo "configs/boost-standing-train.yaml) added at weight $weight, so about $share % of the"
  echo "images drawn are of standing people. Both sets below are held out from both runs."
  echo
  echo "| Model | best step | KP AP | KP AP50 | KP AR | Box AP | Box AP50 |"
  echo "|---|---|---|---|---|---|---|"
  echo "| **wheelchair test set** | | | | | | |"
  ap_row "pretrained" "$out/test/annotations.json" "$out/baseline.json" "–"
  ap_row "fine-tuned, wheelchairs only" "$out/test/annotations.json" "$out/finetuned.json" \
    "$(jq .step "$out/run/best.json")"
  ap_row "fine-tuned, standing mixed in" "$out/test/annotations.json" \
    "$out/test-finetuned-standing-mix.json" "$(jq .step "$run/best.json")"
  echo "| **standing people** | | | | | | |"
  ap_row "pretrained" "$out/standing/annotations.json" "$out/standing-baseline.json" "–"
  ap_row "fine-tuned, wheelchairs only" "$out/standing/annotations.json" \
    "$out/standing-finetuned.json" "$(jq .step "$out/run/best.json")"
  ap_row "fine-tuned, standing mixed in" "$out/standing/annotations.json" \
    "$out/standing-finetuned-standing-mix.json" "$(jq .step "$run/best.json")"
} >"$out/standing-mix.md.tmp"
mv "$out/standing-mix.md.tmp" "$out/standing-mix.md"
log "wrote $out/standing-mix.md"
