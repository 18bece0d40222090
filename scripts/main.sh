#!/usr/bin/env bash
# README command 1: set up, build, and run the main job: `oitref study` over every built-in
# scene (every method and its variants, timed and measured against the A-buffer), writing the
# HTML report into ./out/study and printing where it is.
set -euo pipefail
cd "$(dirname "$0")/.."
# Only the command-line program: the tests and benchmarks build with scripts/test.sh.
OITREF_BUILD_TARGET=oitref scripts/setup.sh
build/oitref study --out out/study "$@"
