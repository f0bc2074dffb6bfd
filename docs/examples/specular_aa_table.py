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
import argparse
import json
import math
import os


def fmt(x, digits=3):
    return "n/a" if x is None or x != x else f"{x:.{digits}g}"


def table(path, only):
    summary = json.load(open(path))

    def mean(v, k):
        x = (v.get("metrics", {}).get(k) or {}).get("mean")
        return math.nan if x is None else x

    run = os.path.basename(os.path.dirname(os.path.abspath(path)))
    cols = ["run", "variant", "ΔE00", "flicker excess", "lag", "temporal_error_mc", "glint density ratio",
            "GPU ms/frame"]
    print("| " + " | ".join(cols) + " |")
    print("|" + "---|" * len(cols))
    for v in summary["variants"]:
        if only and not any(o in v["name"] for o in only):
            continue
        ref = mean(v, "glint_density_ref")
        density = mean(v, "glint_density_test") / ref if ref > 0 else math.nan
        row = [run, f"`{v['name']}`", fmt(mean(v, "deltaE2000")), fmt(mean(v, "flicker_excess")),
               fmt(mean(v, "temporal_lag")), fmt(mean(v, "temporal_error_mc")), fmt(density),
               fmt(v["gpu_ms"]["mean"])]
        print("| " + " | ".join(row) + " |")
    for r in summary.get("references", []):
        floor = r.get("floor") or {}
        print(f"\n{run}: truth `{r.get('name', '?')}` noise floor: " + ", ".join(
            f"{k} {fmt(floor.get(k))}" for k in ("deltaE2000", "flicker_excess", "temporal_lag", "temporal_error_mc")))
    print()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("summaries", nargs="+", help="summary.json of a run")
    parser.add_argument("--only", action="append", default=[], help="keep variants whose name contains this")
    args = parser.parse_args()
    for path in args.summaries:
        table(path, args.only)


if __name__ == "__main__":
    main()
