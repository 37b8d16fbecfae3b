#!/usr/bin/env bash
# The wall time of gonio-simulate.sbatch under the one-node Slurm of
# local-cluster.sh against one `gonio simulate` process on the same cores,
# for docs/slurm.md:
#
#   scripts/slurm/measure.sh [ROUNDS] [PHOTONS] [ITERATIONS]   (default 3 1000000 4)
#
# Each round runs, one after the other, one process with --threads $(nproc)
# and the job as $(nproc) tasks of one core (srun --mpi=pmix), on the bell
# sample with seed 1; both write into build/slurm/measure/. Prints per
# round: the process's wall and CPU (user + sys) seconds, the job's srun
# wall seconds (the script's own "traced in" line), sbatch-to-end seconds,
# and whether the files are the same bytes.
set -euo pipefail
cd "$(dirname "$0")/../.."
rounds=${1:-3}
photons=${2:-1000000}
iterations=${3:-4}
root=$(pwd)
gonio=$root/build/tools/gonio
model=$root/build/samples/bell/bell.gltf
dir=$root/build/slurm/measure
cores=$(nproc)
[ -x "$gonio" ] && [ -f "$model" ] || { echo "measure: build gonio and gonio_samples first" >&2; exit 1; }
rm -rf "$dir"
mkdir -p "$dir/bin"
ln -s "$gonio" "$dir/bin/gonio"
export PATH="$dir/bin:$PATH"
export SLURM_CONF
SLURM_CONF=$(bash scripts/slurm/local-cluster.sh start "$dir/cluster" $$)
trap 'bash scripts/slurm/local-cluster.sh stop "$dir/cluster"' EXIT

echo "round | one process: wall s, cpu s | job: srun wall s, sbatch to end s | same bytes"
for r in $(seq "$rounds"); do
  rm -rf "$dir/one" "$dir/job"
  /usr/bin/time -f '%e %U %S' -o "$dir/time" "$gonio" simulate "$model" --out "$dir/one" --seed 1 \
    --photons "$photons" --iterations "$iterations" --threads "$cores" >/dev/null 2>&1
  read -r wall user sys <"$dir/time"
  start=$(date +%s.%N)
  job=$(sbatch --parsable --output="$dir/job.out" --nodes=1 --ntasks-per-node="$cores" --cpus-per-task=1 \
    --time=30 scripts/slurm/gonio-simulate.sbatch "$model" "$dir/job" --seed 1 \
    --photons "$photons" --iterations "$iterations")
  job=${job%%;*}
  while [ -n "$(squeue -h -j "$job" -o %T 2>/dev/null)" ]; do sleep 0.2; done
  end=$(date +%s.%N)
  traced=$(grep -o 'traced in [0-9.]* s' "$dir/job.out" | awk '{print $3}')
  same=yes
  for f in "$dir"/one/*; do
    [ "$(basename "$f")" = report.json ] && continue
    cmp -s "$f" "$dir/job/$(basename "$f")" || same=no
  done
  awk -v r="$r" -v w="$wall" -v u="$user" -v s="$sys" -v t="${traced:-nan}" -v a="$start" -v b="$end" -v same="$same" \
    'BEGIN { printf "%d | %.2f, %.2f | %s, %.2f | %s\n", r, w, u + s, t, b - a, same }'
done
uptime
