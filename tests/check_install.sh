#!/usr/bin/env bash
# The installed package as a user meets it: `cmake --install` of this build into a temporary
# prefix, examples/consumer configured with find_package(oitref) against that prefix alone, built
# and run. Its blend bits must be those `oitref blend` prints, and its frame's hash the one
# reference/manifest.txt keeps for the scene.
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
[ "$status" -eq 0 ] && echo "the installed package built the consumer, and it gave the CLI's and the manifest's bits"
exit "$status"
