#!/usr/bin/env bash
# Opens an `oitref study` report in headless Chromium and checks that it renders: the page loads,
# every image on it decodes, and nothing is written to the console as an error. Writes a
# screenshot beside the report (report.png) for a person to look at.
# Usage: scripts/check_report.sh out/study/index.html      Exit 77 when Chromium is missing.
set -euo pipefail
page=$(realpath "$1")
browser=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$browser" ]; then echo "check_report: chromium is not installed (apt-get install chromium)"; exit 77; fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
flags=(--headless=new --no-sandbox --disable-gpu --hide-scrollbars --user-data-dir="$work/profile"
       --enable-logging=stderr --v=0 --virtual-time-budget=20000)
"$browser" "${flags[@]}" --dump-dom "file://$page" > "$work/dom.html" 2> "$work/log.txt" || true
"$browser" "${flags[@]}" --window-size=1300,3000 --screenshot="$(dirname "$page")/report.png" "file://$page" \
  > /dev/null 2>> "$work/log.txt" || true
fail=0
if ! grep -q '</html>' "$work/dom.html"; then echo "check_report: the page did not load"; fail=1; fi
images=$(grep -o 'data-images="[0-9]*"' "$work/dom.html" | grep -o '[0-9]*' || true)
broken=$(grep -o 'data-broken="[0-9]*"' "$work/dom.html" | grep -o '[0-9]*' || true)
if [ -z "$images" ]; then echo "check_report: the page's load handler did not run"; fail=1
elif [ "$broken" != 0 ]; then echo "check_report: $broken of $images images failed to load"; fail=1; fi
svgs=$(grep -c '<svg class="scatter"' "$work/dom.html" || true)
if grep -q 'INFO:CONSOLE' "$work/log.txt"; then echo "check_report: console messages:"; grep 'INFO:CONSOLE' "$work/log.txt"; fail=1; fi
[ "$fail" = 0 ] && echo "check_report: $page renders in $("$browser" --version 2>/dev/null | head -1): $images images, $svgs scatter plots, no console errors; screenshot $(dirname "$page")/report.png"
exit $fail
