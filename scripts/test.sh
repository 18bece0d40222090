#!/usr/bin/env bash
# README command 2: set up, build, and run the whole test suite (including the exhaustive
# 2^32-input conversion sweeps, about 30 s on two cores).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
