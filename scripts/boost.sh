#!/usr/bin/env bash
# The model-boosting experiment in one command (the paper's Table 4, on synthetic data):
# generate a training set, a validation set (training's distribution, another seed) and a
# held-out test set (other seed, other motion clips, and a wheelchair type and a mobility aid
# never drawn in training: configs/boost-*), score the pretrained MoveNet MultiPose on the test
# set, fine-tune it on the training set (validating every VAL_EVERY steps, keeping the best
# weights by validation keypoint AP), score the best weights on the test set, and write
# OUT/report.md and OUT/report.html. Every step resumes: re-running after an interruption redoes
# only what is missing.
#
# Both models are also scored on a second held-out test set in a realistic scenario
# (configs/boost-realistic.yaml: furnished rooms, eye-level cameras, people near and far), on
# people without wheelchairs (a generated set of standing people, configs/boost-standing.yaml),
# and, with --real, on real photos, to show what fine-tuning gains beyond our renders and costs on
# ordinary people.
#
# usage: scripts/boost.sh [--quick] [--recipe paper|transfer] [--ablate] [--mix-standing]
#                         [--real COCO.json]... [--ranking RANKING.json] [OUT]
#   OUT: the experiment's folder (default out/boost)
#   --quick: a few frames and steps (a smoke test of the whole chain, minutes on 2 cores)
#   --recipe: paper (default): train on the paper-preset training set at predict's scale;
#     transfer: also the realistic scenario (configs/boost-realistic-train.yaml) and standing
#     people mixed in, people shown at every size from 30 px to filling the input
#     (train --people-size 30:256); PULL > 0 also pulls the weights toward the pretrained
#     ones (train --pull-to-start PULL). docs/results.md, "Real photos", has what each part gains
#   --ablate: also the training-set size ablation (scripts/ablate.sh; hours at full size)
#   --mix-standing: also a run with standing people mixed into training (scripts/standing-mix.sh)
#   --real COCO.json: real people to score on, repeatable (images in images/ beside it, or beside
#     it); keypoint and box AP, or box AP alone for box-only files (e.g. `coco import-yolo`)
#   --ranking RANKING.json: train only on the training clips that `wheelpose review filter` kept
#     (the review-filter ablation is a run with and a run without it, into two OUT folders)
# Environment overrides: TRAIN_FRAMES, VAL_FRAMES, TEST_FRAMES, REALISTIC_TEST_FRAMES,
# STANDING_FRAMES, STEPS, BATCH, LR, FREEZE, VAL_EVERY, EXTRA_TRAIN_ARGS, ABLATION_SIZES,
# STANDING_TRAIN_FRAMES, STANDING_WEIGHT; with --recipe transfer also REALISTIC_TRAIN_FRAMES,
# RECIPE_STANDING_WEIGHT, PEOPLE_SIZE, PULL; WISE (0..1, default 1): score the weight-space blend
# pretrained + WISE × (fine-tuned − pretrained) (`wheelpose model blend`) instead of best.pt;
# DISTILL (default 0): with any recipe, soft targets from the frozen pretrained model's heatmaps
# at this weight (train --distill); ENSEMBLE=1: score the pretrained and the fine-tuned model
# together (predict --model movenet-multipose --model FINE-TUNED: their people fused) in place
# of the fine-tuned model alone; FLIP=1: score both columns with predict --flip (each model
# also sees the mirrored image); REAL_SIZE=S: score the --real photos at predict --size S (256:
# their best single size) instead of predict's default input.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
wp="$root/build/release/wheelpose"
quick=0
ablate=0
mix_standing=0
reals=()
recipe=paper
ranking=""
out=out/boost
while (($#)); do
  case "$1" in
    --quick) quick=1 ;;
    --ablate) ablate=1 ;;
    --mix-standing) mix_standing=1 ;;
    --real)
      [[ $# -ge 2 ]] || { echo "boost: --real needs a COCO file" >&2; exit 2; }
      reals+=("$2")
      shift
      ;;
    --recipe)
      [[ $# -ge 2 && ( $2 == paper || $2 == transfer ) ]] ||
        { echo "boost: --recipe needs paper or transfer" >&2; exit 2; }
      recipe=$2
      shift
      ;;
    --ranking)
      [[ $# -ge 2 ]] || { echo "boost: --ranking needs a ranking.json" >&2; exit 2; }
      ranking=$2
      shift
      ;;
    -h|--help) sed -n '2,42p' "$0"; exit 0 ;;
    -*) echo "boost: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) out="$1" ;;
  esac
  shift
done
declare -A real_names=()
for real in "${reals[@]}"; do
  [[ -f $real ]] || { echo "boost: --real $real: no such file" >&2; exit 2; }
  name="real-$(basename "$real" .json)"
  [[ -z ${real_names[$name]:-} ]] ||
    { echo "boost: --real $real: a second file named $(basename "$real")" >&2; exit 2; }
  real_names[$name]=$real
done
[[ -x "$wp" ]] || { echo "boost: $wp is missing: cmake --build --preset release" >&2; exit 1; }

if ((quick)); then
  train_frames=${TRAIN_FRAMES:-24} val_frames=${VAL_FRAMES:-4} test_frames=${TEST_FRAMES:-8}
  standing_frames=${STANDING_FRAMES:-4} realistic_test_frames=${REALISTIC_TEST_FRAMES:-4}
  realistic_train_frames=${REALISTIC_TRAIN_FRAMES:-8} recipe_standing_frames=${STANDING_TRAIN_FRAMES:-4}
  steps=${STEPS:-16} batch=${BATCH:-4} val_every=${VAL_EVERY:-8} size_args="--input-size 128"
  export ABLATION_SIZES=${ABLATION_SIZES:-8 16} STANDING_TRAIN_FRAMES=${STANDING_TRAIN_FRAMES:-4}
else
  train_frames=${TRAIN_FRAMES:-5000} val_frames=${VAL_FRAMES:-200} test_frames=${TEST_FRAMES:-500}
  standing_frames=${STANDING_FRAMES:-300} realistic_test_frames=${REALISTIC_TEST_FRAMES:-300}
  realistic_train_frames=${REALISTIC_TRAIN_FRAMES:-2500}
  recipe_standing_frames=${STANDING_TRAIN_FRAMES:-1000}
  steps=${STEPS:-3000} batch=${BATCH:-16} val_every=${VAL_EVERY:-250} size_args=""
fi
lr=${LR:-1e-4}
freeze=${FREEZE:-0}
# The transfer recipe's own settings (docs/results.md, "Real photos": chosen on the real dev set).
people_size=${PEOPLE_SIZE:-30:256}
pull=${PULL:-0}
distill=${DISTILL:-0}
ensemble=${ENSEMBLE:-0}
flip=${FLIP:-0}
[[ $ensemble == [01] && $flip == [01] ]] || { echo "boost: ENSEMBLE and FLIP take 0 or 1" >&2; exit 2; }
# FLIP scores both columns mirrored too; their files are kept apart from unflipped ones.
flip_args=() base_tag=""
if [[ $flip == 1 ]]; then flip_args=(--flip) base_tag="-flip"; fi
real_size=${REAL_SIZE:-}
real_args=() real_tag=""
if [[ -n $real_size ]]; then
  [[ $real_size =~ ^[1-9][0-9]*$ ]] || { echo "boost: REAL_SIZE takes a size such as 256" >&2; exit 2; }
  real_args=(--size "$real_size") real_tag="-$real_size"
fi
if [[ $flip == 1 ]] && ((ablate || mix_standing)); then
  echo "boost: --ablate and --mix-standing score unmirrored: run them without FLIP=1" >&2
  exit 2
fi
recipe_standing_weight=${RECIPE_STANDING_WEIGHT:-0.5}

# The training clips: configs/boost-train-clips.json, or those of them a review ranking keeps.
train_clips="$root/configs/boost-train-clips.json"
clips_note="the clips of configs/boost-train-clips.json"
if [[ -n $ranking ]]; then
  [[ -f $ranking ]] || { echo "boost: --ranking $ranking: no such file" >&2; exit 2; }
  jq -e '.kept | arrays' "$ranking" >/dev/null 2>&1 ||
    { echo "boost: --ranking $ranking: not a ranking.json (no \"kept\" list)" >&2; exit 2; }
  filtered=$(jq --slurpfile ranking "$ranking" --arg from "$ranking" '
    [$ranking[0].kept[].id] as $kept
    | .kept |= map(select(.id as $id | $kept | index($id)))
    | .note = "The training clips of configs/boost-train-clips.json that \($from) keeps."
  ' "$train_clips")
  kept=$(jq '.kept | length' <<<"$filtered")
  ((kept > 0)) || { echo "boost: --ranking $ranking keeps none of the training clips" >&2; exit 2; }
  clips_note="the $kept of configs/boost-train-clips.json's $(jq '.kept | length' "$train_clips") clips that $ranking keeps"
  train_clips="$out/train-clips.json"
fi
mkdir -p "$out"
if [[ -n $ranking ]]; then
  echo "$filtered" >"$train_clips.tmp"
  mv "$train_clips.tmp" "$train_clips"
fi
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
# wheelchair and forearm crutches are held out of training by content. The standing people play
# the held-out clips too.
declare -A clip_files=([train]="$train_clips" [test]="$root/configs/boost-test-clips.json")
sets=(train val test test-realistic standing)
[[ $recipe == transfer ]] && sets+=(train-realistic standing-train)
for set in "${sets[@]}"; do
  frames=$train_frames seed=101 config=(--config "$root/configs/boost-train.yaml") clips=train
  if [[ $set == val ]]; then frames=$val_frames seed=303; fi
  if [[ $set == test ]]; then frames=$test_frames seed=202 config=() clips=test; fi
  if [[ $set == test-realistic ]]; then
    frames=$realistic_test_frames seed=606 config=(--config "$root/configs/boost-realistic.yaml")
    clips=test
  fi
  if [[ $set == standing ]]; then
    frames=$standing_frames seed=404 config=(--config "$root/configs/boost-standing.yaml")
    clips=test
  fi
  if [[ $set == train-realistic ]]; then
    frames=$realistic_train_frames seed=707
    config=(--config "$root/configs/boost-realistic-train.yaml")
  fi
  if [[ $set == standing-train ]]; then  # the set scripts/standing-mix.sh makes too
    frames=$recipe_standing_frames seed=505
    config=(--config "$root/configs/boost-standing-train.yaml")
  fi
  if [[ ! -f "$out/$set/annotations.json" ]]; then
    log "generating the $set set ($frames frames, seed $seed)"
    resume=""
    [[ -d "$out/$set" ]] && resume="--resume"
    timed "generate_$set" "$wp" -q generate --out "$out/$set" --frames "$frames" --seed "$seed" \
      "${config[@]}" --clips-from "${clip_files[$clips]}" $resume
  fi
done

# The held-out content, checked on the labels themselves.
shared_clips=$(jq -n --slurpfile a "$out/train/annotations.json" \
  --slurpfile b "$out/test/annotations.json" \
  '([$a[0].annotations[].motion_id] | unique) - (([$a[0].annotations[].motion_id] | unique) - ([$b[0].annotations[].motion_id] | unique)) | length')
train_sets=("$out/train/annotations.json")
[[ $recipe == transfer ]] &&
  train_sets+=("$out/train-realistic/annotations.json" "$out/standing-train/annotations.json")
train_held=$(jq -s '[.[].annotations[] | select(.wheelchair_type == "sport" or .mobility_aid == "crutches")] | length' "${train_sets[@]}")
if [[ $shared_clips != 0 || $train_held != 0 ]]; then
  echo "boost: the training set shares $shared_clips clip(s) with the test set and has $train_held sport-chair/crutches people" >&2
  exit 1
fi
# A training set from an earlier run with other clips (e.g. before --ranking) is not reused.
foreign=$(jq -r --slurpfile clips "$train_clips" '[.annotations[].motion_id] - [$clips[0].kept[].id] | unique | join(", ")' "$out/train/annotations.json")
if [[ -n $foreign ]]; then
  echo "boost: $out/train plays clips $train_clips does not keep ($foreign): use another OUT" >&2
  exit 1
fi
# Held-out clothes and hair, when the labels record assets (datasets generated before they did
# cannot be checked and say so in the report).
held_assets=$(sed -n 's/^ *exclude_assets: *\[\(.*\)\]/\1/p' "$root/configs/boost-train.yaml" | tr -d ' ')
assets_note="the labels carry no asset ids (generated before they did), so clothes and hair were not checked"
if jq -e '.annotations[0] | has("assets")' "$out/train/annotations.json" >/dev/null; then
  train_assets=$(jq -c --arg held "$held_assets" '[.annotations[].assets[] | select(. as $a | $held | split(",") | index($a))] | unique' "$out/train/annotations.json")
  if [[ $train_assets != "[]" ]]; then
    echo "boost: the training set wears held-out assets $train_assets" >&2
    exit 1
  fi
  test_assets=$(jq --arg held "$held_assets" '[.annotations[] | select(any(.assets[]; . as $a | $held | split(",") | index($a)))] | length' "$out/test/annotations.json")
  assets_note="$test_assets test people wear clothes or hair training never drew ($held_assets)"
fi
test_held=$(jq '[.annotations[] | select(.wheelchair_type == "sport" or .mobility_aid == "crutches")] | length' "$out/test/annotations.json")

test_gt="$out/test/annotations.json"
test_images="$out/test/images"
baseline="$out/baseline$base_tag.json"
if [[ ! -f $baseline ]]; then
  log "scoring the pretrained model"
  timed predict_baseline "$wp" -q predict "${flip_args[@]}" --coco "$test_gt" \
    --images "$test_images" --out "$baseline"
fi

train_sources=(--train "$out/train/annotations.json")
recipe_args=()
recipe_note="the paper-preset training set at predict's scale"
if [[ $recipe == transfer ]]; then
  train_sources+=(--train "$out/train-realistic/annotations.json"
    --train "$out/standing-train/annotations.json:$recipe_standing_weight")
  recipe_args=(--people-size "$people_size")
  recipe_note="the transfer recipe: the paper-preset training set, $realistic_train_frames frames of the realistic scenario (seed 707) and $recipe_standing_frames of standing people (seed 505, weight $recipe_standing_weight), people $people_size px in the input"
  if [[ $pull != 0 ]]; then
    recipe_args+=(--pull-to-start "$pull")
    recipe_note+=", weights pulled toward the pretrained ones (--pull-to-start $pull)"
  fi
fi
if [[ $distill != 0 ]]; then
  recipe_args+=(--distill "$distill")
  recipe_note+=", distilled from the frozen pretrained model's heatmaps (--distill $distill)"
fi
if [[ ! -f "$out/run/last.pt" || ! -f "$out/run/done" ]]; then
  resume=""
  [[ -f "$out/run/checkpoint.pt" ]] && resume="--resume"
  log "fine-tuning ($steps steps of $batch images, recipe $recipe)"
  # shellcheck disable=SC2086
  timed train "$wp" train "${train_sources[@]}" "${recipe_args[@]}" --out "$out/run" \
    --val "$out/val/annotations.json" --val-every "$val_every" \
    --steps "$steps" --batch "$batch" --lr "$lr" --freeze-backbone "$freeze" $size_args \
    ${EXTRA_TRAIN_ARGS:-} $resume
  touch "$out/run/done"
fi

# WISE=ALPHA scores a blend of the pretrained and the fine-tuned weights instead (model blend,
# WiSE-FT): alpha 1 is best.pt itself.
scored_model="$out/run/best.pt"
wise=${WISE:-1}
if [[ $wise != 1 ]]; then
  "$wp" -q model blend --finetuned "$out/run/best.pt" --alpha "$wise" --out "$out/run/wise.pt"
  scored_model="$out/run/wise.pt"
  recipe_note+="; the scored weights are pretrained + $wise × (fine-tuned − pretrained) (model blend)"
fi
scored=(--model "$scored_model" "${flip_args[@]}")
if [[ $ensemble == 1 ]]; then
  scored=(--model movenet-multipose "${scored[@]}")
  recipe_note+="; scored as an ensemble with the pretrained model (predict --model movenet-multipose --model FINE-TUNED)"
fi
[[ $flip == 1 ]] && recipe_note+="; both columns scored with predict --flip (each model also sees the mirrored image)"
log "scoring the fine-tuned model (best.pt: step $(jq .step "$out/run/best.json"), alpha $wise, ensemble $ensemble, flip $flip)"
timed predict_finetuned "$wp" -q predict "${scored[@]}" --coco "$test_gt" \
  --images "$test_images" --out "$out/finetuned.json"
# People without wheelchairs: the generated standing people and, with --real, the user's own.
# Box-only ground truth (no labelled keypoint, e.g. `coco import-yolo` of real photos) is scored
# for boxes alone.
eval_type() { jq -e 'any(.annotations[]; (.num_keypoints // 0) > 0)' "$1" >/dev/null && echo both || echo bbox; }
score_both() {  # score_both NAME GT IMAGES [TAG [PREDICT ARGS...]]: OUT/NAME-{baseline,finetuned}.json, OUT/NAME-eval
  local base="$out/$1-baseline$base_tag${4:-}.json" extra=("${@:5}")
  [[ -f $base ]] || timed "predict_baseline_$1" "$wp" -q predict "${flip_args[@]}" "${extra[@]}" \
    --coco "$2" --images "$3" --out "$base"
  timed "predict_finetuned_$1" "$wp" -q predict "${scored[@]}" "${extra[@]}" --coco "$2" \
    --images "$3" --out "$out/$1-finetuned.json"
  "$wp" -q eval --gt "$2" --dt "$out/$1-finetuned.json" --baseline "$base" \
    --type "$(eval_type "$2")" --out "$out/$1-eval" >/dev/null
}
log "scoring both models on the realistic test set and on people without wheelchairs"
score_both test-realistic "$out/test-realistic/annotations.json" "$out/test-realistic/images"
score_both standing "$out/standing/annotations.json" "$out/standing/images"
for name in "${!real_names[@]}"; do
  real=${real_names[$name]}
  real_images="$(dirname "$real")/images"
  [[ -d $real_images ]] || real_images="$(dirname "$real")"
  score_both "$name" "$real" "$real_images" "$real_tag" "${real_args[@]}"
done
if ((ablate)); then "$root/scripts/ablate.sh" "$out"; fi
if ((mix_standing)); then "$root/scripts/standing-mix.sh" "$out"; fi

# The same test images before (red) and after (green) fine-tuning, over white GT: evenly spread
# ones, and those where the fine-tuned model does worst.
"$wp" -q eval --gt "$test_gt" --dt "$out/finetuned.json" --baseline "$baseline" \
  --type both --out "$out/eval" --viz 6 --images "$test_images" >/dev/null
"$wp" -q eval --gt "$test_gt" --dt "$out/finetuned.json" --baseline "$baseline" \
  --type both --out "$out/eval-worst" --viz 4 --viz-pick worst --images "$test_images" >/dev/null

# The paper's Table 4 layout: baseline and fine-tuned side by side, AP in points.
table4() {  # table4 [EVAL_DIR (default OUT/eval)]
  jq -r '
    def p(x): if x == null or x < 0 then "n/a" else (x * 1000 | round / 10 | tostring) end;
    def d(a; b): if a == null or b == null or a < 0 or b < 0 then "n/a" else ((a - b) * 1000 | round / 10 | tostring) end;
    def row(name; r): "| \(name) | \(p(r.keypoints.stats.AP)) | \(p(r.keypoints.stats.AP50)) | \(p(r.keypoints.stats.AP75)) | \(p(r.keypoints.stats.APm)) | \(p(r.keypoints.stats.APl)) | \(p(r.keypoints.stats.AR)) | \(p(r.bbox.stats.AP)) | \(p(r.bbox.stats.AP50)) | \(p(r.bbox.stats.APm)) | \(p(r.bbox.stats.APl)) |";
    "| Model | KP AP | KP AP50 | KP AP75 | KP APm | KP APl | KP AR | Box AP | Box AP50 | Box APm | Box APl |",
    "|---|---|---|---|---|---|---|---|---|---|---|",
    row("MoveNet MultiPose (pretrained)"; .baseline),
    row("fine-tuned on generated data"; .results),
    "| change (points) | \(d(.results.keypoints.stats.AP; .baseline.keypoints.stats.AP)) | \(d(.results.keypoints.stats.AP50; .baseline.keypoints.stats.AP50)) | \(d(.results.keypoints.stats.AP75; .baseline.keypoints.stats.AP75)) | | | \(d(.results.keypoints.stats.AR; .baseline.keypoints.stats.AR)) | \(d(.results.bbox.stats.AP; .baseline.bbox.stats.AP)) | \(d(.results.bbox.stats.AP50; .baseline.bbox.stats.AP50)) | | |"
  ' "${1:-$out/eval}/metrics.json"
}
count() { jq "[.$2[]] | length" "$1"; }

first_loss=$(awk -F, 'NR==2 {print $3}' "$out/run/train_log.csv")
last_loss=$(awk -F, 'NR>1 {n++; if (n > 0) v[n]=$3} END {s=0; k=0; for (i=n; i>n-10 && i>0; i--) {s+=v[i]; k++} print s/k}' "$out/run/train_log.csv")
{
  echo "# Model boosting on synthetic wheelchair users"
  echo
  echo "Training set: $train_frames generated frames (seed 101, configs/boost-train.yaml,"
  echo "$clips_note); test set: $test_frames frames (seed 202, paper"
  echo "preset, the 12 held-out clips). No clip is shared (checked on the labels); $test_held test"
  echo "people sit in the sport wheelchair or use forearm crutches, which training never drew;"
  echo "$assets_note. Model: MoveNet MultiPose, fine-tuned $steps steps ×"
  echo "$batch images (lr $lr, backbone frozen for $freeze steps) on $recipe_note;"
  echo "scored at predict's default input (256 and 640 merged)."
  echo
  echo "## Baseline vs fine-tuned on the test set ($test_frames frames, predict's default input)"
  echo
  table4
  echo
  cat "$out/eval/comparison.md"
  echo
  echo "## The realistic test set"
  echo
  echo "$realistic_test_frames frames (seed 606, configs/boost-realistic.yaml: furnished rooms,"
  echo "eye-level cameras, 1–4 people near and far; the held-out clips, chairs and aids)."
  echo
  table4 "$out/test-realistic-eval"
  echo
  echo "## People without wheelchairs"
  echo
  echo "What fine-tuning costs on ordinary people: $standing_frames generated frames of"
  echo "$(count "$out/standing/annotations.json" annotations) standing people (seed 404,"
  echo "configs/boost-standing.yaml: no wheelchair, aid or limb difference; the held-out clips,"
  echo "their upper body on straight legs)."
  echo
  table4 "$out/standing-eval"
  for name in $(printf '%s\n' "${!real_names[@]}" | sort); do
    real=${real_names[$name]}
    echo
    echo "Real people ($name): $(count "$real" images) images," \
      "$(jq '[.annotations[] | select(.iscrowd == 0)] | length' "$real") people of $real" \
      "($(jq -r '.info.description // "no description"' "$real"))${real_size:+, both columns at predict --size $real_size}."
    echo
    table4 "$out/$name-eval"
  done
  echo
  if [[ -f "$out/standing-mix.md" ]] && ((mix_standing)); then
    cat "$out/standing-mix.md"
    echo
  fi
  if [[ -f "$out/ablation.md" ]] && ((ablate)); then
    cat "$out/ablation.md"
    echo
  fi
  echo "## Training"
  echo
  echo "Loss at step 1: $first_loss; mean of the last 10 steps: $last_loss (run/train_log.csv)."
  echo "Validation ($val_frames frames of the training distribution, seed 303; run/val_log.csv),"
  echo "the weights scored on the test set are those of step $(jq .step "$out/run/best.json"):"
  echo
  echo "| step | KP AP | KP AP50 | KP AR | Box AP | Box AP50 |"
  echo "|---|---|---|---|---|---|"
  awk -F, 'NR > 1 {printf "| %d | %.3f | %.3f | %.3f | %.3f | %.3f |\n", $1, $2, $3, $4, $5, $6}' \
    "$out/run/val_log.csv"
  echo
  echo "![loss and validation curves](run/curves.png)"
  echo
  echo "## Wall time (s, this machine)"
  echo
  sed 's/^/    /' "$out/times.txt"
  echo
  echo "## The same test images before and after"
  echo
  echo "White: ground truth; red: pretrained; green: fine-tuned (people scoring at least 0.5)."
  echo
  for f in "$out"/eval/viz/*.jpg "$out"/eval-worst/viz/*.jpg; do
    [[ -f $f ]] && echo "![${f#"$out"/}](${f#"$out"/})"
  done
} >"$out/report.md.tmp"
mv "$out/report.md.tmp" "$out/report.md"

# The same report as one HTML page (tables, headings, images and paragraphs are all it uses).
awk '
  function esc(s) { gsub(/&/, "\\&amp;", s); gsub(/</, "\\&lt;", s); gsub(/>/, "\\&gt;", s); return s }
  function close_table() { if (in_table) print "</table>"; in_table = 0 }
  BEGIN { print "<!doctype html><html><head><meta charset=\"utf-8\"><title>WheelPose model boosting</title>";
          print "<style>body{font-family:sans-serif;max-width:1200px;margin:2em auto}table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:2px 8px;text-align:right}img{max-width:100%}</style></head><body>" }
  /^\|---/ { next }
  /^\|/ { if (!in_table) { print "<table>"; in_table = 1 }
          n = split($0, cells, "|"); row = "<tr>";
          for (i = 2; i < n; i++) row = row "<td>" esc(cells[i]) "</td>";
          print row "</tr>"; next }
  { close_table() }
  /^# / { print "<h1>" esc(substr($0, 3)) "</h1>"; next }
  /^## / { print "<h2>" esc(substr($0, 4)) "</h2>"; next }
  /^!\[/ { src = $0; sub(/^!\[[^]]*\]\(/, "", src); sub(/\)$/, "", src); print "<p><img src=\"" src "\"></p>"; next }
  /^    / { print "<pre>" esc(substr($0, 5)) "</pre>"; next }
  /^$/ { next }
  { print "<p>" esc($0) "</p>" }
  END { close_table(); print "</body></html>" }
' "$out/report.md" >"$out/report.html.tmp"
mv "$out/report.html.tmp" "$out/report.html"
log "wrote $out/report.md and $out/report.html"
