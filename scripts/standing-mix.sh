#!/usr/bin/env bash
# Generated standing people mixed into training (a run with, a run without), kept for a release
# or two as a thin wrapper over `wheelpose experiment run configs/experiments/standing-mix.yaml`
# (docs/commands/experiment.md), resumable into OUT.
#
# usage: scripts/standing-mix.sh [OUT (default out/standing-mix)]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
source "$root/scripts/lib/experiment-wrapper.sh"
out=out/standing-mix
while (($#)); do
  case "$1" in
    -h | --help) sed -n '2,6p' "$0"; exit 0 ;;
    -*) refuse_legacy_flag standing-mix "$1" ;;
    *) out="$1" ;;
  esac
  shift
done
refuse_legacy_variables standing-mix
run_experiment standing-mix "$out"
