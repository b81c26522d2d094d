#!/usr/bin/env bash
# README command 1: sets everything up (scripts/setup.sh), then runs the main job on data the
# project ships (testdata/forestmod/lmo_mini). Outputs go to ./out (overwritten on every run:
# the folder belongs to this script).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${FORESTMOD_BUILD_DIR:-$root/build}
"$root/scripts/setup.sh"
out="$root/out"
mkdir -p "$out"
frame="$root/testdata/forestmod/lmo_mini/test/000002/rgb/000902.png"
"$build/bin/forestmod_hue" "$frame" "$out/hue_000902.png" --force
echo "demo: wrote $out/hue_000902.png"
