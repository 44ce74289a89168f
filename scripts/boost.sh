#!/usr/bin/env bash
# The model-boosting experiment in one command (the paper's Table 4, on synthetic data):
# generate a training set and a held-out test set (other seed, other motion clips, and a
# wheelchair type and a mobility aid never drawn in training: configs/boost-*), score the
# pretrained MoveNet MultiPose on the test set, fine-tune it on the training set, score it
# again, and write OUT/report.md. Every step resumes: re-running after an interruption redoes only what is missing.
#
# usage: scripts/boost.sh [--quick] [OUT (default out/boost)]
#   --quick: a few frames and steps (a smoke test of the whole chain, minutes on 2 cores)
# Environment overrides: TRAIN_FRAMES, TEST_FRAMES, STEPS, BATCH, LR, FREEZE, EXTRA_TRAIN_ARGS.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
wp="$root/build/release/wheelpose"
quick=0
out=out/boost
for arg in "$@"; do
  case "$arg" in
    --quick) quick=1 ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    -*) echo "boost: unknown option $arg (see --help)" >&2; exit 2 ;;
    *) out="$arg" ;;
  esac
done
[[ -x "$wp" ]] || { echo "boost: $wp is missing: cmake --build --preset release" >&2; exit 1; }

if ((quick)); then
  train_frames=${TRAIN_FRAMES:-24} test_frames=${TEST_FRAMES:-8} steps=${STEPS:-16}
  batch=${BATCH:-4} size_args="--input-size 128"
else
  train_frames=${TRAIN_FRAMES:-5000} test_frames=${TEST_FRAMES:-500} steps=${STEPS:-3000}
  batch=${BATCH:-16} size_args=""
fi
lr=${LR:-1e-4}
freeze=${FREEZE:-0}
mkdir -p "$out"
log() { echo "boost: $*" >&2; }
timed() {  # timed NAME command...: runs it, appends "NAME seconds" to OUT/times.txt
  local name=$1 start end
  shift
  start=$(date +%s)
  "$@"
  end=$(date +%s)
  echo "$name $((end - start))" >>"$out/times.txt"
}

# Seeds differ between the sets, so no frame, scene or person draw is shared; clips, the sport
# wheelchair and forearm crutches are held out of training by content.
for set in train test; do
  frames=$train_frames seed=101 config=(--config "$root/configs/boost-train.yaml")
  if [[ $set == test ]]; then frames=$test_frames seed=202 config=(); fi
  if [[ ! -f "$out/$set/annotations.json" ]]; then
    log "generating the $set set ($frames frames, seed $seed)"
    resume=""
    [[ -d "$out/$set" ]] && resume="--resume"
    timed "generate_$set" "$wp" -q generate --out "$out/$set" --frames "$frames" --seed "$seed" \
      "${config[@]}" --clips-from "$root/configs/boost-$set-clips.json" $resume
  fi
done

# The held-out content, checked on the labels themselves.
shared_clips=$(jq -n --slurpfile a "$out/train/annotations.json" \
  --slurpfile b "$out/test/annotations.json" \
  '([$a[0].annotations[].motion_id] | unique) - (([$a[0].annotations[].motion_id] | unique) - ([$b[0].annotations[].motion_id] | unique)) | length')
train_held=$(jq '[.annotations[] | select(.wheelchair_type == "sport" or .mobility_aid == "crutches")] | length' "$out/train/annotations.json")
if [[ $shared_clips != 0 || $train_held != 0 ]]; then
  echo "boost: the training set shares $shared_clips clip(s) with the test set and has $train_held sport-chair/crutches people" >&2
  exit 1
fi
test_held=$(jq '[.annotations[] | select(.wheelchair_type == "sport" or .mobility_aid == "crutches")] | length' "$out/test/annotations.json")

test_gt="$out/test/annotations.json"
test_images="$out/test/images"
if [[ ! -f "$out/baseline.json" ]]; then
  log "scoring the pretrained model"
  timed predict_baseline "$wp" -q predict --coco "$test_gt" --images "$test_images" \
    --out "$out/baseline.json"
fi

if [[ ! -f "$out/run/last.pt" || ! -f "$out/run/done" ]]; then
  resume=""
  [[ -f "$out/run/checkpoint.pt" ]] && resume="--resume"
  log "fine-tuning ($steps steps of $batch images)"
  # shellcheck disable=SC2086
  timed train "$wp" train --train "$out/train/annotations.json" --out "$out/run" \
    --steps "$steps" --batch "$batch" --lr "$lr" --freeze-backbone "$freeze" $size_args \
    ${EXTRA_TRAIN_ARGS:-} $resume
  touch "$out/run/done"
fi

log "scoring the fine-tuned model"
timed predict_finetuned "$wp" -q predict --model "$out/run/last.pt" --coco "$test_gt" \
  --images "$test_images" --out "$out/finetuned.json"
"$wp" -q eval --gt "$test_gt" --dt "$out/finetuned.json" --baseline "$out/baseline.json" \
  --type both --out "$out/eval" --viz 4 --viz-pick worst --images "$test_images" >/dev/null

first_loss=$(awk -F, 'NR==2 {print $3}' "$out/run/train_log.csv")
last_loss=$(awk -F, 'NR>1 {n++; if (n > 0) v[n]=$3} END {s=0; k=0; for (i=n; i>n-10 && i>0; i--) {s+=v[i]; k++} print s/k}' "$out/run/train_log.csv")
{
  echo "# Model boosting on synthetic wheelchair users"
  echo
  echo "Training set: $train_frames generated frames (seed 101, configs/boost-train.yaml, the"
  echo "clips of configs/boost-train-clips.json); test set: $test_frames frames (seed 202, paper"
  echo "preset, the 12 held-out clips). No clip is shared (checked on the labels); $test_held test"
  echo "people sit in the sport wheelchair or use forearm crutches, which training never drew. Model: MoveNet MultiPose, fine-tuned $steps steps ×"
  echo "$batch images (lr $lr, backbone frozen for $freeze steps), scored at predict's default input."
  echo
  echo "## Baseline vs fine-tuned on the test set"
  echo
  cat "$out/eval/comparison.md"
  echo
  echo "## Training"
  echo
  echo "Loss at step 1: $first_loss; mean of the last 10 steps: $last_loss (train_log.csv)."
  echo
  echo "## Wall time (s, this machine)"
  echo
  sed 's/^/    /' "$out/times.txt"
  echo
  echo "Overlays of the test images where the fine-tuned model does worst: eval/viz/."
} >"$out/report.md.tmp"
mv "$out/report.md.tmp" "$out/report.md"
log "wrote $out/report.md"
