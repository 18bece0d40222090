#!/usr/bin/env bash
# The layers' rule (docs/design.md): a layer includes only itself and the layers below it.
# core (src/core, include/oitref/core) includes nothing of oit or apps; oit (src/oit,
# include/oitref/oit) nothing of apps. Internal headers are included by folder, so a folder
# names its layer: core's are format/ blend/ pipeline/ texture/ util/, oit's scene/ methods/
# groundtruth/ frame/ io/ metrics/, apps' tools/ glcheck/ gpucapture/ python/.
#   tests/check_layers.sh SOURCE_DIR
set -euo pipefail
cd "$1"
oit='"(oitref/oit/|scene/|methods/|groundtruth/|frame/|io/|metrics/)'
apps='"(oitref/apps/|tools/|glcheck/|gpucapture/|python/)'
status=0
check() {  # check WHAT PATTERN FOLDERS...
  local what=$1 pattern=$2; shift 2
  local found
  found=$(grep -rnE "^\s*#\s*include\s*$pattern" "$@" || true)
  if [ -n "$found" ]; then
    echo "$what:"; echo "$found"; status=1
  fi
}
check "the core includes the oit layer" "$oit" src/core include/oitref/core
check "the core includes the applications" "$apps" src/core include/oitref/core
check "the oit layer includes the applications" "$apps" src/oit include/oitref/oit
files=$(find src/core src/oit include/oitref/core include/oitref/oit -name '*.h' -o -name '*.cpp' | wc -l)
[ "$status" -eq 0 ] && echo "$files files of the core and oit layers include nothing of a layer above them"
exit "$status"
