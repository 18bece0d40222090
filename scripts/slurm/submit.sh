#!/usr/bin/env bash
# Submits the jobs of an oitref plan folder that are not done yet as one Slurm job array (a task
# per job), and `oitref collect` after them (afterok: it starts when every task succeeded).
#
#   scripts/slurm/submit.sh PLAN [sbatch options for both, e.g. --partition=gpu --time=02:00:00]
#
# Environment: OITREF the oitref executable (default: `oitref` on PATH, else build/oitref beside
# these scripts), OITREF_CPUS_PER_TASK CPUs per task (default 2; `oitref job` renders with as
# many threads, from SLURM_CPUS_PER_TASK), OITREF_ARRAY_LIMIT at most this many tasks at once.
# Run it again after tasks failed or were cancelled: it submits only the jobs still missing.
set -euo pipefail
if [ $# -lt 1 ]; then
  echo "usage: $0 PLAN [sbatch options]" >&2
  exit 2
fi
plan=$1
shift
here=$(cd "$(dirname "$0")" && pwd)
oitref=${OITREF:-$(command -v oitref || echo "$here/../../build/oitref")}
[ -x "$oitref" ] || { echo "$0: no oitref executable at $oitref (set OITREF)" >&2; exit 2; }
oitref=$(realpath "$oitref")
[ -d "$plan" ] || { echo "$0: $plan: no such plan folder" >&2; exit 2; }
plan=$(realpath "$plan")
missing=$("$oitref" collect "$plan" --missing)
if [ -z "$missing" ]; then
  echo "every job of $plan is done; collecting"
  exec "$oitref" collect "$plan"
fi
mkdir -p "$plan/logs"
array_spec=$missing${OITREF_ARRAY_LIMIT:+%$OITREF_ARRAY_LIMIT}
array=$(sbatch --parsable --job-name=oitref-job --array="$array_spec" --cpus-per-task="${OITREF_CPUS_PER_TASK:-2}" \
  --output="$plan/logs/job-%a.out" --export=ALL,OITREF="$oitref" "$@" "$here/job.sbatch" "$plan")
array=${array%%;*}
collect=$(sbatch --parsable --job-name=oitref-collect --dependency=afterok:"$array" --kill-on-invalid-dep=yes \
  --cpus-per-task=1 --output="$plan/logs/collect-%j.out" --export=ALL,OITREF="$oitref" "$@" "$here/collect.sbatch" "$plan")
collect=${collect%%;*}
echo "submitted jobs $missing of $plan as Slurm array $array; collect as job $collect (runs when all succeed)"
echo "array=$array collect=$collect"
