#!/usr/bin/env python3
"""glintlab report: turns a run directory into a self-contained report.html.

    python3 glintlab_report.py RUN_DIR

Reads RUN_DIR/summary.json (schema glintlab-summary/1), RUN_DIR/frames.csv and
the PNG previews RUN_DIR/<variant or reference>/frame_NNNN.png, and writes

    RUN_DIR/report.html          one file: plots as inline SVG, images and
                                 animations as data URIs; nothing is fetched
                                 (the page from the Jinja2 templates in
                                 templates/ beside this script)
    RUN_DIR/figures/*.svg|pdf    every plot, for papers (matplotlib)
    RUN_DIR/figures/*.png|webp|gif|mp4
                                 the glint crops and the side-by-side sequences
                                 (MP4 only where ffmpeg is installed)

Exit codes (experiments/cli/exit_codes.h): 0 written, 2 bad input (no
summary.json, not a glintlab summary), 4 a file could not be read or written,
5 internal error, 10 a Python module is missing (numpy, scipy, matplotlib, PIL,
jinja2; the message names the Debian packages).

Debian 12 packages: python3-matplotlib python3-pil python3-numpy python3-scipy
python3-jinja2 (bootstrap.sh).
"""

import base64
import concurrent.futures
import csv
import datetime
import io
import json
import math
import multiprocessing
import os
import shutil
import subprocess
import sys
import traceback

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import glintlab_pareto  # noqa: E402  (beside this file: here and where installed)

EXIT_OK, EXIT_BAD_INPUT, EXIT_IO, EXIT_INTERNAL, EXIT_MISSING_MODULE = 0, 2, 4, 5, 10

_missing = []
try:
    import numpy as np
except ImportError:
    _missing.append(("numpy", "python3-numpy"))
try:
    import scipy.ndimage
except ImportError:
    _missing.append(("scipy", "python3-scipy"))
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker
except ImportError:
    _missing.append(("matplotlib", "python3-matplotlib"))
try:
    from PIL import Image, ImageDraw, ImageFont, features
except ImportError:
    _missing.append(("PIL", "python3-pil"))
try:
    import jinja2
except ImportError:
    _missing.append(("jinja2", "python3-jinja2"))

TEMPLATE_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "templates")


class BadInput(Exception):
    pass


# ------------------------------------------------------------------ metrics
# What a metric is -- its label, direction ("min" lower is better, "max" higher is better, "one" closest
# to 1, "ref" closest to the reference's value, "none" not ranked), description and unit -- is read from
# summary.json "metric_info", which the run writes from the metric table (metrics/metric_registry.cpp);
# this file keeps no list of its own. Which metrics the report's table and panels show is its choice:
TABLE_METRICS = ["deltaE2000", "flip", "temporal_score", "flicker_excess", "temporal_lag", "flicker_ratio",
                 "glint_density_ratio", "temporal_error_mc", "flicker_excess_fixed", "temporal_error", "flicker_contrast",
                 "deltaEITP", "psnr",
                 "pooled_error", "glint_density_test", "glint_density_ref", "glint_hist_emd_oct", "nonfinite_pixels",
                 "negative_pixels"]
# Temporal stability is ranked by temporal_score (the displayed error's change where the eye rests, which
# ranks the variants as ColorVideoVDP's temporal channel does: metrics/README.md); flicker excess and lag
# are its diagnostics ("twinkles too much", "smooth but wrong"), the flicker ratio another (it ranks lag
# as flicker and magnitude over agreement).
# The glint density ratio as |ln ratio|: whether a variant keeps the truth's glints, at its cost.
PARETO_METRICS = ["deltaE2000", "flip", "temporal_score", "glint_density_ratio"]
RATIO_METRICS = ("flicker_ratio", "glint_density_ratio")  # plotted and ranked as |ln ratio|
CURVE_METRICS = ["flicker_ratio", "deltaE2000"]
AA_MARKERS = {"none": "o", "ssaa": "s", "taa": "^"}


DIRECTIONS = ("min", "max", "one", "ref", "none")
# summary.json "metric_info" ({metric: {"label", "direction", "description", "unit", ...}}) of the run
# reported (use_metric_info). A metric it lacks is shown by its name, ranked lower-is-better.
METRIC_INFO = {}


def use_metric_info(summary):
    """Keeps the well-formed fields of summary.json's "metric_info" (absent or malformed: none)."""
    METRIC_INFO.clear()
    info = summary.get("metric_info")
    if not isinstance(info, dict):
        return
    for name, row in info.items():
        if not isinstance(row, dict):
            continue
        kept = {k: row[k] for k in ("label", "description", "unit") if isinstance(row.get(k), str) and row[k]}
        if row.get("direction") in DIRECTIONS:
            kept["direction"] = row["direction"]
        METRIC_INFO[name] = kept


def label_of(name):
    return METRIC_INFO.get(name, {}).get("label") or name


def direction_of(name):
    return METRIC_INFO.get(name, {}).get("direction") or "min"


def description_of(name):
    """The metric's explanation, or None where metric_info has none."""
    return METRIC_INFO.get(name, {}).get("description")


def unit_of(units, name, default=""):
    """The metric's unit from summary.json "units", else from "metric_info", else default."""
    return units.get(name) or METRIC_INFO.get(name, {}).get("unit") or default


# ------------------------------------------------------------------ small helpers
def finite(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def fmt(x, sig=3):
    """A number with `sig` significant digits, no exponent for usual magnitudes."""
    if x is None:
        return "–"
    if isinstance(x, bool):
        return str(x).lower()
    if not isinstance(x, (int, float)):
        return str(x)
    if math.isnan(x):
        return "–"
    if math.isinf(x):
        return "∞" if x > 0 else "−∞"
    if x == 0:
        return "0"
    if isinstance(x, int) or (float(x).is_integer() and abs(x) < 1e7):
        return str(int(x))
    a = abs(x)
    if a < 1e-4 or a >= 1e7:
        return f"{x:.{sig - 1}e}"
    decimals = max(0, sig - 1 - int(math.floor(math.log10(a))))
    return f"{x:.{decimals}f}"


def stat(d, key="mean"):
    if isinstance(d, dict):
        v = d.get(key)
        return float(v) if finite(v) else None
    return None


def data_uri(mime, data):
    return f"data:{mime};base64," + base64.b64encode(data).decode("ascii")


def write_bytes(path, data):
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(data)
    os.replace(tmp, path)


# ------------------------------------------------------------------ input
def load_run(run_dir):
    if not os.path.isdir(run_dir):
        raise BadInput(f"{run_dir}: no such directory")
    path = os.path.join(run_dir, "summary.json")
    if not os.path.isfile(path):
        raise BadInput(f"{path}: missing; {run_dir} is not a glintlab run directory (`glintlab run` writes one)")
    with open(path, "rb") as f:
        raw = f.read()
    try:
        summary = json.loads(raw.decode("utf-8"))
    except (ValueError, UnicodeDecodeError) as e:
        raise BadInput(f"{path}: not valid JSON ({e})")
    if not isinstance(summary, dict) or summary.get("schema") != "glintlab-summary/1":
        got = summary.get("schema") if isinstance(summary, dict) else type(summary).__name__
        raise BadInput(f"{path}: key \"schema\" is {json.dumps(got)}; expected \"glintlab-summary/1\"")
    if not isinstance(summary.get("variants"), list):
        raise BadInput(f"{path}: key \"variants\" must be an array")
    for i, v in enumerate(summary["variants"]):
        if not isinstance(v, dict) or not isinstance(v.get("name"), str):
            raise BadInput(f"{path}: variants[{i}] has no \"name\"")
    # The glint density ratio, derived here from the two densities' means (a ratio of per-frame values
    # would divide by frames without a glint in the truth).
    for v in summary["variants"]:
        m = v.get("metrics")
        if isinstance(m, dict) and "glint_density_ratio" not in m:
            t, r = stat(m.get("glint_density_test")), stat(m.get("glint_density_ref"))
            if t is not None and r is not None and r > 0:
                m["glint_density_ratio"] = {"mean": t / r}
    frames = {}  # variant -> list of row dicts (floats or None), ascending frame
    csv_path = os.path.join(run_dir, "frames.csv")
    if os.path.isfile(csv_path):
        with open(csv_path, newline="", encoding="utf-8") as f:
            reader = csv.DictReader(f)
            if not reader.fieldnames or "variant" not in reader.fieldnames or "frame" not in reader.fieldnames:
                raise BadInput(f"{csv_path}: no \"variant\" and \"frame\" columns in the header")
            for row in reader:
                rec = {}
                for k, cell in row.items():
                    if k == "variant" or k is None:
                        continue
                    try:
                        rec[k] = float(cell) if cell not in ("", None) else None
                    except ValueError:
                        rec[k] = None
                if rec.get("frame") is None:
                    continue
                frames.setdefault(row["variant"], []).append(rec)
        for rows in frames.values():
            rows.sort(key=lambda r: r["frame"])
    return summary, frames


def png_frames(run_dir, row):
    """{frame index: path} of the PNG previews of a variant or reference."""
    d = os.path.join(run_dir, row)
    out = {}
    if not os.path.isdir(d):
        return out
    for n in os.listdir(d):
        if n.startswith("frame_") and n.endswith(".png"):
            try:
                out[int(n[6:-4])] = os.path.join(d, n)
            except ValueError:
                pass
    return out


def load_rgb(path):
    with Image.open(path) as im:
        return np.asarray(im.convert("RGB"))


# ------------------------------------------------------------------ figures
class Figures:
    """Saves every matplotlib figure as SVG + PDF under DIR/figures and keeps
    the SVG text for inlining (unique ids per figure via svg.hashsalt)."""

    def __init__(self, fig_dir):
        self.dir = fig_dir
        self.files = []  # (title, [relative paths])

    def save(self, fig, name, title, inline=True):
        """Writes the figure; returns {"svg": its SVG element, "title"} for inlining, or None."""
        matplotlib.rcParams["svg.hashsalt"] = "glintlab-" + name
        buf = io.BytesIO()
        fig.savefig(buf, format="svg", metadata={"Date": None})
        svg = buf.getvalue()
        write_bytes(os.path.join(self.dir, name + ".svg"), svg)
        pdf = io.BytesIO()
        fig.savefig(pdf, format="pdf", metadata={"CreationDate": None})
        write_bytes(os.path.join(self.dir, name + ".pdf"), pdf.getvalue())
        plt.close(fig)
        self.files.append((title, [f"figures/{name}.svg", f"figures/{name}.pdf"]))
        if not inline:
            return None
        text = svg.decode("utf-8")
        return {"svg": text[text.find("<svg"):], "title": title}

    def add_file(self, title, rel):
        for t, paths in self.files:
            if t == title:
                paths.append(rel)
                return
        self.files.append((title, [rel]))


def setup_matplotlib():
    matplotlib.rcParams.update({
        "svg.fonttype": "none",  # text stays text: selectable in the page, editable in the SVG
        "pdf.fonttype": 42,
        "font.family": "DejaVu Sans",
        "font.size": 9,
        "axes.titlesize": 10,
        "axes.labelsize": 9,
        "legend.fontsize": 8,
        "axes.grid": True,
        "grid.alpha": 0.3,
        "axes.spines.top": False,
        "axes.spines.right": False,
        "figure.dpi": 100,
    })


def variant_colors(names):
    n = max(len(names), 1)
    if n <= 10:
        cmap = plt.get_cmap("tab10")
        return {v: cmap(i) for i, v in enumerate(names)}
    if n <= 20:
        cmap = plt.get_cmap("tab20")
        return {v: cmap(i) for i, v in enumerate(names)}
    cmap = plt.get_cmap("turbo")
    return {v: cmap(0.05 + 0.9 * i / (n - 1)) for i, v in enumerate(names)}


def pareto_front(points, floors=None):
    """points: [(x, y, name)] to minimise in both; floors: {name: the noise floor of its y} (absent = 0).
    Two errors closer than the larger of their floors are not ranked apart: q dominates p when it costs
    no more and is not worse beyond the floors, and is cheaper or better beyond them. Returns the
    non-dominated points sorted by x."""
    floors = floors or {}

    def slack(q, p):  # the cost is exact; the error is compared up to the larger floor
        return (0.0, max(floors.get(q[2]) or 0.0, floors.get(p[2]) or 0.0))

    return sorted(glintlab_pareto.front(points, lambda p: (p[0], p[1]), slack), key=lambda p: (p[0], p[1]))


def floor_items(reference):
    """[(label, value)] of a truth's noise floor (summary.json references[].floor) for the facts list."""
    floor = reference.get("floor") or {}
    return [(label_of(m), floor[m]) for m in ("deltaE2000", "flip", "temporal_score", "flicker_excess",
                                                "temporal_lag", "temporal_error_mc") if isinstance(floor.get(m), (int, float))]


def floor_of(summary, variant_name, metric):
    """The noise floor of `metric` of the truth `variant_name` is measured against (summary.json
    references[].floor), or None; ratios have none."""
    if metric in RATIO_METRICS:
        return None
    v = next((x for x in summary["variants"] if x["name"] == variant_name), None)
    r = next((r for r in summary.get("references") or [] if v and r.get("name") == v.get("reference")), None)
    f = ((r or {}).get("floor") or {}).get(metric)
    return f if isinstance(f, (int, float)) and math.isfinite(f) else None


def pareto_value(metric, m):
    """The quantity minimised on the Pareto plot's y axis."""
    if m is None:
        return None
    if metric in RATIO_METRICS:
        return abs(math.log(m)) if m > 0 else None
    return m


def pareto_points(summary, metric):
    pts = []
    for v in summary["variants"]:
        x = stat(v.get("gpu_ms"))
        m = stat(v.get("metrics", {}).get(metric))
        y = pareto_value(metric, m)
        if x is not None and y is not None and x > 0:
            pts.append((x, y, v["name"], m))
    return pts


def draw_pareto(ax, summary, metric, colors, markers, annotate):
    pts = pareto_points(summary, metric)
    floors = {p[2]: floor_of(summary, p[2], metric) for p in pts}
    front = pareto_front([(p[0], p[1], p[2]) for p in pts], floors)
    on_front = {p[2] for p in front}
    if len(front) > 1:
        ax.plot([p[0] for p in front], [p[1] for p in front], "--", color="0.35", lw=1.2, zorder=1,
                label="Pareto front")
    xs = [p[0] for p in pts]
    logx = bool(xs) and max(xs) / min(xs) > 8
    if logx:
        ax.set_xscale("log")
    # Labels: points closer than a label's size get their labels stacked
    # downwards instead of printed over each other.
    def norm(v, lo, hi):
        return (v - lo) / (hi - lo) if hi > lo else 0.5
    nx = [math.log(p[0]) if logx else p[0] for p in pts]
    ymax = max([p[1] for p in pts] + [1e-12])
    placed = []
    for (x, y, name, m), lx in sorted(zip(pts, nx), key=lambda t: -t[0][1]):
        opt = name in on_front
        ax.scatter([x], [y], s=64 if opt else 36, marker=markers[name], color=colors[name],
                   edgecolors="black" if opt else "none", linewidths=1.2, zorder=3 if opt else 2)
        if floors.get(name):  # the truth's noise floor: errors closer than this are not ranked apart
            ax.errorbar([x], [y], yerr=[floors[name]], fmt="none", ecolor=colors[name], elinewidth=1, capsize=2,
                        alpha=0.7, zorder=1)
        if annotate or opt:
            px, py = norm(lx, min(nx), max(nx)), y / ymax
            k = sum(1 for qx, qy in placed if abs(qx - px) < 0.3 and abs(qy - py) < 0.08)
            placed.append((px, py))
            text = name + (f" ({fmt(m)})" if metric in RATIO_METRICS else "")
            ax.annotate(text, (x, y), xytext=(5, 3 - 8.5 * k), textcoords="offset points", fontsize=7,
                        color="black" if opt else "0.35")
    ax.set_xlabel("GPU ms / frame (mean)")
    if metric in RATIO_METRICS:
        ax.set_ylabel(f"|ln({label_of(metric)})|   (0 = truth)")
        ax.axhline(0, color="0.5", lw=0.8)
    else:
        ax.set_ylabel(f"{label_of(metric)} (mean)")
    ax.set_ylim(0, ymax * 1.15)
    ax.set_title(f"{label_of(metric)} against cost")
    return pts, front


def legend_handles(summary, colors, markers):
    from matplotlib.lines import Line2D
    handles = [Line2D([], [], ls="none", marker=markers[v["name"]], color=colors[v["name"]], markersize=7,
                      label=v["name"]) for v in summary["variants"]]
    handles.append(Line2D([], [], ls="--", color="0.35", label="Pareto front (ringed: Pareto-optimal)"))
    return handles


# ------------------------------------------------------------------ crops
def box_mean(a, kh, kw):
    """Means of every kh x kw window of a, indexed by the window's top-left corner (windows inside a
    only). uniform_filter's window at index i covers i - k // 2 ... i - k // 2 + k - 1, so the window
    that starts at row y is its value at row y + kh // 2 (columns likewise)."""
    m = scipy.ndimage.uniform_filter(np.asarray(a, dtype=np.float64), size=(kh, kw), mode="constant")
    return m[kh // 2:kh // 2 + a.shape[0] - kh + 1, kw // 2:kw // 2 + a.shape[1] - kw + 1]


OUTLIER_MIN_EXCESS = 0.08  # display-encoded luma, 0..1
OUTLIER_TOP_FRACTION = 0.005


def luma(rgb8):
    """Display-encoded luma in [0, 1] (Rec. 709 weights on the encoded values)."""
    return (rgb8.astype(np.float32) / 255.0) @ np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)


def median7(y):
    """Separable 7x7 median (rows, then columns; the border pixels repeated): a local background level
    that edges do not drag around and a few-pixel glint does not move."""
    rows = scipy.ndimage.median_filter(y, size=(1, 7), mode="nearest")
    return scipy.ndimage.median_filter(rows, size=(7, 1), mode="nearest")


def bright_outliers(rgb8):
    """Glint-like pixels: brighter than the median of their 7x7 neighbourhood
    by at least OUTLIER_MIN_EXCESS and among the frame's OUTLIER_TOP_FRACTION
    brightest by that excess. Edges (the horizon, a ridge) are not outliers: on
    their bright side the median is bright too."""
    y = luma(rgb8)
    excess = y - median7(y)
    thr = max(OUTLIER_MIN_EXCESS, float(np.percentile(excess, 100.0 * (1.0 - OUTLIER_TOP_FRACTION))))
    return (excess > thr).astype(np.float64), y


def choose_region(frames_rgb, cw, ch):
    """The cw x ch window with the most bright outliers summed over the given
    frames; falls back to the highest-contrast window. Returns (x, y, how,
    per-frame outlier counts in the window)."""
    h, w = frames_rgb[0].shape[:2]
    acc = np.zeros((h, w))
    maps, lums = [], []
    for f in frames_rgb:
        o, y = bright_outliers(f)
        maps.append(o)
        lums.append(y)
        acc += o
    # Outlier counts are whole numbers: rounding takes away the filter's last-bit error in its means.
    counts = np.rint(box_mean(acc, ch, cw) * (cw * ch))
    how = "outliers"
    if counts.max() <= 0:
        y = np.mean(lums, axis=0)
        # Each window's luminance variance from float64 means: on the frames of `glintlab run default
        # --frames 4 --resolution 320x180` within 2e-9 of the exact value, where cumulative sums of the
        # float32 luma are off by up to 5e-4 (the windows chosen are the same).
        counts = box_mean(y * y, ch, cw) - box_mean(y, ch, cw) ** 2
        how = "contrast"
    # Ties go to the window nearest the image centre.
    yy, xx = np.mgrid[0:counts.shape[0], 0:counts.shape[1]]
    cy, cx = (counts.shape[0] - 1) / 2.0, (counts.shape[1] - 1) / 2.0
    dist = np.hypot(yy - cy, xx - cx)
    score = counts - 1e-6 * (counts.max() + 1) * dist / (dist.max() + 1)
    y0, x0 = np.unravel_index(int(np.argmax(score)), score.shape)
    per_frame = [float(m[y0:y0 + ch, x0:x0 + cw].sum()) for m in maps]
    return int(x0), int(y0), how, per_frame, float(counts[y0, x0])


def load_font(size, bold=False):
    names = ["DejaVuSans-Bold.ttf" if bold else "DejaVuSans.ttf"]
    for n in names:
        for d in ("/usr/share/fonts/truetype/dejavu", os.path.join(os.path.dirname(matplotlib.__file__),
                                                                    "mpl-data", "fonts", "ttf")):
            p = os.path.join(d, n)
            if os.path.isfile(p):
                try:
                    return ImageFont.truetype(p, size)
                except OSError:
                    pass
    return ImageFont.load_default()


def text_width(draw, text, font):
    try:
        return draw.textlength(text, font=font)
    except AttributeError:
        return font.getsize(text)[0]


def fit_text(draw, text, font, width):
    if text_width(draw, text, font) <= width:
        return text
    while text and text_width(draw, text + "…", font) > width:
        text = text[:-1]
    return text + "…"


def tile_grid(tiles, labels, cols, label_h, font, gap=2, bg=(34, 34, 34)):
    """Tiles (equal-size RGB arrays) with a label bar above each, in a grid."""
    th, tw = tiles[0].shape[:2]
    rows = (len(tiles) + cols - 1) // cols
    W = cols * tw + (cols + 1) * gap
    H = rows * (th + label_h) + (rows + 1) * gap
    canvas = Image.new("RGB", (W, H), bg)
    draw = ImageDraw.Draw(canvas)
    for i, (t, lab) in enumerate(zip(tiles, labels)):
        r, c = divmod(i, cols)
        x = gap + c * (tw + gap)
        y = gap + r * (th + label_h + gap)
        draw.text((x + 3, y + 1), fit_text(draw, lab, font, tw - 6), fill=(235, 235, 235), font=font)
        canvas.paste(Image.fromarray(t), (x, y + label_h))
    return canvas


def upscale(a, s):
    return np.repeat(np.repeat(a, s, axis=0), s, axis=1) if s > 1 else a


def encode_png(im):
    buf = io.BytesIO()
    im.save(buf, format="PNG", optimize=True)
    return buf.getvalue()


def encode_animation(frames, duration_ms, fmt_, lossless):
    buf = io.BytesIO()
    if fmt_ == "WEBP":
        kw = {"lossless": True} if lossless else {"quality": 85, "method": 4}
        frames[0].save(buf, format="WEBP", save_all=True, append_images=frames[1:], duration=duration_ms, loop=0,
                       **kw)
    else:
        pal = [f.convert("P", palette=Image.ADAPTIVE, colors=255) for f in frames]
        pal[0].save(buf, format="GIF", save_all=True, append_images=pal[1:], duration=duration_ms, loop=0,
                    disposal=1, optimize=False)
    return buf.getvalue()


def encode_mp4(frames, fps, out_path):
    """MP4 (H.264, lossless-looking CRF 12) through ffmpeg where it is
    installed; returns an error text or None."""
    ffmpeg = shutil.which("ffmpeg")
    if not ffmpeg:
        return "ffmpeg is not installed"
    w, h = frames[0].size
    tmp = out_path + ".tmp.mp4"
    cmd = [ffmpeg, "-nostdin", "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", f"{w}x{h}",
           "-framerate", f"{fps:g}", "-i", "pipe:0", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264",
           "-crf", "12", "-pix_fmt", "yuv420p", "-movflags", "+faststart", tmp]
    raw = b"".join(f.convert("RGB").tobytes() for f in frames)
    try:
        p = subprocess.run(cmd, input=raw, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=300)
    except (OSError, subprocess.TimeoutExpired) as e:
        return f"ffmpeg failed: {e}"
    if p.returncode != 0:
        if os.path.exists(tmp):
            os.remove(tmp)
        return "ffmpeg failed: " + p.stdout.decode("utf-8", "replace").strip()[-300:]
    os.replace(tmp, out_path)
    return None


# ------------------------------------------------------------------ the report
SECTIONS = (("pareto", "error vs cost"), ("sweep", "density sweep"), ("curves", "per frame"), ("table", "table"),
            ("crops", "glint crops"),
            ("sequences", "sequences"), ("glossary", "metrics"), ("files", "files"))
AA_SYMBOLS = {"none": "●", "ssaa": "■", "taa": "▲"}


def template_env():
    """The Jinja2 environment of templates/ (beside this script): autoescaped, block tags leave no
    blank lines, a file's last newline stays (report.css's, the page's)."""
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(TEMPLATE_DIR), autoescape=True, trim_blocks=True,
                             lstrip_blocks=True, keep_trailing_newline=True, undefined=jinja2.StrictUndefined)
    env.filters["fmt"] = fmt
    env.filters["label"] = label_of
    return env


class Report:
    """One report: the run's data and the figures written so far. Each section method draws its plots
    and returns the data its template shows; write() renders templates/page.html.j2."""

    def __init__(self, run_dir):
        self.run_dir = run_dir
        self.summary, self.frames = load_run(run_dir)
        use_metric_info(self.summary)
        self.figs = Figures(os.path.join(run_dir, "figures"))
        os.makedirs(self.figs.dir, exist_ok=True)
        setup_matplotlib()
        self.variants = self.summary["variants"]
        self.names = [v["name"] for v in self.variants]
        self.colors = variant_colors(self.names)
        self.markers = {v["name"]: AA_MARKERS.get(v.get("aa"), "D") for v in self.variants}
        self.units = self.summary.get("units") or {}
        self.measured = bool(self.summary.get("measured", True)) and any(v.get("metrics") for v in self.variants)
        self.glance = []  # the "at a glance" items, one per Pareto metric

    def floor_of(self, variant_name, metric):
        return floor_of(self.summary, variant_name, metric)

    def variant(self, name):
        return next(v for v in self.variants if v["name"] == name)

    def within_floor(self, pts, best, metric):
        """The variants whose figure lies within the truth's noise floor of the best one's (same truth)."""
        f = self.floor_of(best[2], metric)
        if f is None:
            return []
        ref = self.variant(best[2]).get("reference")
        return [p[2] for p in pts if p[2] != best[2] and abs(p[3] - best[3]) < f
                and self.variant(p[2]).get("reference") == ref]

    def metric_stat(self, v, metric, key="mean"):
        return stat((v.get("metrics") or {}).get(metric), key)

    def title(self):
        return self.summary.get("experiment") or os.path.basename(os.path.abspath(self.run_dir))

    # ------------------------------------------------------------ header
    def header(self):
        """The data of templates/header.html.j2 (after the sections: it lists their best variants)."""
        s = self.summary
        exp_file = s.get("file")
        res = s.get("resolution")
        refs = s.get("references") or []
        me = s.get("motion_explained") or {}
        rendered = [{"name": r.get("name"), "spp": r.get("spp"), "gpu": stat(r.get("gpu_ms")),
                     "rendered": r.get("frames_rendered", 0), "cached": r.get("frames_cached", 0),
                     "floor": floor_items(r)} for r in refs if not r.get("frames")]
        from_files = [{"name": r.get("name"), "frames": r["frames"], "frames_b": r.get("frames_b"),
                       "floor": floor_items(r)} for r in refs if r.get("frames")]
        return {"title": self.title(), "description": experiment_description(exp_file), "exp_file": exp_file,
                "s": s, "n_variants": len(self.variants),
                "resolution": f"{res[0]}×{res[1]}" if isinstance(res, list) and len(res) == 2 else res,
                "rendered_refs": rendered, "file_refs": from_files,
                "explained": me if isinstance(me.get("mean"), (int, float)) else None,
                "measure_ms": stat(s.get("metric_ms_per_frame")), "run_dir": os.path.abspath(self.run_dir),
                "written": datetime.datetime.now().strftime("%Y-%m-%d %H:%M"), "defects": self.defects(),
                "measured": self.measured, "glance": self.glance}

    def defects(self):
        """[(variant, [(metric, worst per-frame count)])] of the variants with NaN/Inf or negative pixels."""
        out = []
        for v in self.variants:
            bad = [(k, self.metric_stat(v, k, "max")) for k in ("nonfinite_pixels", "negative_pixels")]
            bad = [(k, x) for k, x in bad if x]
            if bad:
                out.append((v["name"], bad))
        return out

    def temporal_detail(self, name):
        """The flicker excess and lag of a variant, shown beside its temporal score."""
        v = self.variant(name)
        return self.metric_stat(v, "flicker_excess"), self.metric_stat(v, "temporal_lag")

    # ------------------------------------------------------------ error against cost
    def pareto(self):
        """The Pareto section's data: its state, the plot and per metric the best and the front."""
        s = self.summary
        if not self.measured:
            return {"state": "unmeasured"}
        avail = [m for m in PARETO_METRICS if pareto_points(s, m)]
        if not avail:
            return {"state": "files" if s.get("command") == "measure" else "none"}
        fronts = {m: None for m in avail}
        svg = plot_pareto(self, avail, fronts)
        items = []
        for metric in avail:
            pts, front = fronts[metric]
            by = {p[2]: p for p in pts}
            best = min(pts, key=lambda p: p[1])
            detail = self.temporal_detail(best[2]) if metric == "temporal_score" else None
            items.append({"metric": metric, "best": best, "ratio": metric in RATIO_METRICS, "detail": detail,
                          "front": [by[p[2]] for p in front]})
            tied = self.within_floor(pts, best, metric)
            self.glance.append({"metric": metric, "best": best, "detail": detail, "tied": tied,
                                "floor": self.floor_of(best[2], metric),
                                "cheapest": by[front[0][2]] if front else None})
        return {"state": "plotted", "svg": svg, "lines": items}

    # ------------------------------------------------------------ density sweep
    def density_sweep(self):
        """The sweep's figure and its matched-density rows beside each method's published default, or None."""
        figs = plot_density_sweep(self)
        if figs is None:
            return None
        rows = []
        for name, m in (self.summary.get("matched_density") or {}).items():
            default = next((v for v in self.variants if v["name"] == name), None)
            rows.append({"name": name, "parameter": m.get("parameter"), "value": m.get("value"),
                         "reason": m.get("reason"), "rounds": m.get("rounds"), "how": m.get("how"),
                         "nearest_value": m.get("nearest_value"), "nearest_ratio": m.get("nearest_ratio"),
                         "matched": [m.get(k) for k in SWEEP_METRICS] + [m.get("gpu_ms")],
                         "default": [self.metric_stat(default, k) if default else None for k in SWEEP_METRICS] +
                                    [stat(default.get("gpu_ms")) if default else None]})
        return {"figs": figs, "rows": rows, "columns": [label_of(k) for k in SWEEP_METRICS] + ["GPU ms/frame"]}

    # ------------------------------------------------------------ per-frame curves
    def curves(self):
        """The per-frame plot's SVG, or None where frames.csv has none of CURVE_METRICS."""
        metrics = [m for m in CURVE_METRICS if any(r.get(m) is not None for rows in self.frames.values() for r in rows)]
        return plot_curves(self, metrics) if metrics else None

    # ------------------------------------------------------------ table of means
    def table(self):
        passes = []
        for v in self.variants:
            for p in (v.get("gpu_ms_per_pass") or {}):
                if p not in passes:
                    passes.append(p)
        cols = self.table_columns(passes)
        best, tied = self.table_best(cols)
        rows = []
        for v in self.variants:
            cells = []
            for key, _, _, _ in cols:
                mean, p95 = self.cell(v, key)
                cls = "best" if v["name"] in best.get(key, ()) else "tied" if v["name"] in tied.get(key, ()) else ""
                floor = self.floor_of(v["name"], key[7:]) if key.startswith("metric:") else None
                cells.append({"cls": cls, "mean": mean, "p95": p95, "floor": floor})
            rows.append({"v": v, "color": matplotlib.colors.to_hex(self.colors[v["name"]]),
                         "symbol": AA_SYMBOLS.get(v.get("aa"), "◆"), "cells": cells})
        return {"cols": cols, "rows": rows, "settings": self.settings(), "gpu_svg": plot_gpu_passes(self, passes)}

    def table_columns(self, passes):
        """[(key, label, unit, direction)]: the GPU time, each pass's, and each metric the run has."""
        variants, units = self.variants, self.units
        present = [m for m in TABLE_METRICS if any(m in (v.get("metrics") or {}) for v in variants)]
        # Defect counts only when there is a defect; they are 0 otherwise.
        present = [m for m in present if m not in ("nonfinite_pixels", "negative_pixels")
                   or any(self.metric_stat(v, m, "max") for v in variants)]
        cols = [("gpu", "GPU ms/frame", units.get("gpu_ms", "ms (GPU timestamps)"), "min")]
        cols += [("pass:" + p, f"GPU ms: {p}", units.get("gpu_ms_" + p, "ms (GPU timestamps)"), "min") for p in passes]
        cols += [("metric:" + m, label_of(m), unit_of(units, m), direction_of(m)) for m in present]
        return cols

    @staticmethod
    def cell(v, key):
        """(mean, p95) of a table column's key for variant v."""
        if key == "gpu":
            d = v.get("gpu_ms")
        elif key.startswith("pass:"):
            d = (v.get("gpu_ms_per_pass") or {}).get(key[5:])
        else:
            d = (v.get("metrics") or {}).get(key[7:])
        return stat(d), stat(d, "p95")

    def table_best(self, cols):
        """({key: names of the best}, {key: names within the truth's noise floor of the best})."""
        best, tied = {}, {}
        for key, _, _, direction in cols:
            vals = [(self.cell(v, key)[0], v) for v in self.variants]
            vals = [(x, v) for x, v in vals if x is not None]
            if len(vals) < 2 or direction == "none":
                continue
            if direction == "max":
                dist = [(-x, v) for x, v in vals]
            elif direction == "one":
                dist = [(abs(math.log(x)) if x > 0 else math.inf, v) for x, v in vals]
            elif direction == "ref":
                ref = lambda v: self.metric_stat(v, "glint_density_ref")
                dist = [(abs(x - ref(v)) if ref(v) is not None else math.inf, v) for x, v in vals]
            else:
                dist = vals
            target = min(d for d, _ in dist)
            if math.isfinite(target) and any(d != target for d, _ in dist):
                best[key] = {v["name"] for d, v in dist if d == target}
                if direction == "min" and key.startswith("metric:"):  # ties within the truth's noise floor
                    best_v = next(v for d, v in dist if d == target)
                    f, ref = self.floor_of(best_v["name"], key[7:]), best_v.get("reference")
                    if f is not None:
                        tied[key] = {v["name"] for d, v in dist
                                     if d != target and d - target < f and v.get("reference") == ref}
        return best, tied

    def settings(self):
        """The variants' settings list: [(variant, {"taa": own options | "ssaa" | ...})] and the TAA
        options every TAA variant shares."""
        variants = self.variants
        taa = [v for v in variants if isinstance(v.get("taa"), dict)]
        shared = {}
        if len(taa) > 1:
            shared = {k: x for k, x in taa[0]["taa"].items() if all(v["taa"].get(k, object()) == x for v in taa)}
        items = []
        for v in variants:
            own = ({k: x for k, x in v["taa"].items() if k not in shared} if isinstance(v.get("taa"), dict)
                   else None)
            items.append({"v": v, "own": None if own is None else [(k, option_text(x)) for k, x in own.items()],
                          "params": list((v.get("glint_parameters") or {}).items())})
        return {"lines": items, "shared": [(k, option_text(x)) for k, x in shared.items()],
                "models": len({v.get("glint_model") for v in variants}) > 1}

    # ------------------------------------------------------------ glossary
    def glossary(self):
        units, present = self.units, set()
        for v in self.variants:
            present.update((v.get("metrics") or {}).keys())
        pooled = sorted({int(k.rsplit("_", 1)[1]) for k in present
                         if k.startswith(("pooled_bias_", "pooled_rms_")) and k.rsplit("_", 1)[1].isdigit()})
        first = TABLE_METRICS + ["relative", "frame_diff_ratio"]
        rest = sorted(k for k in present if k not in first and not k.endswith("_max")
                      and not k.startswith(("pooled_bias_", "pooled_rms_")))
        # The report's table order first, then the other metrics metric_info describes, then the rest by name.
        order = [m for m in first if m in present]
        order += [k for k in rest if description_of(k)]
        described = [(m, description_of(m), unit_of(units, m)) for m in order]
        others = [k for k in rest if not description_of(k)]
        return {"described": described, "pooled": pooled,
                "pooled_unit": units.get("pooled_rms_%d" % pooled[0], "Y (block means)") if pooled else "",
                "others": [(k, unit_of(units, k, None)) for k in others],
                "has_max": any(k.endswith("_max") for k in present),
                "device": self.summary.get("device", "?"), "gpu_unit": units.get("gpu_ms", "ms"),
                "referred": self.summary.get("per_pixel_metrics_referred", "scene")}

    # ------------------------------------------------------------ the page
    def write(self):
        # The crops and sequences (image work in Pillow) run in a forked process while this one draws
        # the plots (matplotlib): on two cores the report takes the longer of the two, not the sum.
        crops = start_crops(self)
        page = {"pareto": self.pareto(), "sweep": self.density_sweep(), "curves": self.curves(),
                "table": self.table()}
        page["crops"], crops_files = crops()
        for title, paths in crops_files:
            for rel in paths:
                self.figs.add_file(title, rel)
        page["glossary"] = self.glossary()
        page["files"] = self.figs.files
        shown = {"pareto", "table", "crops", "glossary", "files"}
        shown |= {"curves"} if page["curves"] is not None else set()
        shown |= {"sweep"} if page["sweep"] is not None else set()
        shown |= {"sequences"} if page["crops"] is not None else set()
        s = self.summary
        doc = template_env().get_template("page.html.j2").render(
            page, header=self.header(), nav=[(i, t) for i, t in SECTIONS if i in shown],
            version=s.get("glintlab_version", "?"), schema=s.get("schema"), matplotlib_version=matplotlib.__version__,
            pil_version=getattr(__import__("PIL"), "__version__", "?"),
            outlier_min_excess=f"{OUTLIER_MIN_EXCESS:g}", outlier_top_percent=f"{100 * OUTLIER_TOP_FRACTION:g}")
        out = os.path.join(self.run_dir, "report.html")
        write_bytes(out, doc.encode("utf-8"))
        return out


def experiment_description(exp_file):
    """The experiment file's "description", or "" where it is not readable."""
    if not (isinstance(exp_file, str) and os.path.isfile(exp_file)):
        return ""
    try:
        with open(exp_file, encoding="utf-8") as f:
            return json.load(f).get("description", "") or ""
    except (OSError, ValueError, AttributeError):
        return ""


def option_text(x):
    """A TAA option's value as the settings list prints it."""
    return json.dumps(x) if isinstance(x, bool) else (fmt(x) if isinstance(x, float) else x)


# ------------------------------------------------------------------ the report's plots
def plot_pareto(rep, avail, fronts):
    """Draws the Pareto panels side by side (inline) and one file each; fills fronts[metric] with
    (points, front)."""
    s, figs = rep.summary, rep.figs
    fig, axes = plt.subplots(1, len(avail), figsize=(3.7 * len(avail) + 0.4, 3.6), squeeze=False)
    for ax, metric in zip(axes[0], avail):
        fronts[metric] = draw_pareto(ax, s, metric, rep.colors, rep.markers, len(rep.variants) <= 12)
    ncol = min(len(rep.variants) + 1, 6)
    fig.legend(handles=legend_handles(s, rep.colors, rep.markers), loc="lower center", ncol=ncol,
               frameon=False, bbox_to_anchor=(0.5, 0.0))
    nrows_leg = math.ceil((len(rep.variants) + 1) / ncol)
    fig.tight_layout(rect=(0, 0.06 + 0.045 * nrows_leg, 1, 1))
    svg = figs.save(fig, "pareto", "Error against GPU cost with Pareto fronts")
    for metric in avail:  # one panel per file as well, for papers
        f1, ax = plt.subplots(figsize=(4.6, 3.6))
        draw_pareto(ax, s, metric, rep.colors, rep.markers, True)
        f1.tight_layout()
        figs.save(f1, f"pareto_{metric}", f"{label_of(metric)} against GPU cost", inline=False)
    return svg


def plot_curves(rep, metrics):
    """Draws the per-frame curves of metrics, one panel each; returns the inline SVG."""
    frames, variants = rep.frames, rep.variants
    fig, axes = plt.subplots(len(metrics), 1, figsize=(9.0, 2.7 * len(metrics) + 0.3), sharex=True,
                             squeeze=False)
    nframes = max(len(rows) for rows in frames.values())
    for ax, metric in zip(axes[:, 0], metrics):
        for v in variants:
            pts = [(r["frame"], r[metric]) for r in frames.get(v["name"], [])
                   if r.get(metric) is not None and math.isfinite(r[metric])]
            if pts:
                ax.plot([p[0] for p in pts], [p[1] for p in pts], lw=1.4, ms=4, color=rep.colors[v["name"]],
                        marker=rep.markers[v["name"]] if nframes <= 40 else None, label=v["name"])
        if metric == "flicker_ratio":
            ax.axhline(1.0, color="black", lw=1.0, ls=":", label="reference (1)")
            ax.set_ylabel("flicker ratio\n(1 = as stable as truth)")
        else:
            ax.set_ylabel(label_of(metric))
        ax.set_title(f"{label_of(metric)} per frame", loc="left")
    axes[-1, 0].set_xlabel("frame")
    axes[-1, 0].xaxis.get_major_locator().set_params(integer=True)
    handles, labels = [], []
    for ax in axes[:, 0]:
        for h, l in zip(*ax.get_legend_handles_labels()):
            if l not in labels:
                handles.append(h)
                labels.append(l)
    fig.legend(handles, labels, loc="center right", frameon=False, fontsize=8 if len(labels) <= 18 else 6.5)
    fig.tight_layout(rect=(0, 0, 0.80, 1))
    return rep.figs.save(fig, "per_frame", "Per-frame flicker ratio and ΔE00")


SWEEP_METRICS = ("glint_density_ratio", "temporal_score", "flicker_excess", "temporal_error_mc", "deltaE2000")


def plain_log_ticks(axis):
    """A log axis labelled 0.5, 1, 2 (not 5×10⁻¹), minor ticks unlabelled."""
    axis.set_major_locator(matplotlib.ticker.LogLocator(base=10, subs=(0.2, 0.3, 0.5, 0.7, 1.0)))
    axis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
    axis.set_minor_formatter(matplotlib.ticker.NullFormatter())


def plot_density_sweep(rep):
    """The density sweep (summary.json "density_sweep", "matched_density"): per method its glint density
    ratio against its own parameter, then the errors against the ratio (where methods show as many
    glints as the truth they are compared at ratio 1), each method's matched-density point as a star, the
    truth's value (ratio 1, 0 for the errors) with its noise-floor band. Returns the two inline SVGs, or
    None without a sweep."""
    s = rep.summary
    sweep, matched = s.get("density_sweep") or {}, s.get("matched_density") or {}
    if not sweep:
        return None
    floor = ((s.get("references") or [{}])[0].get("floor") or {})
    colors = variant_colors(list(sweep))

    def points(rows, xkey, ykey):
        return [(r.get(xkey), r.get(ykey)) for r in rows if finite(r.get(xkey)) and finite(r.get(ykey))
                and (ykey != "glint_density_ratio" or r[ykey] > 0) and (xkey != "glint_density_ratio" or r[xkey] > 0)]

    def star(ax, name, xkey, ykey):
        m = matched.get(name) or {}
        p = points([m], xkey, ykey)
        if p:
            ax.plot([p[0][0]], [p[0][1]], marker="*", ms=11, color=colors[name], mec="black", mew=0.6, ls="")

    n = len(sweep)
    fig1, axes = plt.subplots(1, n, figsize=(2.6 * n + 0.4, 2.9), squeeze=False)
    for ax, (name, rows) in zip(axes[0], sweep.items()):
        ax.axhspan(0.8, 1.25, color="0.85", lw=0)
        ax.axhline(1.0, color="black", lw=1.0, ls=":")
        p = points(rows, "value", "glint_density_ratio")
        if p:
            ax.plot([q[0] for q in p], [q[1] for q in p], lw=1.4, marker="o", ms=3.5, color=colors[name])
        star(ax, name, "value", "glint_density_ratio")
        ax.set_yscale("log")
        plain_log_ticks(ax.yaxis)
        ax.set_xlabel(rows[0]["parameter"] if rows else "")
        ax.set_title(name, loc="left", fontsize=9)
    axes[0, 0].set_ylabel("glint density ratio")
    fig1.tight_layout()
    svg1 = rep.figs.save(fig1, "density_sweep_parameter",
                         "Glint density ratio against each method's density parameter (star: matched)")

    metrics = SWEEP_METRICS[1:]
    fig, axes = plt.subplots(1, len(metrics), figsize=(3.5 * len(metrics) + 1.6, 3.4), squeeze=False)
    for ax, metric in zip(axes[0], metrics):
        ax.axvspan(0.8, 1.25, color="0.9", lw=0)
        ax.axvline(1.0, color="black", lw=1.0, ls=":")
        f = floor.get(metric)
        if isinstance(f, (int, float)) and math.isfinite(f):
            ax.axhspan(0.0, f, color="0.8", lw=0, label="truth's noise floor")
        for name, rows in sweep.items():
            p = sorted(points(rows, "glint_density_ratio", metric))
            if p:
                ax.plot([q[0] for q in p], [q[1] for q in p], lw=1.4, marker="o", ms=3.5, color=colors[name],
                        label=name)
            star(ax, name, "glint_density_ratio", metric)
        ax.set_xscale("log")
        plain_log_ticks(ax.xaxis)
        ax.set_xlabel("glint density ratio (1 = the truth's)")
        ax.set_ylim(bottom=0)
        ax.set_title(label_of(metric), loc="left")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="center right", frameon=False, fontsize=8)
    fig.tight_layout(rect=(0, 0, 0.84, 1))
    svg2 = rep.figs.save(fig, "density_sweep", "Error and flicker against glint density (star: matched)")
    return svg1, svg2


def plot_gpu_passes(rep, passes):
    """The per-pass GPU time bars' SVG, or None without GPU times."""
    variants = rep.variants
    if not passes or all(stat(v.get("gpu_ms")) is None for v in variants):
        return None
    fig, ax = plt.subplots(figsize=(8.0, 0.9 + 0.32 * len(variants)))
    left = np.zeros(len(variants))
    pcm = plt.get_cmap("Set2")
    for i, p in enumerate(passes):
        vals = np.array([stat((v.get("gpu_ms_per_pass") or {}).get(p)) or 0.0 for v in variants])
        ax.barh(range(len(variants)), vals, left=left, color=pcm(i % 8), label=p, edgecolor="white", lw=0.5)
        left += vals
    for i, v in enumerate(variants):
        g = stat(v.get("gpu_ms"))
        if g is not None:
            ax.text(left[i], i, f"  {fmt(g)} ms", va="center", fontsize=8)
    ax.set_yticks(range(len(variants)))
    ax.set_yticklabels(rep.names)
    ax.invert_yaxis()
    ax.set_xlabel("GPU ms / frame (mean per pass)")
    ax.set_xlim(0, max(float(left.max()), 1e-9) * 1.18)
    ax.grid(axis="y", visible=False)
    ax.legend(loc="lower right", bbox_to_anchor=(1.0, 1.0), frameon=False, ncol=len(passes), title="pass",
              title_fontsize=8)
    fig.tight_layout()
    return rep.figs.save(fig, "gpu_per_pass", "GPU time per pass")


# ------------------------------------------------------------------ crops and sequences
MAX_ANIMATION_FRAMES = 120
MAX_ANIMATION_PIXELS = 1_600_000  # per animation frame


def crops_in_child(rep):
    """crops_section in a forked child: its data and the files it listed."""
    rep.figs.files = []
    data = crops_section(rep)
    return data, rep.figs.files


def start_crops(rep):
    """Starts crops_section(rep) in a forked process and returns a function that waits for it and
    gives (data, [(title, [paths])]); where no process can be forked, it runs here when asked. An
    exception in the child (bad input, an I/O error, a bug) is raised again by the function."""
    try:
        pool = concurrent.futures.ProcessPoolExecutor(max_workers=1, mp_context=multiprocessing.get_context("fork"))
        future = pool.submit(crops_in_child, rep)
    except (OSError, ValueError):
        return lambda: (crops_section(rep), [])

    def wait():
        try:
            return future.result()
        finally:
            pool.shutdown()
    return wait


class CropSource:
    """The rows the crops show (each reference once, first, then the variants in run order) with their
    PNG previews, the frames all of them have, and the crop region."""

    def __init__(self, rep):
        summary = rep.summary
        rows = [(r["name"], "reference", r) for r in summary.get("references") or [] if isinstance(r.get("name"), str)]
        rows += [(v["name"], "variant", v) for v in rep.variants]
        self.pngs = {name: png_frames(rep.run_dir, name) for name, _, _ in rows}
        self.rows = [r for r in rows if self.pngs[r[0]]]
        if not self.rows:
            return
        pngs = self.pngs
        self.common = sorted(set.intersection(*[set(pngs[n]) for n, _, _ in self.rows])) or \
            sorted(pngs[self.rows[0][0]])
        self.region_source = self.rows[0][0]
        self.h, self.w = load_rgb(pngs[self.region_source][self.common[0]]).shape[:2]
        self.choose_region()

    def choose_region(self):
        """The crop window, chosen on at most 16 frames spread over the sequence, and the frame shown."""
        common, h, w = self.common, self.h, self.w
        sel = sorted({round(i * (len(common) - 1) / 15) for i in range(16)}) if len(common) > 16 else \
            list(range(len(common)))
        src, src_frames = [], []
        for i in sel:
            a = load_rgb(self.pngs[self.region_source][common[i]])
            if a.shape[:2] == (h, w):
                src.append(a)
                src_frames.append(common[i])
        side = int(min(64, max(8, min(w, h) // 4)))
        self.cw, self.ch = min(side, w), min(side, h)
        self.x0, self.y0, self.how, per_frame, self.total = choose_region(src, self.cw, self.ch)
        self.n_src = len(src)
        self.crop_frame = (src_frames[int(np.argmax(per_frame))] if max(per_frame) > 0
                           else src_frames[len(src_frames) // 2])
        self.scale = int(max(2, min(16, 256 // max(self.cw, self.ch))))

    def load(self, name, frame):
        p = self.pngs[name].get(frame)
        if p is None:
            return None
        a = load_rgb(p)
        return a if a.shape[:2] == (self.h, self.w) else None

    def crop(self, a, s):
        if a is None:
            return np.zeros((self.ch * s, self.cw * s, 3), np.uint8)
        return upscale(a[self.y0:self.y0 + self.ch, self.x0:self.x0 + self.cw], s)


def region_overview(src, figs):
    """The frame the crops show with the region outlined, written to figures/; (PNG bytes, width, height)."""
    ov = Image.fromarray(load_rgb(src.pngs[src.region_source][src.crop_frame]))
    ov_scale = max(1, 480 // ov.width)
    if ov_scale > 1:
        ov = ov.resize((ov.width * ov_scale, ov.height * ov_scale), Image.NEAREST)
    d = ImageDraw.Draw(ov)
    lw = max(2, ov_scale)
    x0, y0, cw, ch = src.x0, src.y0, src.cw, src.ch
    for i in range(lw):
        d.rectangle([x0 * ov_scale - lw + i, y0 * ov_scale - lw + i, (x0 + cw) * ov_scale + lw - 1 - i,
                     (y0 + ch) * ov_scale + lw - 1 - i], outline=(230, 40, 40) if i < lw - 1 else (255, 255, 255))
    ov_png = encode_png(ov)
    write_bytes(os.path.join(figs.dir, "glint_region.png"), ov_png)
    figs.add_file("Glint region on the reference frame", "figures/glint_region.png")
    return ov_png, ov.width, ov.height


def crop_caption(rep, frames, src, name, kind, obj):
    """(caption lines under a crop, the first in bold; the label on its tile)."""
    if kind == "reference":
        if obj.get("frames"):
            return [name, "read from files, the reference"], f"{name} (files)"
        return [name, f"{obj.get('spp')} spp, the ground truth"], f"{name} ({obj.get('spp')} spp)"
    de = next((r.get("deltaE2000") for r in frames.get(name, []) if r["frame"] == src.crop_frame), None)
    fl = rep.metric_stat(obj, "flicker_ratio")
    how = "read from files" if obj.get("source") == "frames" else f"{obj.get('aa')}, {obj.get('spp')} spp"
    lines = [name, how]
    if de is not None:
        lines.append(f"ΔE00 {fmt(de)} (whole frame)")
    if fl is not None:
        lines.append(f"flicker ratio {fmt(fl)} (run mean)")
    return lines, name


def crops_section(rep):
    """The glint crops' and the sequences' data for templates/crops.html.j2; None without PNG previews."""
    src = CropSource(rep)
    if not src.rows:
        return None
    ov_png, ov_w, ov_h = region_overview(src, rep.figs)
    tiles, labels, crops = [], [], []
    for name, kind, obj in src.rows:
        t = src.crop(src.load(name, src.crop_frame), src.scale)
        tiles.append(t)
        caption, label = crop_caption(rep, rep.frames, src, name, kind, obj)
        labels.append(label)
        crops.append({"name": name, "caption": caption, "width": t.shape[1], "height": t.shape[0],
                      "uri": data_uri("image/png", encode_png(Image.fromarray(t)))})
    font = load_font(12)
    cols = min(len(tiles), max(1, 1400 // (tiles[0].shape[1] + 2)), 6)
    write_bytes(os.path.join(rep.figs.dir, "glint_crops.png"), encode_png(tile_grid(tiles, labels, cols, 17, font)))
    rep.figs.add_file("Glint crops (one frame, labelled)", "figures/glint_crops.png")
    region = {k: getattr(src, k) for k in ("region_source", "cw", "ch", "how", "total", "n_src", "crop_frame", "scale",
                                           "x0", "y0")}
    return {"region": region, "overview": {"uri": data_uri("image/png", ov_png), "width": ov_w, "height": ov_h},
            "crops": crops, "sequences": sequences(rep, src, labels, cols, font) if len(src.common) >= 2 else None}


def play_timing(rep, src, step):
    """(ms per animation image, images per second, the camera path's frames per second)."""
    frames, variants, common = rep.frames, rep.variants, src.common
    times = [r.get("time_s") for r in frames.get(variants[0]["name"], [])] if variants else []
    times = [t for t in times if t is not None]
    dts = sorted(b - a for a, b in zip(times, times[1:]) if b > a)
    path_fps = round(1.0 / dts[len(dts) // 2], 2) if dts else 30.0
    saved_step = max(1, (common[1] - common[0]) if len(common) > 1 else 1) * step
    duration = max(100, int(round(1000.0 * saved_step / path_fps)))  # at most 10 images per second
    return duration, 1000.0 / duration, path_fps


def whole_frame_size(src, n):
    """(width, height, how) of the whole frames in the animation of n rows: shrunk (box filter) to at
    most 320 px wide, or enlarged (nearest) when tiny; smaller still when there are many rows."""
    w, h = src.w, src.h
    if w > 320:
        f_div = math.ceil(w / 320)
        while n * (w // f_div) * (h // f_div) > MAX_ANIMATION_PIXELS:
            f_div += 1
        return w // f_div, h // f_div, f"shrunk {f_div}× (box filter: averaging hides some single-pixel flicker; " \
                                       "the crops do not)"
    f_mul = max(1, 320 // w)
    while f_mul > 1 and n * (w * f_mul) * (h * f_mul) > MAX_ANIMATION_PIXELS:
        f_mul -= 1
    return w * f_mul, h * f_mul, f"enlarged {f_mul}× (nearest neighbour)" if f_mul > 1 else "at full resolution"


def whole_frame(src, a, fw, fh):
    """A frame resized to fw x fh with the crop region outlined in red (black where it is missing)."""
    if a is None:
        return np.zeros((fh, fw, 3), np.uint8)
    im = Image.fromarray(a).resize((fw, fh), Image.BOX if fw < src.w else Image.NEAREST)
    t = np.asarray(im).copy()
    sx, sy = fw / src.w, fh / src.h
    rx0, ry0 = int(src.x0 * sx), int(src.y0 * sy)
    rx1, ry1 = min(fw - 1, int((src.x0 + src.cw) * sx)), min(fh - 1, int((src.y0 + src.ch) * sy))
    t[ry0, rx0:rx1 + 1] = t[ry1, rx0:rx1 + 1] = (230, 40, 40)
    t[ry0:ry1 + 1, rx0] = t[ry0:ry1 + 1, rx1] = (230, 40, 40)
    return t


def sequences(rep, src, labels, cols, font):
    """Animates the crops and the whole frames over the saved frames; their data for the template."""
    step = math.ceil(len(src.common) / MAX_ANIMATION_FRAMES)
    seq = src.common[::step]
    duration, play_fps, path_fps = play_timing(rep, src, step)
    n = len(src.rows)
    a_scale = src.scale
    while a_scale > 1 and n * (src.cw * a_scale) * (src.ch * a_scale) > MAX_ANIMATION_PIXELS:
        a_scale -= 1
    fw, fh, f_note = whole_frame_size(src, n)
    anim_crops, anim_whole = [], []
    for f in seq:
        images = [src.load(name, f) for name, _, _ in src.rows]
        labs = [f"{labels[0]} · f{f}"] + labels[1:]
        anim_crops.append(tile_grid([src.crop(a, a_scale) for a in images], labs, cols, 17, font))
        anim_whole.append(tile_grid([whole_frame(src, a, fw, fh) for a in images], labs, min(n, 3), 17, font))
    webp = features.check("webp_anim")
    kind, mime = ("webp", "image/webp") if webp else ("gif", "image/gif")
    out = {"saved": src.common, "step": step, "play_fps": play_fps, "path_fps": path_fps, "a_scale": a_scale,
           "f_note": f_note}
    for name, frames_, lossless in (("crops", anim_crops, True), ("frames", anim_whole, False)):
        data = encode_animation(frames_, duration, kind.upper(), lossless=lossless)
        also, err = write_animation(rep.figs, name, kind, data, frames_, duration, play_fps, webp)
        out[name] = {"uri": data_uri(mime, data), "width": frames_[0].width, "height": frames_[0].height,
                     "also": also, "err": err}
    return out


def write_animation(figs, name, kind, data, frames_, duration, play_fps, webp):
    """Writes figures/<name>.<kind>, a GIF beside a WebP and an MP4 where ffmpeg is installed; returns
    (the other formats written, why there is no MP4 or None)."""
    title = "Crop sequence" if name == "crops" else "Whole-frame sequence"
    write_bytes(os.path.join(figs.dir, f"{name}.{kind}"), data)
    figs.add_file(title, f"figures/{name}.{kind}")
    also = []
    if webp:
        write_bytes(os.path.join(figs.dir, f"{name}.gif"), encode_animation(frames_, duration, "GIF", False))
        figs.add_file(title, f"figures/{name}.gif")
        also.append("GIF")
    err = encode_mp4(frames_, play_fps, os.path.join(figs.dir, f"{name}.mp4"))
    if err is None:
        figs.add_file(title, f"figures/{name}.mp4")
        also.append("MP4")
    return also, err


def build_report(run_dir):
    return Report(run_dir).write()


def main(argv):
    if len(argv) != 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip(), file=sys.stderr if len(argv) != 2 else sys.stdout)
        return EXIT_OK if len(argv) == 2 else EXIT_BAD_INPUT
    if _missing:
        print("error: report: " + sys.executable + " lacks the Python module" + ("s " if len(_missing) > 1 else " ")
              + ", ".join(m for m, _ in _missing) + "; install the Debian package"
              + ("s " if len(_missing) > 1 else " ") + " ".join(p for _, p in _missing)
              + " (./bootstrap.sh installs them)", file=sys.stderr)
        return EXIT_MISSING_MODULE
    run_dir = argv[1]
    try:
        out = build_report(run_dir)
    except BadInput as e:
        print(f"error: report: {e}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except OSError as e:
        print(f"error: report: {e}", file=sys.stderr)
        return EXIT_IO
    except Exception:  # a bug: say so, with the trace
        traceback.print_exc()
        print("error: report: internal error (a bug in experiments/report/glintlab_report.py; please report it "
              "with the trace above)", file=sys.stderr)
        return EXIT_INTERNAL
    print(f"wrote {out}")
    return EXIT_OK


if __name__ == "__main__":
    sys.exit(main(sys.argv))
