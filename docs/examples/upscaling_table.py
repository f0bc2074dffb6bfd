#!/usr/bin/env python3
"""The temporal upscaling table of core/README.md from the upscaling runs:

    for e in flyover orbit grazing-pan; do
      build/glintlab run upscaling/$e --out results/upscaling/$e --no-report; done
    python3 docs/examples/upscaling_table.py results/upscaling/*/summary.json

Per run, one Markdown row per variant: its render resolution, ΔE00, flicker excess, lag, temporal_error_mc
(means over the frames), the glint density ratio (test over truth, from the means of both densities),
the GPU ms of the surface pass and of the resolve, and GPU ms per frame over that of native TAA with
the same glint model (`falcor`, `zirr-falcor`, `chermain-falcor`); then the run's truth floors.
`--only NAME` (repeatable) keeps the rows whose variant name contains NAME."""
import json
import math
import os

from summary_tables import fmt, glint_density_ratio, main, mean, print_floors


def table(path, only):
    summary = json.load(open(path))

    def pass_ms(v, p):
        x = (v.get("gpu_ms_per_pass", {}).get(p) or {}).get("mean")
        return math.nan if x is None else x

    run = os.path.basename(os.path.dirname(os.path.abspath(path)))
    native = {}
    for v in summary["variants"]:
        if v["name"].endswith("falcor"):
            native[v["name"][: -len("falcor")]] = v["gpu_ms"]["mean"]
    cols = ["run", "variant", "render", "ΔE00", "flicker excess", "lag", "temporal_error_mc",
            "glint density ratio", "surface ms", "resolve ms", "GPU ms ÷ native TAA"]
    print("| " + " | ".join(cols) + " |")
    print("|" + "---|" * len(cols))
    width, height = summary["resolution"]
    for v in summary["variants"]:
        if only and not any(o in v["name"] for o in only):
            continue
        density = glint_density_ratio(v)
        rw, rh = v.get("render_resolution", [width, height])
        prefix = next((p for p in sorted(native, key=len, reverse=True) if v["name"].startswith(p)), "")
        ratio = v["gpu_ms"]["mean"] / native[prefix] if prefix in native and native[prefix] > 0 else math.nan
        row = [run, f"`{v['name']}`", f"{rw}×{rh}", fmt(mean(v, "deltaE2000")), fmt(mean(v, "flicker_excess")),
               fmt(mean(v, "temporal_lag")), fmt(mean(v, "temporal_error_mc")), fmt(density),
               fmt(pass_ms(v, "surface")), fmt(pass_ms(v, "taa")), fmt(ratio)]
        print("| " + " | ".join(row) + " |")
    print_floors(summary, run)


if __name__ == "__main__":
    main(__doc__, table)
