#!/usr/bin/env bash
# README command 1: sets everything up (scripts/setup.sh), then runs the main job on data the
# project ships (testdata/forestmod/lmo_mini: the LM-O ape mesh and three real LM-O frames):
#   1. forestmod_train renders 2880 templates of the ape (view hemisphere up to 60 degrees of
#      elevation, 700 and 850 mm, in-plane rotations every 20 degrees) and trains the forest;
#   2. forestmod_detect finds the ape in each frame (RGB only: the LM-O frames have no depth),
#      prints its 6-DoF pose and the errors against the ground truth, and writes an overlay.
# Outputs go to ./out, which belongs to this script (its files are replaced on every run).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${FORESTMOD_BUILD_DIR:-$root/build}
"$root/scripts/setup.sh"
out="$root/out"
data="$root/testdata/forestmod/lmo_mini"
mkdir -p "$out"
"$build/bin/forestmod_hue" "$data/test/000002/rgb/000902.png" "$out/hue_000902.png" --force
echo "== training (about a minute on 2 cores)"
"$build/bin/forestmod_train" --meshes="$data/models/obj_000001.ply" --ids=obj_000001 \
  --out="$out/ape_model.yml.gz" --force --modalities=line --level=2 --min_elevation=0 \
  --max_elevation=60 --radii=700,850 --inplane=-180,160,20 --fuzzy=0.5
for frame in 224 902 1038; do
  echo "== frame $frame"
  "$build/bin/forestmod_detect" --model="$out/ape_model.yml.gz" --dataset="$data" --scene=2 \
    --frame=$frame --out="$out/detect_$(printf %06d $frame).png" --force
done
echo "demo: model, overlays and the quantized hue are in $out"
