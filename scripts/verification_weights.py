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

With --held_out_from N the frames of the files (in the order of their (scene, image) ids) from
the N-th on are held out: the grid's best tuple is chosen on the others and counted on them, and
so is a learned ranker (--help), against the lists' own order (the detector's defaults) and
their ceiling (a correct hypothesis anywhere in the list).

usage: scripts/verification_weights.py eval.json [more.json ...] [--step 0.1] [--top 10]
           [--held_out_from N]
"""
import argparse
import itertools
import json
import math


def frames_of(doc, ids=None):
    """Every frame's hypotheses of the verified rows, over objects and rows; with `ids` a list,
    each frame's (scene id, image id) appended to it in the same order."""
    out = []
    for obj in doc.get("objects", []):
        for row in ("forestmod_verified", "linemod_verified"):
            for f in obj.get(row, {}).get("per_frame", []):
                hyps = [[float("nan") if v == "n/a" else float(v) for v in h]
                        for h in f.get("hypotheses", [])]
                for h in hyps:  # files written before region_score / background: zeros
                    h.extend([0.0] * (9 - len(h)))
                out.append(hyps)
                if ids is not None:
                    ids.append((int(f.get("scene_id", -1)), int(f.get("im_id", -1))))
    return out


# The learned ranker: a list's hypotheses compete in a softmax of w . parts(h), w fitted by
# gradient ascent on the log-probability that the list's choice is one of its correct hypotheses
# (lists with no correct or no wrong one teach nothing), with an L2 penalty. "quadratic" adds the
# products of every two parts, so that a part's weight may depend on another.
PARTS = (0, 1, 2, 3, 4, 7, 8)  # similarity, colour, edges, depth, occlusion, region, background


def parts_of(h, quadratic):
    x = [h[0] / 100.0, h[1], h[2], max(h[3], 0.0), h[4], h[7], h[8] / 100.0]
    if quadratic:
        x += [x[a] * x[b] for a in range(len(x)) for b in range(a, len(x))]
    return x


def correct(h, target):
    return h[5] >= 0.5 if target == "2d" else h[6] < 5.0


def fit_ranker(frames, target, quadratic, epochs=400, rate=0.5, l2=1e-2):
    data = []
    for hyps in frames:
        y = [correct(h, target) for h in hyps]
        if any(y) and not all(y):
            data.append(([parts_of(h, quadratic) for h in hyps], y))
    if not data:
        return None
    d = len(data[0][0][0])
    w = [0.0] * d
    for _ in range(epochs):
        g = [0.0] * d
        for xs, y in data:
            s = [sum(a * b for a, b in zip(w, x)) for x in xs]
            top = max(s)
            e = [math.exp(v - top) for v in s]
            z = sum(e)
            p = [v / z for v in e]
            pos = sum(pj for pj, yj in zip(p, y) if yj)
            for x, pj, yj in zip(xs, p, y):
                q = (pj / pos if yj else 0.0) - pj
                for k in range(d):
                    g[k] += q * x[k]
        w = [wk + rate * (gk / len(data) - l2 * wk) for wk, gk in zip(w, g)]
    return w


def first_correct(frames, target, value):
    """Lists whose first hypothesis under `value` (ties: the earlier) is correct."""
    ok = 0
    for hyps in frames:
        if hyps:
            best = max(range(len(hyps)), key=lambda j: (value(hyps[j]), -j))
            ok += correct(hyps[best], target)
    return ok


def held_out(frames, ids, first, step):
    """Weights and rankers chosen on the frames before the `first`-th, counted on the others."""
    order = sorted(set(ids))
    if not 0 < first < len(order):
        raise SystemExit("--held_out_from %d: the files hold %d frames" % (first, len(order)))
    cut = order[first]
    fit = [h for h, i in zip(frames, ids) if i < cut and h]
    test = [h for h, i in zip(frames, ids) if i >= cut and h]
    steps = int(round(1.0 / step))
    grid = [i * step for i in range(steps + 1)]
    print("\nfitted on %d lists (frames %s..), counted on %d (frames %s..)"
          % (len(fit), order[0], len(test), cut))
    print("| ranking | 2D@1 fitted | 2D@1 held out | proj@1 fitted | proj@1 held out |")
    print("|---|---|---|---|---|")
    rows = [("the lists' own order", lambda h: 0.0, lambda h: 0.0)]
    for target in ("2d", "proj"):
        best = None
        for w_sim, w_col, w_reg in itertools.product(grid, grid, grid):
            w_edge = 1.0 - w_sim - w_col - w_reg
            if w_edge < -1e-9:
                continue
            w = (w_sim, w_col, max(0.0, w_edge), w_reg)
            v = (lambda w: lambda h: w[0] * h[0] / 100.0 + w[1] * h[1] + w[2] * h[2]
                 + w[3] * h[7])(w)
            n = first_correct(fit, target, v)
            if best is None or n > best[0]:
                best = (n, w, v)
        rows.append(("grid's best for %s %s" % (target, "/".join("%.1f" % x for x in best[1])),
                     best[2], best[2]))
    for quadratic in (False, True):
        w2 = fit_ranker(fit, "2d", quadratic)
        wp = fit_ranker(fit, "proj", quadratic)
        score = (lambda w: lambda h: sum(a * b for a, b in zip(w, parts_of(h, quadratic)))
                 if w else 0.0)
        rows.append(("learned, %s parts" % ("quadratic" if quadratic else "linear"),
                     score(w2), score(wp)))
    for name, v2, vp in rows:
        print("| %s | %d | %d | %d | %d |" % (name, first_correct(fit, "2d", v2),
                                            first_correct(test, "2d", v2),
                                            first_correct(fit, "proj", vp),
                                            first_correct(test, "proj", vp)))
    ceiling = [sum(any(correct(h, t) for h in hyps) for hyps in s)
               for t in ("2d", "proj") for s in (fit, test)]
    print("| ceiling (a correct hypothesis in the list) | %d | %d | %d | %d |" % tuple(ceiling))


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
    ap.add_argument("--held_out_from", type=int, default=0,
                    help="choose on the frames before the N-th, count on the others; also fits "
                         "a listwise logistic ranker on the parts (linear, and with their "
                         "products)")
    args = ap.parse_args()
    frames, ids = [], []
    for path in args.json:
        with open(path) as f:
            frames += frames_of(json.load(f), ids)
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
    if args.held_out_from:
        held_out(frames, ids, args.held_out_from, args.step)


if __name__ == "__main__":
    main()
