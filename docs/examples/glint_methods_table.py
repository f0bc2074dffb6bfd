#!/usr/bin/env python3
"""The method table of shaders/README.md from a run of `glintlab run glint-methods`:

    python3 docs/examples/glint_methods_table.py results/glint-methods/summary.json

One Markdown row per variant: the glint density ratio (test over truth, from the means of both densities),
the glint histogram EMD, pooled bias and RMS at 2, 8 and 64 px, flicker excess, lag, temporal_error_mc,
ΔE00 (means over the frames), GPU ms per frame and its ratio to the `beckmann` variant of the same run;
then each truth's noise floor."""
import json
import math
import sys


def main(path):
    summary = json.load(open(path))
    variants = {v["name"]: v for v in summary["variants"]}

    def mean(v, k):
        x = (v.get("metrics", {}).get(k) or {}).get("mean")
        return math.nan if x is None else x

    def fmt(x, digits=3):
        return "n/a" if x != x else f"{x:.{digits}g}"

    base = variants["beckmann"]["gpu_ms"]["mean"] if "beckmann" in variants else math.nan
    cols = ["variant", "glint density ratio", "histogram EMD (oct)", "pooled bias 2/8/64 px", "pooled RMS 2/8/64 px",
            "flicker excess", "lag", "temporal_error_mc", "ΔE00", "GPU ms/frame", "× beckmann"]
    print("| " + " | ".join(cols) + " |")
    print("|" + "---|" * len(cols))
    for name, v in variants.items():
        ref = mean(v, "glint_density_ref")
        density = mean(v, "glint_density_test") / ref if ref > 0 else math.nan
        gpu = v["gpu_ms"]["mean"]
        row = [f"`{name}`", fmt(density), fmt(mean(v, "glint_hist_emd_oct")),
               "/".join(fmt(mean(v, f"pooled_bias_{p}"), 2) for p in (2, 8, 64)),
               "/".join(fmt(mean(v, f"pooled_rms_{p}"), 2) for p in (2, 8, 64)),
               fmt(mean(v, "flicker_excess")), fmt(mean(v, "temporal_lag")), fmt(mean(v, "temporal_error_mc")),
               fmt(mean(v, "deltaE2000")), fmt(gpu), fmt(gpu / base)]
        print("| " + " | ".join(row) + " |")
    for r in summary.get("references", []):
        floor = r.get("floor") or {}
        print(f"\ntruth `{r.get('name', '?')}` noise floor: " + ", ".join(
            f"{k} {fmt(floor.get(k, math.nan))}" for k in ("deltaE2000", "flicker_excess", "temporal_lag",
                                                           "temporal_error_mc")))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: glint_methods_table.py SUMMARY_JSON")
    main(sys.argv[1])
