"""`import glintlab` against the command line: compare, flip and measure give the CLI's numbers to
the bit on the same inputs (paths and arrays), each wrong input raises the documented exception,
and two threads measure at once. ctest runs it (python.api) with the build's module on PYTHONPATH
and the CLI in $GLINTLAB_CLI."""

import json
import math
import os
import subprocess
import sys
import threading

import numpy as np
import pytest

import glintlab

CLI = os.environ["GLINTLAB_CLI"]
DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data")
FLIP = os.path.join(DATA, "flip")
BLENDER = os.path.join(DATA, "blender")
HDR_REF, HDR_TEST = os.path.join(FLIP, "hdr_bimodal_ref.exr"), os.path.join(FLIP, "hdr_bimodal_test.exr")
LDR_REF, LDR_TEST = os.path.join(FLIP, "ldr_ref.png"), os.path.join(FLIP, "ldr_test_noise.png")
COMBINED = "ViewLayer.Combined"


def cli(*args, check=True):
    p = subprocess.run([CLI, *args], capture_output=True, text=True)
    if check and p.returncode not in (0, 1):
        raise AssertionError(f"glintlab {' '.join(args)}: exit {p.returncode}\n{p.stderr}")
    return p


def cli_compare(test, ref, *options):
    return json.loads(cli("compare", test, ref, "--json", *options).stdout)


def same(a, b):
    """Equal to the bit, NaN equal to NaN."""
    a, b = np.asarray(a, dtype=np.float32), np.asarray(b, dtype=np.float32)
    return a.shape == b.shape and np.array_equal(a.view(np.uint32), b.view(np.uint32))


def cli_map(tmp_path, test, ref, metric, *options):
    path = str(tmp_path / f"map-{metric}.exr")
    cli("compare", test, ref, "--metric", metric, "--map", path, *options)
    return glintlab.read_image(path)[..., 0]


def assert_metrics_equal(py, js):
    assert set(py) == set(js["metrics"])
    for name, values in js["metrics"].items():
        for key, v in values.items():
            assert py[name][key] == v, (name, key)  # the JSON's doubles, to the bit (None for null)


# ---------------------------------------------------------------- compare

@pytest.mark.parametrize("ref,test", [(HDR_REF, HDR_TEST), (LDR_REF, LDR_TEST)])
def test_compare_paths_equal_cli(tmp_path, ref, test):
    py = glintlab.compare(ref, test)
    js = cli_compare(test, ref)
    assert_metrics_equal(py, js)
    assert py["flip"]["p95"] is not None and py["flip"]["p95"] <= py["flip"]["max"]
    for metric in ("flip", "deltaE2000"):
        assert same(py[metric]["map"], cli_map(tmp_path, test, ref, metric)), metric


def test_compare_float_arrays_equal_cli_on_files(tmp_path):
    py = glintlab.compare(glintlab.read_image(HDR_REF), glintlab.read_image(HDR_TEST))
    assert_metrics_equal(py, cli_compare(HDR_TEST, HDR_REF))
    assert same(py["flip"]["map"], cli_map(tmp_path, HDR_TEST, HDR_REF, "flip"))


def test_compare_multilayer_arrays_equal_cli_on_files():
    ref = os.path.join(BLENDER, "ref", "frame_0001.exr")
    test = os.path.join(BLENDER, "spp1", "frame_0001.exr")
    py = glintlab.compare(glintlab.read_image(ref, COMBINED), glintlab.read_image(test, COMBINED), metrics=["flip"])
    assert_metrics_equal(py, cli_compare(test, ref, "--metric", "flip"))


def test_compare_and_flip_read_float32_arrays_in_place(tmp_path):
    # C-contiguous float32 arrays of 1, 3 and 4 channels reach the C++ side as the arrays themselves
    # (the addresses it read, through a test hook), and give the CLI's numbers on the files to the bit.
    ref, test = glintlab.read_image(HDR_REF), glintlab.read_image(HDR_TEST)
    js = cli_compare(HDR_TEST, HDR_REF)
    alpha = np.ones_like(ref[..., :1])
    grey = np.ascontiguousarray(ref[..., 1]), np.ascontiguousarray(test[..., 1])
    for r, t, equal_cli in [(ref, test, True),
                            (np.concatenate([ref, alpha], axis=2), np.concatenate([test, alpha], axis=2), True),
                            (grey[0][..., np.newaxis], grey[1][..., np.newaxis], False), (grey[0], grey[1], False)]:
        py = glintlab.compare(r, t)
        assert glintlab._core._last_compare_pixels() == [r.ctypes.data, t.ctypes.data]
        if equal_cli:
            assert_metrics_equal(py, js)
    grey_py = glintlab.compare(*grey)  # grey reads as R = G = B, as a 1-channel file does
    grey_as_rgb = glintlab.compare(*[np.repeat(g[..., np.newaxis], 3, axis=2) for g in grey])
    for m, values in grey_as_rgb.items():
        assert grey_py[m]["mean"] == values["mean"], m
        assert values["map"] is None or same(grey_py[m]["map"], values["map"]), m
    error_map, mean, _ = glintlab.flip(ref, test)
    assert glintlab._core._last_compare_pixels() == [ref.ctypes.data, test.ctypes.data]
    assert mean == js["metrics"]["flip"]["mean"] and same(error_map, cli_map(tmp_path, HDR_TEST, HDR_REF, "flip"))
    # A file is read by the C++ side (address 0); a non-contiguous array is made contiguous first.
    glintlab.compare(HDR_REF, test[:, ::-1], metrics="psnr")
    addresses = glintlab._core._last_compare_pixels()
    assert addresses[0] == 0 and addresses[1] not in (0, test.ctypes.data)


def test_compare_uint8_arrays_are_srgb_code_values():
    # The PNG's 8-bit values as a uint8 array give what the CLI gives for the file (tagged sRGB).
    png = np.round(glintlab.read_image(LDR_REF) * 255).astype(np.uint8)
    png_test = np.round(glintlab.read_image(LDR_TEST) * 255).astype(np.uint8)
    assert np.array_equal(png.astype(np.float32) * np.float32(1 / 255), glintlab.read_image(LDR_REF))
    assert_metrics_equal(glintlab.compare(png, png_test), cli_compare(LDR_TEST, LDR_REF))


def test_compare_conversions_float64_noncontiguous_grey():
    ref, test = glintlab.read_image(HDR_REF), glintlab.read_image(HDR_TEST)
    base = glintlab.compare(ref, test, metrics="deltaE2000")["deltaE2000"]
    as64 = glintlab.compare(ref.astype(np.float64), test.astype(np.float64), metrics="deltaE2000")["deltaE2000"]
    assert as64["mean"] == base["mean"] and same(as64["map"], base["map"])
    flipped = glintlab.compare(ref[:, ::-1], test[:, ::-1], metrics="deltaE2000")["deltaE2000"]
    assert same(flipped["map"][:, ::-1], base["map"])
    grey = glintlab.compare(ref[..., 1], test[..., 1], metrics="deltaE2000")["deltaE2000"]
    grey3 = glintlab.compare(np.repeat(ref[..., 1:2], 3, axis=2), np.repeat(test[..., 1:2], 3, axis=2),
                             metrics="deltaE2000")["deltaE2000"]
    assert grey["mean"] == grey3["mean"] and grey["mean"] != base["mean"]


def test_compare_several_tests_and_options():
    py = glintlab.compare(LDR_REF, [LDR_TEST, os.path.join(FLIP, "ldr_test_shift.png")], metrics=["flip"],
                          ppd=40.0, flip_ldr=True)
    js = json.loads(cli("compare", "-r", LDR_REF, "-t", LDR_TEST, os.path.join(FLIP, "ldr_test_shift.png"),
                        "--metric", "flip", "--ppd", "40", "--flip-ldr", "--json").stdout)
    assert len(py) == 2
    for p, j in zip(py, js["tests"]):
        assert_metrics_equal(p, j)
    assert py[0]["flip"]["mean"] != py[1]["flip"]["mean"]


# ---------------------------------------------------------------- flip

def test_flip_hdr_equals_cli():
    error_map, mean, parameters = glintlab.flip(HDR_REF, HDR_TEST, "HDR")
    js = cli_compare(HDR_TEST, HDR_REF, "--metric", "flip")
    assert mean == js["metrics"]["flip"]["mean"]
    assert parameters == {"ppd": js["flip"]["ppd"], "startExposure": js["flip"]["start_exposure"],
                          "stopExposure": js["flip"]["stop_exposure"], "numExposures": js["flip"]["num_exposures"],
                          "tonemapper": js["flip"]["tone_mapper"]}
    assert error_map.dtype == np.float32 and error_map.shape == (64, 96)
    assert float(np.mean(error_map, dtype=np.float64)) == pytest.approx(mean, rel=1e-6)


def test_flip_parameters_by_flips_names(tmp_path):
    error_map, mean, parameters = glintlab.flip(
        glintlab.read_image(HDR_REF), glintlab.read_image(HDR_TEST), "hdr",
        parameters={"tonemapper": "reinhard", "startExposure": -2.0, "stopExposure": 3.0, "numExposures": 4})
    js = cli_compare(HDR_TEST, HDR_REF, "--metric", "flip", "--tone-mapper", "reinhard", "--start-exposure", "-2",
                     "--stop-exposure", "3", "--num-exposures", "4")
    assert mean == js["metrics"]["flip"]["mean"]
    assert parameters["tonemapper"] == "reinhard" and parameters["numExposures"] == 4
    assert same(error_map, cli_map(tmp_path, HDR_TEST, HDR_REF, "flip", "--tone-mapper", "reinhard",
                                   "--start-exposure", "-2", "--stop-exposure", "3", "--num-exposures", "4"))


def test_flip_ldr_equals_cli():
    _, mean, parameters = glintlab.flip(LDR_REF, LDR_TEST, mode="LDR", ppd=30.0)
    js = cli_compare(LDR_TEST, LDR_REF, "--metric", "flip", "--flip-ldr", "--ppd", "30")
    assert mean == js["metrics"]["flip"]["mean"] and parameters == {"ppd": 30.0}


# ---------------------------------------------------------------- wrong input

def test_wrong_inputs_raise_documented_exceptions(tmp_path):
    ref = glintlab.read_image(HDR_REF)
    with pytest.raises(ValueError, match=r"unknown metric 'nope'; allowed: deltaE2000"):
        glintlab.compare(HDR_REF, HDR_TEST, metrics="nope")
    with pytest.raises(ValueError, match=r"image sizes differ: test 'test' is 48x64, reference 'reference' is 96x64"):
        glintlab.compare(ref, ref[:, :48])
    with pytest.raises(ValueError, match=r"shape \(64, 96, 5\) is not allowed; allowed: H x W \[x C\]"):
        glintlab.compare(ref, np.zeros((64, 96, 5), np.float32))
    with pytest.raises(ValueError, match=r"dtype int32 is not allowed; allowed: float32"):
        glintlab.compare(ref, np.zeros((64, 96, 3), np.int32))
    with pytest.raises(ValueError, match=r"unknown option 'gamma'; allowed: itp_nits"):
        glintlab.compare(ref, ref, gamma=2.2)
    with pytest.raises(ValueError, match=r"--threshold must be a number in \[0, 1\]"):
        glintlab.compare(ref, ref, threshold=2.0)
    with pytest.raises(ValueError, match=r"flip: unknown parameter 'vc'"):
        glintlab.flip(ref, ref, vc=[0.7, 0.7, 3840])
    with pytest.raises(ValueError, match=r"mode 'xdr' is not allowed"):
        glintlab.flip(ref, ref, "xdr")
    missing = str(tmp_path / "missing.exr")
    with pytest.raises(ValueError, match="missing.exr"):
        glintlab.compare(missing, HDR_TEST)
    assert cli("compare", HDR_TEST, missing, check=False).returncode == 2  # the CLI calls it bad input too
    with pytest.raises(ValueError, match=r"no colour channels NoSuchLayer.R, NoSuchLayer.G"):
        glintlab.read_image(os.path.join(BLENDER, "ref", "frame_0001.exr"), "NoSuchLayer")
    with pytest.raises(ValueError, match=r"--fps: 0 is not allowed"):
        glintlab.measure(None, os.path.join(BLENDER, "ref") + ":" + COMBINED, fps=0)
    with pytest.raises(ValueError, match=r"--motion-convention: 'sideways' is not known"):
        glintlab.measure(None, os.path.join(BLENDER, "ref") + ":" + COMBINED, convention="sideways")
    with pytest.raises(ValueError, match=r"shape \(2, 45, 80, 7\) is not allowed; allowed: T x H x W \[x C\]"):
        glintlab.measure(None, np.zeros((2, 45, 80, 7), np.float32))
    with pytest.raises(ValueError, match=r"--resolution: expected WxH with each in 1 ... 16384"):
        glintlab.run("regression", out=str(tmp_path / "run"), resolution=(0, 0))
    with pytest.raises(ValueError, match=r"--frames: 0 is not allowed"):
        glintlab.run("regression", out=str(tmp_path / "run"), frames=0)
    with pytest.raises(ValueError, match=r"no-such-experiment: no such experiment file"):
        glintlab.run("no-such-experiment", out=str(tmp_path / "run"))
    no_summary = str(tmp_path / "no-summary.json")
    with pytest.raises(ValueError, match="no-summary.json: cannot open file"):
        glintlab.check(no_summary, no_summary)
    assert cli("check", no_summary, no_summary, check=False).returncode == 2  # bad input for the CLI too
    with pytest.raises(OSError):  # a run folder that cannot be made
        glintlab.measure(None, os.path.join(BLENDER, "ref") + ":" + COMBINED, out="/proc/glintlab-cannot-write")
    assert not os.path.exists(tmp_path / "run")  # every error came before anything was written


def test_arguments_of_the_wrong_kind_are_value_errors_naming_them(tmp_path):
    """A wrong type, NaN or 0 where a number >= 1 is asked: ValueError naming the argument and what it
    allows (not pybind11's TypeError, not "not given"); a bytes path is a path; a summary dict with an
    integer no summary holds is a ValueError naming its key; the CLI refuses --ppd nan as it does
    --threshold nan."""
    ref = glintlab.read_image(HDR_REF)
    cases = [(dict(ppd="abc"), r"compare: ppd='abc' is not allowed; allowed: a finite number"),
             (dict(ppd=math.nan), r"ppd=nan is not allowed"),
             (dict(threshold=math.nan), r"threshold=nan is not allowed"),
             (dict(num_exposures=2**40), r"num_exposures=1099511627776 is not allowed; allowed: a whole number"),
             (dict(num_exposures=0), r"num_exposures=0 is not allowed"),
             (dict(tone_mapper=None), r"tone_mapper=None is not allowed; allowed: a string"),
             (dict(flip_ldr=1), r"flip_ldr=1 is not allowed; allowed: True or False")]
    for options, message in cases:
        with pytest.raises(ValueError, match=message):
            glintlab.compare(ref, ref, **options)
    with pytest.raises(ValueError, match=r"metrics=5 is not allowed"):
        glintlab.compare(ref, ref, metrics=5)
    with pytest.raises(ValueError, match=r"flip: numExposures=0 is not allowed"):
        glintlab.flip(ref, ref, numExposures=0)
    with pytest.raises(ValueError, match=r"flip: tonemapper=None is not allowed"):
        glintlab.flip(ref, ref, tonemapper=None)
    assert glintlab.compare(os.fsencode(HDR_REF), os.fsencode(HDR_TEST), metrics="deltaE2000")["deltaE2000"]["mean"] \
        == glintlab.compare(HDR_REF, HDR_TEST, metrics="deltaE2000")["deltaE2000"]["mean"]
    summary = {"schema": "glintlab-summary/1", "experiment": "x", "variants": [
        {"name": "a", "metrics": {"deltaE2000": {"mean": 10**400}}}]}
    with pytest.raises(ValueError, match=r"summary.variants\[0\].metrics.deltaE2000.mean: the integer"):
        glintlab.check(summary, summary)
    p = cli("compare", HDR_TEST, HDR_REF, "--ppd", "nan", check=False)
    assert p.returncode == 2 and "--ppd must be a finite number" in p.stderr, p.stderr


def test_no_vulkan_device_raises_runtime_error(tmp_path):
    env = dict(os.environ, VK_ICD_FILENAMES="/nonexistent.json", VK_DRIVER_FILES="/nonexistent.json")
    code = ("import glintlab\ntry:\n    glintlab.run('regression', out=%r, frames=1)\n"
            "except RuntimeError as e:\n    print('RuntimeError:', e)\n") % str(tmp_path / "run")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert "RuntimeError: Vulkan: no Vulkan driver found" in p.stdout, p.stdout + p.stderr


# ---------------------------------------------------------------- measure

def timing_free(rows):
    return [{k: v for k, v in r.items() if "ms" not in k.split("_") and k != "wall_s"} for r in rows]


def summary_metrics(summary):
    return {v["name"]: {m: x for m, x in v["metrics"].items() if not m.endswith("_ms")} for v in summary["variants"]}


def cli_measure(out, *args):
    cli("measure", "--out", str(out), "--no-report", *args)
    with open(out / "summary.json") as f:
        summary = json.load(f)
    return summary, glintlab._read_records(str(out / "frames.csv"))  # the rows as measure() returns them


def rows_equal(a, b):
    assert len(a) == len(b)
    for x, y in zip(a, b):
        assert x.keys() == y.keys()
        for k in x:
            if isinstance(x[k], float) and math.isnan(x[k]):
                assert isinstance(y[k], float) and math.isnan(y[k]), k
            else:
                assert x[k] == y[k], k


def test_measure_paths_and_arrays_equal_cli(tmp_path):
    ref_seq = os.path.join(BLENDER, "ref", "frame_####.exr") + ":" + COMBINED
    test_seq = os.path.join(BLENDER, "spp4", "frame_####.exr") + ":" + COMBINED
    cs, crows = cli_measure(tmp_path / "cli", "--reference", ref_seq, "--test", "spp4=" + test_seq,
                            "--metrics", "deltaE2000,flip")
    ps, prows = glintlab.measure(ref_seq, {"spp4": test_seq}, metrics="deltaE2000,flip", out=tmp_path / "py")
    assert summary_metrics(ps) == summary_metrics(cs)
    rows_equal(timing_free(prows), timing_free(crows))
    # The same frames as arrays: the same numbers.
    ref, test = glintlab.read_sequence(ref_seq), glintlab.read_sequence(test_seq)
    assert ref.shape == (8, 45, 80, 3) and ref.dtype == np.float32
    s, rows = glintlab.measure(ref, {"spp4": test}, metrics=["deltaE2000", "flip"])
    assert summary_metrics(s) == summary_metrics(cs)
    assert [r["flicker_ratio"] for r in timing_free(rows)][1:] == [r["flicker_ratio"] for r in crows][1:]
    assert rows[3]["deltaE2000"] == crows[3]["deltaE2000"] and rows[3]["deltaE2000"] > 0


def test_measure_view_equals_cli_and_is_checked(tmp_path):
    """view= is --view: temporal_score through sRGB/Standard instead of the ACES view, recorded in the summary;
    a malformed or unknown DISPLAY/VIEW is a ValueError before anything is measured."""
    ref_seq = os.path.join(BLENDER, "ref", "frame_####.exr") + ":" + COMBINED
    test_seq = os.path.join(BLENDER, "spp4", "frame_####.exr") + ":" + COMBINED
    cs, _ = cli_measure(tmp_path / "cli", "--reference", ref_seq, "--test", "spp4=" + test_seq, "--metrics",
                        "deltaE2000", "--view", "sRGB/Standard")
    ps, _ = glintlab.measure(ref_seq, {"spp4": test_seq}, metrics="deltaE2000", view="sRGB/Standard",
                             out=tmp_path / "py")
    assert cs["temporal_score_view"] == ps["temporal_score_view"] == "sRGB/Standard"
    assert summary_metrics(ps) == summary_metrics(cs)
    ds, _ = glintlab.measure(ref_seq, {"spp4": test_seq}, metrics="deltaE2000")
    assert ds["temporal_score_view"] == "sRGB/ACES 1.0 SDR-video"
    score = lambda s: s["variants"][0]["metrics"]["temporal_score"]["mean"]
    assert score(ds) > 0 and score(ps) > 0 and score(ds) != score(ps)
    with pytest.raises(ValueError, match="view"):
        glintlab.measure(ref_seq, {"spp4": test_seq}, view="sRGB")
    with pytest.raises(ValueError, match="--view: display \"sRGB\" has no view \"Nope\""):
        glintlab.measure(ref_seq, {"spp4": test_seq}, view="sRGB/Nope")


def small_run_with_motion(tmp_path):
    """A 64x36, 4-frame glintlab render with its exact motion written (output.motion): RGBA EXRs of
    glintlab's four motion channels, the `pixels` convention with distances."""
    with open(os.path.join(DATA, "..", "..", "experiments", "data", "regression.json")) as f:
        e = json.load(f)
    e.update(name="motion-arrays", resolution=[64, 36], variants=[{"name": "no-aa"}], reference={"grid": 4},
             output={"exr": True, "png": False, "every": 1, "contact_sheet": False, "motion": True})
    e["camera_path"]["frames"] = 4
    with open(tmp_path / "exp.json", "w") as f:
        json.dump(e, f)
    cli("run", str(tmp_path / "exp.json"), "--out", str(tmp_path / "run"), "--no-report")
    return tmp_path / "run"


def oiiotool_channels(src, dst, channels, names):
    """dst/frame_####.exr: channels of src's frames renamed (OpenImageIO's own tool)."""
    os.makedirs(dst)
    for name in sorted(os.listdir(src)):
        subprocess.run(["oiiotool", os.path.join(src, name), "--ch", channels, "--chnames", names,
                        "-o", os.path.join(dst, name)], check=True)


def test_measure_motion_and_depth_arrays_read_in_place(tmp_path):
    run = small_run_with_motion(tmp_path)
    motion_dir = str(run / "motion")
    oiiotool_channels(motion_dir, str(tmp_path / "alpha"), "A,A,A", "R,G,B")
    oiiotool_channels(motion_dir, str(tmp_path / "xy"), "R,G", "X,Y")
    oiiotool_channels(motion_dir, str(tmp_path / "z"), "B", "Z")
    seq = lambda d: str(d) + "/frame_####.exr"  # noqa: E731
    # The four channels as one array; the frames from 0, as the arrays' are.
    motion = np.concatenate([glintlab.read_sequence(motion_dir), glintlab.read_sequence(str(tmp_path / "alpha"))[..., :1]],
                            axis=3)
    assert motion.shape == (4, 36, 64, 4) and np.isfinite(motion).all() and motion[..., 2].max() > 0
    ref, test = glintlab.read_sequence(str(run / "reference")), glintlab.read_sequence(str(run / "no-aa"))
    base = ["--reference", seq(run / "reference"), "--test", "no-aa=" + seq(run / "no-aa"), "--metrics", "deltaE2000,flip"]
    cases = [  # glintlab's own four channels; then X, Y with a depth sequence
        (["--motion", seq(run / "motion")], dict(motion=motion)),
        (["--motion", seq(tmp_path / "xy"), "--depth", seq(tmp_path / "z")],
         dict(motion=np.ascontiguousarray(motion[..., :2]), depth=np.ascontiguousarray(motion[..., 2]))),
    ]
    for i, (args, arrays) in enumerate(cases):
        cs, crows = cli_measure(tmp_path / f"cli{i}", *base, *args)
        out = tmp_path / f"py{i}"
        ps, prows = glintlab.measure(ref, {"no-aa": test}, metrics="deltaE2000,flip", out=out, **arrays)
        assert ps["motion"] == "exact" and ps["disocclusion"] == cs["disocclusion"]
        assert summary_metrics(ps) == summary_metrics(cs)
        rows_equal(timing_free(prows), timing_free(crows))
        # The arrays were read where they are (no copy of them written), known by their hashes.
        assert "inputs" not in os.listdir(out) and not list(out.rglob("*.exr"))
        with open(out / "records.jsonl") as f:
            inputs = json.loads(f.readline())["inputs"]
        assert sorted(inputs) == sorted(["array reference", "array no-aa"] + [f"array {k}" for k in arrays])
        assert len(set(inputs.values())) == len(inputs) and all(len(h) == 32 for h in inputs.values())
    # The frame count of every array is the run's.
    with pytest.raises(ValueError, match=r"'array motion' has 3 frame\(s\) but the run has 4"):
        glintlab.measure(ref, test, motion=np.ascontiguousarray(motion[:3]))


def test_two_threads_measure_at_once(tmp_path):
    seq = glintlab.read_sequence(os.path.join(BLENDER, "spp1"), COMBINED)
    ref = glintlab.read_sequence(os.path.join(BLENDER, "ref"), COMBINED)
    results, errors = {}, []

    def work(i):
        try:
            results[i] = glintlab.measure(ref, seq, metrics="flip", out=tmp_path / f"t{i}")
        except Exception as e:  # noqa: BLE001 - reported below
            errors.append(e)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=300)
    assert not errors and len(results) == 2
    assert summary_metrics(results[0][0]) == summary_metrics(results[1][0])
    rows_equal(timing_free(results[0][1]), timing_free(results[1][1]))


# ---------------------------------------------------------------- check

def test_check_passes_and_finds_a_regression(tmp_path):
    seq = os.path.join(BLENDER, "spp1") + ":" + COMBINED
    summary, _ = glintlab.measure(os.path.join(BLENDER, "ref") + ":" + COMBINED, seq, metrics="deltaE2000",
                                  out=tmp_path / "m")
    passed, regressions = glintlab.check(summary, str(tmp_path / "m" / "summary.json"))
    assert passed and regressions == []
    better = json.loads(json.dumps(summary))
    better["variants"][0]["metrics"]["deltaE2000"]["mean"] *= 0.5
    passed, regressions = glintlab.check(summary, better)
    assert not passed and [(r["variant"], r["metric"]) for r in regressions] == [("spp1", "deltaE2000")]
    with open(tmp_path / "better.json", "w") as f:
        json.dump(better, f)
    assert cli("check", str(tmp_path / "m" / "summary.json"), str(tmp_path / "better.json")).returncode == 1
    passed, _ = glintlab.check(summary, better, tolerances={"deltaE2000": 1.5})
    assert passed
    with pytest.raises(ValueError, match="nope"):
        glintlab.check(summary, better, tolerances={"nope": 1})
