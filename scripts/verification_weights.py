#!/usr/bin/env python3
# This file is part of OpenCV project.
# It is subject to the license terms in the LICENSE file found in the top-level directory
# of this distribution and at http://opencv.org/license.html
"""Weights of the verification stage (VerificationParams::w_*) from forestmod_eval JSON files.

forestmod_eval writes, for its *_verified rows, the features of every hypothesis of every frame
("hypotheses": [similarity, color, edges, depth, occlusion, box IoU, projection error px,
region, background]). This script re-ranks them under every weight tuple (w_similarity, w_color,
w_edges, w_region) on a grid of the simplex (w_depth on a grid too when the features have depth) and
prints the tuples with the most correct first hypotheses (box IoU >= 0.5 plus projection error
< 5 px, summed). Run it on rendered scenes (forestmod_eval --synthetic=N) or on frames that a
reported evaluation does not use (--first_frame), never on the frames it reports.

usage: scripts/verification_weights.py eval.json [more.json ...] [--step 0.1] [--top 10]
"""
import argparse
import itertools
import json


def frames_of(doc):
    """Every frame's hypotheses of the verified rows, over objects and rows."""
    out = []
    for obj in doc.get("objects", []):
        for row in ("forestmod_verified", "linemod_verified"):
            for f in obj.get(row, {}).get("per_frame", []):
                hyps = [[float("nan") if v == "n/a" else float(v) for v in h]
                        for h in f.get("hypotheses", [])]
                for h in hyps:  # files written before region_score: no region
                    h.extend([0.0] * (8 - len(h)))
                out.append(hyps)
    return out


def score(frames, w_sim, w_col, w_edge, w_depth, w_region=0.0):
    ok2d = okproj = 0
    for hyps in frames:
        if not hyps:
            continue
        def value(h):
            v = w_sim * h[0] / 100.0 + w_col * h[1] + w_edge * h[2] + w_region * h[7]
            if h[3] >= 0:
                v += w_depth * h[3]
            return v
        best = max(hyps, key=value)  # ties: the first (the matcher's order is lost here)
        ok2d += best[5] >= 0.5
        okproj += best[6] < 5.0
    return ok2d, okproj


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("json", nargs="+")
    ap.add_argument("--step", type=float, default=0.1)
    ap.add_argument("--top", type=int, default=10)
    args = ap.parse_args()
    frames = []
    for path in args.json:
        with open(path) as f:
            frames += frames_of(json.load(f))
    with_depth = any(h[3] >= 0 for hyps in frames for h in hyps)
    n = len(frames)
    steps = int(round(1.0 / args.step))
    grid = [i * args.step for i in range(steps + 1)]
    results = []
    for w_sim, w_col, w_reg in itertools.product(grid, grid, grid):
        w_edge = 1.0 - w_sim - w_col - w_reg
        if w_edge < -1e-9:
            continue
        w_edge = max(0.0, w_edge)
        for w_depth in (grid if with_depth else [0.0]):
            ok2d, okproj = score(frames, w_sim, w_col, w_edge, w_depth, w_reg)
            results.append((ok2d + okproj, ok2d, okproj, w_sim, w_col, w_edge, w_depth, w_reg))
    results.sort(key=lambda r: -r[0])
    print("%d frames x rows with hypotheses%s" % (n, ", with depth" if with_depth else ""))
    print("| w_similarity | w_color | w_edges | w_region | w_depth | 2D@1 | proj@1 |")
    print("|---|---|---|---|---|---|---|")
    for r in results[:args.top]:
        print("| %.2f | %.2f | %.2f | %.2f | %.2f | %d (%.1f %%) | %d (%.1f %%) |"
              % (r[3], r[4], r[5], r[7], r[6], r[1], 100.0 * r[1] / max(1, n), r[2],
                 100.0 * r[2] / max(1, n)))
    plain = score(frames, 1.0, 0.0, 0.0, 0.0)
    print("similarity alone: 2D@1 %d, proj@1 %d" % plain)


if __name__ == "__main__":
    main()
