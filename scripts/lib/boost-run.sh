# Shared by the variants of a finished `scripts/boost.sh OUT` run (ablate.sh, standing-mix.sh):
# the main run's training settings, so that a variant differs from it only where it means to,
# and one Markdown row of test-set AP. Source it after setting `wp` (the wheelpose binary) and
# `out` (the boost folder).

# main_run_args: prints nothing, fills the array `train_args` from OUT/run/options.json.
main_run_args() {
  local options="$out/run/options.json"
  opt() { jq -r "$1" "$options"; }
  train_args=(--steps "$(opt .steps)" --batch "$(opt .batch)" --lr "$(opt .learning_rate)"
    --weight-decay "$(opt .weight_decay)" --warmup "$(opt .warmup_steps)"
    --freeze-backbone "$(opt .freeze_backbone_steps)" --backbone-lr-scale "$(opt .backbone_lr_scale)"
    --clip "$(opt .clip_norm)" --input-size "$(opt '.augment[0]')" --seed "$(opt .seed)"
    --val "$(opt .val)" --val-every "$(opt .val_every)" --val-size "$(opt .val_size)")
  # The transfer recipe's options (present only when the main run used them).
  local people_size pull
  people_size=$(opt '.people_size // empty | "\(.[0]):\(.[1])"')
  pull=$(opt '.pull_to_start // empty')
  [[ -n $people_size ]] && train_args+=(--people-size "$people_size")
  [[ -n $pull ]] && train_args+=(--pull-to-start "$pull")
  return 0
}

# ap_row LABEL GT DETECTIONS [EXTRA CELL]: "| LABEL | [EXTRA |] KP AP | KP AP50 | KP AR | Box AP |
# Box AP50 |" in points, scored by `wheelpose eval` into OUT/row-eval.
ap_row() {
  "$wp" -q eval --gt "$2" --dt "$3" --type both --out "$out/row-eval" >/dev/null
  jq -r --arg name "$1" --arg extra "${4:-}" '
    def p(x): x * 1000 | round / 10 | tostring;
    "| \($name) |\(if $extra == "" then "" else " \($extra) |" end) \(p(.results.keypoints.stats.AP)) | \(p(.results.keypoints.stats.AP50)) | \(p(.results.keypoints.stats.AR)) | \(p(.results.bbox.stats.AP)) | \(p(.results.bbox.stats.AP50)) |"
  ' "$out/row-eval/metrics.json"
}
