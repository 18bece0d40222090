#!/usr/bin/env bash
# README command 1: set up, build, and run the main job: every built-in scene with every OIT
# method, images into ./out/suite, and a table per scene (time, memory, error vs the A-buffer).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
build/oitref suite --out out/suite "$@"
