#!/usr/bin/env python3
"""The method table of shaders/README.md from a run of `glintlab run glint-methods`:

    python3 docs/examples/glint_methods_table.py results/glint-methods/summary.json

One Markdown row per variant: the glint density ratio (test over truth, from the means of both densities),
the glint histogram EMD, pooled bias and RMS at 2, 8 and 64 px, temporal score, flicker excess, lag,
temporal_error_mc, ΔE00 (means over the frames), GPU ms per frame and its ratio to the `beckmann` variant of
the same run;
then each truth's noise floor. Where the run has a density sweep (summary.json "density_sweep" and
"matched_density"), two more tables: each method at matched glint density beside its published default,
and every row of the sweep."""
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
            "temporal score", "flicker excess", "lag", "temporal_error_mc", "ΔE00", "GPU ms/frame", "× beckmann"]
    print("| " + " | ".join(cols) + " |")
    print("|" + "---|" * len(cols))
    for name, v in variants.items():
        ref = mean(v, "glint_density_ref")
        density = mean(v, "glint_density_test") / ref if ref > 0 else math.nan
        gpu = v["gpu_ms"]["mean"]
        row = [f"`{name}`", fmt(density), fmt(mean(v, "glint_hist_emd_oct")),
               "/".join(fmt(mean(v, f"pooled_bias_{p}"), 2) for p in (2, 8, 64)),
               "/".join(fmt(mean(v, f"pooled_rms_{p}"), 2) for p in (2, 8, 64)),
               fmt(mean(v, "temporal_score")), fmt(mean(v, "flicker_excess")), fmt(mean(v, "temporal_lag")),
               fmt(mean(v, "temporal_error_mc")),
               fmt(mean(v, "deltaE2000")), fmt(gpu), fmt(gpu / base)]
        print("| " + " | ".join(row) + " |")
    for r in summary.get("references", []):
        floor = r.get("floor") or {}
        print(f"\ntruth `{r.get('name', '?')}` noise floor: " + ", ".join(
            f"{k} {fmt(floor.get(k, math.nan))}" for k in ("deltaE2000", "temporal_score", "flicker_excess",
                                                           "temporal_lag", "temporal_error_mc")))
    sweep_tables(summary, variants, mean, fmt)


def sweep_tables(summary, variants, mean, fmt):
    sweep, matched = summary.get("density_sweep") or {}, summary.get("matched_density") or {}
    if not sweep:
        return
    keys = ("glint_density_ratio", "temporal_score", "flicker_excess", "temporal_lag", "temporal_error_mc",
            "deltaE2000", "gpu_ms")
    head = ["method", "row", "parameter", "glint density ratio", "temporal score", "flicker excess", "lag",
            "temporal_error_mc", "ΔE00", "GPU ms/frame"]
    num = lambda x: math.nan if x is None else x
    print("\nAt matched glint density (the parameter where the ratio is 1, interpolated, then rendered):\n")
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for name, m in matched.items():
        v = variants.get(name, {})
        ref = mean(v, "glint_density_ref")
        default = [mean(v, "glint_density_test") / ref if ref > 0 else math.nan] + \
                  [mean(v, k) for k in keys[1:-1]] + [(v.get("gpu_ms") or {}).get("mean", math.nan)]
        print(f"| `{name}` | published default | | " + " | ".join(fmt(x) for x in default) + " |")
        if m.get("value") is None:
            print(f"| `{name}` | not matched | nearest: {m['parameter']} {fmt(num(m.get('nearest_value')))} | "
                  f"{fmt(num(m.get('nearest_ratio')))} |" + " |" * (len(keys) - 1))
            continue
        print(f"| `{name}` | matched ({m.get('how', '')}) | {m['parameter']} {fmt(m['value'])} | " +
              " | ".join(fmt(num(m.get(k))) for k in keys) + " |")
    print("\nThe sweep (means over the frames):\n")
    print("| " + " | ".join(["method"] + head[2:]) + " |")
    print("|" + "---|" * (len(head) - 1))
    for name, rows in sweep.items():
        for r in rows:
            print(f"| `{name}` | {r['parameter']} {fmt(r['value'])} | " +
                  " | ".join(fmt(num(r.get(k))) for k in keys) + " |")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: glint_methods_table.py SUMMARY_JSON")
    main(sys.argv[1])
