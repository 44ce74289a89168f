#!/usr/bin/env bash
# The model-boosting experiment (the paper's Table 4, on renders), kept for a release or two as a
# thin wrapper: it is the experiment file configs/experiments/paper.yaml (quick.yaml with
# --quick), run by `wheelpose experiment run` (docs/commands/experiment.md), resumable into OUT.
# The old flags and environment variables are refused with what replaced them.
#
# usage: scripts/boost.sh [--quick] [OUT (default out/boost)]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
source "$root/scripts/lib/experiment-wrapper.sh"
config=paper
out=out/boost
while (($#)); do
  case "$1" in
    --quick) config=quick ;;
    -h | --help) sed -n '2,7p' "$0"; exit 0 ;;
    -*) refuse_legacy_flag boost "$1" ;;
    *) out="$1" ;;
  esac
  shift
done
refuse_legacy_variables boost
run_experiment "$config" "$out"
