"""What the table scripts of docs/examples share: number formatting, a variant's metric means, the truth
floors line of a run, and the command line (summary.json files, --only)."""
import argparse
import math


def fmt(x, digits=3):
    return "n/a" if x is None or x != x else f"{x:.{digits}g}"


def mean(v, k):
    """The mean over the frames of metric k of variant v of a summary.json (NaN where it has none)."""
    x = (v.get("metrics", {}).get(k) or {}).get("mean")
    return math.nan if x is None else x


def glint_density_ratio(v):
    ref = mean(v, "glint_density_ref")
    return mean(v, "glint_density_test") / ref if ref > 0 else math.nan


def print_floors(summary, run):
    for r in summary.get("references", []):
        floor = r.get("floor") or {}
        print(f"\n{run}: truth `{r.get('name', '?')}` noise floor: " + ", ".join(
            f"{k} {fmt(floor.get(k))}" for k in ("deltaE2000", "flicker_excess", "temporal_lag", "temporal_error_mc")))
    print()


def main(doc, table):
    """Runs table(path, only) for every summary.json on the command line."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("summaries", nargs="+", help="summary.json of a run")
    parser.add_argument("--only", action="append", default=[], help="keep variants whose name contains this")
    args = parser.parse_args()
    for path in args.summaries:
        table(path, args.only)
