#!/usr/bin/env bash
# `oitref study --plan`, `oitref job` and `oitref collect` without a cluster: jobs run one by one
# in any order give the single-machine study (compare_study.py); a job killed half-way (SIGKILL)
# leaves no result, and collect names it; a failed job leaves its error, which collect repeats;
# a plan from another oitref executable, a job index out of range and a damaged result file each
# give an error naming the folder and the job; --resume runs just what is missing.
#   check_study_jobs.sh OITREF SOURCE_DIR
set -euo pipefail
oitref=$(realpath "$1")
cd "$(realpath "$2")"
work=$(mktemp -d /tmp/oitref-jobs-test.XXXXXX)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAILED: $*"; exit 1; }
# expect STATUS PATTERN COMMAND…: the command exits with STATUS and says PATTERN on stderr.
expect() {
  local want=$1 pattern=$2 status=0
  shift 2
  "$@" > "$work/out.txt" 2> "$work/err.txt" || status=$?
  [ "$status" = "$want" ] || { cat "$work/err.txt"; fail "$* exited $status, not $want"; }
  grep -q -- "$pattern" "$work/err.txt" || { cat "$work/err.txt"; fail "$* did not say '$pattern'"; }
}

study=(scenes/glass.json scenes/veils.json --size 64x36 --runs 1)
"$oitref" study "${study[@]}" --threads 2 --quiet --out "$work/local" > /dev/null
"$oitref" study "${study[@]}" --out "$work/report" --plan "$work/plan" --configurations-per-job 30 > /dev/null
n=$(python3 -c 'import json,sys; print(len(json.load(open(sys.argv[1]))["jobs"]))' "$work/plan/plan.json")
[ "$n" = 6 ] || fail "72 configurations in runs of at most 30 per scene should make 6 jobs, not $n"

expect 2 "$work/plan: there is no job 6; the plan has jobs 0–5" "$oitref" job "$work/plan" 6
expect 2 "job index '2x' is not a whole number" "$oitref" job "$work/plan" 2x
expect 2 "$work/nothing: no such plan folder" "$oitref" job "$work/nothing" 0
cp "$oitref" "$work/other-oitref" && printf 'another build' >> "$work/other-oitref"
expect 2 "$work/plan: planned by oitref .* but this is oitref" "$work/other-oitref" job "$work/plan" 0
expect 2 "already holds a plan" "$oitref" study "${study[@]}" --plan "$work/plan"

# Jobs in another order, with different thread counts.
for i in 5 2 0 4; do "$oitref" job "$work/plan" $i --threads $((i % 2 + 1)) --quiet; done
expect 2 "job 1: missing" "$oitref" collect "$work/plan"
grep -q "2 of 6 jobs are missing or failed (1,3)" "$work/err.txt" || fail "collect did not list jobs 1 and 3"
[ "$("$oitref" collect "$work/plan" --missing)" = "1,3" ] || fail "--missing is not '1,3'"

# A damaged result, a result of another plan: named, by job.
"$oitref" job "$work/plan" 1 --quiet
head -c 200 "$work/plan/jobs/0001/result.json" > "$work/cut.json" && cp "$work/cut.json" "$work/plan/jobs/0001/result.json"
expect 2 "job 1: damaged result: .*jobs/0001/result.json is damaged" "$oitref" collect "$work/plan"

# A failed job: its error is kept and repeated by collect; the plan's inputs are held to their hashes.
cp -r scenes "$work/scenes"
"$oitref" study "$work/scenes/glass.json" --size 64x36 --runs 1 --out "$work/report-f" --plan "$work/plan-f" > /dev/null
echo " " >> "$work/scenes/glass.json"
expect 2 "job 0 failed: .*glass.json (or a file it names) changed since the plan was made" "$oitref" job "$work/plan-f" 0
"$oitref" study "$work/scenes/atrium.json" --size 32x18 --runs 1 --out "$work/report-m" --plan "$work/plan-m" > /dev/null
echo "# changed" >> "$work/scenes/meshes/atrium/pane.mtl"
expect 2 "atrium.json (or a file it names) changed since the plan was made" "$oitref" job "$work/plan-m" 0
[ -f "$work/plan-f/jobs/0000.failed" ] || fail "a failed job left no record"
[ ! -e "$work/plan-f/jobs/0000" ] || fail "a failed job left a result folder"
expect 2 "job 0: failed: .*changed since the plan was made; plan again (on " "$oitref" collect "$work/plan-f"

# A job killed half-way leaves nothing collect could take for a result.
"$oitref" study scenes/glass.json --size 480x270 --runs 8 --out "$work/report-k" --plan "$work/plan-k" > /dev/null
"$oitref" job "$work/plan-k" 0 --threads 1 --quiet &
pid=$!
sleep 1.5
kill -9 $pid 2>/dev/null || fail "the job finished before it could be killed"
wait $pid 2>/dev/null || true
[ ! -e "$work/plan-k/jobs/0000" ] || fail "a killed job left a result folder"
ls -A "$work/plan-k/jobs" | grep -q '\.partial$' || fail "the killed job's staging folder is not where it should be"
expect 2 "job 0: missing" "$oitref" collect "$work/plan-k"

# --resume runs jobs 1 and 3 (3 missing, 1 damaged), then collects the single machine's study.
"$oitref" collect "$work/plan" --resume --quiet > /dev/null
python3 tests/compare_study.py "$work/local" "$work/report"
grep -q "the jobs had different thread counts" "$work/report/index.html" || fail "the report hides that its jobs' thread counts differ"

# The other commands with --plan: the atlas's files, the suite's tables (but their times) and
# images, the golden set's check, each as the single machine writes them.
stress=(--methods wboit,mboit --conditions base,hdr --max-layers 64)
"$oitref" stress "${stress[@]}" --quiet --out "$work/atlas-local" > /dev/null
"$oitref" stress "${stress[@]}" --out "$work/atlas" --plan "$work/plan-s" --rows-per-job 3 > /dev/null
"$oitref" collect "$work/plan-s" --resume --quiet > /dev/null
for f in atlas.json atlas.csv; do cmp "$work/atlas-local/$f" "$work/atlas/$f" || fail "the collected atlas's $f differs"; done
grep -q "Run as 8 jobs" "$work/atlas/atlas.html" || fail "the collected atlas does not say it was run as jobs"
suite=(scenes/glass.json scenes/veils.json --size 48x27)
"$oitref" suite "${suite[@]}" --out "$work/suite-local" > "$work/suite-local.txt"
"$oitref" suite "${suite[@]}" --out "$work/suite" --plan "$work/plan-u" > /dev/null
"$oitref" collect "$work/plan-u" --resume --quiet > "$work/suite.txt"
untimed() { grep -v '^Run as' "$1" | sed -E 's/^(  [a-z0-9]+) +[0-9.]+/\1/; s|images in .*||'; }
diff <(untimed "$work/suite-local.txt") <(untimed "$work/suite.txt") || fail "the collected suite's tables differ beyond their times"
diff -r "$work/suite-local" "$work/suite" || fail "the collected suite's images differ"
"$oitref" reference --plan "$work/plan-r" > /dev/null
"$oitref" collect "$work/plan-r" --resume --quiet > "$work/reference.txt" || fail "the golden set's check through jobs failed"
[ "$(tail -n 1 "$work/reference.txt")" = "$("$oitref" reference | tail -n 1)" ] || fail "collect's check of the golden set is not the single machine's"
grep -q "^identical: " "$work/reference.txt" || fail "the golden set is not identical through jobs"
echo "plan, job and collect: every check passed"
