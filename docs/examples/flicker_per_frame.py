#!/usr/bin/env python3
"""Flicker per frame of two Cycles renders (1 and 16 samples a pixel) against their converged
reference, measured from numpy arrays with `import glintlab`, plotted with matplotlib.

    python3 docs/examples/flicker_per_frame.py [--data tests/data/blender] [--out flicker.png]

Reads the three sequences of tests/data/blender (80x45, 8 frames, layer ViewLayer.Combined) into
T x H x W x 3 float32 arrays, measures both against the reference (the motion estimated by optical
flow, as `glintlab measure` without --motion) and draws each frame's flicker_ratio: the test's
temporal change along the motion over the reference's (1 = flickers as much as the reference).
"""

import argparse
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import glintlab  # noqa: E402

here = os.path.dirname(os.path.abspath(__file__))
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--data", default=os.path.join(here, "..", "..", "tests", "data", "blender"))
parser.add_argument("--out", default="flicker.png")
args = parser.parse_args()

layer = "ViewLayer.Combined"
reference = glintlab.read_sequence(os.path.join(args.data, "ref"), layer)
tests = {name: glintlab.read_sequence(os.path.join(args.data, name), layer) for name in ("spp1", "spp16")}
print(f"read {len(tests) + 1} sequences of {reference.shape[0]} frames, {reference.shape[2]}x{reference.shape[1]}")

summary, records = glintlab.measure(reference, tests, metrics=["deltaE2000", "flicker"])

fig, ax = plt.subplots(figsize=(6, 3.4), dpi=120)
for name in tests:
    rows = [r for r in records if r["variant"] == name and r["frame"] > 0]  # frame 0 has no frame before it
    if not rows or not all(math.isfinite(r["flicker_ratio"]) for r in rows):
        raise SystemExit(f"{name}: no finite flicker_ratio per frame: {[r['flicker_ratio'] for r in rows]}")
    ax.plot([r["frame"] for r in rows], [r["flicker_ratio"] for r in rows], marker="o", label=name)
    mean = next(v for v in summary["variants"] if v["name"] == name)["metrics"]["flicker_ratio"]["mean"]
    print(f"{name}: mean flicker_ratio {mean:.3f}")
ax.axhline(1.0, color="grey", lw=0.8, ls="--")
ax.set_xlabel("frame (index in the sequence)")
ax.set_ylabel("flicker_ratio (test / reference)")
ax.set_title("Cycles, 80x45: flicker per frame against the converged render")
ax.legend()
fig.tight_layout()
os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
fig.savefig(args.out)
print(f"wrote {args.out}")
