#!/usr/bin/env python3
# This file is part of OpenCV project.
# It is subject to the license terms in the LICENSE file found in the top-level directory
# of this distribution and at http://opencv.org/license.html
"""Tests of scripts/verification_weights.py on lists made up here (CTest: forestmod_scripts)."""
import contextlib
import io
import json
import os
import random
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import verification_weights as vw  # noqa: E402


def hypothesis(rng, right):
    """[similarity, colour, edges, depth, occlusion, box IoU, projection px, region,
    background]: a right hypothesis has the better edges, the similarity tells nothing."""
    edges = rng.uniform(0.7, 0.9) if right else rng.uniform(0.3, 0.6)
    return [rng.uniform(80, 100), rng.uniform(0, 1), edges, -1.0, 0.0,
            0.8 if right else 0.0, 2.0 if right else 300.0, rng.uniform(0, 1), 90.0]


def dataset(frames, seed):
    """One object, one verified row: a list per frame, its right hypothesis at a random place
    (none in every fifth frame), the others sorted by similarity as the matcher does."""
    rng = random.Random(seed)
    per_frame = []
    for i in range(frames):
        hyps = [hypothesis(rng, False) for _ in range(9)]
        if i % 5:
            hyps.insert(rng.randrange(10), hypothesis(rng, True))
        hyps.sort(key=lambda h: -h[0])
        per_frame.append({"scene_id": 2, "im_id": 100 + i, "hypotheses": hyps})
    return {"objects": [{"forestmod_verified": {"per_frame": per_frame}}]}


class VerificationWeights(unittest.TestCase):
    def setUp(self):
        self.doc = dataset(40, seed=3)
        ids = []
        self.frames = vw.frames_of(self.doc, ids)
        self.ids = ids

    def test_frames_and_ids_are_read_in_order(self):
        self.assertEqual(40, len(self.frames))
        self.assertEqual([(2, 100 + i) for i in range(40)], self.ids)
        self.assertTrue(all(len(h) == 9 for hyps in self.frames for h in hyps))

    def test_learned_ranker_finds_the_part_that_tells(self):
        fit, test = self.frames[:20], self.frames[20:]
        w = vw.fit_ranker(fit, "2d", quadratic=False)
        self.assertGreater(w[2], max(abs(w[0]), abs(w[1]), abs(w[5])))  # the edges, index 2
        value = lambda h: sum(a * b for a, b in zip(w, vw.parts_of(h, False)))
        ceiling = sum(any(vw.correct(h, "2d") for h in hyps) for hyps in test)
        self.assertEqual(16, ceiling)
        self.assertEqual(ceiling, vw.first_correct(test, "2d", value))
        # the matcher's order (similarity) finds few
        self.assertLess(vw.first_correct(test, "2d", lambda h: h[0]), ceiling // 2)

    def test_held_out_table_counts_each_half(self):
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            vw.held_out(self.frames, self.ids, 20, 0.1)
        lines = out.getvalue().splitlines()
        self.assertIn("fitted on 20 lists (frames (2, 100)..), counted on 20 (frames (2, 120)..)",
                      out.getvalue())
        ceiling = [l for l in lines if l.startswith("| ceiling")][0]
        self.assertEqual("| ceiling (a correct hypothesis in the list) | 16 | 16 | 16 | 16 |",
                         ceiling)
        learned = [l for l in lines if l.startswith("| learned, linear")][0]
        self.assertEqual(16, int(learned.split("|")[3]))  # 2D@1 held out

    def test_held_out_refuses_a_split_outside_the_frames(self):
        with self.assertRaises(SystemExit):
            vw.held_out(self.frames, self.ids, 40, 0.1)
        with self.assertRaises(SystemExit):
            vw.held_out(self.frames, self.ids, 0, 0.1)

    def test_command_line(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "eval.json")
            with open(path, "w") as f:
                json.dump(self.doc, f)
            out = io.StringIO()
            argv = sys.argv
            sys.argv = ["verification_weights.py", path, "--step", "0.5", "--held_out_from", "20"]
            try:
                with contextlib.redirect_stdout(out):
                    vw.main()
            finally:
                sys.argv = argv
            self.assertIn("40 frames x rows with hypotheses", out.getvalue())
            self.assertIn("| the lists' own order |", out.getvalue())


if __name__ == "__main__":
    unittest.main()
