"""glintlab from Python: colour-managed image and sequence metrics, the experiment runner and the
regression gate, as the command line has them (the same C++ functions, in this process).

    read_image(path, layer=None)             -> float32 H x W x 3 (R, G, B of the file or layer)
    read_sequence(pattern, layer=None)       -> float32 T x H x W x 3 (SEQ as `glintlab measure`)
    compare(reference, test, metrics=None, space=None, **options)
                                             -> {metric: {"mean", "max", "p95", "map", ...}}
    flip(reference, test, mode="hdr", **parameters) -> (error_map, mean, parameters)
    measure(reference, tests, motion=None, convention="pixels", depth=None, metrics=None, fps=None,
            out=None)                        -> (summary, records)
    run(experiment, out=None, variants=None, frames=None, resolution=None) -> summary
    check(summary, baseline, tolerances=None) -> (passed, regressions)

Images are paths (anything OpenImageIO reads) or numpy arrays, H x W (grey) or H x W x C with C in
1 ... 4 (grey, grey + alpha, RGB, RGBA), sequences T x H x W [x C]. The array rule:
  - float32 is taken as it is (compare and flip read a C-contiguous array in place, without a copy;
    any other is made contiguous first); float64 and float16 are converted to float32 (nearest).
    Their values are scene-linear (the OCIO role scene_linear) unless `space` names another OCIO
    colour space.
  - uint8 are sRGB code values: v x (1/255 in float32, as OpenImageIO converts an 8-bit file) in the
    config's "sRGB" space (the IEC 61966-2-1 curve) unless `space` is given.
  - Any other dtype, and any other shape, raises ValueError.
Errors: bad input (an unknown metric or option, a size mismatch, a file that is not an image)
raises ValueError with the command line's message; a file that cannot be read or written for the
system's reason OSError; no usable Vulkan device (run) RuntimeError. The GIL is released while a
function reads, measures or renders, so threads run them at once. Messages the command line
prints on stderr (warnings, progress) go to sys.stderr.
"""

import csv
import json
import math
import os
import shutil
import sys
import tempfile

import numpy as np

from . import _core

__version__ = _core.__version__
__all__ = ["read_image", "read_sequence", "compare", "flip", "measure", "run", "check"]


def _say(text):
    if text:
        sys.stderr.write(text)


def _finish(code, log):
    """What the command prints, on sys.stderr; its exit codes (experiments/cli/exit_codes.h) raised with
    its "error: " lines: 2 (bad input) as ValueError, 3 (the Vulkan device) and 5 as RuntimeError, 4
    (I/O) as OSError."""
    errors = [line[len("error: "):] for line in log.splitlines() if line.startswith("error: ")]
    raising = {2: ValueError, 3: RuntimeError, 4: OSError, 5: RuntimeError}.get(code)
    if raising:
        raise raising("\n".join(errors) or log.strip())
    _say(log)


def _pixels(value, what, frames):
    """An array as float32 C-contiguous (T x) H x W x C and the colour space its values are in."""
    a = np.asarray(value)
    if a.dtype == np.uint8:
        space = "sRGB"
        a = a.astype(np.float32) * np.float32(1 / 255)  # as OpenImageIO converts an 8-bit file's values
    elif a.dtype in (np.float32, np.float64, np.float16):
        space = "scene_linear"
        a = np.ascontiguousarray(a, dtype=np.float32)
    else:
        raise ValueError(f"{what}: an array of dtype {a.dtype} is not allowed; allowed: float32, float64, "
                         "float16 (scene-linear) or uint8 (sRGB code values)")
    base = 3 if frames else 2
    if a.ndim == base:
        a = a[..., np.newaxis]
    shape = "T x H x W [x C]" if frames else "H x W [x C]"
    if a.ndim != base + 1 or not 1 <= a.shape[-1] <= 4 or min(a.shape[:-1]) < 1:
        raise ValueError(f"{what}: an array of shape {tuple(np.shape(value))} is not allowed; allowed: {shape} "
                         "with C in 1 ... 4 and every size at least 1")
    return np.ascontiguousarray(a), space


def _is_path(value):
    return isinstance(value, (str, bytes, os.PathLike))


# The compare options by kind: numbers (finite), whole numbers >= 1 (at most 2**31 - 1), names, a flag.
# A value of another kind is a ValueError naming the option and what it allows, as the command line's;
# NaN and 0 are refused, not read as "not given".
_NUMBER_OPTIONS = ("itp_nits", "threshold", "ppd", "monitor_distance", "monitor_width", "start_exposure",
                   "stop_exposure")
_COUNT_OPTIONS = ("monitor_width_pixels", "num_exposures")
_TEXT_OPTIONS = ("view", "tone_mapper", "ocio_config")


def _checked_option(what, key, value, shown=None):
    key_shown = shown or key
    if key in _NUMBER_OPTIONS:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ValueError(f"{what}: {key_shown}={value!r} is not allowed; allowed: a finite number")
        return float(value)
    if key in _COUNT_OPTIONS:
        if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= 2**31 - 1:
            raise ValueError(f"{what}: {key_shown}={value!r} is not allowed; allowed: a whole number >= 1")
        return value
    if key in _TEXT_OPTIONS:
        if not isinstance(value, str):
            raise ValueError(f"{what}: {key_shown}={value!r} is not allowed; allowed: a string")
        return value
    if not isinstance(value, bool):  # flip_ldr
        raise ValueError(f"{what}: {key_shown}={value!r} is not allowed; allowed: True or False")
    return value


# ---------------------------------------------------------------- images

def read_image(path, layer=None):
    """R, G and B of an image file (of `layer` of a multi-layer OpenEXR) as float32 H x W x 3, as
    `glintlab measure` reads a frame (grey is copied to all three)."""
    return _core.read_image(os.fsdecode(path), layer or "")


def read_sequence(pattern, layer=None):
    """The frames of a SEQ (a folder of numbered frames, a pattern with %04d or ####, optionally
    :LAYER; experiments/sources/sequence.h) as float32 T x H x W x 3, in frame-number order."""
    frames, _numbers = _core.read_sequence(os.fsdecode(pattern), layer or "")
    return frames


_COMPARE_OPTIONS = ("itp_nits", "view", "threshold", "flip_ldr", "ppd", "monitor_distance", "monitor_width",
                    "monitor_width_pixels", "tone_mapper", "start_exposure", "stop_exposure", "num_exposures",
                    "ocio_config")


def _compare_input(value, name, space):
    if _is_path(value):
        return (os.fsdecode(value), None, "", 0)
    a, tag = _pixels(value, f"compare: {name}", frames=False)
    return (name, a, space or tag, a.shape[2])


def _comparison(reference, tests, metrics, space, options):
    unknown = sorted(set(options) - set(_COMPARE_OPTIONS))
    if unknown:
        raise ValueError(f"compare: unknown option '{unknown[0]}'; allowed: {', '.join(_COMPARE_OPTIONS)}")
    o = _core.CompareOptions()
    # A given space applies to files and arrays alike (--space); an array's own rule otherwise.
    o.space = space or ""
    if metrics is not None and not isinstance(metrics, str) and not (
            isinstance(metrics, (list, tuple)) and all(isinstance(m, str) for m in metrics)):
        raise ValueError(f"compare: metrics={metrics!r} is not allowed; allowed: a metric name or a list of names")
    o.metrics = [metrics] if isinstance(metrics, str) else list(metrics or [])
    for key, value in options.items():
        setattr(o, key, _checked_option("compare", key, value))
    names = ["test"] if len(tests) == 1 else [f"test {i + 1}" for i in range(len(tests))]
    ref = _compare_input(reference, "reference", space)
    text, maps, err, _code = _core.compare(ref, [_compare_input(t, n, space) for t, n in zip(tests, names)], o)
    _say(err)
    return json.loads(text), maps


def _metric_dicts(test_json, maps):
    out = {}
    for (name, values), m in zip(test_json["metrics"].items(), maps):
        out[name] = dict(values, map=m)
    return out


def compare(reference, test, metrics=None, space=None, **options):
    """The comparison of `glintlab compare`: per metric a dict with "mean", "max", "p95" (None where
    the JSON of `glintlab compare --json` has null), FLIP's pooled values for "flip", and "map", the
    per-pixel error as float32 H x W (NaN at NaN, Inf or negative input pixels; None for a metric
    without one). `test` may be a list: then a list of such dicts. metrics: a name or a list
    (default: every metric); space: the OCIO colour space of every input; options: itp_nits, view
    ("DISPLAY/VIEW"), threshold, flip_ldr, ppd, monitor_distance, monitor_width,
    monitor_width_pixels, tone_mapper, start_exposure, stop_exposure, num_exposures, ocio_config
    (the command's options of the same names)."""
    tests = list(test) if isinstance(test, (list, tuple)) else [test]
    result, maps = _comparison(reference, tests, metrics, space, options)
    if not isinstance(test, (list, tuple)):
        return _metric_dicts(result, maps[0])
    per_test = result["tests"] if len(tests) > 1 else [result]
    return [_metric_dicts(t, m) for t, m in zip(per_test, maps)]


# NVIDIA FLIP's `evaluate` parameter names -> the compare options.
_FLIP_PARAMETERS = {"ppd": "ppd", "startExposure": "start_exposure", "stopExposure": "stop_exposure",
                    "numExposures": "num_exposures", "tonemapper": "tone_mapper"}


def flip(reference, test, mode="hdr", parameters=None, space=None, **more):
    """FLIP as NVIDIA FLIP's `flip_evaluator.evaluate(reference, test, "HDR", parameters={...})`:
    returns (error_map float32 H x W, mean error, parameters used: ppd, startExposure, stopExposure,
    numExposures, tonemapper). mode: "hdr" or "ldr" (any case); the parameters by FLIP's names, as
    a dict or as keywords. The error map holds the FLIP values (no magma colour map)."""
    given = dict(parameters or {}, **more)
    unknown = sorted(set(given) - set(_FLIP_PARAMETERS))
    if unknown:
        raise ValueError(f"flip: unknown parameter '{unknown[0]}'; allowed: {', '.join(_FLIP_PARAMETERS)}")
    if str(mode).lower() not in ("hdr", "ldr"):
        raise ValueError(f"flip: mode '{mode}' is not allowed; allowed: hdr, ldr (any case)")
    options = {_FLIP_PARAMETERS[k]: _checked_option("flip", _FLIP_PARAMETERS[k], v, k) for k, v in given.items()}
    options["flip_ldr"] = str(mode).lower() == "ldr"
    result, maps = _comparison(reference, [test], ["flip"], space, options)
    mean = result["metrics"]["flip"]["mean"]
    settings = result["flip"]
    used = {"ppd": settings["ppd"]}
    if settings["mode"] == "hdr":
        used.update(startExposure=settings["start_exposure"], stopExposure=settings["stop_exposure"],
                     numExposures=settings["num_exposures"], tonemapper=settings["tone_mapper"])
    return maps[0][0], (math.nan if mean is None else mean), used


# ---------------------------------------------------------------- sequences

def _sequence(value, what, name, channel_names):
    """(SEQ, space, None) for a SEQ; ("", space, (array, name, channel names)) for an array, which the
    measurement reads in place as frames in memory, its channels named as a file's would be."""
    if _is_path(value):
        return os.fsdecode(value), "", None
    a, space = _pixels(value, what, frames=True)
    names = channel_names(a.shape[3])
    if names is None:
        raise ValueError(f"{what}: an array with {a.shape[3]} channels is not allowed here")
    return "", space, (a, name, names)


def _colour_names(c):
    return [["Y"], None, ["R", "G", "B"], ["R", "G", "B", "A"]][c - 1]


def _motion_names(c):  # the `pixels` convention: X, Y, or R, G and the distances B, A
    return {2: ["X", "Y"], 4: ["R", "G", "B", "A"]}.get(c)


def _depth_names(c):
    return ["Z"] if c == 1 else None


def _number(cell):
    if cell == "":
        return math.nan
    try:
        return float(cell)
    except ValueError:
        return cell


def _read_records(path):
    with open(path, newline="") as f:
        return [{k: _number(v) for k, v in row.items()} for row in csv.DictReader(f)]


def measure(reference, tests, motion=None, convention="pixels", depth=None, metrics=None, fps=None, out=None,
            view=None):
    """`glintlab measure`: the run's metrics for image sequences. reference: a SEQ, a T x H x W [x C]
    array or None (then each test's own flicker); tests: one SEQ or array, a list of them, or a dict
    name -> SEQ or array; motion: a SEQ or T x H x W x 2|4 array of vectors in `convention`
    (arrays: the `pixels` convention's X, Y or R, G and the distances B, A); depth: a SEQ or
    T x H x W array; metrics: names and groups as --metrics (a list or a comma-separated string);
    fps: frames per second (default 24); out: the run folder (None: a temporary folder, removed
    afterwards, and no report.html is written); view: "DISPLAY/VIEW" the previews and temporal_score
    show the frames through, as --view (default "sRGB/ACES 1.0 SDR-video"; "sRGB/Standard" for frames
    already display-referred). Arrays are read in place, never written to files:
    frame k of an array is the run's frame k (numbered from 0 where the reference, or the first test
    without one, is an array), and the journal knows an array by a hash of its values. Returns
    (summary as summary.json, per-frame records as frames.csv's rows: a list of dicts, numbers as
    floats, empty cells NaN)."""
    temporary = out is None
    folder = tempfile.mkdtemp(prefix="glintlab-measure-") if temporary else os.fspath(out)
    try:
        o = _core.MeasureOptions()
        o.out_dir = folder
        o.report = not temporary  # a report in a folder about to be removed is not written
        ref_array = motion_array = depth_array = None
        if reference is not None:
            o.reference, o.reference_space, ref_array = _sequence(reference, "measure: reference", "array reference",
                                                                  _colour_names)
        if isinstance(tests, dict):
            named = list(tests.items())
        else:
            given = tests if isinstance(tests, (list, tuple)) else [tests]
            arrays = sum(not _is_path(t) for t in given)
            named = [("" if _is_path(t) else ("test" if arrays == 1 else f"test{i + 1}"), t)
                     for i, t in enumerate(given)]
        sources, test_arrays = [], []
        for i, (name, value) in enumerate(named):
            s = _core.MeasureSource()
            s.name = name
            s.seq, s.space, array = _sequence(value, f"measure: test {name or i + 1}", f"array {name or i + 1}",
                                              _colour_names)
            sources.append(s)
            test_arrays.append(array)
        o.tests = sources
        if motion is not None:
            o.motion, _, motion_array = _sequence(motion, "measure: motion", "array motion", _motion_names)
        o.motion_convention = convention
        if depth is not None:
            o.depth, _, depth_array = _sequence(depth, "measure: depth", "array depth", _depth_names)
        if metrics is not None:
            o.metrics = metrics.split(",") if isinstance(metrics, str) else list(metrics)
        if fps is not None:
            o.fps = float(fps)
        if view is not None:
            parts = str(view).split("/")
            if len(parts) != 2 or not all(parts):
                raise ValueError(f"measure: view {view!r}: expected DISPLAY/VIEW, e.g. 'sRGB/Standard'")
            o.display, o.view = parts
        _finish(*_core.measure(o, ref_array, test_arrays, motion_array, depth_array))
        with open(os.path.join(folder, "summary.json")) as f:
            summary = json.load(f)
        return summary, _read_records(os.path.join(folder, "frames.csv"))
    finally:
        if temporary:
            shutil.rmtree(folder, ignore_errors=True)


def run(experiment, out=None, variants=None, frames=None, resolution=None):
    """`glintlab run`: renders and measures an experiment (a built-in name or a file) and returns its
    summary (summary.json). out: the run folder (default: results/<experiment name>, as the
    command); variants: names (a list or a comma-separated string); frames: only the first N;
    resolution: "WxH" or (W, H). Raises RuntimeError without a usable Vulkan device."""
    o = _core.RunOptions()
    o.experiment = os.fspath(experiment)
    o.out_dir = os.fspath(out) if out is not None else ""
    if variants is not None:
        o.variants = variants.split(",") if isinstance(variants, str) else list(variants)
    if frames is not None:
        if isinstance(frames, bool) or not isinstance(frames, int) or frames < 1:
            raise ValueError(f"--frames: {frames!r} is not allowed; allowed: a whole number >= 1")
        o.max_frames = frames
    if isinstance(resolution, (tuple, list)):
        resolution = "x".join(str(v) for v in resolution)
    code, log, folder = _core.run(o, resolution or "")
    _finish(code, log)
    with open(os.path.join(folder, "summary.json")) as f:
        return json.load(f)


def _json_numbers_fit(value, where):
    """ValueError naming the key of a number no summary holds: an integer beyond 64 bits (glintlab
    reads summary.json numbers as doubles and 64-bit integers)."""
    if isinstance(value, dict):
        for k, v in value.items():
            _json_numbers_fit(v, f"{where}.{k}")
    elif isinstance(value, (list, tuple)):
        for i, v in enumerate(value):
            _json_numbers_fit(v, f"{where}[{i}]")
    elif isinstance(value, int) and not isinstance(value, bool) and not -2**63 <= value < 2**64:
        raise ValueError(f"{where}: the integer {str(value)[:20]}... is not allowed; allowed: a number of 64 bits")


def _json_source(value, what):
    if isinstance(value, dict):
        _json_numbers_fit(value, what)
        try:
            return json.dumps(value, allow_nan=False), True
        except ValueError as e:
            raise ValueError(f"{what}: {e}") from None
    return os.fsdecode(value), False


def check(summary, baseline, tolerances=None):
    """`glintlab check`: (passed, regressions). summary and baseline: summary.json paths or their
    dicts; tolerances: {metric: allowed worsening} over the defaults (as --tolerance metric=x).
    regressions: the rows that failed, each {"variant", "metric", "baseline", "current", "change",
    "tolerance", "note"}."""
    tol = [f"{k}={float(v)!r}" for k, v in (tolerances or {}).items()]
    s, s_text = _json_source(summary, "summary")
    b, b_text = _json_source(baseline, "baseline")
    rows = _core.check(s, s_text, b, b_text, tol)
    regressions = [{k: r[k] for k in ("variant", "metric", "baseline", "current", "change", "tolerance", "note")}
                   for r in rows if r["regression"]]
    return not regressions, regressions
