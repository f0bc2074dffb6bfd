#!/usr/bin/env python3
"""The specular AA table of shaders/README.md from runs that have specular_aa variants:

    for e in waves-far waves-close sphere-far sphere-close; do
      build/glintlab run specular-aa/$e --out results/specular-aa/$e; done
    python3 docs/examples/specular_aa_table.py results/specular-aa/*/summary.json

Per run, one Markdown row per variant: ΔE00, flicker excess, lag, temporal_error_mc (means over the frames),
the glint density ratio (test over truth, from the means of both densities; n/a where the truth shows no
glint), GPU ms per frame; then the run's truth floors. `glintlab run default` and `glintlab run
glint-methods` have specular_aa variants too: pass their summary.json, and `--only NAME` (repeatable)
keeps the rows whose variant name contains NAME."""
import json
import os

from summary_tables import fmt, glint_density_ratio, main, mean, print_floors


def table(path, only):
    summary = json.load(open(path))
    run = os.path.basename(os.path.dirname(os.path.abspath(path)))
    cols = ["run", "variant", "ΔE00", "flicker excess", "lag", "temporal_error_mc", "glint density ratio",
            "GPU ms/frame"]
    print("| " + " | ".join(cols) + " |")
    print("|" + "---|" * len(cols))
    for v in summary["variants"]:
        if only and not any(o in v["name"] for o in only):
            continue
        density = glint_density_ratio(v)
        row = [run, f"`{v['name']}`", fmt(mean(v, "deltaE2000")), fmt(mean(v, "flicker_excess")),
               fmt(mean(v, "temporal_lag")), fmt(mean(v, "temporal_error_mc")), fmt(density),
               fmt(v["gpu_ms"]["mean"])]
        print("| " + " | ".join(row) + " |")
    print_floors(summary, run)


if __name__ == "__main__":
    main(__doc__, table)
