#!/usr/bin/env bash
# Slurm job: `wheelpose train` data-parallel over NODES × TASKS processes (LibTorch's Gloo
# backend), each taking BATCH / (NODES × TASKS) images of every step. Submit with
#   TRAIN=/scratch/wheelpose/dataset/annotations.json VAL=/scratch/val/annotations.json \
#   OUT=/scratch/run NODES=4 bash deploy/slurm-train.sh
# OUT must be on a filesystem every node shares: rank 0 writes the run there, and every rank
# reads checkpoint.pt on --resume. The processes meet at the first node's PORT. Re-submitting
# after a pre-emption or a time limit resumes from the last checkpoint (--requeue does it too).
set -euo pipefail

TRAIN=${TRAIN:?set TRAIN to a COCO keypoints file}
VAL=${VAL:-}
OUT=${OUT:?set OUT to a shared folder}
NODES=${NODES:-2}
TASKS=${TASKS:-1}  # processes per node
CPUS=${CPUS:-8}    # torch threads per process
STEPS=${STEPS:-3000}
BATCH=${BATCH:-16}  # the whole batch, split over the processes
PORT=${PORT:-29500}
WHEELPOSE=${WHEELPOSE:-build/release/wheelpose}

mkdir -p "$OUT/logs"
val_args=""
[[ -n $VAL ]] && val_args="--val $VAL"
# What each process runs; it decides on --resume when the job starts, so a requeued job
# continues the run instead of refusing to overwrite it.
cat >"$OUT/logs/rank.sh" <<RANK
#!/usr/bin/env bash
set -euo pipefail
resume=""
[[ -f $OUT/checkpoint.pt ]] && resume="--resume"
exec $WHEELPOSE train --train $TRAIN $val_args --out $OUT --steps $STEPS --batch $BATCH \\
  --threads $CPUS --world-size "\$SLURM_NTASKS" --rank "\$SLURM_PROCID" \\
  --rendezvous "tcp://\$MASTER:$PORT" \$resume
RANK
chmod +x "$OUT/logs/rank.sh"
sbatch --parsable --nodes="$NODES" --ntasks-per-node="$TASKS" --cpus-per-task="$CPUS" \
  --job-name=wheelpose-train --output="$OUT/logs/train-%j.log" --requeue \
  --wrap="export MASTER=\$(scontrol show hostnames \"\$SLURM_JOB_NODELIST\" | head -n 1)
    srun $OUT/logs/rank.sh"
echo "submitted: $((NODES * TASKS)) processes training into $OUT"
