#!/usr/bin/env bash
# README command 1: set up, build, and run the main job on the built-in default scene,
# writing images to ./out/demo.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
build/oitref demo --out out/demo "$@"
