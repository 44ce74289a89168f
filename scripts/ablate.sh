#!/usr/bin/env bash
# The training-set size ablation, kept for a release or two as a thin wrapper over
# `wheelpose experiment run configs/experiments/sizes.yaml` (docs/commands/experiment.md),
# resumable into OUT.
#
# usage: scripts/ablate.sh [OUT (default out/sizes)]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
source "$root/scripts/lib/experiment-wrapper.sh"
out=out/sizes
while (($#)); do
  case "$1" in
    -h | --help) sed -n '2,6p' "$0"; exit 0 ;;
    -*) refuse_legacy_flag ablate "$1" ;;
    *) out="$1" ;;
  esac
  shift
done
refuse_legacy_variables ablate
run_experiment sizes "$out"
