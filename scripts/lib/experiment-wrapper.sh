# Shared by the scripts kept for a release or two as thin wrappers over `wheelpose experiment
# run` (boost.sh, ablate.sh, standing-mix.sh, ship-model.sh). Source it after setting `root`.
# The experiments themselves are files in configs/experiments/ (docs/commands/experiment.md).

# The environment variables the bash experiment read; each is now a key in an experiment file.
legacy_variables=(TRAIN_FRAMES VAL_FRAMES TEST_FRAMES REALISTIC_TEST_FRAMES STANDING_FRAMES STEPS
  BATCH LR FREEZE VAL_EVERY EXTRA_TRAIN_ARGS ABLATION_SIZES STANDING_TRAIN_FRAMES STANDING_WEIGHT
  REALISTIC_TRAIN_FRAMES RECIPE_STANDING_WEIGHT PEOPLE_SIZE PULL WISE DISTILL ENSEMBLE FLIP
  REAL_SIZE SHIP_DIR)

# refuse_legacy_variables SCRIPT: one line and exit 2 if any of them is set (a typo or an old
# habit would otherwise be silently ignored).
refuse_legacy_variables() {
  local name
  for name in "${legacy_variables[@]}"; do
    if [[ -v $name ]]; then
      echo "$1: the environment variable $name is no longer read: set it in a copy of the" \
        "experiment file (frames under datasets, train options under training.options, blends" \
        "and ensembles under models; docs/commands/experiment.md)" >&2
      exit 2
    fi
  done
}

# refuse_legacy_flag SCRIPT FLAG: what replaced a flag of the bash experiment, then exit 2.
refuse_legacy_flag() {
  local instead
  case "$2" in
    --recipe) instead="configs/experiments/transfer.yaml (the transfer recipe is its variant)" ;;
    --ablate) instead="configs/experiments/sizes.yaml (scripts/ablate.sh runs it)" ;;
    --mix-standing) instead="configs/experiments/standing-mix.yaml (scripts/standing-mix.sh runs it)" ;;
    --real) instead="a coco: dataset and a scores: entry in the experiment file (as in configs/experiments/transfer.yaml)" ;;
    --ranking) instead="clips_from: RANKING.json on the training set's generate: entry (generate --clips-from takes a review ranking)" ;;
    *) instead="" ;;
  esac
  if [[ -n $instead ]]; then
    echo "$1: $2 is gone: use $instead" >&2
  else
    echo "$1: unknown option $2 (see --help)" >&2
  fi
  exit 2
}

# run_experiment CONFIG OUT: runs configs/experiments/CONFIG.yaml into OUT, continuing a run
# already there.
run_experiment() {
  local resume=()
  [[ -f "$2/experiment.yaml" ]] && resume=(--resume)
  "$root/build/release/wheelpose" experiment run "$root/configs/experiments/$1.yaml" --out "$2" \
    "${resume[@]}"
}
