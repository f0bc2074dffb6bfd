#!/usr/bin/env python3
"""glintlab tune's driver: workers of one Optuna study (experiments/tune/tune.h checked its definition).

    python3 glintlab_tune.py STUDY_DIR [--workers K]

STUDY_DIR/study.json is the definition `glintlab tune` wrote; STUDY_DIR/experiment.json the experiment
as it was when the study began. The study lives in STUDY_DIR/study.db (Optuna's SQLite storage) or
STUDY_DIR/study.journal (its journal-file storage, for workers on several machines sharing a file
system). Each worker loops, under STUDY_DIR/.tune.lock:
  - trials RUNNING whose worker is gone (its process on this host is dead, or its heartbeat is older
    than GRACE_S) are marked FAIL and their settings enqueued again: a killed worker loses only its
    running trial, which is retried;
  - stop when N trials are COMPLETE; wait while COMPLETE + RUNNING >= N (a running trial may still
    fail); else ask the sampler for a trial (an enqueued retry first).
A trial writes STUDY_DIR/trials/NNNN/experiment.json (the experiment with only the base variant, the
trial's settings applied, named trial-NNNN) and runs `glintlab run` on it with the shared reference
cache, so it renders only its variant; its objectives come from the run's summary.json. When the study
is complete a worker writes (atomically) STUDY_DIR/trials.csv, STUDY_DIR/pareto.json and
STUDY_DIR/tune_report.html.
Each worker samples with a seed of its own: the study's seed for the first worker to join it, seeds derived
from it and the worker's number for the others (worker_seed), so no two workers, on this machine or under
a scheduler, nor a resumed study's new ones, draw the same settings. A journal whose last line was cut (a
writer killed mid-append) loses that line and goes on; a storage file that cannot be read as a study is
exit 2, naming it.
Exit codes: 0 complete, 1 trials failed beyond the budget's retries, 2 bad input (a damaged storage file
too), 4 I/O, 10 missing module.
"""
import copy
import csv
import fcntl
import html
import io
import json
import math
import os
import socket
import subprocess
import sys
import threading
import time

# The report's folder, beside this one in the source tree and where installed: Pareto dominance.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "report"))
import glintlab_pareto  # noqa: E402

try:
    import optuna
except ImportError as e:  # pragma: no cover - the package is a bootstrap dependency
    print(f"error: tune: the Python module optuna is missing ({e}); install the Debian package python3-optuna "
          "(./bootstrap.sh does)", file=sys.stderr)
    sys.exit(10)

HEARTBEAT_S = 5.0
GRACE_S = 120.0          # a heartbeat older than this: the worker is gone (another host, or a hung one)
POLL_S = 1.0
STALE_LOCK_S = 60.0      # Optuna's journal lock file older than this was left by a killed writer


def atomic_write(path, text):
    tmp = f"{path}.tmp.{os.getpid()}"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


class Lock:
    def __init__(self, path):
        self.path = path

    def __enter__(self):
        self.fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
        fcntl.flock(self.fd, fcntl.LOCK_EX)
        return self

    def __exit__(self, *exc):
        fcntl.flock(self.fd, fcntl.LOCK_UN)
        os.close(self.fd)


class StorageDamaged(Exception):
    """The study's storage file cannot be read as an Optuna study (exit 2, naming the file)."""


def storage_path(study_dir, kind):
    return os.path.join(study_dir, "study.journal" if kind == "journal" else "study.db")


def recover_torn_journal(path):
    """Drops a journal's last line when it was cut (no newline at its end: a writer killed mid-append).

    Optuna's reader skips such a line, but the next append would be written onto it and make the journal
    unreadable. Appends are made under Optuna's lock file (PATH.lock); one older than STALE_LOCK_S was left
    by a killed writer (an append takes milliseconds) and is removed, so no worker waits on it forever.
    Called under STUDY_DIR/.tune.lock."""
    if not os.path.isfile(path):
        return
    lock_file = path + ".lock"  # JournalFileOpenLock's name for it
    try:
        if time.time() - os.path.getmtime(lock_file) > STALE_LOCK_S:
            os.unlink(lock_file)
            print(f"tune: {lock_file} was left by a writer killed mid-append: removed", file=sys.stderr)
    except FileNotFoundError:
        pass
    lock = optuna.storages.JournalFileOpenLock(path)
    lock.acquire()
    try:
        with open(path, "rb+") as f:
            size = f.seek(0, os.SEEK_END)
            if size == 0:
                return
            f.seek(size - 1)
            if f.read(1) == b"\n":
                return
            keep = size - 1
            while keep > 0:  # back to the last newline, a block at a time
                start = max(0, keep - 65536)
                f.seek(start)
                block = f.read(keep - start)
                nl = block.rfind(b"\n")
                if nl >= 0:
                    keep = start + nl + 1
                    break
                keep = start
            if keep == 0:  # not one whole line: not a journal a killed writer cut short
                raise StorageDamaged(f"{path} holds no complete line: it is not an Optuna journal; restore it "
                                     "from a copy, or start a new study in another --study folder")
            f.truncate(keep)
            f.flush()
            os.fsync(f.fileno())
        print(f"tune: {path}: its last line was cut ({size - keep} bytes; a writer killed mid-append): dropped, "
              "the study goes on (a trial whose record it was is retried)", file=sys.stderr)
    finally:
        lock.release()


def storage_of(study_dir, kind):
    path = storage_path(study_dir, kind)
    if kind == "journal":
        return optuna.storages.JournalStorage(
            optuna.storages.JournalFileStorage(path, lock_obj=optuna.storages.JournalFileOpenLock(path)))
    return optuna.storages.RDBStorage(f"sqlite:///{path}", engine_kwargs={"connect_args": {"timeout": 60}})


def open_study(study_dir, d, sampler=None, create=False):
    """The study in its storage (created when `create`); StorageDamaged naming the file when the storage
    cannot be read as one."""
    path = storage_path(study_dir, d["storage"])
    name = d["experiment"] + "/" + d["base"]
    try:
        if d["storage"] == "journal":
            recover_torn_journal(path)
        storage = storage_of(study_dir, d["storage"])
        if create:
            return optuna.create_study(study_name=name, storage=storage, sampler=sampler,
                                       directions=["minimize"] * len(d["objectives"]), load_if_exists=True)
        return optuna.load_study(study_name=name, storage=storage, sampler=sampler)
    except StorageDamaged:
        raise
    except Exception as e:  # what a damaged file raises depends on where it is damaged
        raise StorageDamaged(f"{path} cannot be read as an Optuna study ({type(e).__name__}: {e}); restore it "
                             "from a copy, or start a new study in another --study folder") from e


def worker_seed(seed, worker):
    """The sampler seed of the study's `worker`-th worker (0, 1, ... in the order they joined it): the
    study's seed for the first, so a one-worker study is reproducible; distinct ones for the others, so
    no two workers draw the same settings."""
    return (seed + worker * 0x9E3779B9) % 2**32


def sampler_of(d, worker=0):
    seed = worker_seed(d["seed"], worker)
    if d["sampler"] == "nsga2":
        return optuna.samplers.NSGAIISampler(seed=seed)
    return optuna.samplers.TPESampler(seed=seed, n_startup_trials=max(4, min(10, d["trials"] // 4)))


def distributions(d):
    out = {}
    for s in d["space"]:
        if s["kind"] == "int":
            out[s["key"]] = optuna.distributions.IntDistribution(int(s["lo"]), int(s["hi"]), log=s["log"])
        elif s["kind"] == "float":
            out[s["key"]] = optuna.distributions.FloatDistribution(float(s["lo"]), float(s["hi"]), log=s["log"])
        else:
            out[s["key"]] = optuna.distributions.CategoricalDistribution(s["choices"])
    return out


def with_value(variant, key, value):
    v = copy.deepcopy(variant)
    at = v
    parts = key.split(".")
    for p in parts[:-1]:
        at = at.setdefault(p, {})
    at[parts[-1]] = value
    return v


def variant_of(d, params, name):
    v = copy.deepcopy(d["base_variant"])
    for key, value in params.items():
        v = with_value(v, key, value)
    v["name"] = name
    return v


def metric_mean(variant, name):
    m = (variant.get("metrics") or {}).get(name)
    if isinstance(m, dict) and isinstance(m.get("mean"), (int, float)) and math.isfinite(m["mean"]):
        return float(m["mean"])
    return None


def objective_value(variant, name, metric_info):
    """The value minimised for objective `name` from a summary's variant, or None; metric_info: the
    summary's "metric_info" (a metric whose best value is 1 is minimised as |ln ratio|)."""
    if name == "gpu_ms":
        g = variant.get("gpu_ms")
        return float(g["mean"]) if isinstance(g, dict) and isinstance(g.get("mean"), (int, float)) else None
    if name == "glint_density_ratio":
        t, r = metric_mean(variant, "glint_density_test"), metric_mean(variant, "glint_density_ref")
        return abs(math.log(t / r)) if t and r and t > 0 and r > 0 else None
    m = metric_mean(variant, name)
    if m is not None and (metric_info.get(name) or {}).get("direction") == "one":
        return abs(math.log(m)) if m > 0 else None
    return m


class Worker:
    def __init__(self, study_dir):
        self.dir = study_dir
        with open(os.path.join(study_dir, "study.json"), encoding="utf-8") as f:
            self.d = json.load(f)
        with open(os.path.join(study_dir, "experiment.json"), encoding="utf-8") as f:
            self.experiment = json.load(f)
        self.lock = os.path.join(study_dir, ".tune.lock")
        self.me = f"{socket.gethostname()}:{os.getpid()}"
        optuna.logging.set_verbosity(optuna.logging.WARNING)
        with Lock(self.lock):  # one creator: the others load it
            study = open_study(study_dir, self.d, create=True)
            # The workers are numbered in the order they join the study (a resumed study's new workers
            # get new numbers): each samples with a seed of its own.
            self.number = study.user_attrs.get("workers_joined", 0)
            study.set_user_attr("workers_joined", self.number + 1)
            self.study = open_study(study_dir, self.d, sampler=sampler_of(self.d, self.number))
        self.dists = distributions(self.d)

    # ---- the study's bookkeeping, always under the lock
    def reap_stale(self):
        now = time.time()
        host = socket.gethostname()
        for t in self.study.get_trials(deepcopy=False, states=(optuna.trial.TrialState.RUNNING,)):
            who = t.user_attrs.get("worker", "")
            beat = t.user_attrs.get("heartbeat", 0.0)
            gone = now - beat > GRACE_S
            h, _, pid = who.rpartition(":")
            if h == host and pid.isdigit() and int(pid) != os.getpid():
                try:
                    os.kill(int(pid), 0)
                except ProcessLookupError:
                    gone = True
                except PermissionError:
                    pass
            if gone:
                self.study._storage.set_trial_state_values(t._trial_id, optuna.trial.TrialState.FAIL)
                self.study.enqueue_trial(t.params, user_attrs={"retry_of": t.number})
                print(f"tune: trial {t.number} of worker {who} is stale (its worker is gone): marked FAIL, its "
                      "settings queued again", file=sys.stderr)

    def next_trial(self):
        """A new trial, or "done" / "wait"."""
        with Lock(self.lock):
            self.reap_stale()
            trials = self.study.get_trials(deepcopy=False)
            done = sum(t.state == optuna.trial.TrialState.COMPLETE for t in trials)
            running = sum(t.state == optuna.trial.TrialState.RUNNING for t in trials)
            failed = sum(t.state == optuna.trial.TrialState.FAIL and "error" in t.user_attrs for t in trials)
            if done >= self.d["trials"]:
                return "done"
            if failed > self.d["trials"]:
                return "failing"
            if done + running >= self.d["trials"]:
                return "wait"
            trial = self.study.ask(self.dists)
            trial.set_user_attr("worker", self.me)
            trial.set_user_attr("heartbeat", time.time())
            return trial

    def heartbeat(self, trial, stop):
        while not stop.wait(HEARTBEAT_S):
            try:
                trial.set_user_attr("heartbeat", time.time())
            except Exception:  # a storage hiccup: the next beat retries
                pass

    def run_trial(self, trial):
        t0 = time.time()
        n = trial.number
        name = f"trial-{n:04d}"
        tdir = os.path.join(self.dir, "trials", f"{n:04d}")
        os.makedirs(tdir, exist_ok=True)
        e = copy.deepcopy(self.experiment)
        e["variants"] = [variant_of(self.d, trial.params, name)]
        e.pop("density_sweep", None)  # a trial is one variant; the experiment's sweep names others
        out = e.setdefault("output", {})
        out.update({"png": False, "exr": False, "contact_sheet": False})
        exp_path = os.path.join(tdir, "experiment.json")
        atomic_write(exp_path, json.dumps(e, indent=1))
        cmd = [self.d["glintlab"], "run", exp_path, "--out", os.path.join(tdir, "run"), "--cache", self.d["cache"],
               "--no-report"]
        if self.d.get("device"):
            cmd += ["--device", self.d["device"]]
        stop = threading.Event()
        beat = threading.Thread(target=self.heartbeat, args=(trial, stop), daemon=True)
        beat.start()
        r0 = time.time()
        with open(os.path.join(tdir, "run.log"), "w", encoding="utf-8") as logf:
            rc = subprocess.call(cmd, stdout=logf, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)
        run_s = time.time() - r0
        stop.set()
        beat.join()
        values, why = None, ""
        if rc == 0:
            with open(os.path.join(tdir, "run", "summary.json"), encoding="utf-8") as f:
                v = json.load(f)["variants"][0]
            values = [objective_value(v, m, self.d["metric_info"]) for m in self.d["objectives"]]
            missing = [m for m, x in zip(self.d["objectives"], values) if x is None]
            if missing:
                why = "no value for " + ", ".join(missing)
                values = None
            else:
                trial.set_user_attr("gpu_ms", objective_value(v, "gpu_ms", self.d["metric_info"]))
                for m in self.d["objectives"]:
                    trial.set_user_attr("raw_" + m, metric_mean(v, m) if m != "gpu_ms" else objective_value(v, m, self.d["metric_info"]))
        else:
            why = f"glintlab run exited {rc} (see {os.path.join(tdir, 'run.log')})"
        trial.set_user_attr("run_s", run_s)
        with Lock(self.lock):
            if values is None:
                trial.set_user_attr("error", why)
                self.study.tell(trial, state=optuna.trial.TrialState.FAIL)
                print(f"tune: trial {n} failed: {why}", file=sys.stderr)
            else:
                trial.set_user_attr("wall_s", time.time() - t0)
                self.study.tell(trial, values)
        print(f"tune: trial {n} {'done' if values else 'failed'} in {time.time() - t0:.1f} s "
              f"({run_s:.1f} s rendering and measuring)", file=sys.stderr)

    def loop(self):
        while True:
            t = self.next_trial()
            if t == "done":
                return 0
            if t == "failing":
                print("error: tune: more trials failed than the study's budget; see trials/*/run.log", file=sys.stderr)
                return 1
            if t == "wait":
                time.sleep(POLL_S)
                continue
            self.run_trial(t)


# ------------------------------------------------------------------ outputs
def finished(study):
    return [t for t in study.get_trials(deepcopy=False) if t.state == optuna.trial.TrialState.COMPLETE]


def pareto(trials):
    return glintlab_pareto.front(trials, lambda t: t.values)


def write_outputs(study_dir):
    with open(os.path.join(study_dir, "study.json"), encoding="utf-8") as f:
        d = json.load(f)
    study = open_study(study_dir, d)
    trials = study.get_trials(deepcopy=False)
    keys = [s["key"] for s in d["space"]]
    objs = d["objectives"]
    buf = io.StringIO()
    cw = csv.writer(buf, lineterminator="\n")
    cw.writerow(["trial", "state"] + keys + objs + [f"raw_{m}" for m in objs] +
                ["gpu_ms", "wall_s", "run_s", "overhead_s", "worker", "retry_of", "error"])
    for t in trials:
        vals = list(t.values) if t.values else [""] * len(objs)
        ua = t.user_attrs
        wall, run = ua.get("wall_s"), ua.get("run_s")
        cw.writerow([t.number, t.state.name] + [t.params.get(k, "") for k in keys] + vals +
                    [ua.get(f"raw_{m}", "") for m in objs] +
                    [ua.get("gpu_ms", ""), wall if wall is not None else "", run if run is not None else "",
                     (wall - run) if wall is not None and run is not None else "", ua.get("worker", ""),
                     ua.get("retry_of", ""), ua.get("error", "")])
    atomic_write(os.path.join(study_dir, "trials.csv"), buf.getvalue())
    done = finished(study)
    front = sorted(pareto(done), key=lambda t: tuple(t.values))
    base = d["base_variant"]
    pj = {"schema": "glintlab-pareto/1", "experiment": d["experiment"], "base": d["base"], "objectives": objs,
          "trials_complete": len(done),
          "front": [{"trial": t.number, "values": dict(zip(objs, t.values)), "params": t.params,
                     "variant": variant_of(d, t.params, f"{d['base']}-tuned-{t.number}")} for t in front]}
    atomic_write(os.path.join(study_dir, "pareto.json"), json.dumps(pj, indent=1) + "\n")
    write_report(study_dir, d, study, done, front)
    return len(done)


def baseline(study_dir, d):
    """Every shipped variant of the experiment with the base's glint model, run once (cached
    references): where they fall."""
    out = os.path.join(study_dir, "baseline")
    summary = os.path.join(out, "summary.json")
    if not os.path.isfile(summary):
        rc = subprocess.call([d["glintlab"], "run", os.path.join(study_dir, "experiment.json"), "--out", out,
                              "--cache", d["cache"], "--no-report", "--resume"],
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, stdin=subprocess.DEVNULL)
        if rc != 0 or not os.path.isfile(summary):
            return []
    with open(summary, encoding="utf-8") as f:
        s = json.load(f)
    pts = []
    # Only the variants measured against the same truth as the base (the same glint model).
    model = next((v.get("glint_model") for v in s["variants"] if v["name"] == d["base"]), None)
    for v in s["variants"]:
        if model is not None and v.get("glint_model") != model:
            continue
        vals = [objective_value(v, m, d["metric_info"]) for m in d["objectives"]]
        if all(x is not None for x in vals):
            pts.append((v["name"], vals))
    return pts


def write_report(study_dir, d, study, done, front):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    objs, keys = d["objectives"], [s["key"] for s in d["space"]]
    label = lambda m: f"|ln {m}|" if (d["metric_info"].get(m) or {}).get("direction") == "one" else m
    figs = []

    def svg(fig):
        b = io.StringIO()
        fig.savefig(b, format="svg", bbox_inches="tight")
        plt.close(fig)
        return b.getvalue()[b.getvalue().find("<svg"):]

    shipped = baseline(study_dir, d) if done else []
    if done and len(objs) >= 2:
        fig, ax = plt.subplots(figsize=(6, 4.2))
        ax.scatter([t.values[0] for t in done], [t.values[1] for t in done], s=14, c="0.6", label="trials")
        fr = sorted(front, key=lambda t: t.values[0])
        ax.plot([t.values[0] for t in fr], [t.values[1] for t in fr], "o--", c="C3", ms=5, label="Pareto front")
        for name, vals in shipped:
            ax.scatter([vals[0]], [vals[1]], marker="^" if name != d["base"] else "*", s=60 if name != d["base"] else 140,
                       c="C0" if name != d["base"] else "C2", zorder=3)
            ax.annotate(name, (vals[0], vals[1]), xytext=(4, 3), textcoords="offset points", fontsize=6)
        ax.set_xlabel(label(objs[0]))
        ax.set_ylabel(label(objs[1]))
        ax.set_title("Trials, their Pareto front, and the shipped variants (▲; ★ base)")
        ax.legend(fontsize=7)
        figs.append(("Pareto front", svg(fig)))
    imp_html = ""
    if len(done) >= 4:
        rows = []
        for i, m in enumerate(objs):
            try:
                imp = optuna.importance.get_param_importances(study, target=lambda t, i=i: t.values[i])
                rows.append((m, imp))
            except Exception as e:  # too few distinct trials, or a missing module
                rows.append((m, {"(unavailable)": str(e)}))
        imp_html = "<table><tr><th>objective</th>" + "".join(f"<th>{html.escape(k)}</th>" for k in keys) + "</tr>"
        for m, imp in rows:
            cells = "".join(f"<td>{imp[k]:.3f}</td>" if isinstance(imp.get(k), float) else
                            f"<td>{html.escape(str(imp.get(k, imp.get('(unavailable)', ''))))}</td>" for k in keys)
            imp_html += f"<tr><td>{html.escape(label(m))}</td>{cells}</tr>"
        imp_html += "</table>"
    if done:
        fig, axes = plt.subplots(len(objs), len(keys), figsize=(2.8 * len(keys) + 0.5, 2.3 * len(objs) + 0.3),
                                 squeeze=False)
        for i, m in enumerate(objs):
            for j, k in enumerate(keys):
                ax = axes[i][j]
                xs = [t.params[k] for t in done]
                if any(isinstance(x, (bool, str)) for x in xs):
                    cats = sorted({json.dumps(x) for x in xs})
                    ax.scatter([cats.index(json.dumps(x)) for x in xs], [t.values[i] for t in done], s=10)
                    ax.set_xticks(range(len(cats)))
                    ax.set_xticklabels(cats, fontsize=6)
                else:
                    ax.scatter(xs, [t.values[i] for t in done], s=10)
                if i == len(objs) - 1:
                    ax.set_xlabel(k, fontsize=8)
                if j == 0:
                    ax.set_ylabel(label(m), fontsize=8)
                ax.tick_params(labelsize=6)
        figs.append(("Each objective against each searched option", svg(fig)))
    dom_html = ""
    base_pt = next((vals for name, vals in shipped if name == d["base"]), None)
    if base_pt is not None:
        better = [t for t in done if glintlab_pareto.dominates(t.values, base_pt)]
        dom_html = ("<h2>Against the base variant</h2><p>The base variant <b>" + html.escape(d["base"]) + "</b>: "
                    + ", ".join(f"{html.escape(label(m))} {v:.4g}" for m, v in zip(objs, base_pt)) + ". "
                    + (f"{len(better)} trial(s) dominate it on every objective: "
                       + ", ".join(f"{t.number} (" + ", ".join(f"{v:.4g}" for v in t.values) + ")" for t in better)
                       if better else "No trial dominates it on every objective in the space searched.") + "</p>")
    rows = "".join(f"<tr><td>{t.number}</td>" + "".join(f"<td>{v:.4g}</td>" for v in t.values) +
                   f"<td><code>{html.escape(json.dumps(t.params))}</code></td></tr>" for t in front)
    body = (f"<h1>glintlab tune: {html.escape(d['experiment'])} / {html.escape(d['base'])}</h1>"
            f"<p>{len(done)} finished trials of {d['trials']}; sampler {html.escape(d['sampler'])} (seed {d['seed']}), "
            f"storage {html.escape(d['storage'])}. Objectives, all minimised: "
            + ", ".join(html.escape(label(m)) for m in objs) + ". Every trial is a <code>glintlab run</code> in "
            "<code>trials/NNNN/</code>; settings and objectives of all of them in <code>trials.csv</code>, the "
            "non-dominated ones as variants to paste in <code>pareto.json</code>.</p>"
            + dom_html + "".join(f"<h2>{html.escape(t)}</h2><figure>{s}</figure>" for t, s in figs)
            + "<h2>Pareto-optimal settings</h2><table><tr><th>trial</th>"
            + "".join(f"<th>{html.escape(label(m))}</th>" for m in objs) + f"<th>settings</th></tr>{rows}</table>"
            + ("<h2>Parameter importances (Optuna, fANOVA)</h2>" + imp_html if imp_html else ""))
    page = ("<!doctype html><meta charset=utf-8><title>glintlab tune</title><style>body{font-family:sans-serif;"
            "max-width:1100px;margin:2em auto}table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:2px 6px;"
            f"font-size:13px}}</style>{body}")
    atomic_write(os.path.join(study_dir, "tune_report.html"), page)


def main(argv):
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    study_dir = argv[1]
    workers = int(argv[argv.index("--workers") + 1]) if "--workers" in argv else 1
    try:
        if workers > 1:
            procs = [subprocess.Popen([sys.executable, "-B", __file__, study_dir]) for _ in range(workers)]
            codes = [p.wait() for p in procs]
            rc = max(codes)
        else:
            rc = Worker(study_dir).loop()
        if rc == 0 and workers >= 1:
            with Lock(os.path.join(study_dir, ".tune.lock")):
                n = write_outputs(study_dir)
            print(f"tune: {n} trials complete; {os.path.join(study_dir, 'trials.csv')}, pareto.json, "
                  "tune_report.html", file=sys.stderr)
    except StorageDamaged as e:
        print(f"error: tune: {e}", file=sys.stderr)
        return 2
    return rc


if __name__ == "__main__":
    sys.exit(main(sys.argv))
