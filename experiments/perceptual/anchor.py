#!/usr/bin/env python3
"""glintlab's perceptual anchor: ColorVideoVDP's verdict on glintlab's renders, beside glintlab's metrics.

    python3 experiments/perceptual/anchor.py --render --cvvdp PATH/ColorVideoVDP \\
        --runs results/perceptual --out tests/data/perceptual/anchor.csv

--render runs `glintlab run perceptual/<scene>` for the three scenes (experiments/data/perceptual/) into
RUNS/<scene>; without it the runs must be there. --cvvdp is a source checkout of ColorVideoVDP
(github.com/gfxdisp/ColorVideoVDP; checked with commit 7ca201a) with torch and torchvision importable
(Debian: python3-torch python3-torchvision python3-tqdm); without it only glintlab's columns are
written. The tests never run this: they read the table it wrote (tests/data/perceptual/anchor.csv).

What ColorVideoVDP sees is what glintlab's PNGs show: every frame through the run's OCIO view
(sRGB-encoded 8 bit), on the display `standard_fhd` (24-inch 1920x1080, 200 cd/m², 0.6 m), at the
path's frame rate. Per variant it compares the variant's frames with its truth's and writes the JOD of
the video and of two channel groups pooled alone: `jod_transient` (the achromatic transient channel,
what flicker and lag are seen through) and `jod_sustained` (the sustained achromatic and the two
chromatic channels). Higher JOD = closer to the truth; 10 = indistinguishable.

Only the metric's own code (pycvvdp/cvvdp_metric.py and what it imports) runs: the package's
`__init__` also imports the video-file readers and the learned variant, whose modules (ffmpeg,
imageio.v2, einops, huggingface_hub) this script replaces with empty stand-ins before the import,
since no code path it calls uses them; and Debian's torch 1.13 needs int64 index tensors where the
checkout's quick interpolant makes int32 ones (widened here, the same indices). Run it with Debian's
python3 (/usr/bin/python3), which has numpy, torch and PIL.

Columns: scene, variant, truth, jod, jod_transient, jod_sustained, then the run's summary means of
glintlab's temporal metrics (TEMPORAL_METRICS) and deltaE2000, then score_p1 ... score_p6: temporal_score's
definition (metrics/flicker.h) computed here from the same PNGs with Minkowski exponent p = 1, 2, 3, 4, 6 —
the family the exponent was chosen from, so the test can fit it on two scenes and check the third
(tests/python/test_perceptual_anchor.py). The 8-bit PNGs make score_p4 differ slightly from glintlab's
temporal_score, which is measured on the float image before encoding."""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import types

SCENES = ("orbit", "grazing-pan", "dunes")
TEMPORAL_METRICS = ("temporal_score", "flicker_excess", "temporal_lag", "temporal_error_mc", "temporal_error",
                    "flicker_ratio", "deltaE2000")
CHANNELS = {"transient": [3], "sustained": [0, 1, 2]}  # cvvdp's Q_per_ch channels: A-sust, RG, YV, A-trans
POWERS = (1, 2, 3, 4, 6)  # score_p<k>: temporal_score's Minkowski exponent candidates


def render(glintlab, runs):
    for scene in SCENES:
        subprocess.run([glintlab, "run", f"perceptual/{scene}", "--out", os.path.join(runs, scene)], check=True)


def load_cvvdp(checkout):
    """The metric class of a ColorVideoVDP source checkout (see the module's docstring)."""
    pkg = os.path.join(checkout, "pycvvdp")
    if not os.path.isdir(pkg):
        sys.exit(f"anchor.py: {checkout}: no pycvvdp/ folder (expected a ColorVideoVDP source checkout)")
    for name in ("ffmpeg", "imageio", "imageio.v2", "einops", "einops.layers", "einops.layers.torch",
                 "huggingface_hub"):
        try:
            __import__(name)
        except ImportError:
            stub = types.ModuleType(name)
            stub.__getattr__ = lambda attr, _n=name: (lambda *a, **k: None) if attr != "__path__" else []
            sys.modules[name] = stub
    sys.path[:0] = [checkout, pkg]
    import pycvvdp  # noqa: E402
    # torch 1.13 (Debian 12) indexes only with int64 tensors; the quick interpolant makes int32 ones
    # (newer torch accepts both): the same indices, widened. The module is loaded twice (as `interp`
    # and `pycvvdp.interp`), so both copies get it.
    import torch
    for name in ("interp", "pycvvdp.interp"):
        module = sys.modules.get(name)
        if module is not None and hasattr(module, "get_interpolants_quick"):
            quick = module.get_interpolants_quick
            module.get_interpolants_quick = lambda x_q, x, _q=quick: tuple(
                t.to(torch.int64) if t.dtype == torch.int32 else t for t in _q(x_q, x))
    return pycvvdp


def read_frames(folder, count):
    import numpy as np
    from PIL import Image
    frames = []
    for f in range(count):
        path = os.path.join(folder, f"frame_{f:04d}.png")
        if not os.path.isfile(path):
            sys.exit(f"anchor.py: {path}: missing (the run must write every frame as PNG: output.every 1)")
        frames.append(np.asarray(Image.open(path).convert("RGB")))
    return np.stack(frames)  # F, H, W, C uint8


def displayed_lightness(frames):
    """CIE L* (white = 100) of the display-linear luminance of sRGB-encoded 8-bit frames (F, H, W, C)."""
    import numpy as np
    v = frames.astype(np.float64) / 255.0
    linear = np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)
    y = linear @ np.array([0.2126, 0.7152, 0.0722])
    d = 6.0 / 29.0
    return 116.0 * np.where(y > d ** 3, np.cbrt(y), y / (3 * d * d) + 4.0 / 29.0) - 16.0


def score_family(test, truth):
    """{score_p<k>: mean over frames of (mean_px c^p)^(1/p)}, c = |ΔL*(test) − ΔL*(truth)| at a fixed pixel."""
    import numpy as np
    lt, lr = displayed_lightness(test), displayed_lightness(truth)
    per_frame = {p: [] for p in POWERS}
    for t in range(1, len(lt)):
        c = np.abs((lt[t] - lt[t - 1]) - (lr[t] - lr[t - 1]))
        for p in POWERS:
            per_frame[p].append(float(np.mean(c ** p) ** (1.0 / p)))
    return {f"score_p{p}": float(np.mean(v)) for p, v in per_frame.items()}


def jods(pycvvdp, metric, test, truth, fps):
    import torch
    q, stats = metric.predict(test, truth, dim_order="FHWC", frames_per_second=fps)
    out = {"jod": float(q)}
    per_ch = torch.as_tensor(stats["Q_per_ch"], device=metric.device)
    for group, channels in CHANNELS.items():
        only = torch.zeros_like(per_ch)
        only[:, channels] = per_ch[:, channels]
        out[f"jod_{group}"] = float(metric.do_pooling_and_jods(only))
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", required=True, help="folder of the three runs (RUNS/<scene>)")
    parser.add_argument("--out", required=True, help="CSV to write")
    parser.add_argument("--cvvdp", help="ColorVideoVDP source checkout")
    parser.add_argument("--render", action="store_true", help="render the three scenes first")
    parser.add_argument("--glintlab", default=os.path.join("build", "glintlab"), help="the glintlab program")
    parser.add_argument("--display", default="standard_fhd", help="ColorVideoVDP display model")
    args = parser.parse_args()
    if args.render:
        render(args.glintlab, args.runs)
    pycvvdp = load_cvvdp(args.cvvdp) if args.cvvdp else None
    metric = pycvvdp.cvvdp(display_name=args.display, quiet=True, device=None) if pycvvdp else None
    rows = []
    for scene in SCENES:
        run = os.path.join(args.runs, scene)
        summary = json.load(open(os.path.join(run, "summary.json")))
        frames = summary["frames"]
        fps = json.load(open(summary["file"]))["camera_path"].get("fps", 30) if os.path.isfile(summary["file"]) else 30
        truths = {}
        for v in summary["variants"]:
            row = {"scene": scene, "variant": v["name"], "truth": v["reference"]}
            for m in TEMPORAL_METRICS:
                x = (v["metrics"].get(m) or {}).get("mean")
                row[m] = "" if x is None or (isinstance(x, float) and math.isnan(x)) else x
            if v["reference"] not in truths:
                truths[v["reference"]] = read_frames(os.path.join(run, v["reference"]), frames)
            test = read_frames(os.path.join(run, v["name"]), frames)
            row.update(score_family(test, truths[v["reference"]]))
            if metric is not None:
                row.update(jods(pycvvdp, metric, test, truths[v["reference"]], fps))
                print(f"{scene} {v['name']}: JOD {row['jod']:.3f}, transient {row['jod_transient']:.3f}",
                      file=sys.stderr)
            rows.append(row)
    keys = ["scene", "variant", "truth", "jod", "jod_transient", "jod_sustained", *TEMPORAL_METRICS,
            *(f"score_p{p}" for p in POWERS)]
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    tmp = args.out + ".tmp"
    with open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{r[k]:.6g}" if isinstance(r.get(k), float) else r.get(k, "")) for k in keys})
    os.replace(tmp, args.out)


if __name__ == "__main__":
    main()
