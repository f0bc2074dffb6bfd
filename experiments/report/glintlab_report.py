#!/usr/bin/env python3
"""glintlab report: turns a run directory into a self-contained report.html.

    python3 glintlab_report.py RUN_DIR

Reads RUN_DIR/summary.json (schema glintlab-summary/1), RUN_DIR/frames.csv and
the PNG previews RUN_DIR/<variant or reference>/frame_NNNN.png, and writes

    RUN_DIR/report.html          one file: plots as inline SVG, images and
                                 animations as data URIs; nothing is fetched
    RUN_DIR/figures/*.svg|pdf    every plot, for papers (matplotlib)
    RUN_DIR/figures/*.png|webp|gif|mp4
                                 the glint crops and the side-by-side sequences
                                 (MP4 only where ffmpeg is installed)

Exit codes (experiments/cli/exit_codes.h): 0 written, 2 bad input (no
summary.json, not a glintlab summary), 4 a file could not be read or written,
5 internal error, 10 a Python module is missing (numpy, matplotlib, PIL; the
message names the Debian packages).

Debian 12 packages: python3-matplotlib python3-pil python3-numpy (bootstrap.sh).
"""

import base64
import concurrent.futures
import csv
import datetime
import html
import io
import json
import math
import multiprocessing
import os
import shutil
import subprocess
import sys
import traceback

EXIT_OK, EXIT_BAD_INPUT, EXIT_IO, EXIT_INTERNAL, EXIT_MISSING_MODULE = 0, 2, 4, 5, 10

_missing = []
try:
    import numpy as np
except ImportError:
    _missing.append(("numpy", "python3-numpy"))
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    _missing.append(("matplotlib", "python3-matplotlib"))
try:
    from PIL import Image, ImageDraw, ImageFont, features
except ImportError:
    _missing.append(("PIL", "python3-pil"))


class BadInput(Exception):
    pass


# ------------------------------------------------------------------ metrics
# name -> (label, direction, explanation). direction: "min" lower is better,
# "max" higher is better, "one" closest to 1 is best, "ref" closest to the
# reference's value. The unit comes from summary.json "units".
METRICS = {
    "deltaE2000": ("ΔE00", "min",
                   "CIEDE2000 colour difference of each pixel against the reference, averaged over the frame. "
                   "About 1 is a just-noticeable difference between flat patches side by side; lower is better."),
    "deltaEITP": ("ΔE_ITP", "min",
                  "ITU-R BT.2124 colour difference, built for HDR (scene Y = 1 is shown at 100 cd/m²); "
                  "1 is about one just-noticeable step. Lower is better."),
    "flip": ("FLIP", "min",
             "How different the frame looks from the reference when one flips between them (HDR-FLIP, "
             "Andersson et al. 2020/2021), per-pixel mean in [0, 1]; 0 = indistinguishable. Lower is better."),
    "psnr": ("PSNR", "max",
             "Peak signal-to-noise ratio of luminance (peak 1) in dB. Higher is better; it rewards blur more "
             "than the perceptual metrics do."),
    "relative": ("relative error", "min",
                 "Mean |Y_test − Y_ref| / (Y_ref + 0.01): luminance error relative to the reference. Lower is better."),
    "flicker_ratio": ("flicker ratio", "one",
                      "How much the frame changes between consecutive frames, along the motion, compared with how "
                      "much the reference changes: 1 = as stable as the truth, above 1 = flickers more than the "
                      "truth (aliasing), below 1 = changes less (blur, ghosting, history lag). Best is closest to 1; "
                      "the plots rank |ln(ratio)|, so 0.5 and 2 count as equally far off."),
    "temporal_error": ("temporal error", "min",
                       "Mean |e_t − e_(t−1)| with e = PQ(test) − PQ(reference) at a fixed pixel: the part of the "
                       "frame-to-frame change that the reference does not have. 0 = the error is constant over "
                       "time. Lower is better."),
    "temporal_error_mc": ("temporal error (motion-compensated)", "min",
                          "The temporal error measured along the motion instead of at a fixed pixel: the change "
                          "that does not match the truth's. This report ranks temporal stability by it. Lower is "
                          "better."),
    "flicker_excess": ("flicker excess", "min",
                       "The change along the motion the test has beyond the truth's, per pixel and one-sided, both "
                       "frames low-passed at the eye's resolution (σ = 2 px) first, as Weber contrast: 0 = no "
                       "added flicker. “Twinkles too much”. Lower is better."),
    "temporal_lag": ("temporal lag", "min",
                     "The truth's change along the motion that the test lacks (one-sided, low-passed as flicker "
                     "excess): history lag and ghosting. “Smooth but wrong”. Lower is better."),
    "flicker_excess_fixed": ("flicker excess (fixed gaze)", "min",
                             "Flicker excess at a fixed pixel instead of along the motion: what an eye that does "
                             "not follow the surface sees. Screen-fixed artefacts have excess along the motion "
                             "only. Lower is better."),
    "flicker_contrast": ("flicker contrast", "min",
                         "The test's own change along the motion as Weber contrast against its own low-passed "
                         "luminance; needs no reference (what `measure` gives without one). Lower is steadier."),
    "frame_diff_ratio": ("frame-difference ratio", "one",
                         "Mean |ΔT| / mean |ΔR| between consecutive frames at a fixed pixel (PQ): like the flicker "
                         "ratio but without following the motion. Best is closest to 1."),
    "pooled_error": ("pooled error", "min",
                     "RMS difference of 8×8-pixel block means of luminance: the error that survives spatial "
                     "averaging (brightness bias, missing or extra glint energy), blind to per-pixel noise. "
                     "Lower is better."),
    "glint_density_test": ("glint density", "ref",
                           "Pixels brighter than 4× their local 15×15 mean, per 1000 pixels. Compare with the "
                           "reference's density (next column): best is closest to it."),
    "glint_density_ratio": ("glint density ratio", "one",
                            "The test's mean glint density over the reference's (means over the frames): 1 keeps "
                            "the truth's sparkle, below 1 erases glints, above 1 adds them. Best is closest to 1."),
    "glint_density_ref": ("glint density of the reference", "none",
                          "The same count in the reference frames."),
    "glint_hist_emd_oct": ("glint histogram EMD", "min",
                           "Earth mover's distance between the glint-intensity histograms of test and reference, in "
                           "octaves (factors of 2 of intensity). Lower is better."),
    "nonfinite_pixels": ("NaN/Inf pixels", "min", "Pixels that are NaN or infinite (a defect: should be 0)."),
    "negative_pixels": ("negative pixels", "min", "Pixels with a finite negative value (a defect: should be 0)."),
}
TABLE_METRICS = ["deltaE2000", "flip", "temporal_error_mc", "flicker_excess", "temporal_lag", "flicker_ratio",
                 "glint_density_ratio", "flicker_excess_fixed", "temporal_error", "flicker_contrast", "deltaEITP", "psnr",
                 "pooled_error", "glint_density_test", "glint_density_ref", "glint_hist_emd_oct", "nonfinite_pixels",
                 "negative_pixels"]
# Temporal stability is ranked by temporal_error_mc (the change that does not match the truth); the
# flicker ratio is a diagnostic (it ranks lag as flicker and magnitude over agreement).
# The glint density ratio as |ln ratio|: whether a variant keeps the truth's glints, at its cost.
PARETO_METRICS = ["deltaE2000", "flip", "temporal_error_mc", "glint_density_ratio"]
RATIO_METRICS = ("flicker_ratio", "glint_density_ratio")  # plotted and ranked as |ln ratio|
CURVE_METRICS = ["flicker_ratio", "deltaE2000"]
AA_MARKERS = {"none": "o", "ssaa": "s", "taa": "^"}


def label_of(name):
    return METRICS.get(name, (name,))[0]


# ------------------------------------------------------------------ small helpers
def esc(x):
    return html.escape(str(x), quote=True)


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
            return ""
        text = svg.decode("utf-8")
        start = text.find("<svg")
        text = text[start:]
        return f'<div class="plot" role="img" aria-label="{esc(title)}">{text}</div>'

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


def pareto_front(points):
    """points: [(x, y, name)] to minimise in both; returns the non-dominated
    ones sorted by x."""
    pts = sorted(points, key=lambda p: (p[0], p[1]))
    front, best = [], math.inf
    for p in pts:
        if p[1] < best:
            front.append(p)
            best = p[1]
    return front


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
    front = pareto_front([(p[0], p[1], p[2]) for p in pts])
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
def box_sum(a, kh, kw):
    """Sums of every kh x kw window of a (valid positions only)."""
    s = np.zeros((a.shape[0] + 1, a.shape[1] + 1), dtype=np.float64)
    s[1:, 1:] = np.cumsum(np.cumsum(a, axis=0), axis=1)
    return s[kh:, kw:] - s[:-kh, kw:] - s[kh:, :-kw] + s[:-kh, :-kw]


OUTLIER_MIN_EXCESS = 0.08  # display-encoded luma, 0..1
OUTLIER_TOP_FRACTION = 0.005


def luma(rgb8):
    """Display-encoded luma in [0, 1] (Rec. 709 weights on the encoded values)."""
    return (rgb8.astype(np.float32) / 255.0) @ np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)


def median7(y):
    """Separable 7x7 median (rows, then columns): a local background level
    that edges do not drag around and a few-pixel glint does not move."""
    from numpy.lib.stride_tricks import sliding_window_view
    p = np.pad(y, 3, mode="edge")
    rows = np.median(sliding_window_view(p, 7, axis=1), axis=-1)
    return np.median(sliding_window_view(rows, 7, axis=0), axis=-1)


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
    counts = box_sum(acc, ch, cw)
    how = "outliers"
    if counts.max() <= 0:
        y = np.mean(lums, axis=0)
        s1 = box_sum(y, ch, cw)
        s2 = box_sum(y * y, ch, cw)
        n = float(cw * ch)
        counts = s2 / n - (s1 / n) ** 2
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
CSS = """
:root { --fg:#1d2126; --muted:#5b6570; --line:#d9dee3; --accent:#2a5d8f; --bg:#fff; --soft:#f4f6f8; }
* { box-sizing: border-box; }
body { margin:0; background:var(--bg); color:var(--fg);
       font: 15px/1.55 "DejaVu Sans", "Segoe UI", Roboto, Helvetica, Arial, sans-serif; }
main { max-width: 1140px; margin: 0 auto; padding: 28px 28px 60px; }
h1 { font-size: 26px; margin: 0 0 4px; }
h1 small { font-weight: normal; color: var(--muted); font-size: 16px; }
h2 { font-size: 20px; margin: 40px 0 8px; padding-top: 10px; border-top: 1px solid var(--line); }
h3 { font-size: 16px; margin: 22px 0 6px; }
p, li { max-width: 860px; }
.lede { color: var(--muted); margin: 4px 0 18px; }
.muted { color: var(--muted); }
.note { background: var(--soft); border-left: 3px solid var(--accent); padding: 8px 12px; margin: 10px 0;
        max-width: 860px; }
.warn { background: #fff4e5; border-left: 3px solid #d9822b; padding: 8px 12px; margin: 10px 0; }
dl.facts { display: grid; grid-template-columns: max-content 1fr; gap: 2px 18px; margin: 12px 0; font-size: 14px; }
dl.facts dt { color: var(--muted); }
dl.facts dd { margin: 0; }
code { font-family: "DejaVu Sans Mono", Menlo, Consolas, monospace; font-size: 0.9em; background: var(--soft);
       padding: 0 3px; border-radius: 3px; }
nav { font-size: 14px; margin: 12px 0 0; }
nav a { margin-right: 14px; }
a { color: var(--accent); }
.plot svg { max-width: 100%; height: auto; display: block; }
figure { margin: 14px 0; }
figcaption { color: var(--muted); font-size: 13.5px; max-width: 860px; margin-top: 4px; }
.tablewrap { overflow-x: auto; border: 1px solid var(--line); border-radius: 4px; }
table { border-collapse: collapse; font-size: 13px; white-space: nowrap; }
th, td { padding: 5px 9px; border-bottom: 1px solid var(--line); text-align: right; vertical-align: top; }
th { background: var(--soft); font-weight: 600; }
th .unit { display: block; font-weight: normal; color: var(--muted); font-size: 11px; white-space: normal;
           min-width: 70px; max-width: 150px; }
td:first-child, th:first-child { text-align: left; position: sticky; left: 0; background: var(--bg); }
th:first-child { background: var(--soft); }
td.best, b.bestkey { font-weight: 700; color: #135e2e; }
td.tied, i.tiedkey { color: #135e2e; font-style: italic; }
td .sub { color: var(--muted); font-size: 11px; display: block; }
tr:hover td { background: #fafbfc; }
.crops { display: flex; flex-wrap: wrap; gap: 14px; }
.crops figure { margin: 0; }
.crops img { display: block; image-rendering: pixelated; border: 1px solid var(--line); }
.crops figcaption { font-size: 12.5px; max-width: none; }
.crops figcaption b { color: var(--fg); }
img.frame { max-width: 100%; height: auto; image-rendering: pixelated; border: 1px solid var(--line); }
img.anim { max-width: 100%; height: auto; image-rendering: pixelated; }
.glossary dt { font-weight: 600; margin-top: 10px; }
.glossary dd { margin: 2px 0 0 0; max-width: 860px; }
.glossary .unit { color: var(--muted); font-size: 13px; }
ul.files { font-size: 14px; }
footer { margin-top: 50px; color: var(--muted); font-size: 12.5px; }
"""


class Report:
    """One report: the run's data and the figures written so far; each
    section method returns its HTML."""

    def __init__(self, run_dir):
        self.run_dir = run_dir
        self.summary, self.frames = load_run(run_dir)
        self.figs = Figures(os.path.join(run_dir, "figures"))
        os.makedirs(self.figs.dir, exist_ok=True)
        setup_matplotlib()
        self.variants = self.summary["variants"]
        self.names = [v["name"] for v in self.variants]
        self.colors = variant_colors(self.names)
        self.markers = {v["name"]: AA_MARKERS.get(v.get("aa"), "D") for v in self.variants}
        self.units = self.summary.get("units") or {}
        self.measured = bool(self.summary.get("measured", True)) and any(v.get("metrics") for v in self.variants)
        self.glance = []  # (metric, best point, front, variants within the floor of the best) for "at a glance"
        self.sections = []  # (id, title) of the sections written, for the navigation

    def floor_of(self, variant_name, metric):
        """The noise floor of `metric` of the truth `variant_name` is measured against (summary.json
        references[].floor), or None."""
        v = next((x for x in self.variants if x["name"] == variant_name), None)
        r = next((r for r in self.summary.get("references") or [] if v and r.get("name") == v.get("reference")), None)
        f = (r or {}).get("floor", {}).get(metric)
        return f if isinstance(f, (int, float)) and math.isfinite(f) else None

    def within_floor(self, pts, best, metric):
        """The variants whose figure lies within the truth's noise floor of the best one's (same truth)."""
        f = self.floor_of(best[2], metric)
        if f is None or metric in RATIO_METRICS:
            return []
        ref = next(x for x in self.variants if x["name"] == best[2]).get("reference")
        return [p[2] for p in pts if p[2] != best[2] and abs(p[3] - best[3]) < f
                and next(x for x in self.variants if x["name"] == p[2]).get("reference") == ref]

    def metric_stat(self, v, metric, key="mean"):
        return stat((v.get("metrics") or {}).get(metric), key)

    # ------------------------------------------------------------ header
    def header(self):
        s, variants = self.summary, self.variants
        res = s.get("resolution")
        res_text = f"{res[0]}×{res[1]}" if isinstance(res, list) and len(res) == 2 else esc(res)
        title = self.title()
        description = ""
        exp_file = s.get("file")
        if isinstance(exp_file, str) and os.path.isfile(exp_file):
            try:
                with open(exp_file, encoding="utf-8") as f:
                    description = json.load(f).get("description", "") or ""
            except (OSError, ValueError, AttributeError):
                description = ""
        warm = s.get("timing_warmup_frames_excluded")
        facts = [("experiment", esc(title) + (f" <span class=muted>({esc(exp_file)})</span>" if exp_file else "")),
                 ("device", esc(s.get("device") or "none (frames read from files)")),
                 ("glintlab version", esc(s.get("glintlab_version", "?"))),
                 ("resolution", res_text + " px"),
                 ("frames", esc(s.get("frames", "?")) + (
                     f" <span class=muted>(GPU timings leave out the first {esc(warm)} as warm-up)</span>"
                     if warm else "")),
                 ("variants", str(len(variants))),
                 ("working space", esc(s.get("working_space", "?")))]
        if s.get("per_pixel_metrics_referred"):
            facts.append(("per-pixel metrics", esc(s["per_pixel_metrics_referred"]) + "-referred"))
        for r in [r for r in s.get("references") or [] if not r.get("frames")]:
            g = stat(r.get("gpu_ms"))
            cost = f", {fmt(g)} GPU ms/frame" if g is not None else ""
            floor = r.get("floor") or {}
            shown = [m for m in ("deltaE2000", "flip", "temporal_error_mc", "flicker_excess", "temporal_lag")
                     if isinstance(floor.get(m), (int, float))]
            floor_text = ("; its noise floor (half its halves' difference): " + ", ".join(
                f"{esc(label_of(m))} {fmt(floor[m])}" for m in shown)) if shown else ""
            facts.append((f"reference “{esc(r.get('name'))}”",
                          f"{esc(r.get('spp'))} samples per pixel (stratified, box filter){cost}; "
                          f"{esc(r.get('frames_rendered', 0))} frames rendered, "
                          f"{esc(r.get('frames_cached', 0))} from the cache" + floor_text))
        if s.get("command") == "measure":  # frames read from files (`glintlab measure`)
            me = s.get("motion_explained") or {}
            explained = ""
            if isinstance(me.get("mean"), (int, float)):
                explained = (f"; they explain the reference's change to {fmt(me['mean'])} of no motion (negated "
                             f"{fmt(me.get('negated'))}, y flipped {fmt(me.get('flip_y'))}, x flipped "
                             f"{fmt(me.get('flip_x'))}; lower is better)")
            facts.append(("motion vectors", f"<b>{esc(s.get('motion', '?'))}</b>: {esc(s.get('motion_source', ''))}"
                          + (f", convention {esc(s['motion_convention'])}" if s.get("motion_convention") else "")
                          + explained))
            facts.append(("disocclusion", esc(s.get("disocclusion", "?"))))
            for r in s.get("references") or []:
                if r.get("frames"):
                    facts.append((f"reference “{esc(r.get('name'))}”", f"frames read from {esc(r['frames'])}"))
        if stat(s.get("metric_ms_per_frame")) is not None:
            facts.append(("measuring", f"{fmt(stat(s['metric_ms_per_frame']))} ms per variant frame (CPU)"))
        facts.append(("run directory", esc(os.path.abspath(self.run_dir))))
        facts.append(("report written", datetime.datetime.now().strftime("%Y-%m-%d %H:%M")))
        # Defects first: a reader must not miss them.
        notes = [f"<p class=warn><b>Warning:</b> {esc(w)}</p>" for w in s.get("warnings") or []]
        if s.get("motion") == "estimated":
            notes.append("<p class=note>No motion vectors were given: flicker is measured along optical flow "
                         "<b>estimated</b> from the frames (OpenCV DIS), which is wrong where the frames change for "
                         "other reasons than motion (glints); give the renderer's vectors where it has them.</p>")
        for v in variants:
            bad = [(k, self.metric_stat(v, k, "max")) for k in ("nonfinite_pixels", "negative_pixels")]
            bad = [(k, x) for k, x in bad if x]
            if bad:
                notes.append(f"<p class=warn><b>{esc(v['name'])}</b> has defective pixels: " + ", ".join(
                    f"up to {fmt(x)} {esc(label_of(k))} per frame" for k, x in bad) + " (see frames.csv).</p>")
        if not self.measured:
            notes.append("<p class=note>This run was not measured (<code>glintlab render</code>, or no reference): "
                         "the report shows timings and images only. <code>glintlab run</code> measures every frame "
                         "against the reference.</p>")
        glance = []
        for metric, best, front, tied in self.glance:
            cheapest = front[0] if front else None
            extra = ""
            if metric == "temporal_error_mc":
                bv = next(v for v in self.variants if v["name"] == best[2])
                extra = (f"; flicker excess {fmt(self.metric_stat(bv, 'flicker_excess'))}, lag "
                         f"{fmt(self.metric_stat(bv, 'temporal_lag'))}")
            g = (f"<li><b>{esc(label_of(metric))}</b>: {esc(best[2])} is best ({fmt(best[3])}"
                 f"{' ratio' if metric == 'flicker_ratio' else ''}{extra}, {fmt(best[0])} ms/frame)")
            if tied:
                g += (f"; within the truth's noise floor ({fmt(self.floor_of(best[2], metric))}) of it, so as good "
                      f"as far as this truth can tell: {esc(', '.join(tied))}")
            if cheapest and cheapest[2] != best[2]:
                g += (f"; the cheapest Pareto-optimal variant is {esc(cheapest[2])} ({fmt(cheapest[3])} at "
                      f"{fmt(cheapest[0])} ms/frame)")
            glance.append(g + ".</li>")
        nav = "<nav>" + "".join(f"<a href=#{i}>{t}</a>" for i, t in self.sections) + "</nav>"
        return (f"<h1>{esc(title)} <small>glintlab report</small></h1>"
                + (f"<p class=lede>{esc(description)}</p>" if description else
                   (f"<p class=lede>{len(variants)} sequence(s) read from files, measured "
                    + ("against a reference" if s.get("references") else "without a reference") + ".</p>"
                    if s.get("command") == "measure" else
                    f"<p class=lede>{len(variants)} anti-aliasing variants against the ground truth.</p>"))
                + "<dl class=facts>" + "".join(f"<dt>{k}</dt><dd>{v}</dd>" for k, v in facts) + "</dl>"
                + "".join(notes)
                + (f"<h3>At a glance</h3><ul>{''.join(glance)}</ul>" if glance else "")
                + nav)

    def title(self):
        return self.summary.get("experiment") or os.path.basename(os.path.abspath(self.run_dir))

    # ------------------------------------------------------------ error against cost
    def pareto(self):
        s = self.summary
        head = "<h2 id=pareto>Error against cost</h2>"
        if not self.measured:
            return head + "<p class=muted>No error metrics in this run.</p>"
        avail = [m for m in PARETO_METRICS if pareto_points(s, m)]
        if not avail and s.get("command") == "measure":
            return head + ("<p class=muted>The variants are frames read from files: they have no render cost "
                           "here, so there is no error against cost (see the table and the per-frame curves).</p>")
        if not avail:
            return head + "<p class=muted>None of ΔE00, FLIP and temporal error was measured in this run.</p>"
        fig, axes = plt.subplots(1, len(avail), figsize=(3.7 * len(avail) + 0.4, 3.6), squeeze=False)
        fronts = {}
        for ax, metric in zip(axes[0], avail):
            fronts[metric] = draw_pareto(ax, s, metric, self.colors, self.markers, len(self.variants) <= 12)
        ncol = min(len(self.variants) + 1, 6)
        fig.legend(handles=legend_handles(s, self.colors, self.markers), loc="lower center", ncol=ncol,
                   frameon=False, bbox_to_anchor=(0.5, 0.0))
        nrows_leg = math.ceil((len(self.variants) + 1) / ncol)
        fig.tight_layout(rect=(0, 0.06 + 0.045 * nrows_leg, 1, 1))
        svg = self.figs.save(fig, "pareto", "Error against GPU cost with Pareto fronts")
        for metric in avail:  # one panel per file as well, for papers
            f1, ax = plt.subplots(figsize=(4.6, 3.6))
            draw_pareto(ax, s, metric, self.colors, self.markers, True)
            f1.tight_layout()
            self.figs.save(f1, f"pareto_{metric}", f"{label_of(metric)} against GPU cost", inline=False)
        items = []
        for metric in avail:
            pts, front = fronts[metric]
            by = {p[2]: p for p in pts}
            best = min(pts, key=lambda p: p[1])
            val = fmt(best[3]) + (f" (|ln| = {fmt(best[1])})" if metric in RATIO_METRICS else "")
            if metric == "temporal_error_mc":
                bv = next(v for v in s["variants"] if v["name"] == best[2])
                val += (f" (flicker excess {fmt(self.metric_stat(bv, 'flicker_excess'))}, lag "
                        f"{fmt(self.metric_stat(bv, 'temporal_lag'))})")
            items.append(f"<li><b>{esc(label_of(metric))}</b>: best {esc(best[2])} at {val}, "
                         f"{fmt(best[0])} GPU ms/frame. Pareto-optimal, cheapest first: "
                         + ", ".join(f"{esc(p[2])} ({fmt(by[p[2]][3])} at {fmt(p[0])} ms)" for p in front) + ".</li>")
            self.glance.append((metric, best, [by[p[2]] for p in front], self.within_floor(pts, best, metric)))
        return (head
                + "<p>Each point is one variant: x is its mean GPU time per frame (all passes, GPU timestamps), y its "
                "mean error against the reference over all frames. A variant is <i>Pareto-optimal</i> (ringed, joined "
                "by the dashed line) when no other variant is both cheaper and better. Temporal stability is ranked "
                "by the <b>temporal error along the motion</b> (the change that does not match the truth's); the "
                "at-a-glance list gives the best variant's flicker excess (change beyond the truth's: twinkling) and "
                "lag (the truth's change it lacks: smooth but wrong) beside it. The flicker ratio stays in the table "
                "as a diagnostic: it ranks lag as if it were flicker.</p>"
                f"<figure>{svg}<figcaption>Error against GPU cost. Markers: ● no AA, ■ SSAA, ▲ TAA. The x axis is "
                "logarithmic when the costs span more than 8×. Single panels: "
                "<code>figures/pareto_&lt;metric&gt;.svg|pdf</code>.</figcaption></figure>"
                f"<ul>{''.join(items)}</ul>")

    # ------------------------------------------------------------ per-frame curves
    def curves(self):
        frames, variants = self.frames, self.variants
        metrics = [m for m in CURVE_METRICS if any(r.get(m) is not None for rows in frames.values() for r in rows)]
        if not metrics:
            return ""
        fig, axes = plt.subplots(len(metrics), 1, figsize=(9.0, 2.7 * len(metrics) + 0.3), sharex=True,
                                 squeeze=False)
        nframes = max(len(rows) for rows in frames.values())
        for ax, metric in zip(axes[:, 0], metrics):
            for v in variants:
                pts = [(r["frame"], r[metric]) for r in frames.get(v["name"], [])
                       if r.get(metric) is not None and math.isfinite(r[metric])]
                if pts:
                    ax.plot([p[0] for p in pts], [p[1] for p in pts], lw=1.4, ms=4, color=self.colors[v["name"]],
                            marker=self.markers[v["name"]] if nframes <= 40 else None, label=v["name"])
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
        svg = self.figs.save(fig, "per_frame", "Per-frame flicker ratio and ΔE00")
        return ("<h2 id=curves>Per frame</h2>"
                "<p>The same metrics frame by frame. Flicker ratio compares consecutive frames, so it starts at frame "
                "1; the dotted line at 1 is the reference's own amount of change. Spikes are frames where a variant "
                "changes much more than the truth (a glint popping in or out); a TAA variant that starts high and "
                "settles shows its history converging.</p>"
                f"<figure>{svg}<figcaption>Per-frame values from <code>frames.csv</code>.</figcaption></figure>")

    # ------------------------------------------------------------ table of means
    def table(self):
        variants, units = self.variants, self.units
        passes = []
        for v in variants:
            for p in (v.get("gpu_ms_per_pass") or {}):
                if p not in passes:
                    passes.append(p)
        present = [m for m in TABLE_METRICS if any(m in (v.get("metrics") or {}) for v in variants)]
        # Defect counts only when there is a defect; they are 0 otherwise.
        present = [m for m in present if m not in ("nonfinite_pixels", "negative_pixels")
                   or any(self.metric_stat(v, m, "max") for v in variants)]
        cols = [("gpu", "GPU ms/frame", units.get("gpu_ms", "ms (GPU timestamps)"), "min")]
        cols += [("pass:" + p, f"GPU ms: {p}", units.get("gpu_ms_" + p, "ms (GPU timestamps)"), "min") for p in passes]
        cols += [("metric:" + m, label_of(m), units.get(m, ""), METRICS.get(m, ("", "min"))[1]) for m in present]

        def cell(v, key):
            if key == "gpu":
                d = v.get("gpu_ms")
            elif key.startswith("pass:"):
                d = (v.get("gpu_ms_per_pass") or {}).get(key[5:])
            else:
                d = (v.get("metrics") or {}).get(key[7:])
            return stat(d), stat(d, "p95")

        best, tied = {}, {}
        for key, _, _, direction in cols:
            vals = [(cell(v, key)[0], v) for v in variants]
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
        head = ("<tr><th>variant</th><th>AA<span class=unit>method</span></th><th>spp<span class=unit>samples per "
                "pixel</span></th>" + "".join(f"<th>{esc(lab)}<span class=unit>{esc(u)}</span></th>"
                                              for _, lab, u, _ in cols) + "</tr>")
        body = []
        for v in variants:
            symbol = {"none": "●", "ssaa": "■", "taa": "▲"}.get(v.get("aa"), "◆")
            cells = [f"<td><span style='color:{matplotlib.colors.to_hex(self.colors[v['name']])}'>{symbol}</span> "
                     f"{esc(v['name'])}</td>", f"<td>{esc(v.get('aa', ''))}</td>", f"<td>{esc(v.get('spp', ''))}</td>"]
            for key, _, _, _ in cols:
                mean, p95 = cell(v, key)
                cls = (" class=best" if v["name"] in best.get(key, ()) else
                       " class=tied" if v["name"] in tied.get(key, ()) else "")
                floor = self.floor_of(v["name"], key[7:]) if key.startswith("metric:") else None
                floor_text = f" · floor {fmt(floor)}" if floor is not None else ""
                sub = (f"<span class=sub>p95 {fmt(p95)}{floor_text}</span>" if p95 is not None and mean is not None
                       else "")
                cells.append(f"<td{cls}>{fmt(mean)}{sub}</td>")
            body.append("<tr>" + "".join(cells) + "</tr>")
        return ("<h2 id=table>Means per variant</h2>"
                "<p>Mean over frames, with the 95th percentile over frames in small print. GPU times leave out the "
                "warm-up frames; temporal metrics start at frame 1. <b class=bestkey>Bold green</b> marks the best "
                "value of a column (flicker ratio: closest to 1; glint density: closest to the reference's; PSNR: "
                "highest; otherwise lowest); <i class=tiedkey>green italics</i> a value within the noise floor of its truth "
                "(printed beside each figure: half the difference of the truth's two halves) of the best one, as "
                "good as far as that truth can tell. Units under each heading; <a href=#glossary>what each metric "
                "means</a>.</p>"
                f"<div class=tablewrap><table><thead>{head}</thead><tbody>{''.join(body)}</tbody></table></div>"
                + self.settings() + self.gpu_passes(passes))

    def settings(self):
        variants = self.variants

        def opt_text(k, x):
            x = json.dumps(x) if isinstance(x, bool) else (fmt(x) if isinstance(x, float) else x)
            return f"{esc(k)} = {esc(x)}"

        taa = [v for v in variants if isinstance(v.get("taa"), dict)]
        shared = {}
        if len(taa) > 1:
            shared = {k: x for k, x in taa[0]["taa"].items() if all(v["taa"].get(k, object()) == x for v in taa)}
        items = []
        models = {v.get("glint_model") for v in variants}
        for v in variants:
            if isinstance(v.get("taa"), dict):
                own = {k: x for k, x in v["taa"].items() if k not in shared}
                text = "TAA, " + (", ".join(opt_text(k, x) for k, x in own.items()) if own else "the shared options")
            elif v.get("aa") == "ssaa":
                g = v.get("ssaa_grid", "?")
                text = f"SSAA, {esc(g)}×{esc(g)} stratified jittered samples per pixel, the same pattern every frame"
            elif v.get("aa") == "none":
                text = "no AA, one sample at each pixel centre"
            elif v.get("source") == "frames":
                text = f"frames read from <code>{esc(v.get('frames', '?'))}</code>"
            else:
                text = esc(v.get("aa", "?"))
            params = v.get("glint_parameters") or {}
            if len(models) > 1 or params:
                text += f"; glint model {esc(v.get('glint_model'))}"
                if params:  # the model's own parameters, as its declaration names them
                    text += " (" + ", ".join(f"{esc(k)} = {esc(x)}" for k, x in params.items()) + ")"
            if v.get("debug") not in (None, "final"):
                text += f"; debug output {esc(v.get('debug'))}"
            items.append(f"<li><b>{esc(v['name'])}</b>: {text}</li>")
        return ("<h3>Variant settings</h3><ul>" + "".join(items) + "</ul>"
                + (f"<p class=muted>Shared by all TAA variants: {', '.join(opt_text(k, x) for k, x in shared.items())}."
                   "</p>" if shared else ""))

    def gpu_passes(self, passes):
        variants = self.variants
        if not passes or all(stat(v.get("gpu_ms")) is None for v in variants):
            return ""
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
        ax.set_yticklabels(self.names)
        ax.invert_yaxis()
        ax.set_xlabel("GPU ms / frame (mean per pass)")
        ax.set_xlim(0, max(float(left.max()), 1e-9) * 1.18)
        ax.grid(axis="y", visible=False)
        ax.legend(loc="lower right", bbox_to_anchor=(1.0, 1.0), frameon=False, ncol=len(passes), title="pass",
                  title_fontsize=8)
        fig.tight_layout()
        return (f"<figure>{self.figs.save(fig, 'gpu_per_pass', 'GPU time per pass')}"
                "<figcaption>GPU time per frame split by render pass (mean over frames; the number is the whole "
                "frame's mean, which need not equal the sum of the pass means exactly).</figcaption></figure>")

    # ------------------------------------------------------------ glossary and files
    def glossary(self):
        units, present = self.units, set()
        for v in self.variants:
            present.update((v.get("metrics") or {}).keys())
        items = []
        for m in TABLE_METRICS + ["relative", "frame_diff_ratio"]:
            if m in present:
                u = units.get(m, "")
                items.append(f"<dt>{esc(label_of(m))} <code>{esc(m)}</code></dt><dd>{esc(METRICS[m][2])}"
                             + (f"<br><span class=unit>unit: {esc(u)}</span>" if u else "") + "</dd>")
        pooled = sorted({int(k.rsplit("_", 1)[1]) for k in present
                         if k.startswith(("pooled_bias_", "pooled_rms_")) and k.rsplit("_", 1)[1].isdigit()})
        if pooled:
            items.append("<dt>pooled bias and RMS <code>pooled_bias_N</code>, <code>pooled_rms_N</code></dt><dd>Mean "
                         "and RMS of the difference of N×N-pixel block means of luminance, for N = "
                         + ", ".join(map(str, pooled)) + ": how the error falls as the image is averaged "
                         "over larger blocks (pooled error is the RMS at 8).<br><span class=unit>unit: "
                         f"{esc(units.get('pooled_rms_%d' % pooled[0], 'Y (block means)'))}</span></dd>")
        others = sorted(k for k in present if k not in METRICS and not k.endswith("_max")
                        and not k.startswith(("pooled_bias_", "pooled_rms_")))
        if others:
            items.append("<dt>also in summary.json and frames.csv</dt><dd>" + ", ".join(
                f"<code>{esc(k)}</code>" + (f" <span class=unit>({esc(units[k])})</span>" if units.get(k) else "")
                for k in others) + "</dd>")
        if any(k.endswith("_max") for k in present):
            items.append("<dt><code>&lt;metric&gt;_max</code></dt><dd>The worst pixel of each frame for that metric "
                         "(its mean over frames in summary.json).</dd>")
        items.append("<dt>GPU ms/frame <code>gpu_ms</code></dt><dd>GPU time of one frame from timestamp queries, "
                     "all passes; per pass in <code>gpu_ms_&lt;pass&gt;</code>. Device: "
                     f"{esc(self.summary.get('device', '?'))}. Compare variants within one run: timings drift "
                     "between runs, above all on a software rasteriser.<br><span class=unit>unit: "
                     f"{esc(units.get('gpu_ms', 'ms'))}</span></dd>")
        return ("<h2 id=glossary>Metrics</h2><dl class=glossary>" + "".join(items) + "</dl>"
                "<p class=muted>Per-pixel colour metrics compare test and reference through OCIO in CIE XYZ "
                f"({esc(self.summary.get('per_pixel_metrics_referred', 'scene'))}-referred); flicker, temporal, glint "
                "and pooled statistics are scene-referred. Units are those summary.json lists.</p>")

    def files(self):
        items = "".join(f"<li>{esc(t)}: " + ", ".join(f"<a href='{esc(p)}'>{esc(p)}</a>" for p in ps) + "</li>"
                        for t, ps in self.figs.files)
        return ("<h2 id=files>Files</h2><p>Beside this report in the run directory (the links work while the "
                "directory stays together; this page itself needs none of them):</p>"
                "<ul class=files><li>data: <a href='summary.json'>summary.json</a>, <a href='frames.csv'>frames.csv"
                f"</a></li>{items}</ul>")

    # ------------------------------------------------------------ the page
    def write(self):
        # The crops and sequences (image work in Pillow) run in a forked process while this one draws
        # the plots (matplotlib): on two cores the report takes the longer of the two, not the sum.
        crops = start_crops(self)
        plots = [self.pareto(), self.curves(), self.table()]
        crops_html, crops_files = crops()
        for title, paths in crops_files:
            for rel in paths:
                self.figs.add_file(title, rel)
        body = plots + [crops_html, self.glossary(), self.files()]
        text = "".join(body)
        self.sections = [(i, t) for i, t in (("pareto", "error vs cost"), ("curves", "per frame"), ("table", "table"),
                                             ("crops", "glint crops"), ("sequences", "sequences"),
                                             ("glossary", "metrics"), ("files", "files")) if f"<h2 id={i}>" in text]
        s = self.summary
        doc = ("<!DOCTYPE html><html lang=en><head><meta charset=utf-8>"
               "<meta name=viewport content='width=device-width, initial-scale=1'>"
               f"<title>{esc(self.title())}: glintlab report</title><style>{CSS}</style></head><body><main>"
               + self.header() + text
               + f"<footer>glintlab {esc(s.get('glintlab_version', '?'))} · {esc(s.get('schema'))} · written by "
                 f"experiments/report/glintlab_report.py with matplotlib {esc(matplotlib.__version__)} and Pillow "
                 f"{esc(getattr(__import__('PIL'), '__version__', '?'))}</footer></main></body></html>\n")
        out = os.path.join(self.run_dir, "report.html")
        write_bytes(out, doc.encode("utf-8"))
        return out


# ------------------------------------------------------------------ crops and sequences
MAX_ANIMATION_FRAMES = 120
MAX_ANIMATION_PIXELS = 1_600_000  # per animation frame


def crops_in_child(rep):
    """crops_section in a forked child: its HTML and the files it listed."""
    rep.figs.files = []
    html_ = crops_section(rep)
    return html_, rep.figs.files


def start_crops(rep):
    """Starts crops_section(rep) in a forked process and returns a function that waits for it and
    gives (html, [(title, [paths])]); where no process can be forked, it runs here when asked. An
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


def crops_section(rep):
    run_dir, summary, frames, figs = rep.run_dir, rep.summary, rep.frames, rep.figs
    variants = rep.variants
    # Rows shown: each reference once (first), then the variants in run order.
    rows = []
    for r in summary.get("references") or []:
        if isinstance(r.get("name"), str):
            rows.append((r["name"], "reference", r))
    for v in variants:
        rows.append((v["name"], "variant", v))
    pngs = {name: png_frames(run_dir, name) for name, _, _ in rows}
    rows = [r for r in rows if pngs[r[0]]]
    if not rows:
        msg = ("<p class=note>No PNG previews in this run directory (the experiment's <code>output.png</code> is "
               "false), so there are no crops or sequences. <code>\"output\": {\"png\": true}</code> writes them."
               "</p>")
        return "<h2 id=crops>Glint crops</h2>" + msg
    common = sorted(set.intersection(*[set(pngs[n]) for n, _, _ in rows])) or sorted(pngs[rows[0][0]])
    region_source = rows[0][0]
    # The region is chosen on at most 16 frames spread over the sequence.
    sel = sorted({round(i * (len(common) - 1) / 15) for i in range(16)}) if len(common) > 16 else \
        list(range(len(common)))
    h, w = load_rgb(pngs[region_source][common[0]]).shape[:2]
    src, src_frames = [], []
    for i in sel:
        a = load_rgb(pngs[region_source][common[i]])
        if a.shape[:2] == (h, w):
            src.append(a)
            src_frames.append(common[i])
    side = int(min(64, max(8, min(w, h) // 4)))
    cw, ch = min(side, w), min(side, h)
    x0, y0, how, per_frame, total = choose_region(src, cw, ch)
    crop_frame = src_frames[int(np.argmax(per_frame))] if max(per_frame) > 0 else src_frames[len(src_frames) // 2]
    scale = int(max(2, min(16, 256 // max(cw, ch))))

    def load(name, frame):
        p = pngs[name].get(frame)
        if p is None:
            return None
        a = load_rgb(p)
        return a if a.shape[:2] == (h, w) else None

    def crop(a, s):
        if a is None:
            return np.zeros((ch * s, cw * s, 3), np.uint8)
        return upscale(a[y0:y0 + ch, x0:x0 + cw], s)

    def csv_value(name, frame, metric):
        for r in frames.get(name, []):
            if r["frame"] == frame:
                return r.get(metric)
        return None

    # Where the region is, on the frame the crops show.
    ov = Image.fromarray(load_rgb(pngs[region_source][crop_frame]))
    ov_scale = max(1, 480 // ov.width)
    if ov_scale > 1:
        ov = ov.resize((ov.width * ov_scale, ov.height * ov_scale), Image.NEAREST)
    d = ImageDraw.Draw(ov)
    lw = max(2, ov_scale)
    for i in range(lw):
        d.rectangle([x0 * ov_scale - lw + i, y0 * ov_scale - lw + i, (x0 + cw) * ov_scale + lw - 1 - i,
                     (y0 + ch) * ov_scale + lw - 1 - i], outline=(230, 40, 40) if i < lw - 1 else (255, 255, 255))
    ov_png = encode_png(ov)
    write_bytes(os.path.join(figs.dir, "glint_region.png"), ov_png)
    figs.add_file("Glint region on the reference frame", "figures/glint_region.png")

    tiles, labels, figures_html = [], [], []
    for name, kind, obj in rows:
        t = crop(load(name, crop_frame), scale)
        tiles.append(t)
        if kind == "reference":
            if obj.get("frames"):
                cap = f"<b>{esc(name)}</b><br>read from files, the reference"
                labels.append(f"{name} (files)")
            else:
                cap = f"<b>{esc(name)}</b><br>{esc(obj.get('spp'))} spp, the ground truth"
                labels.append(f"{name} ({obj.get('spp')} spp)")
        else:
            de = csv_value(name, crop_frame, "deltaE2000")
            fl = rep.metric_stat(obj, "flicker_ratio")
            bits = (["read from files"] if obj.get("source") == "frames"
                    else [f"{esc(obj.get('aa'))}, {esc(obj.get('spp'))} spp"])
            if de is not None:
                bits.append(f"ΔE00 {fmt(de)} (whole frame)")
            if fl is not None:
                bits.append(f"flicker ratio {fmt(fl)} (run mean)")
            cap = f"<b>{esc(name)}</b><br>" + "<br>".join(bits)
            labels.append(name)
        png = encode_png(Image.fromarray(t))
        figures_html.append(f"<figure><img src='{data_uri('image/png', png)}' width={t.shape[1]} "
                            f"height={t.shape[0]} alt='{esc(name)} crop'><figcaption>{cap}</figcaption></figure>")
    font = load_font(12)
    label_h = 17
    cols = min(len(tiles), max(1, 1400 // (tiles[0].shape[1] + 2)), 6)
    write_bytes(os.path.join(figs.dir, "glint_crops.png"), encode_png(tile_grid(tiles, labels, cols, label_h, font)))
    figs.add_file("Glint crops (one frame, labelled)", "figures/glint_crops.png")

    how_text = (f"the {cw}×{ch}-pixel window where the {esc(region_source)} frames have the most bright outliers "
                "against their local level (pixels brighter than the median of their 7×7 neighbourhood by at least "
                f"{OUTLIER_MIN_EXCESS:g} in display-encoded luma and among the frame's "
                f"{100 * OUTLIER_TOP_FRACTION:g} % that exceed it most: {fmt(total)} over {len(src)} frames)"
                if how == "outliers" else
                f"the {cw}×{ch}-pixel window of highest luminance contrast in the {esc(region_source)} frames (they "
                "have no bright outliers)")
    html_ = [
        "<h2 id=crops>Glint crops</h2>"
        f"<p>One region, chosen automatically as {how_text}, shown at frame {crop_frame} (the frame with most "
        f"outliers in it) and enlarged {scale}× with nearest neighbour so every pixel is a visible square. "
        "The images are the run's PNG previews, display-encoded through its OCIO view. Compare how many glints "
        "each variant keeps, how bright and how large they are, against the reference.</p>"
        f"<figure><img class=frame src='{data_uri('image/png', ov_png)}' width={ov.width} height={ov.height} "
        f"alt='the region on the reference frame'><figcaption>The region (red) on the {esc(region_source)} frame "
        f"{crop_frame}: x = {x0}…{x0 + cw - 1}, y = {y0}…{y0 + ch - 1}.</figcaption></figure>"
        f"<div class=crops>{''.join(figures_html)}</div>",
        "<h2 id=sequences>Sequences</h2>"]
    if len(common) < 2:
        html_.append("<p class=note>Only one saved frame: nothing to animate (<code>output.every</code> or "
                     "<code>--frames</code> left one).</p>")
        return "".join(html_)

    # ---------------------------------------------------------------- sequences
    seq = common
    step = math.ceil(len(seq) / MAX_ANIMATION_FRAMES)
    seq = seq[::step]
    times = [r.get("time_s") for r in frames.get(variants[0]["name"], [])] if variants else []
    times = [t for t in times if t is not None]
    dts = sorted(b - a for a, b in zip(times, times[1:]) if b > a)
    path_fps = round(1.0 / dts[len(dts) // 2], 2) if dts else 30.0
    saved_step = max(1, (common[1] - common[0]) if len(common) > 1 else 1) * step
    duration = max(100, int(round(1000.0 * saved_step / path_fps)))  # at most 10 images per second
    play_fps = 1000.0 / duration
    n = len(rows)
    a_scale = scale
    while a_scale > 1 and n * (cw * a_scale) * (ch * a_scale) > MAX_ANIMATION_PIXELS:
        a_scale -= 1
    # Whole frames: shrunk (box filter) to at most 320 px wide, or enlarged
    # (nearest) when tiny; smaller still when there are many rows.
    if w > 320:
        f_div = math.ceil(w / 320)
        while n * (w // f_div) * (h // f_div) > MAX_ANIMATION_PIXELS:
            f_div += 1
        fw, fh = w // f_div, h // f_div
        f_note = f"shrunk {f_div}× (box filter: averaging hides some single-pixel flicker; the crops do not)"
    else:
        f_mul = max(1, 320 // w)
        while f_mul > 1 and n * (w * f_mul) * (h * f_mul) > MAX_ANIMATION_PIXELS:
            f_mul -= 1
        fw, fh = w * f_mul, h * f_mul
        f_note = f"enlarged {f_mul}× (nearest neighbour)" if f_mul > 1 else "at full resolution"

    def whole(a):
        if a is None:
            return np.zeros((fh, fw, 3), np.uint8)
        im = Image.fromarray(a).resize((fw, fh), Image.BOX if fw < w else Image.NEAREST)
        t = np.asarray(im).copy()
        sx, sy = fw / w, fh / h
        rx0, ry0 = int(x0 * sx), int(y0 * sy)
        rx1, ry1 = min(fw - 1, int((x0 + cw) * sx)), min(fh - 1, int((y0 + ch) * sy))
        t[ry0, rx0:rx1 + 1] = t[ry1, rx0:rx1 + 1] = (230, 40, 40)
        t[ry0:ry1 + 1, rx0] = t[ry0:ry1 + 1, rx1] = (230, 40, 40)
        return t

    anim_crops, anim_whole = [], []
    fcols = min(n, 3)
    for f in seq:
        images = [load(name, f) for name, _, _ in rows]
        labs = [f"{labels[0]} · f{f}"] + labels[1:]
        anim_crops.append(tile_grid([crop(a, a_scale) for a in images], labs, cols, label_h, font))
        anim_whole.append(tile_grid([whole(a) for a in images], labs, fcols, label_h, font))
    webp = features.check("webp_anim")
    kind, mime = ("webp", "image/webp") if webp else ("gif", "image/gif")
    crops_data = encode_animation(anim_crops, duration, kind.upper(), lossless=True)
    whole_data = encode_animation(anim_whole, duration, kind.upper(), lossless=False)
    extra = {}
    for name, frames_, data in (("crops", anim_crops, crops_data), ("frames", anim_whole, whole_data)):
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
        extra[name] = (f"Also as {' and '.join(also)} under <code>figures/</code>" if also else "") + (
            f" (no MP4: {esc(err)})" if err else "") + "."
    span = (f"{len(common)} saved frames ({common[0]}…{common[-1]}" + (f"; every {step}th of them" if step > 1 else "")
            + ")")
    html_.append(
        f"<p>The {span} side by side, looping at {fmt(play_fps)} images per second (the camera path "
        f"runs at {fmt(path_fps)} frames per second; slowed so that single frames can be followed). Watch the "
        "reference for how much a glint <i>should</i> change: a variant that sparkles where the reference is steady "
        "flickers (flicker ratio above 1); one that stays smooth where the reference sparkles is blurred or lags "
        "(below 1).</p>"
        f"<h3>Glint region</h3><figure><img class=anim src='{data_uri(mime, crops_data)}' "
        f"width={anim_crops[0].width} height={anim_crops[0].height} alt='crop sequence'><figcaption>The crops above "
        f"over the sequence ({a_scale}× nearest neighbour). {extra['crops']}</figcaption></figure>"
        f"<h3>Whole frames</h3><figure><img class=anim src='{data_uri(mime, whole_data)}' "
        f"width={anim_whole[0].width} height={anim_whole[0].height} alt='whole-frame sequence'><figcaption>Whole "
        f"frames, {f_note}; the red box is the crop region. {extra['frames']}</figcaption></figure>")
    return "".join(html_)


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
