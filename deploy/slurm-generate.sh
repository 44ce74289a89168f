#!/usr/bin/env bash
# Slurm array job: each task renders one shard of a `wheelpose generate` run, then a dependent
# job merges the shards. Submit with
#   FRAMES=20000 SHARDS=50 OUT=/scratch/wheelpose bash deploy/slurm-generate.sh
# Every task writes images with global frame numbers, so the shards' images/ share one folder;
# labels and annotations stay per shard until the merge. Re-submitting resumes (--resume).
set -euo pipefail

FRAMES=${FRAMES:-20000}
SHARDS=${SHARDS:-50}
SEED=${SEED:-0}
OUT=${OUT:?set OUT to a shared folder}
CONFIG=${CONFIG:-configs/wheelpose-paper.yaml}
WHEELPOSE=${WHEELPOSE:-build/release/wheelpose}
CPUS=${CPUS:-8}

mkdir -p "$OUT/logs"
array_job=$(sbatch --parsable --array=0-$((SHARDS - 1)) --cpus-per-task="$CPUS" \
  --job-name=wheelpose-gen --output="$OUT/logs/shard-%a.log" --requeue \
  --wrap="$WHEELPOSE generate --config $CONFIG --frames $FRAMES --seed $SEED \
          --shard \${SLURM_ARRAY_TASK_ID}/$SHARDS --threads $CPUS --resume \
          --out $OUT/shards/\${SLURM_ARRAY_TASK_ID}")

# The merge runs once every shard succeeded: annotations renumbered in shard order (which is
# frame order), images gathered into one folder.
sbatch --dependency=afterok:"$array_job" --job-name=wheelpose-merge \
  --output="$OUT/logs/merge.log" --wrap="set -e
    mkdir -p $OUT/dataset/images
    inputs=''
    for i in \$(seq 0 $((SHARDS - 1))); do
      cp -n $OUT/shards/\$i/images/* $OUT/dataset/images/
      inputs=\"\$inputs $OUT/shards/\$i/annotations.json\"
    done
    cp $OUT/shards/0/scenario.json $OUT/dataset/
    $WHEELPOSE coco merge \$inputs --out $OUT/dataset/annotations.json
    $WHEELPOSE coco validate $OUT/dataset/annotations.json --images $OUT/dataset/images"
echo "submitted array job $array_job ($SHARDS shards of $FRAMES frames) and its merge"
