#!/usr/bin/env bash
# The installed package as a user meets it: `cmake --install` of this build into a temporary
# prefix, examples/consumer configured with find_package(oitref) against that prefix alone, built
# and run. Its blend bits must be those `oitref blend` prints, and its frame's hash the one
# reference/manifest.txt keeps for the scene. examples/custom_method, a method written outside the
# tree with the method kit, is built the same way and must be listed and studied as oitref's own.
#   tests/check_install.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
source=$(cd "$2" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cmake --install "$build" --prefix "$work/prefix" >/dev/null
cmake -S "$source/examples/consumer" -B "$work/consumer" -G Ninja -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/consumer" >/dev/null
"$work/consumer/oitref_consumer" "$source/scenes/glass.json" "$work/glass.png" | tee "$work/out.txt"

status=0
for profile in exact llvmpipe nvidia; do
  expected=$("$work/prefix/bin/oitref" blend --format rgba16f --func src_alpha,one_minus_src_alpha,one,one_minus_src_alpha \
             --dst 0.2,0.4,0.6,1 --src 0.9,0.1,0.3,0.7 --profile "$profile" | sed -n 's/^result *bits \(.*\)  value.*/\1/p')
  got=$(sed -n "s/^blend rgba16f $profile bits //p" "$work/out.txt")
  if [ -z "$expected" ] || [ "$got" != "$expected" ]; then
    echo "blend, profile $profile: the consumer stored '$got', oitref blend '$expected'"; status=1
  fi
done
expected=$(awk '$1 == "glass" && $2 == "wboit" {print $3}' "$source/reference/manifest.txt")
got=$(sed -n 's/^frame wboit 96x72 sha256 //p' "$work/out.txt")
if [ -z "$expected" ] || [ "$got" != "$expected" ]; then
  echo "frame: the consumer's hash '$got', reference/manifest.txt '$expected'"; status=1
fi
[ -s "$work/glass.png" ] || { echo "the consumer wrote no image"; status=1; }
# The Python module, where this build has one: imported from the prefix alone.
module=$(find "$work/prefix" -name 'oitref*.so' | head -1)
if [ -n "$module" ]; then
  got=$(cd "$work" && PYTHONPATH="$(dirname "$module")" /usr/bin/python3 -c "import oitref
print(oitref.render('$source/scenes/glass.json', 'wboit', size=(96, 72), threads=2)['sha256'])")
  if [ "$got" != "$expected" ]; then
    echo "the installed Python module's frame hash '$got', reference/manifest.txt '$expected'"; status=1
  else
    echo "the installed Python module ($module) gave the manifest's hash"
  fi
fi
# The method added from outside: listed, and studied beside wsum against the A-buffer.
cmake -S "$source/examples/custom_method" -B "$work/custom" -G Ninja -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/custom" >/dev/null
"$work/custom/custom_oitref" methods | grep -q '^clamped_sum ' || { echo "custom_oitref methods does not list clamped_sum"; status=1; }
"$work/custom/custom_oitref" study "$source/scenes/glass.json" --methods clamped_sum,wsum --size 96x72 --runs 1 --quiet \
  --out "$work/study" >/dev/null
rows=$(/usr/bin/python3 - "$work/study" <<'PY'
import json, math, os, sys
folder = sys.argv[1]
rows = [r for s in json.load(open(os.path.join(folder, "results.json")))["scenes"] for r in s["rows"]]
ok = [r for r in rows if r["method"] == "clamped_sum" and math.isfinite(r["rmse"]) and r["rmse"] > 0
      and os.path.getsize(os.path.join(folder, r["image"])) > 0]
print(len(ok), " ".join(sorted({r["method"] for r in rows})))
PY
)
if [ "$rows" != "2 abuffer clamped_sum raycast wsum" ]; then
  echo "the study of the custom method: expected its 2 rows (defaults, accum=rgba32f) beside abuffer, raycast and wsum, got '$rows'"; status=1
else
  echo "custom_oitref studied clamped_sum (2 rows) beside wsum, against the A-buffer"
fi
[ "$status" -eq 0 ] && echo "the installed package built the consumer and the custom method, and they gave the CLI's and the manifest's bits"
exit "$status"
