#!/usr/bin/env bash
# A study through a real Slurm (ctest label `slurm`): a one-node cluster on this machine
# (local_slurm.sh; Debian's slurm-wlm and munge installed if missing), a study of two built-in
# scenes at a small size planned as 6 jobs, submitted with scripts/slurm/submit.sh as a job
# array, collected by Slurm after it; the report must be the single-machine study's (identical
# image bits and error figures: compare_study.py). Then a second plan whose task 3 is cancelled
# (scancel): the collect job never runs, `oitref collect` names job 3, and submitting again
# runs just that task and completes the study.
#   check_slurm.sh OITREF SOURCE_DIR
set -euo pipefail
oitref=$(realpath "$1")
source_dir=$(realpath "$2")
cd "$source_dir"
. tests/local_slurm.sh
install_slurm_if_missing
work=$(mktemp -d /tmp/oitref-slurm-test.XXXXXX)
trap 'stop_local_slurm; rm -rf "$work"' EXIT
start_local_slurm "$work/cluster"

study=(scenes/glass.json scenes/veils.json --size 64x36 --runs 1)
start=$(date +%s%N)
"$oitref" study "${study[@]}" --threads 1 --quiet --out "$work/local" > /dev/null
echo "one process, 1 thread: $(( ($(date +%s%N) - start) / 1000000 )) ms"

# Waits (at most $2 seconds) until Slurm has none of the listed jobs left.
wait_for_jobs() {
  local ids=$1 limit=$2 t=0
  while [ -n "$(squeue -h -j "$ids" -o %i 2>/dev/null)" ]; do
    sleep 1
    t=$((t + 1))
    if [ "$t" -ge "$limit" ]; then
      echo "Slurm jobs $ids still queued after $limit s:"; squeue; return 1
    fi
  done
}
submit() {  # submit.sh's output into $submitted, its "array=… collect=…" line into $array and $collect
  local line
  submitted=$(OITREF="$oitref" OITREF_CPUS_PER_TASK=1 bash scripts/slurm/submit.sh "$@")
  echo "$submitted"
  line=$(echo "$submitted" | grep '^array=')
  array=$(echo "$line" | sed 's/array=\([0-9]*\).*/\1/')
  collect=$(echo "$line" | sed 's/.*collect=\([0-9]*\)/\1/')
}

echo "== a study as a Slurm job array"
"$oitref" study "${study[@]}" --out "$work/report" --plan "$work/plan" --configurations-per-job 24
start=$(date +%s%N)
submit "$work/plan"
wait_for_jobs "$array,$collect" 600
echo "Slurm array of 6 tasks (1 CPU each, $(nproc) CPUs) and collect: $(( ($(date +%s%N) - start) / 1000000 )) ms"
cat "$work/plan/logs/collect-$collect.out"
python3 tests/compare_study.py "$work/local" "$work/report"
grep -q "Run as 6 jobs" "$work/report/index.html" || { echo "the report does not say it was run as jobs"; exit 1; }

echo "== a cancelled task: named by collect, and submitted again alone"
"$oitref" study "${study[@]}" --out "$work/report2" --plan "$work/plan2" --configurations-per-job 24
submit "$work/plan2" --hold
scancel "${array}_3"
scontrol release "$array" "$collect" 2>/dev/null || scontrol release "$array"
wait_for_jobs "$array,$collect" 600
[ ! -e "$work/report2/results.json" ] || { echo "collect ran although task 3 was cancelled"; exit 1; }
[ ! -e "$work/plan2/logs/job-3.out" ] || { echo "the cancelled task 3 ran"; exit 1; }
status=0
"$oitref" collect "$work/plan2" > "$work/collect2.txt" 2>&1 || status=$?
cat "$work/collect2.txt"
[ "$status" = 2 ] || { echo "collect with a cancelled job exited $status, not 2"; exit 1; }
grep -q "job 3: missing" "$work/collect2.txt" || { echo "collect did not name job 3"; exit 1; }
[ "$("$oitref" collect "$work/plan2" --missing)" = 3 ] || { echo "--missing is not '3'"; exit 1; }
submit "$work/plan2"
wait_for_jobs "$array,$collect" 600
echo "$submitted" | grep -q "^submitted jobs 3 of " || { echo "the re-submission was not of task 3 alone"; exit 1; }
[ "$(squeue -h -o %i)" = "" ] && [ -f "$work/plan2/logs/job-3.out" ] || { echo "task 3 did not run again"; exit 1; }
python3 tests/compare_study.py "$work/local" "$work/report2"
echo "Slurm: both studies equal the single-machine study"
